"""The slider gantry's two chains in the description vocabulary (docs/mechanisms.md): two PRR legs, each a slider
on its column from the column's foot (-+(d1 + d2), 0) along y, a revolute on it and a link of length l to the
platform's joint (-+d2, -l2/2); their links the steel square tube b_l x b_l x t_l (the parallelogram's two links
one beam of twice its section, in the symmetric variant on both sides), their drives springs k_s along the
columns. Wu's machine, its sliders below their platform joints, is the legs' branch with the sign -1. The
generated model's ``skeleton``, ``elastic`` and ``leg_ends`` (symbolic/mechanisms/slider_gantry.py) follow a
described machine of these legs, so that its stiffness is composed as a described machine's
(:func:`pkm.spec.stiffness.elastic_functions`) and its error model expands them; loaded as a description
(:func:`pkm.load`), the same machine is derived a second time, which the tests compare."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pkm.design import Parameter

NAMES = ("l", "d1", "d2", "l2", "b_l", "t_l", "k_s")  # the parameters the legs' description reads
TUBE = {"shape": "rect_tube", "b": "b_l", "h": "b_l", "t": "t_l"}
TWICE = {"shape": "given", "A": "2 * (b_l**2 - (b_l - 2*t_l)**2)", "I_y": "2 * (b_l**4 - (b_l - 2*t_l)**4) / 12",
         "I_z": "2 * (b_l**4 - (b_l - 2*t_l)**4) / 12", "J": "2 * (b_l - t_l)**3 * t_l"}  # two tubes side by side


def described(parameters: Sequence[Parameter], symmetric: bool) -> dict[str, Any]:
    """The gantry (or its symmetric variant) as a description, its parameters those of ``parameters`` that it
    reads (:data:`NAMES`)."""
    legs = []
    for sign, doubled in (("-", True), ("", symmetric)):
        legs.append({"kind": "PRR", "base": [[f"{sign}(d1 + d2)", 0]], "platform": [[f"{sign}d2", "-l2/2"]],
                     "axis": [0, 1], "distal": "l",
                     "elastic": {"material": "steel", "section": TWICE if doubled else TUBE, "drive": "k_s"}})
    return {
        "name": "slider_gantry_symmetric_legs" if symmetric else "slider_gantry_legs",
        "doc": "the slider gantry as two PRR legs, its links steel square tubes, its drives springs",
        "frame": "planar_point",
        "home": [0, "l2/2 + 0.8*l"],
        "modes": {"below": [-1, -1], "above": [1, 1]},
        "parameters": [p.table() for p in parameters if p.name in NAMES],
        "legs": legs,
    }
