"""The five-bar's normalised design spaces: Gao 1998's solution space and Lara-Molina 2016's, each
with its planar chart (DESIGN.md section 3) and the requirements of an admissible design, which the
atlases and the syntheses share: every normalised length at least MIN_LENGTH inside its bounds and the
maximum inscribed circle's radius at least MIN_RADIUS (in the space's unit length: the designs of a
chart are at scale 1), without which the best designs shrink a link or the MIW to nothing."""

from __future__ import annotations

import math

from pkm.design import Condition
from pkm.design_space import DesignSpace, Requirement, fixed_sum, interval, within_bounds

SQRT2 = math.sqrt(2.0)
SQRT3 = math.sqrt(3.0)
MIN_LENGTH = 0.05  # every normalised length at least this far inside its bounds
MIN_RADIUS = 0.3  # [normalised length] the MIC radius at least this: otherwise the MIW shrinks to a point


def _requirements(coordinates: tuple[str, ...], bounds: tuple[tuple[float, float], ...], unit: str
                  ) -> tuple[Requirement, ...]:
    return (
        *within_bounds(bounds, coordinates, MIN_LENGTH, unit),
        Requirement(f"MIC radius >= {MIN_RADIUS:g} [{unit}]",
                    lambda _c, call: call("maximum_inscribed_circle", "radius"), MIN_RADIUS),
    )


def _gao_to_design(c, scale=1.0):
    """Gao's (r1, r2, base), the full base, 2 r1 + 2 r2 + base = 4, -> (r1, r2, r3 = half base) in metres."""
    return [c[0] * scale, c[1] * scale, c[2] * scale / 2]


def _gao_from_design(d):
    """SI design -> Gao's normalised (r1, r2, base) and the average link length L (Gao eq. 2)."""
    scale = (d[0] + d[1] + d[2]) / 2
    return [d[0] / scale, d[1] / scale, 2 * d[2] / scale], scale


def _gao_to_chart(c):
    """Isometric chart of the plane 2 r1 + 2 r2 + base = 4: u along r1 - r2, v along the base."""
    return (c[0] - c[1]) / SQRT2, 3 * c[2] / (2 * SQRT2)


def _gao_from_chart(u, v):
    base = 2 * SQRT2 * v / 3
    half_sum = (4 - base) / 2
    return [(half_sum + SQRT2 * u) / 2, (half_sum - SQRT2 * u) / 2, base]


GAO1998 = DesignSpace(
    name="gao1998",
    doc=(
        "Gao 1998 eqs. 1-5: r_i = R_i / L with L the average of the five link lengths, base = Gao's r3, "
        "the full base (twice pkm's half base r3), 2 r1 + 2 r2 + base = 4, 0 < r1, r2 < 2, 0 <= base < 2. "
        "Chart: u = (r1 - r2)/sqrt(2), v = 3 base / (2 sqrt(2)), isometric in the plane of the solution space "
        "(trapezoid ABCD)."
    ),
    coordinates=("r1", "r2", "base"),
    chart_axes=("u", "v"),
    chart_labels=("(r1 - r2)/\u221a2", "3 base/(2\u221a2)"),
    note="r_i = R_i / L, L the mean link length, base = Gao's r3 (the full base, 2 r3 / L in pkm's terms), "
    "2 r1 + 2 r2 + base = 4 (Gao 1998 eqs. 1-5)",
    to_design=_gao_to_design,
    from_design=_gao_from_design,
    to_chart=_gao_to_chart,
    from_chart=_gao_from_chart,
    parameters=("r1", "r2", "r3"),
    polygon=((-SQRT2, 0.0), (SQRT2, 0.0), (1 / SQRT2, 3 / SQRT2), (-1 / SQRT2, 3 / SQRT2)),
    bounds=((0.0, 2.0), (0.0, 2.0), (0.0, 2.0)),
    requirements=_requirements(("r1", "r2", "base"), ((0.0, 2.0), (0.0, 2.0), (0.0, 2.0)), "L"),
    conditions=(
        *interval("r1", 0, 2, source=" (Gao eq. 5)"),
        *interval("r2", 0, 2, source=" (Gao eq. 5)"),
        Condition("0 <= base < 2 (Gao eq. 5)", lambda c: c["base"] + 1e-12),
        Condition("0 <= base < 2 (Gao eq. 5)", lambda c: 2 - c["base"]),
        fixed_sum({"r1": 2, "r2": 2, "base": 1}, 4, source=" (Gao eq. 3)"),
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
    chart_labels=("(2 r1 + r3)/\u221a3", "r3"),
    note=(
        "r_i = R_i / D, D the mean of r1, r2 and the half base r3, r1 + r2 + r3 = 3 (Lara-Molina 2016 eqs. 1-2, "
        "32-34)"
    ),
    to_design=_lara_to_design,
    from_design=_lara_from_design,
    to_chart=_lara_to_chart,
    from_chart=_lara_from_chart,
    parameters=("r1", "r2", "r3"),
    polygon=((0.0, 0.0), (2 * SQRT3, 0.0), (4.5 / SQRT3, 1.5), (1.5 / SQRT3, 1.5)),
    bounds=((0.0, 3.0), (0.0, 3.0), (0.0, 1.5)),
    requirements=_requirements(("r1", "r2", "r3"), ((0.0, 3.0), (0.0, 3.0), (0.0, 1.5)), "D"),
    base={"m1": 1.2, "m2": 0.8, "k1": 1.0, "k2": 1.0, "j1": 0.6, "j2": 0.6},
    conditions=(
        *interval("r1", 0, 3, source=" (Lara-Molina eq. 32)"),
        *interval("r2", 0, 3, source=" (Lara-Molina eq. 32)"),
        *interval("r3", 0, 1.5, closed=True, source=" (Lara-Molina eq. 32)"),
        fixed_sum({"r1": 1, "r2": 1, "r3": 1}, 3, source=" (Lara-Molina eq. 2)"),
    ),
)
