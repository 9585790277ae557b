"""The passive-leg manipulator's links and joints for its URDF export (:mod:`pkm.export`).

The actuated revolutes B1 = (R, 0), B2 = (-R, 0) turn the lower links (l_a) to the elbows d_i, the upper
links (l_b) reach the platform's joints b_i = C +- r (cos theta, sin theta); the passive RP leg turns about O
and slides (l_c) to the platform's centre C, to which it is fixed at a right angle. The platform hangs from
leg 1; the loops are cut at b2 (its revolute joint stays on the upper link of leg 2, welded to the platform)
and where the RP leg is fixed to the platform (a weld). The mechanism has no bodies: the links are massless.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pkm.export.structure import Effector, Joint, Link, Structure, placement, reference, rotation_z

Z = np.array([0.0, 0.0, 1.0])


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def _frame(pose: np.ndarray) -> np.ndarray:
    return placement(rotation_z(math.atan2(-pose[0], pose[1])), np.array([pose[0], pose[1], 0.0]))


def _rates(pose: np.ndarray) -> np.ndarray:
    """theta = atan2(-x_c, y_c): d theta = (-y_c dx_c + x_c dy_c) / (x_c^2 + y_c^2)."""
    out = np.zeros((6, 2))
    out[0, 0] = out[1, 1] = 1.0
    out[5] = np.array([-pose[1], pose[0]]) / (pose[0] ** 2 + pose[1] ** 2)
    return out


def structure(mech: Any, design: Any, pose: Any, mode: str | None) -> Structure:
    """The structure at a design, with the reference configuration at ``pose`` in working mode ``mode`` (by
    default the platform level at x_c = 0, each leg's reach from B_i to b_i the longer of l_a and l_b)."""

    def home(d: np.ndarray) -> np.ndarray:
        v = mech.design_dict(d)
        return np.array([0.0, math.sqrt(max(v["l_a"], v["l_b"]) ** 2 - (v["R"] - v["r"]) ** 2)])

    ref = reference(mech, design, pose, mode, home)
    v = ref.design
    phi, theta, psi, l_c = ref.joints[:2], ref.joints[2], ref.joints[3:5], ref.joints[5]
    centre = np.array([ref.pose[0], ref.pose[1], 0.0])
    u = _e(theta)
    bases = (np.array([v["R"], 0.0, 0.0]), np.array([-v["R"], 0.0, 0.0]))
    tips = (centre + v["r"] * u, centre - v["r"] * u)
    links = [Link("base", "the base: the frame of the pose, B1 = (R, 0), B2 = (-R, 0) and O its joints"),
             Link("platform", "the platform, half-width r about its centre C = (x_c, y_c)"),
             Link("leg_cylinder", "the passive leg's cylinder, turning about O"),
             Link("leg_piston", "the passive leg's piston, fixed to the platform at C at a right angle")]
    joints = []
    for i in range(2):
        k = i + 1
        elbow = bases[i] + v["l_a"] * _e(phi[i])
        links += [Link(f"lower{k}", f"lower link B{k} d{k} (l_a)"), Link(f"upper{k}", f"upper link d{k} b{k} (l_b)")]
        joints += [
            Joint(f"phi{k}", "R", "base", f"lower{k}", bases[i], (Z,), f"actuated revolute B{k}: phi{k}, the angle "
                  f"of link B{k} d{k} from x", actuator=f"phi{k}", value=float(phi[i]), along=_e(phi[i])),
            Joint(f"d{k}", "R", f"lower{k}", f"upper{k}", elbow, (Z,), f"elbow d{k}: psi{k} - phi{k}",
                  value=float(psi[i] - phi[i]), along=_e(psi[i])),
        ]
    direction = np.array([-math.sin(theta), math.cos(theta), 0.0])
    joints += [
        Joint("b1", "R", "upper1", "platform", tips[0], (Z,), "b1: theta - psi1", value=float(theta - psi[0]),
              along=u),
        Joint("b2", "R", "upper2", "platform", tips[1], (Z,), "b2, where leg 2 meets the platform"),
        Joint("O", "R", "base", "leg_cylinder", np.zeros(3), (Z,), "the passive leg's revolute at O: theta",
              value=float(theta), along=direction),
        Joint("l_c", "P", "leg_cylinder", "leg_piston", np.zeros(3), (direction,), "the passive leg's length "
              "l_c", value=float(l_c)),
        Joint("C", "fixed", "leg_piston", "platform", centre, (), "the passive leg fixed to the platform at C"),
    ]
    notes = (
        "The platform hangs from leg 1 (B1 d1 b1); the loops are cut at b2, where leg 2 meets the platform (its "
        "revolute joint stays on the upper link, welded to the platform), and at C, where the passive RP leg is "
        "fixed to the platform at a right angle (a weld): so the RP leg keeps x_c cos(theta) + y_c sin(theta) = 0.",
        "Nam and Park's model has no bodies: the links are massless. The joint ranges of their section 4 are "
        "not joint limits here.",
    )
    effector = Effector("platform", "at the platform's centre C = (x_c, y_c, 0), turned by theta = atan2(-x_c, "
                        "y_c) about z (x along b2 -> b1)", _frame, _rates, True)
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, notes)
