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
from pkm.design_space import DesignSpace, fixed_sum, interval
from pkm.mechanism import Branch, Mechanism
from pkm.regions import ParametrisedRegion

SQRT2 = math.sqrt(2.0)
SQRT3 = math.sqrt(3.0)


def _gao_to_design(c, scale=1.0):
    """Gao's (r1, r2, r3), r3 the full base, 2 r1 + 2 r2 + r3 = 4, -> (r1, r2, half base) in metres."""
    return [c[0] * scale, c[1] * scale, c[2] * scale / 2]


def _gao_from_design(d):
    """SI design -> Gao's normalised (r1, r2, r3) and the average link length L (Gao eq. 2)."""
    scale = (d[0] + d[1] + d[2]) / 2
    return [d[0] / scale, d[1] / scale, 2 * d[2] / scale], scale


def _gao_to_chart(c):
    """Isometric chart of the plane 2 r1 + 2 r2 + r3 = 4: u along r1 - r2, v along r3."""
    return (c[0] - c[1]) / SQRT2, 3 * c[2] / (2 * SQRT2)


def _gao_from_chart(u, v):
    r3 = 2 * SQRT2 * v / 3
    half_sum = (4 - r3) / 2
    return [(half_sum + SQRT2 * u) / 2, (half_sum - SQRT2 * u) / 2, r3]


GAO1998 = DesignSpace(
    name="gao1998",
    doc=(
        "Gao 1998 eqs. 1-5: r_i = R_i / L with L the average of the five link lengths, r3 the full "
        "base, 2 r1 + 2 r2 + r3 = 4, 0 < r1, r2 < 2, 0 <= r3 < 2. Chart: u = (r1 - r2)/sqrt(2), "
        "v = 3 r3 / (2 sqrt(2)), isometric in the plane of the solution space (trapezoid ABCD)."
    ),
    coordinates=("r1", "r2", "r3"),
    chart_axes=("u", "v"),
    to_design=_gao_to_design,
    from_design=_gao_from_design,
    to_chart=_gao_to_chart,
    from_chart=_gao_from_chart,
    polygon=((-SQRT2, 0.0), (SQRT2, 0.0), (1 / SQRT2, 3 / SQRT2), (-1 / SQRT2, 3 / SQRT2)),
    bounds=((0.0, 2.0), (0.0, 2.0), (0.0, 2.0)),
    conditions=(
        *interval("r1", 0, 2, source=" (Gao eq. 5)"),
        *interval("r2", 0, 2, source=" (Gao eq. 5)"),
        Condition("0 <= r3 < 2 (Gao eq. 5)", lambda c: c["r3"] + 1e-12),
        Condition("0 <= r3 < 2 (Gao eq. 5)", lambda c: 2 - c["r3"]),
        fixed_sum({"r1": 2, "r2": 2, "r3": 1}, 4, source=" (Gao eq. 3)"),
    ),
)


def _lara_to_design(c, scale=1.0):
    """Lara-Molina's (r1, r2, r3), r3 the half base, r1 + r2 + r3 = 3 -> SI lengths (r_i D)."""
    return [c[0] * scale, c[1] * scale, c[2] * scale]


def _lara_from_design(d):
    """SI design -> normalised (r1, r2, r3) and D = (r1 + r2 + r3) / 3 (Lara-Molina eq. 1)."""
    scale = (d[0] + d[1] + d[2]) / 3
    return [d[0] / scale, d[1] / scale, d[2] / scale], scale


def _lara_to_chart(c):
    """Lara-Molina eqs. 33-34: s = (2 r1 + r3) / sqrt(3), t = r3."""
    return (2 * c[0] + c[2]) / SQRT3, c[2]


def _lara_from_chart(s, t):
    r1 = (SQRT3 * s - t) / 2
    return [r1, 3 - r1 - t, t]


LARA_MOLINA2016 = DesignSpace(
    name="lara_molina2016",
    doc=(
        "Lara-Molina 2016 eqs. 1-2 and 32-34: r_i = R_i / D with D the mean of the three lengths, r3 "
        "the half base, r1 + r2 + r3 = 3, 0 < r1, r2 < 3, 0 <= r3 <= 1.5; chart s = (2 r1 + r3)/sqrt(3), "
        "t = r3 (conformal: distances in the plane scaled by sqrt(2/3)). Non-dimensional dynamics of "
        "section IV: m1 = 1.2, m2 = 0.8 (m1 + m2 = 2), k1 = k2 = 1 (k1 + k2 = 2), j_i = 0.5 m1."
    ),
    coordinates=("r1", "r2", "r3"),
    chart_axes=("s", "t"),
    to_design=_lara_to_design,
    from_design=_lara_from_design,
    to_chart=_lara_to_chart,
    from_chart=_lara_from_chart,
    polygon=((0.0, 0.0), (2 * SQRT3, 0.0), (4.5 / SQRT3, 1.5), (1.5 / SQRT3, 1.5)),
    bounds=((0.0, 3.0), (0.0, 3.0), (0.0, 1.5)),
    base={"m1": 1.2, "m2": 0.8, "k1": 1.0, "k2": 1.0},
    conditions=(
        *interval("r1", 0, 3, source=" (Lara-Molina eq. 32)"),
        *interval("r2", 0, 3, source=" (Lara-Molina eq. 32)"),
        *interval("r3", 0, 1.5, closed=True, source=" (Lara-Molina eq. 32)"),
        fixed_sum({"r1": 1, "r2": 1, "r3": 1}, 3, source=" (Lara-Molina eq. 2)"),
    ),
)


def _optional(name, default, lower, unit, doc, *, closed=False, default_from=None):
    return Parameter(
        name, default, lower, math.inf, unit, doc, closed_lower=closed, required=False, default_from=default_from
    )


DYNAMIC_PARAMETERS = (
    _optional("m1", 1.2, 0.0, "kg", "mass of each proximal link (Lara-Molina section IV: 1.2)"),
    _optional("m2", 0.8, 0.0, "kg", "mass of each distal link (Lara-Molina section IV: 0.8)"),
    Parameter("c1", 0.5, -math.inf, math.inf, "-", "centre of mass of a proximal link from its base joint, in r1",
              required=False),
    Parameter("c2", 0.5, -math.inf, math.inf, "-", "centre of mass of a distal link from its elbow, in r2",
              required=False),
    _optional("g1", 1 / 12, 0.0, "-", "proximal link inertia about its centre of mass, in m1 r1^2 (bar: 1/12)",
              closed=True),
    _optional("g2", 1 / 12, 0.0, "-", "distal link inertia about its centre of mass, in m2 r2^2 (bar: 1/12)",
              closed=True),
    _optional("k1", 1.0, 0.0, "N m/rad", "stiffness of the transmission of motor 1 (eq. 13)"),
    _optional("k2", 1.0, 0.0, "N m/rad", "stiffness of the transmission of motor 2 (eq. 13)"),
    _optional("j1", 0.6, 0.0, "kg m^2", "rotor inertia of motor 1 after the reduction; default 0.5 m1",
              default_from=("m1", 0.5)),
    _optional("j2", 0.6, 0.0, "kg m^2", "rotor inertia of motor 2 after the reduction; default 0.5 m1",
              default_from=("m1", 0.5)),
    _optional("fv", 0.0, 0.0, "N m s/rad", "viscous friction at each actuated joint (eq. 22)", closed=True),
    _optional("fc", 0.0, 0.0, "N m", "Coulomb friction at each actuated joint (eq. 22)", closed=True),
    _optional("vm", 0.0, 0.0, "N m s/rad", "viscous friction at each rotor (eq. 13)", closed=True),
)


class FiveBar(Mechanism):
    name = "five_bar"
    doc = "symmetric planar 5R: two actuated proximal links, two distal links, end effector (x, y)"
    parameters = (
        Parameter("r1", 1.2, 0.0, math.inf, "m", "proximal (actuated) link length, base joint to elbow"),
        Parameter("r2", 1.0, 0.0, math.inf, "m", "distal link length, elbow to end effector"),
        Parameter("r3", 0.8, 0.0, math.inf, "m", "half the distance between the two base joints", closed_lower=True),
        *DYNAMIC_PARAMETERS,
    )
    conditions = (
        Condition("r1 + r2 > r3 (the chains' reaches overlap: Gao eq. 5)", lambda d: d["r1"] + d["r2"] - d["r3"]),
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
    design_spaces: ClassVar[dict[str, DesignSpace]] = {"gao1998": GAO1998, "lara_molina2016": LARA_MOLINA2016}

    def parametrised_regions(self) -> dict[str, ParametrisedRegion]:
        return {
            "miw": ParametrisedRegion(
                "miw",
                "maximum_inscribed_circle",
                "maximum inscribed workspace: the disc of the MIC (Lara-Molina 2016 eqs. 10-12)",
            )
        }

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """The intersection of the chains' annuli lies in |x| <= R - r3, |y| <= sqrt(R^2 - r3^2)."""
        r1, r2, r3 = design[:3]
        reach = r1 + r2
        half_height = math.sqrt(max(reach**2 - r3**2, 0.0))
        return np.array([[r3 - reach, reach - r3], [-half_height, half_height]])

    def maximum_inscribed_circle(self, design=None) -> tuple[np.ndarray, float]:
        """Centre (0, y_MIC) and radius r_MIC of the maximum inscribed circle (Lara-Molina eqs. 10-12)."""
        centre, radius = self.functions["maximum_inscribed_circle"](self._design_vector(design))
        return np.asarray(centre).ravel(), float(radius)
