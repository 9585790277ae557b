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
from pkm.mechanism import Branch, Mechanism
from pkm.regions import ParametrisedRegion

SQRT2 = math.sqrt(2.0)


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
)


class FiveBar(Mechanism):
    name = "five_bar"
    doc = "symmetric planar 5R: two actuated proximal links, two distal links, end effector (x, y)"
    parameters = (
        Parameter("r1", 1.2, 0.0, math.inf, "m", "proximal (actuated) link length, base joint to elbow"),
        Parameter("r2", 1.0, 0.0, math.inf, "m", "distal link length, elbow to end effector"),
        Parameter("r3", 0.8, 0.0, math.inf, "m", "half the distance between the two base joints", closed_lower=True),
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
    design_spaces: ClassVar[dict[str, DesignSpace]] = {"gao1998": GAO1998}

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
        r1, r2, r3 = design
        reach = r1 + r2
        half_height = math.sqrt(max(reach**2 - r3**2, 0.0))
        return np.array([[r3 - reach, reach - r3], [-half_height, half_height]])

    def maximum_inscribed_circle(self, design=None) -> tuple[np.ndarray, float]:
        """Centre (0, y_MIC) and radius r_MIC of the maximum inscribed circle (Lara-Molina eqs. 10-12)."""
        centre, radius = self.functions["maximum_inscribed_circle"](self._design_vector(design))
        return np.asarray(centre).ravel(), float(radius)
