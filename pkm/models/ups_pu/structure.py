"""The 2-UPS-PU platform's links and joints for its URDF export (:mod:`pkm.export`).

The PU leg slides along Z from O (l0) and carries the platform by its universal joint U0: about the base X
axis by theta1, then about the platform's y axis by theta2 (R = Rx(theta1) Ry(theta2)). Each UPS leg turns in
its base universal joint U_i (first axis horizontal and across the leg, fixed in the base; second across both),
slides (l_i) and meets the platform in its spherical joint S_i: the loops are cut there, as point contacts (3d
closures). The platform carries the payload, a point mass payload_height above U0 along its normal.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pkm.export.structure import (
    Effector,
    Inertial,
    Joint,
    Link,
    Structure,
    placement,
    reference,
    rotation_x,
    rotation_y,
    unit,
)

X, Z = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])


def _frame(pose: np.ndarray) -> np.ndarray:
    return placement(rotation_x(pose[1]) @ rotation_y(pose[2]), np.array([0.0, 0.0, pose[0]]))


def _rates(pose: np.ndarray) -> np.ndarray:
    """U0 moves along Z with l0; the platform turns about X with theta1 and about Rx(theta1) Y with theta2."""
    out = np.zeros((6, 3))
    out[2, 0] = 1.0
    out[3:, 1] = X
    out[3:, 2] = rotation_x(pose[1])[:, 1]
    return out


def _circle(radius: float, angle: float) -> np.ndarray:
    return radius * np.array([math.cos(angle), math.sin(angle), 0.0])


def structure(mech: Any, design: Any, pose: Any, mode: str | None) -> Structure:
    """The structure at a design, with the reference configuration at ``pose`` (by default the platform level
    at mid-stroke of the PU leg) in working mode ``mode``."""

    def home(d: np.ndarray) -> np.ndarray:
        v = mech.design_dict(d)
        return np.array([(v["l0_min"] + v["l0_max"]) / 2, 0.0, 0.0])

    ref = reference(mech, design, pose, mode, home)
    v = ref.design
    l0, theta1, _ = ref.pose
    frame = _frame(ref.pose)
    rotation, u0 = frame[:3, :3], frame[:3, 3]
    payload = Inertial.point(v["payload"], u0 + v["payload_height"] * rotation[:, 2])
    links = [Link("base", "the base: O-XYZ, Z up, the frame of the pose"),
             Link("pu_leg", "the PU leg's slider along Z, U0 at its top"),
             Link("platform", "the platform, U0 its centre, S1 and S2 at radius r; it carries the payload", payload)]
    joints = [
        Joint("l0_leg", "P", "base", "pu_leg", u0, (Z,), "actuated PU leg: l0, the height of U0", actuator="l0_leg",
              value=float(l0), limits=(v["l0_min"], v["l0_max"])),
        Joint("U0", "U", "pu_leg", "platform", u0, (X, rotation_x(theta1)[:, 1]), "the platform's universal joint "
              "U0: theta1 about X, then theta2 about the platform's y"),
    ]
    for k, (angle, q) in enumerate(((v["alpha"], ref.joints[0]), (v["beta"], ref.joints[1])), 1):
        base, tip = _circle(v["R"], angle), u0 + rotation @ _circle(v["r"], angle)
        along = unit(tip - base)
        across = unit(np.cross(Z, along))
        links += [Link(f"cylinder{k}", f"UPS leg {k}'s cylinder, turning in U{k}"),
                  Link(f"piston{k}", f"UPS leg {k}'s piston, S{k} at its end")]
        joints += [
            Joint(f"U{k}", "U", "base", f"cylinder{k}", base, (across, np.cross(along, across)), f"universal joint "
                  f"U{k} of UPS leg {k}", along=along),
            Joint(f"l{k}", "P", f"cylinder{k}", f"piston{k}", base, (along,), f"actuated UPS leg {k}: l{k}, the "
                  f"distance U{k} S{k}", actuator=f"l{k}", value=float(q), limits=(v["l_min"], v["l_max"])),
            Joint(f"S{k}", "S", f"piston{k}", "platform", tip, (), f"spherical joint S{k}"),
        ]
    notes = (
        "The platform rides on the PU leg through U0; the loops are cut at the spherical joints S1 and S2, as "
        "point contacts (3d closures): nothing is left of a spherical joint but its centre.",
        "The platform carries the payload (a point mass payload_height above U0 along its normal); the legs have "
        "no bodies in Zhao's model and are massless.",
        "The joints' misalignment ranges (theta_u_max, theta_s_max) and the legs' least distance D are workspace "
        "constraints of pkm, not joint limits of the URDF; the strokes are.",
        "The axes of U1 and U2: the first horizontal and across the leg at the reference configuration (fixed in "
        "the base), the second across the leg and the first.",
    )
    effector = Effector("platform", "at U0 = (0, 0, l0), turned by R = Rx(theta1) Ry(theta2)", _frame, _rates, True)
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, notes,
                     np.array([0.0, 0.0, -v["g"]]))
