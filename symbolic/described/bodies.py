"""The kinetic and potential energy of a described machine's bodies: each leg's, each chain joint's and the
platform's, as terms of its mass matrix in all the joint and pose coordinates."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sympy as sp

from symbolic.bodies import angular_velocity_jacobian
from symbolic.described.legs import Leg, direction

# weight, its Jacobian in z, the inner matrix, and a point mass's position (None for a turning term)
Kinetic = tuple[sp.Expr, Callable[[list[sp.Symbol]], sp.Matrix], sp.Matrix, sp.Matrix | None]


def mass_matrix(kinetic: list[Kinetic], z: list[sp.Symbol]) -> sp.Matrix:
    """sum of weight J^T W J over the kinetic terms (J their Jacobians in z, W their inner matrices)."""
    M = sp.zeros(len(z), len(z))
    for weight, jacobian, inner, _ in kinetic:
        J = jacobian(z)
        M += weight * J.T * inner * J
    return M


def _point(mass: sp.Expr, position: sp.Matrix) -> Kinetic:
    """A point mass: T = m |dp/dt|^2 / 2."""
    return mass, position.jacobian, sp.eye(position.rows), position


def _turning(moment: sp.Expr, angle: sp.Expr) -> Kinetic:
    """A body turning about a fixed axis by ``angle``: T = I angle_dot^2 / 2."""
    return moment, sp.Matrix([angle]).jacobian, sp.eye(1), None


def _across(moment: sp.Expr, direction: sp.Matrix) -> Kinetic:
    """A body along the unit ``direction`` turning across it (its spin about it neglected): omega = u x u_dot,
    |omega| = |u_dot|, T = I |u_dot|^2 / 2."""
    return moment, direction.jacobian, sp.eye(direction.rows), None


def leg_bodies(leg: dict[str, Any], joints: Leg, a: sp.Matrix, c: sp.Matrix, scalar: Any) -> list[Kinetic]:
    """The kinetic terms of a leg's bodies: point masses (their centres) and turning moments (an angle, or a
    direction whose rate is the angular velocity across it)."""
    bodies, out = leg["bodies"], []
    rotor = scalar(bodies["rotor"])
    if rotor != 0:
        out.append(_turning(rotor, joints.actuated))
    if leg["kind"] == "RR":
        theta, (phi,) = joints.actuated, joints.passive
        for name, start, angle in (("proximal", a, theta),
                                   ("distal", a + scalar(leg["proximal"]) * direction(theta), phi)):
            if name in bodies:
                body = bodies[name]
                out += [_point(scalar(body["mass"]), start + scalar(body["centre"]) * direction(angle)),
                        _turning(scalar(body["inertia"]), angle)]
    elif leg["kind"] == "R_parallelogram":
        theta = joints.actuated
        zero, axis = (sp.Matrix([scalar(t) for t in leg[key]]) for key in ("zero", "axis"))
        along = sp.cos(theta) * zero + sp.sin(theta) * axis.cross(zero)
        if "arm" in bodies:
            body = bodies["arm"]
            out += [_point(scalar(body["mass"]), a + scalar(body["centre"]) * along),
                    _turning(scalar(body["inertia"]), theta)]
        if "rod" in bodies:
            half = scalar(bodies["rod"]["mass"]) / 2
            out += [_point(half, a + scalar(leg["arm"]) * along), _point(half, c)]
    elif leg["kind"] == "PRR":
        slide, (phi,) = joints.actuated, joints.passive
        axis = sp.Matrix([scalar(t) for t in leg["axis"]])
        joint = a + slide * axis / sp.sqrt(axis.dot(axis))
        if "slider" in bodies:
            out.append(_point(scalar(bodies["slider"]["mass"]), joint))
        if "distal" in bodies:
            body = bodies["distal"]
            out += [_point(scalar(body["mass"]), joint + scalar(body["centre"]) * direction(phi)),
                    _turning(scalar(body["inertia"]), phi)]
    else:
        d = c - a
        u = d / sp.sqrt(d.dot(d))
        for name, start, sign in (("cylinder", a, 1), ("piston", c, -1)):
            if name in bodies:
                body = bodies[name]
                out += [_point(scalar(body["mass"]), start + sign * scalar(body["centre"]) * u),
                        _across(scalar(body["inertia"]), u)]
    return out


def chain_bodies(leg: dict[str, Any], joints: Leg, *, scalar: Any, vector: Any) -> list[Kinetic]:
    """The kinetic terms of a chain's bodies: each joint's body after it (its centre's point mass; its turning,
    about z in the plane, or with the body's angular velocity and its principal moments in space) and the
    actuated joint's rotor."""
    out: list[Kinetic] = []
    for joint, (origin, rotation, turning, angle) in zip(leg["joints"], joints.frames, strict=True):
        if "rotor" in joint:
            out.append(_turning(scalar(joint["rotor"]), joints.actuated))
        if "body" not in joint:
            continue
        body = joint["body"]
        out.append(_point(scalar(body["mass"]), origin + rotation * vector(body["centre"])))
        if origin.rows == 2:
            out.append(_turning(scalar(body["inertia"]), angle))
            continue

        def angular(z: list[sp.Symbol], turning: tuple[tuple[sp.Symbol, sp.Matrix], ...] = turning) -> sp.Matrix:
            W = sp.zeros(3, len(z))
            for variable, axis in turning:
                W[:, z.index(variable)] += axis
            return W

        out.append((sp.Integer(1), angular, rotation * sp.diag(*vector(body["inertia"])) * rotation.T, None))
    return out


def platform_bodies(body: dict[str, Any] | None, frame: str, pose: tuple[sp.Symbol, ...], rotation: sp.Matrix, *,
              vector: Any, scalar: Any) -> list[Kinetic]:
    """The platform's kinetic terms: its centre of mass and, where it turns, its rotation."""
    if body is None:
        return []
    origin = sp.Matrix(pose[: rotation.rows])
    out = [_point(scalar(body["mass"]), origin + rotation * vector(body["centre"]))]
    if frame == "planar":
        out.append(_turning(scalar(body["inertia"]), pose[2]))
    elif frame == "spatial":
        W = angular_velocity_jacobian(rotation, pose[3:])
        world = rotation * sp.diag(*[scalar(t) for t in body["inertia"]]) * rotation.T

        def angular(z: list[sp.Symbol]) -> sp.Matrix:
            out = sp.zeros(3, len(z))
            for k, angle in enumerate(pose[3:]):
                out[:, z.index(angle)] = W[:, k]
            return out

        out.append((sp.Integer(1), angular, world, None))
    return out


