"""The Cartesian stiffness of a described machine by the virtual joint method (Pashkevich, Klimchik and Chablat,
MMT 44, 2009), composed in CasADi from its derived module leg by leg like the first order.

Each leg is a serial chain from its base joint to its platform joint at c: its drive a spring in its actuated joint
(compliance k_a^-1), each beam (:func:`pkm.spec.vocabulary.beams`) clamped at its start and a 6-D spring at its end
E (3-D in the plane: its Euler-Bernoulli compliance C_b, :mod:`symbolic.described.elastic`), its passive joints free
or, where the leg's ``elastic.passive`` gives their stiffness k_p, springs in their own motion (relative to the link
before them; a kind that measures a passive angle from the base's frame, an RR's distal one, has it turn with the
actuated joint: :attr:`pkm.spec.vocabulary.Kind.follows`). With the closure h(q_a, q_p, c) = 0 of the leg (its rows:
the chain's end less c, or a distance), a small motion closes where H_a dq_a + H_p dq_p + H_theta dtheta + H_c dc =
0, H_theta the chain end's motion under each beam's deflection (a twist at E: dc = du + dphi x (c - E)). The
springs' compliance seen at the chain's end, S = H_a k_a^-1 H_a^T + sum_p H_p k_p^-1 H_p^T + sum_b H_theta,b C_b
H_theta,b^T + (sum_j k_j^-1) H_c H_c^T (each joint's bearing a translational spring k_j: its translation moves the
chain beyond it, and c, by as much) + sum_j t_j^-1 [c - p_j]x (I - a_j a_j^T) [c - p_j]x^T (in space, a revolute's
bearing tilt springs t_j at its point p_j about the two axes across its own a_j: a small turn w of the chain beyond
it moves c by w x (c - p_j)), and the free passive joints (H_p their columns) give the leg's stiffness at c,

    K_i = H_c^T G H_c,   G the first block of [[S, H_p], [H_p^T, 0]]^-1,

the least elastic energy over the passive joints' motion for each motion dc (the platform joint, a revolute in
the plane and a spherical joint in space, leaves the end's rotation free). The platform is rigid: its twist
(dP, dphi) moves c_i by A_i = [I, -[c_i - P]x] (in the plane [I, perp(c_i - P)]), and

    K = sum_i A_i^T K_i A_i

in the twist's coordinates: a point pose's translation alone (A_i = I), else the translation and the small
rotation about the base's axes (in the plane the platform angle's). Its blocks are in N/m, N/rad and N m/rad.
Without the beams and the passive joints' springs (``actuators_only``) K is J^T diag(k_a) J, Gosselin's actuator
stiffness (IEEE TRA 6(3), 1990)."""

from __future__ import annotations

from collections.abc import Mapping

import casadi as ca

from pkm.spec.compose import legs_layout
from pkm.spec.schema import Description
from pkm.spec.vocabulary import beams, kind_of, passive_stiffness


def _cross(v: ca.SX) -> ca.SX:
    """[v]x, v x w = [v]x w."""
    return ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]), ca.horzcat(-v[1], v[0], 0))


def _beam(terms: ca.SX, start: ca.SX, end: ca.SX, c: ca.SX) -> ca.SX:
    """A beam's compliance seen at the chain's end c (its translation): clamped at ``start``, its end at ``end``,
    its compliance terms (axial, bending_uu, bending_uphi, bending_phiphi, torsion) at its end in its frame
    turned into the base's, a symmetric section (in the plane, bending in the plane)."""
    axial, uu, uphi, phiphi, torsion = (terms[k] for k in range(5))
    along = (end - start) / ca.norm_2(end - start)
    dim = along.numel()
    P = along @ along.T
    Q = ca.SX.eye(dim) - P
    r = c - end
    if dim == 2:
        n = ca.vertcat(-along[1], along[0])
        compliance = ca.vertcat(ca.horzcat(axial * P + uu * Q, uphi * n), ca.horzcat(uphi * n.T, phiphi))
        motion = ca.horzcat(ca.SX.eye(2), ca.vertcat(-r[1], r[0]))
    else:
        S = _cross(along)
        compliance = ca.vertcat(ca.horzcat(axial * P + uu * Q, -uphi * S),
                                ca.horzcat(uphi * S, torsion * P + phiphi * Q))
        motion = ca.horzcat(ca.SX.eye(3), -_cross(r))
    return motion @ compliance @ motion.T


def _leg(H_p: ca.SX, H_c: ca.SX, springs: ca.SX) -> ca.SX:
    """K_i = H_c^T G H_c, G the first block of [[S, H_p], [H_p^T, 0]]^-1 (module docstring), taken as
    N (N^T S N)^-1 N^T with N spanning the motions the free passive joints cannot make (H_p^T N = 0): with the
    projector P = I - H_p (H_p^T H_p)^-1 H_p^T onto them, G = P (P S P + s (I - P))^-1 P, s = tr(S) / rows. Where
    the leg has free passive joints S itself is not inverted, whose inverse is as large as the stiffest element
    (a rigid beam beside a soft drive) and would cancel in G to the leg's own stiffness; without them G = S^-1."""
    rows, free = springs.size1(), H_p.size2()
    if free == 0:
        return H_c.T @ ca.solve(springs, H_c)
    eye = ca.SX.eye(rows)
    P = eye - H_p @ ca.solve(H_p.T @ H_p, H_p.T)
    G = P @ ca.solve(P @ springs @ P + ca.trace(springs) / rows * (eye - P), P)
    return H_c.T @ G @ H_c


def composed_stiffness(description: Description, functions: Mapping[str, ca.Function]) -> ca.Function:
    """``stiffness(q, x, design) -> (K, K_drives, K_t)``: the Cartesian stiffness with the beams and with the
    drives alone (module docstring), in the pose's twist coordinates, and K's translational block with the
    rotation free (its Schur complement K_tt - K_tr K_rr^-1 K_rt; K itself for a point pose) [N/m]."""
    constraint, skeleton, elastic, ends = (functions[k] for k in ("constraint", "skeleton", "elastic", "leg_ends"))
    q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
    _, H_q, _ = constraint(q, x, d)
    H_c = ends(q, x, d)
    points = skeleton(q, x, d)
    drives, compliances, terms, bearings = elastic(d)
    tilt_axes, tilts = functions["bearing_tilts"](q, x, d) if "bearing_tilts" in functions else (None, None)
    data = description.data
    frame = data["pose"]["frame"]
    legs = data["legs"]
    n_act = len(legs)
    dim = points.size2()
    origin = x[:dim]
    turning = frame in ("planar", "spatial")
    total = {k: ca.SX.zeros(x.numel(), x.numel()) for k in ("K", "K_drives")}
    first, beam, spring = 0, 0, 0
    for k, (leg, (rows, passive, _)) in enumerate(zip(legs, legs_layout(description), strict=True)):
        own = points[first:first + kind_of(leg).points, :].T
        first += kind_of(leg).points
        c = own[:, -1]
        columns = [H_q[rows, n_act + p] for p in passive]
        # the actuated joint turned with the passive joints' own motions held: the angles its kind measures from
        # the base's frame turn with it
        H_a = H_q[rows, k] + sum((columns[i] for i in kind_of(leg).follows), ca.SX.zeros(len(rows), 1))
        stiff = [j for j, given in enumerate(passive_stiffness(leg)) if given is not None]
        free = [j for j in range(len(columns)) if j not in stiff]
        H_p = ca.horzcat(*(columns[j] for j in free)) if free else ca.SX.zeros(len(rows), 0)
        H_all = ca.horzcat(*columns) if columns else ca.SX.zeros(len(rows), 0)
        drive = drives[k] * (H_a @ H_a.T)
        flexed = drive
        for j in stiff:
            flexed = flexed + compliances[spring + j] * (columns[j] @ columns[j].T)
        spring += len(columns)
        for j in beams(leg):
            flexed = flexed + _beam(terms[beam, :].T, own[:, j], own[:, j + 1], c)
            beam += 1
        flexed = flexed + bearings[k] * (H_c[rows, :] @ H_c[rows, :].T)
        if tilts is not None:
            for j in range(kind_of(leg).points):
                row = first - kind_of(leg).points + j
                arm, axis = _cross(c - own[:, j]), tilt_axes[row, :].T
                flexed = flexed + tilts[row] * (arm @ (ca.SX.eye(3) - axis @ axis.T) @ arm.T)
        if turning:
            offset = c - origin
            A = ca.horzcat(ca.SX.eye(2), ca.vertcat(-offset[1], offset[0])) if dim == 2 else \
                ca.horzcat(ca.SX.eye(3), -_cross(offset))
        else:
            A = ca.SX.eye(dim)
        for name, springs, unconstrained in (("K", flexed, H_p), ("K_drives", drive, H_all)):
            total[name] = total[name] + A.T @ _leg(unconstrained, H_c[rows, :], springs) @ A
    K = total["K"]
    if turning:
        t, r = slice(0, dim), slice(dim, x.numel())
        K_t = K[t, t] - K[t, r] @ ca.solve(K[r, r], K[r, t])
    else:
        K_t = K
    return ca.Function("stiffness", [q, x, d], [K, total["K_drives"], K_t], ["q", "x", "design"],
                       ["K", "K_drives", "K_t"])


def _pose_rates(x: ca.SX) -> ca.SX:
    """E with the platform's twist E x_dot for a spatial pose (x, y, z, roll, pitch, yaw), R = Rz(yaw) Ry(pitch)
    Rx(roll): the translation's rates, and the angular velocity Rz Ry e_x roll_dot + Rz e_y pitch_dot + e_z
    yaw_dot."""
    _, pitch, yaw = x[3], x[4], x[5]
    cy, sy, cp, sp = ca.cos(yaw), ca.sin(yaw), ca.cos(pitch), ca.sin(pitch)
    turning = ca.horzcat(ca.vertcat(cy * cp, sy * cp, -sp), ca.vertcat(-sy, cy, 0), ca.vertcat(0, 0, 1))
    return ca.diagcat(ca.SX.eye(3), turning)


def _cholesky(M: ca.SX) -> ca.SX:
    """The lower triangular L with M = L L^T of a symmetric positive definite matrix, written out."""
    n = M.size1()
    L = ca.SX.zeros(n, n)
    for i in range(n):
        for j in range(i + 1):
            rest = M[i, j] - sum((L[i, k] * L[j, k] for k in range(j)), ca.SX(0))
            L[i, j] = ca.sqrt(rest) if i == j else rest / L[j, j]
    return L


def composed_vibration(stiffness: ca.Function, inertia: ca.Function, frame: str) -> ca.Function:
    """``vibration(q, x, design) -> S_k``: the rigid platform on the elastic structure, its squared natural
    frequencies the eigenvalues of S_k = L^-1 K_x L^-T, M_w = L L^T the task-space inertia and K_x the stiffness in
    the pose's coordinates (E^T K E, E the twist's rates of a spatial pose's; K itself otherwise)."""
    q, x, d = (ca.SX.sym(stiffness.name_in(i), stiffness.size_in(i)) for i in range(3))
    K = stiffness(q, x, d)[0]
    if frame == "spatial":
        E = _pose_rates(x)
        K = E.T @ K @ E
    L = _cholesky(inertia(q, x, d)[1])
    inverse = ca.solve(L, ca.SX.eye(L.size1()))
    return ca.Function("vibration", [q, x, d], [inverse @ K @ inverse.T], ["q", "x", "design"], ["S_k"])


def elastic_functions(description: Description, functions: Mapping[str, ca.Function]) -> dict[str, ca.Function]:
    """``stiffness`` (:func:`composed_stiffness`) of a machine whose functions have its legs' ``elastic``
    compliances, and ``vibration`` (:func:`composed_vibration`) where they have its ``inertia`` too; nothing
    where they have no elastic elements. ``description`` gives the legs' layout: a described machine's own, or
    the legs of a hand-derived machine in the description vocabulary (whose generated ``skeleton``, ``elastic``
    and ``leg_ends`` follow a described machine's conventions)."""
    if "elastic" not in functions:
        return {}
    out = {"stiffness": composed_stiffness(description, functions)}
    if "inertia" in functions:
        out["vibration"] = composed_vibration(out["stiffness"], functions["inertia"], description.data["pose"]["frame"])
    return out
