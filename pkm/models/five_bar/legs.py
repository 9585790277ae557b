"""The five-bar's two chains in the description vocabulary (docs/mechanisms.md): two RR legs from the base joints
O1 = (-r3, 0) and O2 = (r3, 0) to the end effector, their links the aluminium square tube w_l x w_l x t_l, their
drives the transmissions k1 and k2. The generated model's ``skeleton``, ``elastic`` and ``leg_ends``
(symbolic/mechanisms/five_bar.py) follow a described machine of these legs, so that its stiffness is composed
as a described machine's (:func:`pkm.spec.stiffness.elastic_functions`); loaded as a description
(:func:`pkm.load`), the same machine is derived a second time, which the tests compare."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from pkm.design import Parameter

NAMES = ("r1", "r2", "r3", "k1", "k2", "w_l", "t_l")  # the parameters the legs' description reads
TUBE = {"material": "aluminium", "section": {"shape": "rect_tube", "b": "w_l", "h": "w_l", "t": "t_l"}}


def described(parameters: Sequence[Parameter]) -> dict[str, Any]:
    """The five-bar as a description, its parameters those of ``parameters`` that it reads (:data:`NAMES`)."""
    tables = [p.table() for p in parameters if p.name in NAMES]
    return {
        "name": "five_bar_legs",
        "doc": "the symmetric planar 5R as two RR legs, its links aluminium square tubes, its drives springs",
        "frame": "planar_point",
        "home": [0, "r1 + r2 / 2"],
        "modes": {"out_out": [1, -1], "out_in": [1, 1], "in_out": [-1, -1], "in_in": [-1, 1]},
        "parameters": tables,
        "legs": [{"kind": "RR", "base": [[f"{sign}r3", 0]], "platform": [[0, 0]], "proximal": "r1", "distal": "r2",
                  "elastic": {**TUBE, "drive": drive}} for sign, drive in (("-", "k1"), ("", "k2"))],
    }
