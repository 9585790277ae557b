"""The gantry's links and joints for its URDF export (:mod:`pkm.export`).

Slider i slides along +y on its column at x = -+(d1 + d2) (its joint B_i at height q_i); its counterweight
moves opposite on the same column, at -q_i: a joint on the slider that mimics the slider's with multiplier
-2; the links A_iB_i turn
about -z from the vertical by theta_i (so that the URDF angle is pkm's); the platform translates. The
platform hangs from link A1B1; the loops close where the other links (A3B3 of the parallelogram, A2B2, and
A4B4 of the symmetric variant) meet the platform: those revolute joints stay on the links and are welded to
the platform. The bodies are Wu's Table 2 (inertias about the pivots B_i, moved to the centres of mass).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pkm.export.structure import Inertial, Joint, Link, Structure, reference, translation_effector

Y = np.array([0.0, 1.0, 0.0])
TURN = np.array([0.0, 0.0, -1.0])  # theta_i turns a link from +y towards +x


def _up(angle: float) -> np.ndarray:
    return np.array([math.sin(angle), math.cos(angle), 0.0])


def structure(mech: Any, design: Any, pose: Any, mode: str | None) -> Structure:
    """The structure at a design, with the reference configuration at ``pose`` in working mode ``mode`` (by
    default x = 0 with both sliders at mid-stroke)."""
    sign = mech.working_mode(mode).signs[0]

    def home(d: np.ndarray) -> np.ndarray:
        v = mech.design_dict(d)
        return np.array([0.0, (v["qs"] + v["ql"]) / 2 + v["l2"] / 2 + sign * math.sqrt(v["l"] ** 2 - v["d1"] ** 2)])

    ref = reference(mech, design, pose, mode, home)
    v = ref.design
    q, theta = ref.joints[:2], ref.joints[2:]
    x, y = ref.pose
    column = v["d1"] + v["d2"]
    sliders = (np.array([-column, q[0], 0.0]), np.array([column, q[1], 0.0]))
    raised = np.array([0.0, v["l2"], 0.0])
    centre = np.array([x, y, 0.0])
    corners = {name: centre + np.array([side * v["d2"], height * v["l2"] / 2, 0.0])
               for name, side, height in (("A1", -1, -1), ("A3", -1, 1), ("A2", 1, -1), ("A4", 1, 1))}
    symmetric = "m5" in v
    links = [Link("base", "the base: the frame of the pose, x horizontal, y up, the columns at x = -+(d1 + d2)"),
             Link("platform", "the platform, centre O' = (x, y), width 2 d2, height l2; it translates",
                  Inertial.point(v["mN"], centre))]
    joints = []
    for i, (slider, counterweight) in enumerate((("m11", "m13"), ("m21", "m23"))):
        k = i + 1
        low = sliders[i]
        links += [Link(f"slider{k}", f"slider {k}, its joints B{k} and B{k + 2} l2 apart",
                       Inertial.point(v[slider], low)),
                  Link(f"counterweight{k}", f"counterweight {k}, moving opposite to slider {k}",
                       Inertial.point(v[counterweight], [low[0], -low[1], 0.0]))]
        joints += [
            Joint(f"q{k}", "P", "base", f"slider{k}", low, (Y,), f"actuated slider {k}: q{k}, the height of B{k}",
                  actuator=f"q{k}", value=float(q[i]), limits=(v["qs"], v["ql"])),
            Joint(f"counterweight{k}", "P", f"slider{k}", f"counterweight{k}", np.array([low[0], -low[1], 0.0]),
                  (Y,), f"counterweight {k} on its cable, at -q{k}: -2 q{k} from slider {k}", value=float(-2 * q[i]),
                  limits=(-2 * v["ql"], -2 * v["qs"]), mimic=(f"q{k}", -2.0)),
        ]
    chains = [("link1", "B1", "A1", 0, "m12", "I12", "s12"), ("link3", "B3", "A3", 0, "m4", "I4", "s4"),
              ("link2", "B2", "A2", 1, "m22", "I22", "s22")]
    if symmetric:
        chains.append(("link4", "B4", "A4", 1, "m5", "I5", "s5"))
    for name, pivot, tip, i, mass, inertia, offset in chains:
        start = sliders[i] + (raised if pivot in ("B3", "B4") else 0.0)
        body = Inertial.bar(v[mass], start + v[offset] * _up(theta[i]), v[inertia] - v[mass] * v[offset] ** 2,
                            _up(theta[i]))
        links.append(Link(name, f"link {tip}{pivot}, length l", body))
        joints.append(Joint(pivot, "R", f"slider{i + 1}", name, start, (TURN,), f"{pivot}: theta{i + 1}, the angle "
                            "of its link from the vertical", value=float(theta[i]), along=_up(theta[i])))
    joints.append(Joint("A1", "R", "link1", "platform", corners["A1"], (TURN,), "A1: the platform's angle less "
                        "theta1 (-theta1)", value=float(-theta[0])))
    for name, pivot, tip, *_ in chains[1:]:
        joints.append(Joint(tip, "R", name, "platform", corners[tip], (TURN,), f"{tip}, where link {tip}{pivot} "
                            "meets the platform"))
    cuts = "A3 and A2 (and A4)" if symmetric else "A3 and A2"
    notes = (
        f"The platform hangs from link A1B1 on slider 1; the loops are cut at {cuts}, where the other links meet "
        "the platform: their revolute joints stay on the links, welded to the platform.",
        "Each counterweight hangs from a pulley on top of its column and moves opposite to its slider, at -q_i: "
        "in the tree it slides on its slider by -2 q_i, a mimic joint (multiplier -2) of the slider's joint (a "
        "mimic joint follows the joint it mimics in the tree; load with mimic=True).",
        "The links are slender bars: Wu's inertia about the pivot B_i less m s^2, about every axis across the "
        "link; the sliders, counterweights and platform translate (point masses).",
        "Link angles turn about -z so that the URDF's angle of a link from the vertical has pkm's sign.",
    )
    effector = translation_effector("platform", "at the platform's centre O' = (x, y, 0), parallel to the base "
                                    "frame", 2, oriented=True)
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, notes,
                     np.array([0.0, -v["g"], 0.0]))
