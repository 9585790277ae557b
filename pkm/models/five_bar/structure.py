"""The five-bar's links and joints for its URDF export (:mod:`pkm.export`).

Base joints O1 = (-r3, 0), O2 = (r3, 0) about z, the proximal links to the elbows A_i, the distal links to
the end effector P = (x, y) where they meet. The loop is cut at P: the revolute joint there stays in the tree
on distal link 1 and is welded to distal link 2, so that each chain stays whole from its base joint to P. The
links carry the bodies of Lara-Molina's Lagrange model (mass, centre of mass at c r along the link, inertia
g m r^2 about it); the rotors, the transmissions' stiffness and the friction are not in the rigid URDF.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from pkm.export.structure import Inertial, Joint, Link, Structure, reference, translation_effector

Z = np.array([0.0, 0.0, 1.0])


def _e(angle: float) -> np.ndarray:
    return np.array([math.cos(angle), math.sin(angle), 0.0])


def structure(mech: Any, design: Any, pose: Any, mode: str | None) -> Structure:
    """The structure at a design, with the reference configuration at ``pose`` (the centre of the maximum
    inscribed circle by default) in working mode ``mode``."""
    ref = reference(mech, design, pose, mode, lambda d: mech.maximum_inscribed_circle(d)[0])
    v = ref.design
    theta, phi = ref.joints[:2], ref.joints[2:]
    bases = (np.array([-v["r3"], 0.0, 0.0]), np.array([v["r3"], 0.0, 0.0]))
    elbows = [o + v["r1"] * _e(t) for o, t in zip(bases, theta, strict=True)]
    end = elbows[0] + v["r2"] * _e(phi[0])
    links = [Link("base", "the base: the frame of the pose, O1 = (-r3, 0) and O2 = (r3, 0) its joints")]
    joints = []
    for i in range(2):
        k = i + 1
        proximal = Inertial.bar(v["m1"], bases[i] + v["c1"] * v["r1"] * _e(theta[i]),
                                v["g1"] * v["m1"] * v["r1"] ** 2, _e(theta[i]))
        distal = Inertial.bar(v["m2"], elbows[i] + v["c2"] * v["r2"] * _e(phi[i]),
                              v["g2"] * v["m2"] * v["r2"] ** 2, _e(phi[i]))
        links += [Link(f"proximal{k}", f"proximal link {k}, O{k} to A{k} (r1)", proximal),
                  Link(f"distal{k}", f"distal link {k}, A{k} to P (r2)", distal)]
        joints += [
            Joint(f"theta{k}", "R", "base", f"proximal{k}", bases[i], (Z,), f"actuated base joint O{k}: theta{k}, "
                  f"the absolute angle of proximal link {k}", actuator=f"theta{k}", value=float(theta[i]),
                  along=_e(theta[i])),
            Joint(f"elbow{k}", "R", f"proximal{k}", f"distal{k}", elbows[i], (Z,),
                  f"elbow A{k}: phi{k} - theta{k}", along=_e(phi[i])),
        ]
    joints.append(Joint("end", "R", "distal1", "distal2", end, (Z,), "the end effector P, where the distal links "
                        "meet"))
    notes = (
        "The loop O1 A1 P A2 O2 is cut at P, the one joint the two chains share: each chain stays whole from its "
        "base joint to P, and the revolute joint at P stays on distal link 1.",
        "Each link is a slender bar: mass m, centre of mass c r along it from its first joint, inertia g m r^2 "
        "about every axis across it through the centre (about z: Lara-Molina's).",
        "Not in the URDF: the rotors (j1, j2), the transmissions' stiffness (k1, k2) and the friction (fv, fc, vm) "
        "of the flexible model: the URDF is the rigid mechanism, whose inertia in the actuated joints is pkm's M_t.",
        "The plane of the mechanism is horizontal (no gravity in pkm's model); Pinocchio's default gravity along -z "
        "is across it.",
    )
    effector = translation_effector("distal1", "at P on distal link 1 (x, y, 0); the pose fixes its origin, its "
                                    "orientation turns with distal link 1", 2, oriented=False)
    return Structure(mech.name, mech.doc, ref, "base", tuple(links), tuple(joints), effector, notes)
