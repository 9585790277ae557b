"""A machine described as data, derived: ``python -m symbolic.describe DESCRIPTION.json MODULE.py``.

The description is the normalised form that :mod:`pkm.spec` writes (legs with their attachment points as
expressions of the design parameters, patterns already expanded). Each leg is one of the kinds below; its
closure rows, its joints, its inverse kinematics in closed form (the leg's known subproblem) and its
reach margins are derived in sympy, and the module gets the port convention's ``inverse_kinematics(x,
mode, design) -> (q, reach)`` and ``constraint(q, x, design) -> (h, H_q, H_x)`` (through
:func:`symbolic.kinematics.add_kinematics`, ``composed``: the runtime composes the first order from the
constraint in CasADi, so that a 6 x 6 solve is never expanded in sympy), ``home(design) -> x``, and where
given ``characteristic_length(design) -> L``.

Pose (``pose.frame``): ``planar_point`` (x, y), ``planar`` (x, y, phi), ``spatial_point`` (x, y, z) or
``spatial`` (x, y, z, roll, pitch, yaw) with R = Rz(yaw) Ry(pitch) Rx(roll). A platform attachment c
(in the platform frame) is at P + R c in the base frame.

Legs (A the base attachment, C the platform attachment in the base frame, sigma the leg's branch sign):

* ``RR``, planar: an actuated revolute at A (absolute angle theta of the first link, length ``proximal``)
  and a passive revolute (absolute angle phi of the second link, length ``distal``) ending at C:
  h = A + l1 e(theta) + l2 e(phi) - C. With d = C - A, theta = atan2(d) + sigma acos((l1^2 + |d|^2 -
  l2^2) / (2 l1 |d|)) and phi = atan2(C - B), B the elbow (two circles); reach: |d| within [|l1 - l2|,
  l1 + l2].
* ``RPR``, planar: a passive revolute at A, an actuated prismatic joint of length rho along it and a passive
  revolute at C: h = A + rho e(phi) - C, rho = |C - A|, phi = atan2(C - A), one branch.
* ``PRR``, planar: an actuated prismatic joint s along ``axis`` from A, then a link of length ``distal`` at
  the angle phi to C: h = A + s u + l e(phi) - C; the line meets the circle of radius l about C at s = (C -
  A).u + sigma sqrt(l^2 - ((C - A) x u)^2); reach: l^2 - ((C - A) x u)^2.
* ``R_parallelogram``, spatial: an actuated revolute at A about ``axis`` turning an arm of length ``arm``
  from the direction ``zero`` (theta = 0) towards ``axis`` x ``zero``, and a parallelogram of length
  ``rod`` from its tip E to C: h = |C - E|^2 - rod^2. With D = C - A, P = D.u, Q = D.w (u = zero, w =
  axis x zero) and K = (|D|^2 + arm^2 - rod^2) / (2 arm), theta = atan2(Q, P) + sigma acos(K / sqrt(P^2 +
  Q^2)); reach: P^2 + Q^2 - K^2.
* ``UPS``, spatial: an actuated prismatic joint of length l between A and C (universal and spherical joints
  at its ends): h = |C - A|^2 - l^2, l = |C - A|, one branch; with ``cone``, the leg's angle from the base's
  normal and from the platform's at most cone: (C - A).n - cos(cone) |C - A| >= 0 for both normals (two
  stated limits beside its reach).

* ``chain``, planar or spatial: R, P, U and parallelogram joints from A, each with its axes and its link in
  the frame of the body before it (the leg's frame the base's turned about z by ``turn``), ending at C in
  the platform's point joint: h = A + (the chain's end) - C, as many joint variables as h has rows. Its
  inverse kinematics is a closed form where its two joints are a known subproblem (:func:`_closed_chain`),
  else only the start of the runtime's Newton continuation (``continuation_start``, the branch's seed):
  :func:`pkm.spec.composed_inverse_kinematics` solves it from ``chain<k>(q_leg, c, design) -> (h, H)`` and
  ``chain<k>_ends(x, design) -> (a, c)``. Its side is the sign of det H.

A leg's ``range`` (lower, upper) bounds its actuated joint (a stroke, an arm's sweep): two more margins of
``workspace_margins``, not of the reach (the runtime states them as limits: :func:`pkm.kinematics.within_limits`).
With bodies, ``mass_matrix(q, x, design) -> M`` (T = z_dot^T M z_dot / 2 in z = (q, x)) and, with
``gravity``, ``gravity(q, x, design) -> (G, V)`` (dV/dz and V). ``skeleton(q, x, design)`` gives the joints'
points leg by leg (base, the leg's joints between, platform). ``branch_sides(q, x, design)`` has a sign per leg
with passive joints and two branches (RR: the elbow's side, sin(phi - theta); PRR: -e(phi).u) that names them
in the assembly modes. ``workspace_margins(q, x, design)`` gives every leg's margins at a configuration (the
ranges' in the actuated joints), ``region_<name>(design) -> (centre, size)`` places each region, and
``region_<name>_pose(y, design) -> x`` maps a region's coordinates into the pose where it spans fewer or
others.
"""

from __future__ import annotations

import itertools
import json
import math
import sys
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import sympy as sp

from symbolic import codegen
from symbolic.bodies import angular_velocity_jacobian
from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.kinematics import InverseKinematics, add_kinematics
from symbolic.loops import LoopClosure

FRAMES = {
    "planar_point": ("x", "y"),
    "planar": ("x", "y", "phi"),
    "spatial_point": ("x", "y", "z"),
    "spatial": ("x", "y", "z", "roll", "pitch", "yaw"),
}
FUNCTIONS = {"cos": sp.cos, "sin": sp.sin, "tan": sp.tan, "sqrt": sp.sqrt, "asin": sp.asin, "acos": sp.acos,
             "atan": sp.atan}
OPERATORS = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b, "/": lambda a, b: a / b,
             "**": lambda a, b: a**b, "neg": lambda a: -a}


class UndefinedError(ValueError):
    """An expression of the description without a finite value at every design (tan(pi/2), 1/(a - a))."""


def expression(tree: Any, names: dict[str, sp.Symbol]) -> sp.Expr:
    """The sympy expression of one of pkm's expression trees (:mod:`pkm.expressions`: a number, a name, or
    ``[operator, operand, ...]``), built node by node: nothing of the description is parsed or evaluated as
    text here."""
    if isinstance(tree, int):
        return sp.Integer(tree)
    if isinstance(tree, float):
        return sp.Float(tree)
    if isinstance(tree, str):
        return sp.pi if tree == "pi" else names[tree]
    op, *operands = tree
    values = [expression(t, names) for t in operands]
    value = (OPERATORS.get(op) or FUNCTIONS[op])(*values)
    if value.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise UndefinedError(f"{op}({', '.join(map(str, values))}) has no finite value")
    return value


def _rotation(frame: str, pose: tuple[sp.Symbol, ...]) -> sp.Matrix:
    """The platform's rotation in the base frame."""
    if frame == "planar":
        phi = pose[2]
        return sp.Matrix([[sp.cos(phi), -sp.sin(phi)], [sp.sin(phi), sp.cos(phi)]])
    if frame == "spatial":
        roll, pitch, yaw = pose[3:]
        rx = sp.Matrix([[1, 0, 0], [0, sp.cos(roll), -sp.sin(roll)], [0, sp.sin(roll), sp.cos(roll)]])
        ry = sp.Matrix([[sp.cos(pitch), 0, sp.sin(pitch)], [0, 1, 0], [-sp.sin(pitch), 0, sp.cos(pitch)]])
        rz = sp.Matrix([[sp.cos(yaw), -sp.sin(yaw), 0], [sp.sin(yaw), sp.cos(yaw), 0], [0, 0, 1]])
        return rz * ry * rx
    return sp.eye(2 if frame == "planar_point" else 3)


def _e(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


@dataclass(frozen=True)
class _Leg:
    """One leg's closure rows, joints, inverse kinematics, reach margins and branch sign."""

    h: list[sp.Expr]
    actuated: sp.Symbol
    passive: list[sp.Symbol]
    ik: dict[sp.Symbol, sp.Expr]
    reach: list[sp.Expr]
    sign: sp.Symbol | None
    margins: tuple[sp.Expr, ...] = ()
    side: sp.Expr | None = None  # of a leg with passive joints and two branches: its sign tells them apart
    joints: tuple[sp.Matrix, ...] = ()  # the points of its joints between the base's and the platform's
    end: sp.Matrix | None = None  # of a chain leg: the end of its chain, where the platform's joint closes it
    frames: tuple[tuple[sp.Matrix, sp.Matrix, tuple[tuple[sp.Symbol, sp.Matrix], ...], sp.Expr], ...] = ()
    # of a chain leg, per joint: the origin and rotation of the body after it, its angular velocity's axis per
    # joint variable (spatial) and its angle (planar)
    reach_names: tuple[str, ...] = ()  # what each reach margin bounds, where it is not the leg's reach alone
    stated: tuple[tuple[str, sp.Expr], ...] = ()  # limits of its joints beside its reach (a cone), named


def _rr(k: int, a: sp.Matrix, c: sp.Matrix, l1: sp.Expr, l2: sp.Expr) -> _Leg:
    theta, phi, sigma = sp.symbols(f"theta{k + 1} phi{k + 1} sigma{k + 1}", real=True)
    d = c - a
    dist2 = d.dot(d)
    angle = sp.atan2(d[1], d[0]) + sigma * sp.acos((l1**2 + dist2 - l2**2) / (2 * l1 * sp.sqrt(dist2)))
    elbow = a + l1 * _e(angle)
    h = list(a + l1 * _e(theta) + l2 * _e(phi) - c)
    ik = {theta: angle, phi: sp.atan2(c[1] - elbow[1], c[0] - elbow[0])}
    return _Leg(h, theta, [phi], ik, [(l1 + l2) ** 2 - dist2, dist2 - (l1 - l2) ** 2], sigma,
                side=sp.sin(phi - theta), joints=(a + l1 * _e(theta),), reach_names=("reach outer", "reach inner"))


def _rpr(k: int, a: sp.Matrix, c: sp.Matrix) -> _Leg:
    rho, phi = sp.symbols(f"rho{k + 1} phi{k + 1}", real=True)
    d = c - a
    h = list(a + rho * _e(phi) - c)
    return _Leg(h, rho, [phi], {rho: sp.sqrt(d.dot(d)), phi: sp.atan2(d[1], d[0])}, [d.dot(d)], None)


def _prr(k: int, a: sp.Matrix, c: sp.Matrix, axis: sp.Matrix, length: sp.Expr) -> _Leg:
    s, phi, sigma = sp.symbols(f"s{k + 1} phi{k + 1} sigma{k + 1}", real=True)
    u = axis / sp.sqrt(axis.dot(axis))
    d = c - a
    along, across = d.dot(u), d[0] * u[1] - d[1] * u[0]
    slide = along + sigma * sp.sqrt(length**2 - across**2)
    joint = a + slide * u
    h = list(a + s * u + length * _e(phi) - c)
    ik = {s: slide, phi: sp.atan2(c[1] - joint[1], c[0] - joint[0])}
    return _Leg(h, s, [phi], ik, [length**2 - across**2], sigma, side=-(sp.cos(phi) * u[0] + sp.sin(phi) * u[1]),
                joints=(a + s * u,))


def _r_parallelogram(k: int, a: sp.Matrix, c: sp.Matrix, leg: dict[str, Any]) -> _Leg:
    axis, zero, arm, rod = leg["axis"], leg["zero"], leg["arm"], leg["rod"]
    theta, sigma = sp.symbols(f"theta{k + 1} sigma{k + 1}", real=True)
    w = axis.cross(zero)
    tip = a + arm * (sp.cos(theta) * zero + sp.sin(theta) * w)
    d = c - a
    p, q = d.dot(zero), d.dot(w)
    big_k = (d.dot(d) + arm**2 - rod**2) / (2 * arm)
    angle = sp.atan2(q, p) + sigma * sp.acos(big_k / sp.sqrt(p**2 + q**2))
    h = [(c - tip).dot(c - tip) - rod**2]
    return _Leg(h, theta, [], {theta: angle}, [p**2 + q**2 - big_k**2], sigma, joints=(tip,))


def _ups(k: int, a: sp.Matrix, c: sp.Matrix, rotation: sp.Matrix, cone: sp.Expr | None) -> _Leg:
    length = sp.Symbol(f"l{k + 1}", real=True)
    d = c - a
    stated = ()
    if cone is not None:
        normal = rotation[:, 2]
        stated = (("cone at the base", d[2] - sp.cos(cone) * sp.sqrt(d.dot(d))),
                  ("cone at the platform", d.dot(normal) - sp.cos(cone) * sp.sqrt(d.dot(d))))
    return _Leg([d.dot(d) - length**2], length, [], {length: sp.sqrt(d.dot(d))}, [d.dot(d)], None, stated=stated)


def _axis_rotation(axis: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """The rotation by ``angle`` about ``axis`` (Rodrigues)."""
    u = axis / sp.sqrt(axis.dot(axis))
    cross = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return sp.eye(3) * sp.cos(angle) + sp.sin(angle) * cross + (1 - sp.cos(angle)) * u * u.T


def _plane_rotation(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def _chain(k: int, a: sp.Matrix, c: sp.Matrix, leg: dict[str, Any], *, vector: Any, scalar: Any,
           start: dict[sp.Symbol, float]) -> _Leg:
    """A serial chain of R, P, U and parallelogram joints from A, its links fixed in the frame of the joint
    before them, ending at C in the platform's point joint. The leg's frame is the base's turned about z by
    ``turn``; each joint's axes and link are in the frame of the body before it. A parallelogram turns its
    rods (its link) like a universal joint and keeps the frame of the body before it for what follows.

    Its inverse kinematics is a closed form where the chain is two joints of a known subproblem
    (:func:`_closed_chain`; each named seed chooses the candidate nearest it at ``start``, the home pose at
    the default design), else (or with ``newton``) only the start of the runtime's continuation: each
    branch's seed, chosen by the leg's sign where it has two, and ``end`` is set."""
    planar = a.rows == 2
    turn = scalar(leg["turn"])
    frame = _plane_rotation(turn) if planar else _axis_rotation(sp.Matrix([0, 0, 1]), turn)
    rotation, point, variables, angles, points, actuated = frame, a, [], [], [], None
    omega: tuple[tuple[sp.Symbol, sp.Matrix], ...] = ()
    angle_sum, frames = turn, []
    for j, joint in enumerate(leg["joints"]):
        names = [f"q{k + 1}_{j + 1}"] if joint["type"] in ("R", "P") else [f"q{k + 1}_{j + 1}a", f"q{k + 1}_{j + 1}b"]
        mine = [sp.Symbol(n, real=True) for n in names]
        variables += mine
        angles += [joint["type"] != "P"] * len(mine)
        turned, turning, turned_sum = rotation, omega, angle_sum
        if joint["type"] == "P":
            axis = vector(joint["axis"])
            point = point + rotation * axis / sp.sqrt(axis.dot(axis)) * mine[0]
        else:
            for axis, angle in zip(map(vector, joint["axes"]), mine, strict=True):
                if not planar:
                    turning = (*turning, (angle, turned * axis / sp.sqrt(axis.dot(axis))))
                turned = turned * (_plane_rotation(angle) if planar else _axis_rotation(axis, angle))
                turned_sum = turned_sum + angle
        if joint.get("actuated"):
            actuated = mine[0]
        frames.append((point, turned, turning, turned_sum))
        point = point + turned * vector(joint["link"])
        if joint["type"] != "parallelogram":
            rotation, omega, angle_sum = turned, turning, turned_sum
        points.append(point)
    h = list(point - c)
    sigma = sp.Symbol(f"sigma{k + 1}", real=True) if len(leg["branches"]) == 2 else None
    seeds = [[float(v) for v in values] for _, values in leg["branches"]]
    side = sp.Matrix(h).jacobian(variables).det()
    passive = [v for v in variables if v is not actuated]
    closed = None if leg.get("newton") else _closed_chain(leg["joints"], frame.T * (c - a), vector)
    if closed is None:
        first = [sp.Float(v) for v in seeds[0]]
        blend = first if sigma is None else [(1 + sigma) / 2 * p + (1 - sigma) / 2 * sp.Float(m)
                                             for p, m in zip(first, seeds[-1], strict=True)]
        return _Leg(h, actuated, passive, dict(zip(variables, blend, strict=True)), [], sigma, side=side,
                    joints=tuple(points[:-1]), end=point, frames=tuple(frames))
    solution, reach, signs = closed
    chosen = [_nearest_candidate(solution, signs, seed, angles, start) for seed in seeds]
    values = {s: chosen[0][i] if sigma is None else (1 + sigma) / 2 * chosen[0][i] + (1 - sigma) / 2 * chosen[-1][i]
              for i, s in enumerate(signs)}
    ik = {v: e.subs(values) for v, e in zip(variables, solution, strict=True)}
    return _Leg(h, actuated, passive, ik, [m.subs(values) for m in reach], sigma, side=side,
                joints=tuple(points[:-1]), frames=tuple(frames))


def _nearest_candidate(solution: list[sp.Expr], signs: list[sp.Symbol], seed: list[float], angles: list[bool],
                       start: dict[sp.Symbol, float]) -> list[int]:
    """The branch signs of the closed form whose joints at ``start`` are nearest the seed (angles wrapped)."""
    symbols = list(start)
    joints = sp.lambdify([*signs, *symbols], solution, modules="math", cse=True)
    best, chosen = math.inf, [1] * len(signs)
    for combo in itertools.product((1, -1), repeat=len(signs)):
        try:
            values = joints(*combo, *(start[s] for s in symbols))
        except (ValueError, ZeroDivisionError):  # the candidate does not exist there
            continue
        if not all(math.isfinite(v) for v in values):
            continue
        gaps = [math.remainder(v - t, 2 * math.pi) if angle else v - t
                for v, t, angle in zip(values, seed, angles, strict=True)]
        distance = math.fsum(g * g for g in gaps)
        if distance < best:
            best, chosen = distance, list(combo)
    return chosen


def _circle_angle(p: sp.Expr, q: sp.Expr, k: sp.Expr, sign: sp.Symbol) -> tuple[sp.Expr, sp.Expr]:
    """t with p cos t + q sin t = k on the branch ``sign``, and the margin p^2 + q^2 - k^2 (>= 0 where it exists)."""
    return sp.atan2(q, p) + sign * sp.acos(k / sp.sqrt(p**2 + q**2)), p**2 + q**2 - k**2


def _pointing(axes: list[sp.Matrix], p: sp.Matrix, q: sp.Matrix, sign: sp.Symbol | None
              ) -> tuple[list[sp.Expr], list[sp.Expr]]:
    """The angles turning p onto q (|p| = |q|) about one axis (the plane's z) or two (the first's rotation
    applied after the second's, both in the same frame: Paden and Kahan's second subproblem, ``sign`` the
    side of the plane of the axes), and their margin where there are two."""
    if len(axes) == 0:
        return [sp.atan2(q[1], q[0]) - sp.atan2(p[1], p[0])], []
    w1, w2 = (axis / sp.sqrt(axis.dot(axis)) for axis in axes)
    c12 = w1.dot(w2)
    across = w1.cross(w2)
    alpha = (c12 * w2.dot(p) - w1.dot(q)) / (c12**2 - 1)
    beta = (c12 * w1.dot(q) - w2.dot(p)) / (c12**2 - 1)
    gamma2 = (p.dot(p) - alpha**2 - beta**2 - 2 * alpha * beta * c12) / across.dot(across)
    z = alpha * w1 + beta * w2 + sign * sp.sqrt(gamma2) * across

    def about(w: sp.Matrix, u: sp.Matrix, v: sp.Matrix) -> sp.Expr:
        u, v = u - w * w.dot(u), v - w * w.dot(v)
        return sp.atan2(w.dot(u.cross(v)), u.dot(v))

    return [about(w1, z, q), about(w2, p, z)], [gamma2]


def _closed_chain(joints: list[dict[str, Any]], d: sp.Matrix, vector: Any
                  ) -> tuple[list[sp.Expr], list[sp.Expr], list[sp.Symbol]] | None:
    """A two-joint chain's closed form from d = C - A in the leg's frame: the joints in order, the reach
    margins and the branch sign symbols; None where the chain is none of:

    * an actuated R or P, then a pointing joint (a planar R; a U or a parallelogram in space) with its link
      l2: the first joint puts the second's centre at the distance |l2| from C (a circle or a line met by a
      circle or a sphere), the second points l2 at C;
    * a pointing joint without a link, then an actuated P without one: the P's length is |d|, the pointing
      joint points its axis at C."""
    if len(joints) != 2:
        return None
    first, second = joints
    planar = d.rows == 2
    pointing = ("R",) if planar else ("U", "parallelogram")
    sign1, sign2 = sp.symbols("branch_distance branch_pointing", real=True)
    zero = sp.zeros(d.rows, 1)

    def axes(joint: dict[str, Any]) -> list[sp.Matrix]:
        return [] if planar else [vector(a) for a in joint["axes"]]

    if first["actuated"] and first["type"] in ("R", "P") and second["type"] in pointing:
        l1, l2 = vector(first["link"]), vector(second["link"])
        if first["type"] == "R":
            axis = sp.Matrix([0, 0, 1]) if planar else vector(first["axes"][0])
            u = axis / sp.sqrt(axis.dot(axis))
            along = u * u.dot(l1) if not planar else zero
            across = l1 - along
            normal = (u.cross(across) if not planar else sp.Matrix([-across[1], across[0]]))
            k = (d.dot(d) + l1.dot(l1) - l2.dot(l2)) / 2 - d.dot(along)
            t, margin = _circle_angle(d.dot(across), d.dot(normal), k, sign1)
            frame = _plane_rotation(t) if planar else _axis_rotation(axis, t)
            tip = frame * l1
        else:
            e = vector(first["axis"])
            e = e / sp.sqrt(e.dot(e))
            w = d - l1
            off = w - e * e.dot(w)
            margin = l2.dot(l2) - off.dot(off)
            t = e.dot(w) + sign1 * sp.sqrt(margin)
            frame, tip = sp.eye(d.rows), t * e + l1
        angles, more = _pointing(axes(second), l2, frame.T * (d - tip), sign2)
        return [t, *angles], [margin, *more], [sign1, sign2] if not planar else [sign1]
    if second["actuated"] and second["type"] == "P" and first["type"] in pointing and \
            all(e.is_zero for e in (*vector(first["link"]), *vector(second["link"]))):
        e = vector(second["axis"])
        e = e / sp.sqrt(e.dot(e))
        length = sp.sqrt(d.dot(d))
        angles, more = _pointing(axes(first), e, d / length, sign2)
        return [*angles, length], [d.dot(d), *more], [] if planar else [sign2]
    return None


# weight, its Jacobian in z, the inner matrix, and a point mass's position (None for a turning term)
Kinetic = tuple[sp.Expr, Callable[[list[sp.Symbol]], sp.Matrix], sp.Matrix, sp.Matrix | None]


def _mass_matrix(kinetic: list[Kinetic], z: list[sp.Symbol]) -> sp.Matrix:
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


def _leg_bodies(leg: dict[str, Any], joints: _Leg, a: sp.Matrix, c: sp.Matrix, scalar: Any) -> list[Kinetic]:
    """The kinetic terms of a leg's bodies: point masses (their centres) and turning moments (an angle, or a
    direction whose rate is the angular velocity across it)."""
    bodies, out = leg["bodies"], []
    rotor = scalar(bodies["rotor"])
    if rotor != 0:
        out.append(_turning(rotor, joints.actuated))
    if leg["kind"] == "RR":
        theta, (phi,) = joints.actuated, joints.passive
        for name, start, angle in (("proximal", a, theta),
                                   ("distal", a + scalar(leg["proximal"]) * _e(theta), phi)):
            if name in bodies:
                body = bodies[name]
                out += [_point(scalar(body["mass"]), start + scalar(body["centre"]) * _e(angle)),
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
            out += [_point(scalar(body["mass"]), joint + scalar(body["centre"]) * _e(phi)),
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


def _chain_bodies(leg: dict[str, Any], joints: _Leg, *, scalar: Any, vector: Any) -> list[Kinetic]:
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


def _platform(body: dict[str, Any] | None, frame: str, pose: tuple[sp.Symbol, ...], rotation: sp.Matrix, *,
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


def _add_chain(spec: ModuleSpec, k: int, leg: _Leg, ends: tuple[sp.Matrix, sp.Matrix], *, pose: Port, design: Port
               ) -> None:
    """``chain<k>(q_leg, c, design) -> (h, H)``: a chain leg's closure at a platform attachment c and its Jacobian
    in the leg's joints (actuated first), and ``chain<k>_ends(x, design) -> (a, c)``: its base and platform
    attachments at a pose, between which the runtime continues it."""
    a, c = ends
    target = sp.Matrix([sp.Symbol(f"c{j + 1}", real=True) for j in range(a.rows)])
    joints = (leg.actuated, *leg.passive)
    h = leg.end - target
    spec.add(f"chain{k + 1}", (Port("q_leg", joints, "the leg's joints, actuated first"),
                               Port("c", tuple(target), "the platform attachment [m]"), design),
             (Output("h", h, "the chain's end less c [m]"), Output("H", h.jacobian(joints), "dh/dq_leg")),
             f"The closure of chain leg {k + 1} at a platform attachment, and its Jacobian in the leg's joints.")
    spec.add(f"chain{k + 1}_ends", (pose, design),
             (Output("a", a, "the base attachment [m]"), Output("c", c, "the platform attachment [m]")),
             f"The attachments of chain leg {k + 1} at a pose.")


def _add_region(spec: ModuleSpec, region: dict[str, Any], design_port: Port, home: sp.Matrix, vector: Any) -> None:
    """``region_<name>(design) -> (centre, size)`` and, where the region spans other coordinates than the
    pose's own in order, ``region_<name>_pose(y, design) -> x`` (the others at the home pose's values)."""
    name = region["name"]
    spec.add(f"region_{name}", (design_port,),
             (Output("centre", vector(region["centre"]), "[pose units]"),
              Output("size", vector(region["size"]), "[pose units]")),
             f"Placement of the region {name}: {region['doc']}.")
    if region["coordinates"] != list(range(len(home))):
        y = tuple(sp.Symbol(f"y{k + 1}", real=True) for k in range(len(region["coordinates"])))
        x = list(home)
        for k, index in enumerate(region["coordinates"]):
            x[index] = y[k]
        spec.add(f"region_{name}_pose", (Port("y", y, "the region's coordinates"), design_port),
                 (Output("x", sp.Matrix(x), "[pose units]"),),
                 f"The pose at a point of the region {name}.")


def module(description: dict[str, Any]) -> ModuleSpec:
    """The ModuleSpec of a normalised description (:mod:`pkm.spec`)."""
    name = description["name"]
    frame = description["pose"]["frame"]
    parameters = [p["name"] for p in description["parameters"]]
    design = tuple(sp.Symbol(f"design.{p}", real=True) for p in parameters)
    pose = tuple(sp.Symbol(p, real=True) for p in FRAMES[frame])
    env = dict(zip(parameters, design, strict=True))

    def vector(trees: list[Any]) -> sp.Matrix:
        return sp.Matrix([expression(t, env) for t in trees])

    def scalar(tree: Any) -> sp.Expr:
        return expression(tree, env)

    rotation = _rotation(frame, pose)
    dim = rotation.rows
    defaults = {s: p["default"] for s, p in zip(design, description["parameters"], strict=True)}
    start = {**defaults, **{s: float(v.subs(defaults)) for s, v in zip(pose, vector(description["home"]), strict=True)}}
    origin = sp.Matrix(pose[:dim])
    legs = []
    kinetic: list[Kinetic] = []
    skeleton: list[sp.Matrix] = []
    ends: list[tuple[sp.Matrix, sp.Matrix]] = []
    limits: list[str] = []
    for k, leg in enumerate(description["legs"]):
        a, c = vector(leg["base"]), origin + rotation * vector(leg["platform"])
        if leg["kind"] == "RR":
            legs.append(_rr(k, a, c, scalar(leg["proximal"]), scalar(leg["distal"])))
        elif leg["kind"] == "RPR":
            legs.append(_rpr(k, a, c))
        elif leg["kind"] == "PRR":
            legs.append(_prr(k, a, c, vector(leg["axis"]), scalar(leg["distal"])))
        elif leg["kind"] == "R_parallelogram":
            legs.append(_r_parallelogram(k, a, c, {"axis": vector(leg["axis"]), "zero": vector(leg["zero"]),
                                                   "arm": scalar(leg["arm"]), "rod": scalar(leg["rod"])}))
        elif leg["kind"] == "UPS":
            legs.append(_ups(k, a, c, rotation, None if "cone" not in leg else scalar(leg["cone"])))
        else:
            legs.append(_chain(k, a, c, leg, vector=vector, scalar=scalar, start=start))
        last = legs[-1]
        names = last.reach_names or (("reach",) if len(last.reach) == 1 else
                                     tuple(f"reach {i + 1}" for i in range(len(last.reach))))
        margins = (*last.reach, *(m for _, m in last.stated))
        names += tuple(n for n, _ in last.stated)
        if "range" in leg:
            lo, hi = (scalar(t) for t in leg["range"])
            margins += (last.actuated - lo, hi - last.actuated)
            names += ("range lower", "range upper")
        legs[-1] = replace(last, margins=margins)
        limits += [f"leg {k + 1} {name}" for name in names]
        ends.append((a, c))
        skeleton += [a, *legs[-1].joints, c]
        if leg["kind"] == "chain":
            kinetic += _chain_bodies(leg, legs[-1], scalar=scalar, vector=vector)
        elif "bodies" in leg:
            kinetic += _leg_bodies(leg, legs[-1], a, c, scalar)
    q_a = tuple(leg.actuated for leg in legs)
    q_p = tuple(s for leg in legs for s in leg.passive)
    signs = tuple(leg.sign for leg in legs if leg.sign is not None) or (sp.Symbol("branch", real=True),)
    loop = LoopClosure.of([h for leg in legs for h in leg.h], q_a, q_p, pose)
    solution = {s: e for leg in legs for s, e in leg.ik.items()}
    q = sp.Matrix([solution[s] for s in (*q_a, *q_p)])
    spec = ModuleSpec(name, "symbolic/describe.py", description.get("doc", name), limits=tuple(limits))
    design_port = Port("design", design, "; ".join(f"{p['name']} [{p['unit']}]" for p in description["parameters"]))
    pose_port = Port("x", pose, ", ".join(f"{n} [{u}]" for n, u in zip(FRAMES[frame], description["pose"]["units"],
                                                                       strict=True)))
    joints = Port("q", (*q_a, *q_p), "actuated joints, then the passive joints leg by leg")
    actuated = Port("q_a", q_a, "actuated joints")
    mode = Port("mode", signs, "branch sign of each leg with two (+1 or -1)")
    chains = any(leg.end is not None for leg in legs)
    inverse = InverseKinematics(
        q, sp.Matrix([m for leg in legs for m in leg.reach]),
        "Closed-form inverse kinematics, leg by leg, on the branch of the mode's signs"
        + ("; a chain leg's joints are its branch's seed, where the runtime's continuation starts." if chains
           else "."),
        "actuated, then passive joints", "margins of each closed-form leg's reach, >= 0 where it assembles",
    )
    add_kinematics(spec, loop, pose=pose_port, joints=joints, actuated=actuated, design=design_port, mode=mode,
                   inverse=inverse, units=dict.fromkeys(("h", "H_q", "H_x", "J", "J_f", "psi", "det"), "-"),
                   composed=True, inverse_name="continuation_start" if chains else "inverse_kinematics")
    for k, (leg, attachments) in enumerate(zip(legs, ends, strict=True)):
        if leg.end is not None:
            _add_chain(spec, k, leg, attachments, pose=pose_port, design=design_port)
    spec.add("home", (design_port,), (Output("x", vector(description["home"]), "the home pose"),),
             "The home pose: the seed of the forward kinematics.")
    if description.get("platform") is not None or kinetic:
        kinetic += _platform(description.get("platform"), frame, pose, rotation, vector=vector, scalar=scalar)
        z = [*q_a, *q_p, *pose]
        spec.add("mass_matrix", (joints, pose_port, design_port),
                 (Output("M", _mass_matrix(kinetic, z), "the kinetic energy's matrix in (q, x): T = z_dot^T M "
                         "z_dot / 2, z = (q, x) [SI]"),),
                 "The mass matrix of the bodies in all the joint and pose coordinates.")
        if description.get("gravity") is not None:
            g = vector(description["gravity"])
            potential = -sum((w * g.dot(p) for w, _, _, p in kinetic if p is not None), sp.Integer(0))
            spec.add("gravity", (joints, pose_port, design_port),
                     (Output("G", sp.Matrix([potential]).jacobian(z).T, "dV/dz [N or N m]"),
                      Output("V", sp.Matrix([potential]), "the bodies' potential energy in the gravity field [J]")),
                     "The gradient of the bodies' potential energy in all the joint and pose coordinates.")
    spec.add("skeleton", (joints, pose_port, design_port),
             (Output("points", sp.Matrix.hstack(*skeleton).T, "each leg's joints from the base's to the platform's, "
                     "one row each [m]"),),
             "The points of the joints, leg by leg, for drawing the linkage.")
    sides = [leg.side for leg in legs if leg.side is not None]
    if sides:
        spec.add("branch_sides", (joints, pose_port, design_port),
                 (Output("sides", sp.Matrix(sides), "one per leg with passive joints and two branches: its sign "
                         "tells the branches apart"),),
                 "The side of each two-branched leg's passive joints at a configuration.")
    for region in description.get("regions", []):
        _add_region(spec, region, design_port, vector(description["home"]), vector)
    margins = [m for leg in legs for m in leg.margins]
    spec.add("workspace_margins", (joints, pose_port, design_port),
             (Output("margins", sp.Matrix(margins), "each leg's reach margins and its actuated joint's range, >= 0 "
                     "inside the workspace, named by the module's LIMITS"),),
             "The workspace's margins at a configuration: >= 0 where the legs reach and the actuated joints lie "
             "in their ranges.")
    if description.get("characteristic_length"):
        spec.add("characteristic_length", (design_port,),
                 (Output("L", sp.Matrix([scalar(description["characteristic_length"])]), "[m]"),),
                 "The length that turns the pose's angles into arc lengths.")
    return spec


UNDEFINED = 3  # the exit status of a derivation that meets an expression without a finite value


def main(argv: list[str] | None = None) -> int:
    """Derive the description at the first path into the module at the second; an expression without a
    finite value ends it with one line on standard error and :data:`UNDEFINED`."""
    source, target = (Path(a) for a in (argv if argv is not None else sys.argv[1:]))
    description = json.loads(source.read_text())
    try:
        rendered = codegen.RenderedModule.of(module(description), description["key"])
    except (UndefinedError, codegen.UndefinedError) as exc:
        print(f"undefined: {exc}", file=sys.stderr)
        return UNDEFINED
    target.write_text(rendered.text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
