"""Nam and Park's design space (section 6.2): R = 1, r and l_b in [0.5, 2], l_a from l_b - l_a = R - r
(the condition of eq. 15 with equality, which section 4 keeps for the largest workspace)."""

from __future__ import annotations

from pkm.design import Condition
from pkm.design_space import DesignSpace, Requirement, interval

BOUNDS = (0.5, 2.0)


def _to_design(c, scale=1.0):
    """(r/R, l_b/R) and R -> (R, r, l_a, l_b) in metres with l_a = l_b - R + r."""
    r, l_b = c[0], c[1]
    return [scale, r * scale, (l_b + r - 1) * scale, l_b * scale]


def _from_design(d):
    return [d[1] / d[0], d[3] / d[0]], d[0]


NAM2006 = DesignSpace(
    name="nam2006",
    doc=(
        "Nam 2006 eq. 32: R = 1, r and l_b in [0.5, 2] (ratios to R), l_a = l_b - R + r (eq. 15 with "
        "equality); the corner r + l_b <= 1 has l_a <= 0. Chart: (r/R, l_b/R) as they are."
    ),
    coordinates=("r", "l_b"),
    chart_axes=("r", "l_b"),
    chart_labels=("r / R", "l_b / R"),
    note="ratios to the base half-width R, with l_b - l_a = R - r (Nam 2006 eqs. 15, 32)",
    to_design=_to_design,
    from_design=_from_design,
    to_chart=lambda c: (c[0], c[1]),
    from_chart=lambda u, v: [u, v],
    polygon=((0.5, 0.5), (2.0, 0.5), (2.0, 2.0), (0.5, 2.0)),
    parameters=("R", "r", "l_a", "l_b"),
    bounds=(BOUNDS, BOUNDS),
    conditions=(
        *interval("r", *BOUNDS, closed=True, source=" (Nam eq. 32)"),
        *interval("l_b", *BOUNDS, closed=True, source=" (Nam eq. 32)"),
        Condition("l_a = l_b + r - R > 0 (a lower link)", lambda c: c["r"] + c["l_b"] - 1),
    ),
    requirements=(Requirement("r >= R (no folded leg inside the region)", lambda c, _call: c["r"], 1.0),),
)
