"""Each leg of a described machine in sympy: its closure rows, joints, inverse kinematics in closed form (the
leg's known subproblem, or a chain's where its joints match one) and its reach margins."""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Any

import sympy as sp
from sympy.matrices.utilities import dotprodsimp

from pkm import expressions
from symbolic.codegen import free_symbols

FRAMES = {
    "planar_point": ("x", "y"),
    "planar": ("x", "y", "phi"),
    "spatial_point": ("x", "y", "z"),
    "spatial": ("x", "y", "z", "roll", "pitch", "yaw"),
}
class UndefinedError(ValueError):
    """An expression of the description without a finite value at every design (tan(pi/2), 1/(a - a))."""


def _finite(op: str, values: list[sp.Expr], value: sp.Expr) -> None:
    if value.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        raise UndefinedError(f"{op}({', '.join(map(str, values))}) has no finite value")


def _number(number: int | float) -> sp.Expr:
    return sp.Integer(number) if isinstance(number, int) else sp.Float(number)


# pkm's evaluator of expression trees with sympy's numbers and functions, each operation's value checked finite
SYMPY = expressions.Backend({"cos": sp.cos, "sin": sp.sin, "tan": sp.tan, "sqrt": sp.sqrt, "asin": sp.asin,
                             "acos": sp.acos, "atan": sp.atan}, number=_number, constants={"pi": sp.pi},
                            check=_finite)


def expression(tree: Any, names: dict[str, sp.Symbol]) -> sp.Expr:
    """The sympy expression of one of pkm's expression trees (:func:`pkm.expressions.evaluate`: a number, a
    name, or ``[operator, operand, ...]``), built node by node: nothing of the description is parsed or
    evaluated as text here."""
    return expressions.evaluate(tree, names, SYMPY)


def platform_rotation(frame: str, pose: tuple[sp.Symbol, ...]) -> sp.Matrix:
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


def direction(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


@dataclass(frozen=True)
class Leg:
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
    circle: tuple[sp.Matrix, sp.Expr] | None = None  # its actuated joint given, the circle (in the plane) or the
    # sphere (in space) on which its platform joint lies: centre in the base frame, radius
    line: tuple[sp.Matrix, sp.Matrix] | None = None  # or the line (in the plane): a point and a direction
    h_c: sp.Matrix | None = None  # the closure's derivative in the platform joint's point c, where the closure is
    # not the chain's end less c (whose derivative is -I)


def _rr(k: int, a: sp.Matrix, c: sp.Matrix, l1: sp.Expr, l2: sp.Expr) -> Leg:
    theta, phi, sigma = sp.symbols(f"theta{k + 1} phi{k + 1} sigma{k + 1}", real=True)
    d = c - a
    dist2 = d.dot(d)
    angle = sp.atan2(d[1], d[0]) + sigma * sp.acos((l1**2 + dist2 - l2**2) / (2 * l1 * sp.sqrt(dist2)))
    elbow = a + l1 * direction(angle)
    h = list(a + l1 * direction(theta) + l2 * direction(phi) - c)
    ik = {theta: angle, phi: sp.atan2(c[1] - elbow[1], c[0] - elbow[0])}
    return Leg(h, theta, [phi], ik, [(l1 + l2) ** 2 - dist2, dist2 - (l1 - l2) ** 2], sigma,
               side=sp.sin(phi - theta), joints=(a + l1 * direction(theta),),
               reach_names=("reach outer", "reach inner"), circle=(a + l1 * direction(theta), l2))


def _rpr(k: int, a: sp.Matrix, c: sp.Matrix) -> Leg:
    rho, phi = sp.symbols(f"rho{k + 1} phi{k + 1}", real=True)
    d = c - a
    h = list(a + rho * direction(phi) - c)
    return Leg(h, rho, [phi], {rho: sp.sqrt(d.dot(d)), phi: sp.atan2(d[1], d[0])}, [d.dot(d)], None,
               circle=(a, rho))


def _prr(k: int, a: sp.Matrix, c: sp.Matrix, axis: sp.Matrix, length: sp.Expr) -> Leg:
    s, phi, sigma = sp.symbols(f"s{k + 1} phi{k + 1} sigma{k + 1}", real=True)
    u = axis / sp.sqrt(axis.dot(axis))
    d = c - a
    along, across = d.dot(u), d[0] * u[1] - d[1] * u[0]
    slide = along + sigma * sp.sqrt(length**2 - across**2)
    joint = a + slide * u
    h = list(a + s * u + length * direction(phi) - c)
    ik = {s: slide, phi: sp.atan2(c[1] - joint[1], c[0] - joint[0])}
    return Leg(h, s, [phi], ik, [length**2 - across**2], sigma, side=-(sp.cos(phi) * u[0] + sp.sin(phi) * u[1]),
               joints=(a + s * u,), circle=(a + s * u, length))


def _r_parallelogram(k: int, a: sp.Matrix, c: sp.Matrix, leg: dict[str, Any]) -> Leg:
    """The arm turned by theta about the axis from zero, and the parallelogram's rods turned from zero by beta
    about zero x axis, then by alpha about the axis: alpha absolute, like an RR's distal angle (the chain's
    parallelogram turns by alpha - theta in the arm's frame); beta within +-pi/2 (the rods never turn
    over)."""
    axis, zero, arm, rod = leg["axis"], leg["zero"], leg["arm"], leg["rod"]
    theta, alpha, beta, sigma = sp.symbols(f"theta{k + 1} alpha{k + 1} beta{k + 1} sigma{k + 1}", real=True)
    w = axis.cross(zero)
    tip = a + arm * (sp.cos(theta) * zero + sp.sin(theta) * w)
    rods = sp.cos(beta) * (sp.cos(alpha) * zero + sp.sin(alpha) * w) + sp.sin(beta) * axis
    h = list(tip + rod * rods - c)
    d = c - a
    p, q = d.dot(zero), d.dot(w)
    big_k = (d.dot(d) + arm**2 - rod**2) / (2 * arm)
    angle = sp.atan2(q, p) + sigma * sp.acos(big_k / sp.sqrt(p**2 + q**2))
    reached = d - arm * (sp.cos(angle) * zero + sp.sin(angle) * w)
    ik = {theta: angle, alpha: sp.atan2(reached.dot(w), reached.dot(zero)),
          beta: sp.atan2(reached.dot(axis), sp.sqrt(reached.dot(zero) ** 2 + reached.dot(w) ** 2))}
    return Leg(h, theta, [alpha, beta], ik, [p**2 + q**2 - big_k**2], sigma, joints=(tip,), circle=(tip, rod))


def _ups(k: int, a: sp.Matrix, c: sp.Matrix, rotation: sp.Matrix, cone: sp.Expr | None) -> Leg:
    length = sp.Symbol(f"l{k + 1}", real=True)
    d = c - a
    stated = ()
    if cone is not None:
        normal = rotation[:, 2]
        stated = (("cone at the base", d[2] - sp.cos(cone) * sp.sqrt(d.dot(d))),
                  ("cone at the platform", d.dot(normal) - sp.cos(cone) * sp.sqrt(d.dot(d))))
    return Leg([d.dot(d) - length**2], length, [], {length: sp.sqrt(d.dot(d))}, [d.dot(d)], None, stated=stated,
               circle=(a, length), h_c=2 * d.T)


def _axis_rotation(axis: sp.Matrix, angle: sp.Expr) -> sp.Matrix:
    """The rotation by ``angle`` about ``axis`` (Rodrigues)."""
    u = axis / sp.sqrt(axis.dot(axis))
    cross = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return sp.eye(3) * sp.cos(angle) + sp.sin(angle) * cross + (1 - sp.cos(angle)) * u * u.T


def _plane_rotation(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([[sp.cos(angle), -sp.sin(angle)], [sp.sin(angle), sp.cos(angle)]])


def _chain(k: int, a: sp.Matrix, c: sp.Matrix, leg: dict[str, Any], *, vector: Any, scalar: Any,
           start: dict[sp.Symbol, float]) -> Leg:
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
    with dotprodsimp(False):  # sympy's default expands the determinant, which tilted axes make take minutes
        side = sp.Matrix(h).jacobian(variables).det(method="berkowitz")
    passive = [v for v in variables if v is not actuated]
    closed = None if leg.get("newton") else _closed_chain(leg["joints"], frame.T * (c - a), vector)
    circle = _chain_circle(leg["joints"], a, points, actuated, vector=vector, planar=planar)
    line = None
    if circle is None and planar and len(variables) == 2:
        circle, line = _planar_locus(leg["joints"], variables, frames, point)
    if closed is None:
        first = [sp.Float(v) for v in seeds[0]]
        blend = first if sigma is None else [(1 + sigma) / 2 * p + (1 - sigma) / 2 * sp.Float(m)
                                             for p, m in zip(first, seeds[-1], strict=True)]
        return Leg(h, actuated, passive, dict(zip(variables, blend, strict=True)), [], sigma, side=side,
                   joints=tuple(points[:-1]), end=point, frames=tuple(frames), circle=circle, line=line)
    solution, reach, signs = closed
    chosen = [_nearest_candidate(solution, signs, seed, angles, start) for seed in seeds]
    values = {s: chosen[0][i] if sigma is None else (1 + sigma) / 2 * chosen[0][i] + (1 - sigma) / 2 * chosen[-1][i]
              for i, s in enumerate(signs)}
    ik = dict(zip(variables, replaced(solution, values), strict=True))
    return Leg(h, actuated, passive, ik, replaced(reach, values), sigma, side=side,
               joints=tuple(points[:-1]), frames=tuple(frames), circle=circle, line=line)


def _chain_circle(joints: list[dict[str, Any]], a: sp.Matrix, points: list[sp.Matrix], actuated: sp.Symbol, *,
                  vector: Any, planar: bool) -> tuple[sp.Matrix, sp.Expr] | None:
    """A two-joint chain's circle (in the plane) or sphere (in space), where it has one: an actuated R or P,
    then a pointing joint (a passive R in the plane; a U or a parallelogram in space; about it, its link the
    radius); or a pointing joint without a link, then an actuated P without one (about A, the P's value the
    radius). None for any other chain."""
    if len(joints) != 2:
        return None
    first, second = joints
    pointing = ("R",) if planar else ("U", "parallelogram")
    if first["actuated"] and second["type"] in pointing:
        link = vector(second["link"])
        return points[0], sp.sqrt(link.dot(link))
    no_links = all(e.is_zero for j in joints for e in vector(j["link"]))
    if first["type"] in pointing and second["actuated"] and second["type"] == "P" and no_links:
        return a, actuated
    return None


def _planar_locus(joints: list[dict[str, Any]], variables: list[sp.Symbol], frames: list[Any], end: sp.Matrix
                  ) -> tuple[tuple[sp.Matrix, sp.Expr] | None, tuple[sp.Matrix, sp.Matrix] | None]:
    """The circle or the line on which a planar two-joint chain's end lies, its actuated joint given, where
    :func:`_chain_circle` names none: its passive joint a revolute, the circle about that joint (the end turns
    rigidly about it); a prismatic, the line its slide draws (the end at zero slide, and the slide's
    direction)."""
    passive = next(j for j, joint in enumerate(joints) if not joint["actuated"])
    s = variables[passive]
    if joints[passive]["type"] == "P":
        return None, (end.subs(s, 0), end.diff(s))
    centre = frames[passive][0]
    offset = (end - centre).subs(s, 0)
    return (centre, sp.sqrt(sp.trigsimp(offset.dot(offset)))), None


def replaced(expressions: list[sp.Expr], mapping: dict[sp.Symbol, sp.Expr]) -> list[sp.Expr]:
    """The expressions with the symbols of ``mapping`` replaced, as xreplace does, each shared subexpression once
    (sympy's subs and xreplace walk a subexpression at each of its occurrences: minutes for a closed form of tilted
    axes); a subexpression without those symbols is kept as it is."""
    if not all(isinstance(s, sp.Symbol) for s in mapping):
        raise TypeError("replaced replaces symbols only")
    memo: dict[tuple[type, sp.Basic], sp.Basic] = {}

    def walk(e: sp.Basic) -> sp.Basic:
        key = (type(e), e)
        if key not in memo:
            if not e.args:
                memo[key] = mapping.get(e, e) if isinstance(e, sp.Symbol) else e
            else:
                args = tuple(map(walk, e.args))
                memo[key] = e if all(a is b for a, b in zip(args, e.args, strict=True)) else e.func(*args)
        return memo[key]

    return [walk(e) for e in expressions]


def _nearest_candidate(solution: list[sp.Expr], signs: list[sp.Symbol], seed: list[float], angles: list[bool],
                       start: dict[sp.Symbol, float]) -> list[int]:
    """The branch signs of the closed form whose joints at ``start`` are nearest the seed (angles wrapped)."""
    at_start = replaced(solution, {s: sp.Float(v) for s, v in start.items()})
    left = set().union(*(free_symbols(e) for e in at_start)) - set(signs)
    if left:
        raise ValueError(f"the closed form names {sorted(map(str, left))}, which the start pose does not give")
    best, chosen = math.inf, [1] * len(signs)
    for combo in itertools.product((1, -1), repeat=len(signs)):
        numbers = [complex(e) for e in replaced(at_start, dict(zip(signs, map(sp.Integer, combo), strict=True)))]
        if not all(math.isfinite(v.real) and v.imag == 0 for v in numbers):
            continue  # a complex value (an arc cosine beyond 1), or none: no candidate there
        values = [v.real for v in numbers]
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




def derive_leg(k: int, a: sp.Matrix, c: sp.Matrix, leg: dict[str, Any], rotation: sp.Matrix, *, vector: Any,
               scalar: Any, start: dict[sp.Symbol, float]) -> Leg:
    """Leg k of its kind between its attachments a and c (in the base frame), the platform turned by
    ``rotation``: a named kind's closed form, or a chain's."""
    kind = leg["kind"]
    if kind == "RR":
        return _rr(k, a, c, scalar(leg["proximal"]), scalar(leg["distal"]))
    if kind == "RPR":
        return _rpr(k, a, c)
    if kind == "PRR":
        return _prr(k, a, c, vector(leg["axis"]), scalar(leg["distal"]))
    if kind == "R_parallelogram":
        return _r_parallelogram(k, a, c, {"axis": vector(leg["axis"]), "zero": vector(leg["zero"]),
                                          "arm": scalar(leg["arm"]), "rod": scalar(leg["rod"])})
    if kind == "UPS":
        return _ups(k, a, c, rotation, None if "cone" not in leg else scalar(leg["cone"]))
    return _chain(k, a, c, leg, vector=vector, scalar=scalar, start=start)
