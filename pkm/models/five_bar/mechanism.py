"""The symmetric planar 5R mechanism (Gao 1998; Lara-Molina 2016).

Base joints O1 = (-r3, 0) and O2 = (r3, 0) (r3 the half base), proximal links r1 (actuated at the
base), distal links r2 meeting at the end effector P = (x, y). The four working modes are the four
combinations of elbow branches; in Gao's Fig. 3 they are the configurations OABCD (both elbows out),
OABC'D, OA'BCD and OA'BC'D, with A/A' the elbow of the chain at O and C/C' that of the chain at D.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from pkm.design import Condition, Parameter
from pkm.design_space import DesignSpace
from pkm.kinematics import Branch
from pkm.mechanism import Mechanism
from pkm.models.five_bar.legs import described
from pkm.models.five_bar.spaces import GAO1998, LARA_MOLINA2016
from pkm.models.five_bar.structure import structure
from pkm.regions import Disc
from pkm.spec.given_legs import GivenLegs


def _optional(name, default, lower, unit, doc, *, closed=False, default_from=None):
    return Parameter(
        name, default, lower, math.inf, unit, doc, closed_lower=closed, required=False, default_from=default_from
    )


R1, R2, R3 = 1.2, 1.0, 0.8  # m: the default proximal and distal links and half base
LINK_MASS_PER_LENGTH = 0.821  # kg/m: an aluminium square tube 40 x 40 x 2 mm (3.04e-4 m^2, 2700 kg/m^3)
SHAFT_STIFFNESS = 1.25e4  # N m/rad: G pi d^4 / (32 l), a steel shaft (G = 79.3 GPa) d = 20 mm, l = 100 mm
ROTOR_INERTIA = 0.06  # kg m^2: a steel rotor of radius 30 mm and length 60 mm (6.0e-4 kg m^2) behind 10:1

DYNAMIC_PARAMETERS = (
    _optional("m1", LINK_MASS_PER_LENGTH * R1, 0.0, "kg", "mass of each proximal link; default 0.821 kg/m r1 (a "
              "40 x 40 x 2 mm aluminium tube)", default_from=("r1", LINK_MASS_PER_LENGTH)),
    _optional("m2", LINK_MASS_PER_LENGTH * R2, 0.0, "kg", "mass of each distal link; default 0.821 kg/m r2 (the "
              "same tube)", default_from=("r2", LINK_MASS_PER_LENGTH)),
    Parameter("c1", 0.5, -math.inf, math.inf, "-", "centre of mass of a proximal link from its base joint, in r1",
              required=False),
    Parameter("c2", 0.5, -math.inf, math.inf, "-", "centre of mass of a distal link from its elbow, in r2",
              required=False),
    _optional("g1", 1 / 12, 0.0, "-", "proximal link inertia about its centre of mass, in m1 r1^2 (bar: 1/12)",
              closed=True),
    _optional("g2", 1 / 12, 0.0, "-", "distal link inertia about its centre of mass, in m2 r2^2 (bar: 1/12)",
              closed=True),
    _optional("k1", SHAFT_STIFFNESS, 0.0, "N m/rad", "stiffness of the transmission of motor 1 (eq. 13); default "
              "a steel shaft of 20 mm diameter and 100 mm length"),
    _optional("k2", SHAFT_STIFFNESS, 0.0, "N m/rad", "stiffness of the transmission of motor 2 (eq. 13); default "
              "as k1"),
    _optional("j1", ROTOR_INERTIA, 0.0, "kg m^2", "rotor inertia of motor 1 after the reduction; default a steel "
              "rotor of radius 30 mm and length 60 mm behind a 10:1 reduction"),
    _optional("j2", ROTOR_INERTIA, 0.0, "kg m^2", "rotor inertia of motor 2 after the reduction; default as j1"),
    _optional("fv", 0.0, 0.0, "N m s/rad", "viscous friction at each actuated joint (eq. 22)", closed=True),
    _optional("fc", 0.0, 0.0, "N m", "Coulomb friction at each actuated joint (eq. 22)", closed=True),
    _optional("vm", 0.0, 0.0, "N m s/rad", "viscous friction at each rotor (eq. 13)", closed=True),
)
ELASTIC_PARAMETERS = (
    _optional("w_l", 0.04, 0.0, "m", "outer side of the links' aluminium square tube (their beams' section; the "
              "masses' defaults are the 40 mm tube's)"),
    _optional("t_l", 0.002, 0.0, "m", "wall of the links' square tube"),
)


class FiveBar(GivenLegs, Mechanism):
    name = "five_bar"
    doc = "symmetric planar 5R: two actuated proximal links, two distal links, end effector (x, y)"
    parameters = (
        Parameter("r1", R1, 0.0, math.inf, "m", "proximal (actuated) link length, base joint to elbow"),
        Parameter("r2", R2, 0.0, math.inf, "m", "distal link length, elbow to end effector"),
        Parameter("r3", R3, 0.0, math.inf, "m", "half the distance between the two base joints", closed_lower=True),
        *DYNAMIC_PARAMETERS,
        *ELASTIC_PARAMETERS,
    )
    conditions = (
        Condition("r1 + r2 > r3 (the chains' reaches overlap: Gao eq. 5)", lambda d: d["r1"] + d["r2"] - d["r3"]),
        Condition("2 t_l < w_l (the tube's walls within its side)", lambda d: d["w_l"] - 2 * d["t_l"]),
    )
    working_modes = (
        Branch("out_out", (1.0, -1.0), "both elbows outside the triangle O1 P O2", ("OABCD",)),
        Branch("out_in", (1.0, 1.0), "elbow of chain 1 outside, of chain 2 inside", ("OABC'D",)),
        Branch("in_out", (-1.0, -1.0), "elbow of chain 1 inside, of chain 2 outside", ("OA'BCD",)),
        Branch("in_in", (-1.0, 1.0), "both elbows inside the triangle O1 P O2", ("OA'BC'D",)),
    )
    distinct_modes: ClassVar[dict[str, tuple[str, ...]]] = {
        "reachable": ("out_out", "out_in"),
        "miw": ("out_out", "out_in", "in_in"),
    }
    assembly_modes = (
        Branch("up", (1.0,), "P to the left of the directed line A1 -> A2 (above it when A1 is left of A2)"),
        Branch("down", (-1.0,), "P to the right of the directed line A1 -> A2"),
    )
    pose_names = ("x", "y")
    pose_units = ("m", "m")
    actuator_names = ("theta1", "theta2")
    actuator_units = ("rad", "rad")
    design_spaces: ClassVar[dict[str, DesignSpace]] = {"gao1998": GAO1998, "lara_molina2016": LARA_MOLINA2016}
    structure = staticmethod(structure)
    regions: ClassVar[dict[str, Disc]] = {
        "miw": Disc(
            "miw",
            "maximum inscribed workspace: the disc of the MIC (Lara-Molina 2016 eqs. 10-12)",
            function="maximum_inscribed_circle",
        )
    }

    @classmethod
    def legs_description(cls) -> dict:
        """Its two RR legs (:mod:`pkm.models.five_bar.legs`)."""
        return described(cls.parameters)

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """The intersection of the chains' annuli lies in |x| <= R - r3, |y| <= sqrt(R^2 - r3^2)."""
        r1, r2, r3 = design[:3]
        reach = r1 + r2
        half_height = math.sqrt(max(reach**2 - r3**2, 0.0))
        return np.array([[r3 - reach, reach - r3], [-half_height, half_height]])

    def maximum_inscribed_circle(self, design=None) -> tuple[np.ndarray, float]:
        """Centre (0, y_MIC) and radius r_MIC of the maximum inscribed circle (Lara-Molina eqs. 10-12)."""
        centre, radius = self.functions["maximum_inscribed_circle"](self.design_vector(design))
        return np.asarray(centre).ravel(), float(radius)
