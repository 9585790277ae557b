"""What the runtime composes in CasADi from a description's derived module, leg by leg: the first order from
the closure's Jacobians, the inverse kinematics of chain legs by Newton continuation from their seeds, and the
inertia, energy and inverse dynamics from the mass matrix."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.spec.schema import Description, DescriptionError
from pkm.spec.vocabulary import (
    kind_of,
    passive_angles,
)


def legs_layout(description: Description) -> list[tuple[list[int], list[int], int | None]]:
    """Each leg's closure rows, its passive joints' columns among the passive joints, and the mode sign that
    chooses its branch (None where it has one)."""
    row = column = sign = 0
    out = []
    for leg in description.data["legs"]:
        kind = kind_of(leg)
        rows = kind.passive + 1
        out.append((list(range(row, row + rows)), list(range(column, column + kind.passive)),
                    sign if kind.branched else None))
        row, column, sign = row + rows, column + kind.passive, sign + kind.branched
    return out


def _normal(A: ca.SX) -> ca.SX:
    """The vector w with w.v = det([A v]) for every v, of an r x (r - 1) matrix A (its cofactors)."""
    r = A.size1()
    if r == 1:
        return ca.SX.ones(1)
    return ca.vertcat(*[(-1) ** (j + r - 1) * ca.det(A[[i for i in range(r) if i != j], :]) for j in range(r)])


def _reduced_det(H_p: ca.SX, B: ca.SX, legs: list[tuple[list[int], list[int], int | None]]) -> ca.SX:
    """det [H_p B] up to a constant sign, where each leg's rows hold its passive columns of H_p and nothing
    else there (one more row than columns): by the Laplace expansion along the passive columns, the
    determinant of the square matrix whose row k is w_k^T B_k, w_k the normal of leg k's block of H_p
    (:func:`_normal`), so that no determinant larger than a leg's or the pose's is expanded."""
    return ca.det(ca.vertcat(*[_normal(H_p[rows, columns]).T @ B[rows, :] for rows, columns, _ in legs]))


def composed_first_order(constraint: ca.Function, n_act: int,
                         legs: list[tuple[list[int], list[int], int | None]]) -> ca.Function:
    """``first_order(q, x, design) -> (J, J_f, psi, det_type1, det_type2)`` composed in CasADi from the loop
    closure's Jacobians (:mod:`symbolic.loops`), leg by leg: each leg's joint rates dq_k = -B_k^-1 H_x,k
    x_dot with B_k its block of [H_a H_p] (its rows, its actuated and passive columns; the legs share no
    joint), J their actuated rows, J_f = J^-1, Psi from the passive rows times J_f; the determinants of
    [H_a H_p] and [H_p H_x] reduced leg by leg (:func:`_reduced_det`, their signs those of the full
    determinants, found once at random entries)."""
    q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
    _, H_q, H_x = constraint(q, x, d)
    H_a, H_p = H_q[:, :n_act], H_q[:, n_act:]
    inverse = ca.SX.zeros(H_q.size2(), H_x.size2())
    for k, (rows, passive, _) in enumerate(legs):
        columns = [k, *(n_act + p for p in passive)]
        inverse[columns, :] = ca.solve(H_q[rows, columns], -H_x[rows, :])
    J = inverse[:n_act, :]
    J_f = ca.solve(J, ca.SX.eye(n_act))
    psi = ca.vertcat(ca.SX.eye(n_act), inverse[n_act:, :] @ J_f)
    dets = []
    for B, full in ((H_a, H_q), (H_x, ca.horzcat(H_p, H_x))):
        reduced = _reduced_det(H_p, B, legs)
        probe = ca.Function("probe", [q, x, d], [reduced, full])
        values = np.random.default_rng(0).uniform(0.5, 1.5, size=(3, max(q.numel(), x.numel(), d.numel())))
        small, matrix = probe(values[0, : q.numel()], values[1, : x.numel()], values[2, : d.numel()])
        dets.append(float(np.sign(np.linalg.det(np.asarray(matrix, dtype=float)) * float(small))) * reduced)
    return ca.Function("first_order", [q, x, d], [J, J_f, psi, *dets],
                       ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


CONTINUATION_STEPS = 12  # Newton steps along the path from the home pose at the default design
NEWTON_STEPS = 12  # Newton steps at the pose asked for, after the path (8 left one pose in 10^6 of the
# benchmark 4e-10 rad from its root, near a universal joint's own singularity)
START_STEPS = 30  # Newton steps that close a chain's seed at the home pose, at most
CHAIN_TOLERANCE = 1e-13  # [m] a chain leg closes to this where its pose is reached


def _path(a0: Any, c0: Any, a1: Any, c1: Any, t: float, *, straight: bool) -> Any:
    """The platform attachment at t on the path from c0 to c1 (c1 itself at t = 1): straight, or about the base
    attachment (from a0 to a1), with the distance from it interpolated and its direction turned at a constant
    rate in the plane of the two (slerp), so that a leg whose reach is a shell about its base stays in it."""
    if straight or t == 1.0:
        return (1 - t) * c0 + t * c1
    a = (1 - t) * a0 + t * a1
    d0, d1 = c0 - a0, c1 - a1
    r0, r1 = ca.norm_2(d0), ca.norm_2(d1)
    u0, u1 = d0 / r0, d1 / r1
    if u0.numel() == 2:
        angle = t * ca.atan2(u0[0] * u1[1] - u0[1] * u1[0], ca.dot(u0, u1))
        u = ca.vertcat(ca.cos(angle) * u0[0] - ca.sin(angle) * u0[1], ca.sin(angle) * u0[0] + ca.cos(angle) * u0[1])
    else:
        across = u1 - ca.dot(u0, u1) * u0
        sine = ca.norm_2(across)
        angle = t * ca.atan2(sine, ca.dot(u0, u1))
        u = ca.cos(angle) * u0 + ca.sin(angle) * across / ca.if_else(sine > 0, sine, 1)
    return a + ((1 - t) * r0 + t * r1) * u


def _closed_seed(leg: ca.Function, seed: np.ndarray, x: np.ndarray, design: np.ndarray, where: str) -> np.ndarray:
    """A chain leg's seed closed by Newton at the home pose and the default design, each step halved until
    the residual falls, until it falls no more: closed where it is then below CHAIN_TOLERANCE."""
    q = seed.copy()
    h, H = (np.asarray(v, dtype=float) for v in leg(q, x, design))
    for _ in range(START_STEPS):
        if not np.abs(h).max():
            break
        try:
            step = np.linalg.lstsq(H, h, rcond=None)[0].ravel()
        except np.linalg.LinAlgError:
            break
        for _ in range(START_STEPS):
            trial = q - step
            h_trial, H_trial = (np.asarray(v, dtype=float) for v in leg(trial, x, design))
            if np.abs(h_trial).max() < np.abs(h).max():
                q, h, H = trial, h_trial, H_trial
                break
            step = step / 2
        else:
            break
    if np.abs(h).max() < CHAIN_TOLERANCE:
        return q
    raise DescriptionError(f"description field {where} violates: a seed the leg closes from at the home pose "
                           f"(Newton from it stops at the residual {np.abs(h).max():.1e})")


def composed_inverse_kinematics(description: Description, functions: Mapping[str, ca.Function]) -> ca.Function:
    """``inverse_kinematics(x, mode, design) -> (q, reach)`` of a description with chain legs: the closed-form
    legs' joints from ``continuation_start``; each chain leg's by Newton from its branch's seed (closed at the
    home pose and the default design) along a path of its platform attachment (:func:`_path`: about the base
    attachment, straight where the chain starts with a prismatic joint) to the pose and design asked for, one
    step at each of CONTINUATION_STEPS points, then NEWTON_STEPS there; NaN where it does not close to
    CHAIN_TOLERANCE (so that no value depends on the rounding of iterations that diverge). Its reach: the
    closed-form legs', then per chain leg its closure's Jacobian's determinant in its joints with the sign of
    the seed's (the branch not left; 0 at the leg's singularity, the edge of its reach); the legs' ranges are
    the description's stated limits (:func:`pkm.kinematics.within_limits`), not its reach. The joints are
    differentiable in the pose and the design: at a converged Newton step the derivative is the implicit
    function's."""
    start = functions["continuation_start"]
    d0 = np.array([p["default"] for p in description.data["parameters"]])
    (x0,) = evaluate(functions["home"], d0)
    x0 = x0[0, :, 0]
    n_mode = start.numel_in(1)
    x, mode, d = (ca.SX.sym(start.name_in(i), start.size_in(i)) for i in range(3))
    q_start, reach = start(x, mode, d)
    q = ca.vertsplit(q_start)
    margins = [reach]
    n_act = len(description.data["legs"])
    for k, (_, passive, sign) in enumerate(legs_layout(description)):
        if f"chain{k + 1}" not in functions:
            continue
        columns = [k, *(n_act + p for p in passive)]
        leg, ends = functions[f"chain{k + 1}"], functions[f"chain{k + 1}_ends"]
        a0, c0 = (np.asarray(v, dtype=float).ravel() for v in ends(x0, d0))
        seeds, sides = [], []
        names = [name for name, _ in description.data["legs"][k]["branches"]]
        angles = np.array([kind_of(description.data["legs"][k]).unit == "rad",
                           *passive_angles(description.data["legs"][k])])
        for s in (1.0, -1.0):
            q_s = np.asarray(start(x0, np.full(n_mode, s), d0)[0], dtype=float).ravel()[columns]
            where = f"legs (leg {k + 1}) branches.{names[0 if s > 0 or sign is None else 1]}"
            closed = _closed_seed(leg, q_s, c0, d0, where)
            closed[angles] = np.angle(np.exp(1j * closed[angles]))
            seeds.append(closed)
            sides.append(float(np.sign(np.linalg.det(np.asarray(leg(closed, c0, d0)[1], dtype=float)))))
        weight = 1.0 if sign is None else (1 + mode[sign]) / 2
        q_leg = weight * ca.DM(seeds[0]) + (1 - weight) * ca.DM(seeds[1])
        side = weight * sides[0] + (1 - weight) * sides[1]
        a1, c1 = ends(x, d)
        straight = description.data["legs"][k]["joints"][0]["type"] == "P"
        for t in [*np.linspace(1.0 / CONTINUATION_STEPS, 1.0, CONTINUATION_STEPS), *[1.0] * NEWTON_STEPS]:
            h, H = leg(q_leg, _path(a0, c0, a1, c1, t, straight=straight), d0 + t * (d - d0))
            q_leg = q_leg - ca.solve(H, h)
        h, _ = leg(q_leg, c1, d)
        q_leg = ca.if_else(ca.norm_inf(h) <= CHAIN_TOLERANCE, q_leg, np.nan)
        margins.append(side * ca.det(leg(q_leg, c1, d)[1]))
        for j, c in enumerate(columns):
            q[c] = q_leg[j]
    return ca.Function("inverse_kinematics", [x, mode, d], [ca.vertcat(*q), ca.vertcat(*margins)],
                       start.name_in(), start.name_out())




def composed_inertia(mass_matrix: ca.Function, first_order: ca.Function) -> ca.Function:
    """``inertia(q, x, design) -> (M_t, M_w)``: the mass matrix M of the kinetic energy in (q, x) projected
    onto the actuated rates, M_t = P^T M P with P = d(q, x)/d(q_a) = [Psi; J_f], and onto the pose rates,
    M_w = J^T M_t J (q_dot = J x_dot)."""
    q, x, d = (ca.SX.sym(mass_matrix.name_in(i), mass_matrix.size_in(i)) for i in range(3))
    M = mass_matrix(q, x, d)
    J, J_f, psi, *_ = first_order(q, x, d)
    P = ca.vertcat(psi, J_f)
    M_t = P.T @ M @ P
    return ca.Function("inertia", [q, x, d], [M_t, J.T @ M_t @ J], ["q", "x", "design"], ["M_t", "M_w"])


def composed_energy(mass_matrix: ca.Function, first_order: ca.Function, gravity: ca.Function | None) -> ca.Function:
    """``energy(q, x, x_dot, design) -> (T, V)``: the bodies' kinetic energy z_dot^T M z_dot / 2 at the rates
    z_dot = (q_dot, x_dot) of all the joints (q_dot = Psi J x_dot) and the pose, and their potential energy in
    the description's gravity (0 without)."""
    q, x, d = (ca.SX.sym(mass_matrix.name_in(i), mass_matrix.size_in(i)) for i in range(3))
    x_dot = ca.SX.sym("x_dot", x.numel())
    J, _, psi, *_ = first_order(q, x, d)
    z_dot = ca.vertcat(psi @ (J @ x_dot), x_dot)
    T = 0.5 * z_dot.T @ mass_matrix(q, x, d) @ z_dot
    V = gravity(q, x, d)[1] if gravity is not None else ca.SX(1, 1)
    return ca.Function("energy", [q, x, x_dot, d], [T, V], ["q", "x", "x_dot", "design"], ["T", "V"])


def composed_inverse_dynamics(constraint: ca.Function, mass_matrix: ca.Function, first_order: ca.Function,
                              gravity: ca.Function | None) -> ca.Function:
    """``inverse_dynamics(q, x, x_dot, x_ddot, design) -> tau``: Lagrange's equations of the bodies in all
    coordinates z = (q, x), Q = M z_ddot + M_dot z_dot - (d/dz)(z_dot^T M z_dot) / 2 + dV/dz, projected onto
    the actuated joints by virtual work, tau = P^T Q with P = dz/dq_a = [Psi; J_f] (the loop's constraint
    forces do no work along P). The rates: q_dot = Psi J x_dot; the accelerations from the loop's second
    order, H_q q_ddot + H_x x_ddot + (dH_q/dt) q_dot + (dH_x/dt) x_dot = 0."""
    q, x, d = (ca.SX.sym(constraint.name_in(i), constraint.size_in(i)) for i in range(3))
    x_dot, x_ddot = ca.SX.sym("x_dot", x.numel()), ca.SX.sym("x_ddot", x.numel())
    _, H_q, H_x = constraint(q, x, d)
    J, J_f, psi, *_ = first_order(q, x, d)
    z = ca.vertcat(q, x)
    q_dot = psi @ (J @ x_dot)
    rates = ca.SX.sym("rates", z.numel())
    z_dot = ca.vertcat(q_dot, x_dot)
    bias = ca.substitute(ca.jtimes(H_q @ rates[: q.numel()] + H_x @ rates[q.numel() :], z, rates), rates, z_dot)
    q_ddot = ca.solve(H_q, -(H_x @ x_ddot + bias))
    M = mass_matrix(q, x, d)
    coriolis = ca.jtimes(M @ rates, z, rates) - ca.gradient(0.5 * rates.T @ M @ rates, z)
    Q = M @ ca.vertcat(q_ddot, x_ddot) + ca.substitute(coriolis, rates, z_dot)
    if gravity is not None:
        Q = Q + gravity(q, x, d)[0]
    tau = ca.vertcat(psi, J_f).T @ Q
    return ca.Function("inverse_dynamics", [q, x, x_dot, x_ddot, d], [tau],
                       ["q", "x", "x_dot", "x_ddot", "design"], ["tau"])


