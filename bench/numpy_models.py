"""Hand-written, vectorised numpy baselines of every public batch method of pkm's mechanisms (bench/methods.py).

One class per registered mechanism, one static method per pkm method, each the same mathematics as pkm's
generated graph written directly in numpy over the batch (no Python loop per pose), at the mechanism's
working mode ``signs`` and a design given as a mapping of parameter values. Where a benchmark module already
has the mathematics it is imported: bench/throughput.py (five-bar J and 1/kappa_f), bench/dynamics.py
(five-bar M_w and 1/kappa_2(M_w)), bench/gantry.py (gantry inverse dynamics), bench/passive_leg.py (passive
leg J and 1/kappa_f, real roots by ``numpy.roots``) and bench/ups_pu.py (statics); where such a function
computes a little more than the method returns (J beside 1/kappa_f), the extra is a few vector operations.
The rest is written here from symbolic/mechanisms/<name>.py and docs/papers/*.md.

The forward kinematics of passive_leg and ups_pu is the real roots of a polynomial per pose: its coefficients
are vectorised, its roots come from ``numpy.roots`` one pose at a time (:data:`ROOTS_PER_POSE`), the only
honest hand-written way, and assembly k is the k-th real root in ascending order, as pkm defines it.

The machines described as data (pkm/models/described: rrr3, delta, stewart) take their inverse kinematics,
J and legs' closures from tests/oracles.py (independent of pkm, checked against robsynth), and the Delta's
dynamics is written here from its bodies. Their forward kinematics (:data:`SEEDED`, :class:`Seeded`) starts
from pkm's own seeds: the tries :class:`pkm.kinematics.NearestSeeds` picks in pkm's seed table of the
assembly's signature; each is continued to the actuated joints by Newton's method on the legs' loops
h(z, q) = 0 in z = (passive joints, pose) as the description states them (:func:`continued_newton`),
vectorised over the configurations and the tries, and the solutions of the signature are ordered by the
last pose coordinate, as pkm ranks them.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from bench.dynamics import numpy_pipeline
from bench.gantry import numpy_inverse_dynamics
from bench.passive_leg import numpy_ik_jacobian_index, numpy_real_roots
from bench.throughput import numpy_index
from bench.ups_pu import numpy_ik_jacobian_statics
from pkm.kinematics import CANDIDATES, ROOT_TOLERANCE, NearestSeeds, _nearest, _spread
from tests.oracles import (
    DELTA_ARM_ANGLES,
    delta_closure,
    delta_ik,
    delta_jacobian,
    rrr3_elbows,
    rrr3_ik,
    rrr3_jacobian,
    rrr3_points,
    sgp_closure,
    sgp_ik,
    sgp_jacobian,
)

Design = Mapping[str, float]
Signs = tuple[float, ...]
Loop = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def circle_intersection(a1: np.ndarray, a2: np.ndarray, radius: float, sigma: float) -> np.ndarray:
    """The point (n, 2) at ``radius`` from both centres a1, a2 (n, 2), left of a1 -> a2 for sigma = +1."""
    u = a2 - a1
    dist2 = np.einsum("ni,ni->n", u, u)
    with np.errstate(invalid="ignore"):
        step = sigma * np.sqrt(radius * radius - dist2 / 4) / np.sqrt(dist2)
    return (a1 + a2) / 2 + step[:, None] * np.stack([-u[:, 1], u[:, 0]], axis=1)


def polynomial_product(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Products of polynomials row by row: coefficients (n, a) and (n, b), highest first -> (n, a + b - 1)."""
    out = np.zeros((len(p), p.shape[1] + q.shape[1] - 1))
    for i in range(p.shape[1]):
        out[:, i : i + q.shape[1]] += p[:, i : i + 1] * q
    return out


def inverse_condition_f(J: np.ndarray) -> np.ndarray:
    """1/kappa_f = n / sqrt(||J||^2 ||J^-1||^2) (Frobenius norms; Gao eqs. 8-11) of J (N, n, n): for n = 3
    as n |det J| / sqrt(||J||^2 ||adj J||^2) (the adjugate by cross products of the rows), else J^-1 by
    ``numpy.linalg.inv``."""
    n = J.shape[-1]
    if n != 3:
        inverse = np.linalg.inv(J)
        return n / np.sqrt(np.einsum("nij,nij->n", J, J) * np.einsum("nij,nij->n", inverse, inverse))
    rows = J.transpose(1, 0, 2)
    adjugate = np.stack([np.cross(rows[1], rows[2]), np.cross(rows[2], rows[0]), np.cross(rows[0], rows[1])])
    det = np.einsum("ni,ni->n", rows[0], adjugate[0])
    return 3 * np.abs(det) / np.sqrt(np.einsum("nij,nij->n", J, J) * np.einsum("kni,kni->n", adjugate, adjugate))


STEPS, ITERATIONS, POLISH, STALL = 8, 4, 60, 1e-15  # pkm.kinematics.NearestSeeds's continuation of one try
REPEAT = 1e-7  # two solutions closer than this (relative) are one, as pkm.kinematics.REPEAT_TOLERANCE


def newton_step(loop: Loop, z: np.ndarray, q: np.ndarray) -> np.ndarray:
    """z - (dh/dz)^-1 h(z, q), row by row."""
    h, H = loop(z, q)
    return z - np.linalg.solve(H, h[..., None])[..., 0]


def continued_newton(loop: Loop, q0: np.ndarray, gap: np.ndarray, z: np.ndarray, tolerance: float) -> np.ndarray:
    """The solutions z (N, n_z) of the loop h(z, q) = 0 at the actuated joints q0 + gap, from z at q0: the joints
    moved in STEPS equal steps, each solved by ITERATIONS Newton steps, then up to POLISH more until no row
    moves (relative STALL); NaN where some |h| stays above ``tolerance``."""
    z = z.copy()
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for k in range(1, STEPS):
            for _ in range(ITERATIONS):
                z = newton_step(loop, z, q0 + (k / STEPS) * gap)
        q, active = q0 + gap, np.arange(len(z))
        for _ in range(POLISH):
            moved = newton_step(loop, z[active], q[active])
            change = np.abs(moved - z[active])
            z[active] = moved
            active = active[np.any(change > STALL * (1.0 + np.abs(moved)), axis=1)]
            if not len(active):
                break
        closed = np.all(np.abs(loop(z, q)[0]) <= tolerance, axis=1)
    return np.where(closed[:, None], z, np.nan)


def wrap(angles: np.ndarray) -> np.ndarray:
    """Angles wrapped into [-pi, pi), as pkm gives them."""
    return np.mod(angles + np.pi, 2 * np.pi) - np.pi


class Seeded:
    """A described machine's forward kinematics in numpy (module docstring): its loop h(z, q) = 0 in z =
    (passive joints, pose), as pkm's description states it (symbolic/described), ``n_out`` pose
    coordinates, ``periodic`` whether the actuated joints are angles, ``angles`` the angles of z (wrapped into
    [-pi, pi) as pkm gives them), ``unknowns`` the last columns of pkm's z that its loop solves for where it
    eliminates passive joints that pkm keeps (None: all of them)."""

    n_out: int = 3
    periodic: bool = True
    angles: tuple[int, ...] = ()
    unknowns: int | None = None

    @staticmethod
    def loop(z: np.ndarray, q: np.ndarray, d: Design) -> tuple[np.ndarray, np.ndarray]:
        """h (N, n_z) and dh/dz (N, n_z, n_z)."""
        raise NotImplementedError

    @classmethod
    def signature(cls, z: np.ndarray, q: np.ndarray, d: Design) -> np.ndarray:
        """The signs (N, k) that tell the assembly modes apart (pkm.spec.Seeds.signature): here sign det dh/dz."""
        return np.sign(np.linalg.det(cls.loop(z, q, d)[1]))[:, None]

    @classmethod
    def forward_kinematics(cls, q: np.ndarray, d: Design, seeds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
        """Poses (N, n) at the actuated joints q (N, n_act): the first by the last pose coordinate of the
        solutions of one signature from pkm's tries among ``seeds``, the actuated joints (M, n_act) and z (M,
        n_z) of pkm's seed table of the signature, as :class:`pkm.kinematics.NearestSeeds` chooses them; each
        try continued by :func:`continued_newton`, kept where it closes (pkm's ROOT_TOLERANCE) with the
        signature of its seed, repeats dropped."""
        q0, z0 = seeds
        z0 = z0 if cls.unknowns is None else z0[:, -cls.unknowns:]
        tries = min(NearestSeeds.tries, len(q0))
        order, gap = _nearest(q, q0, np.full(q.shape[1], cls.periodic), min(CANDIDATES * tries, len(q0)))
        order, gap = _spread(z0, order, gap, tries)
        start, gap = q0[order].reshape(-1, q.shape[1]), gap.reshape(-1, q.shape[1])
        first = z0[order].reshape(-1, z0.shape[1])
        tolerance = ROOT_TOLERANCE * max(1.0, *map(abs, d.values()))
        z = continued_newton(lambda z, q: cls.loop(z, q, d), start, gap, first, tolerance)
        with np.errstate(invalid="ignore"):
            same = np.all(cls.signature(z, start + gap, d) == cls.signature(first, start, d), axis=1)
        z = np.where(same[:, None], z, np.nan).reshape(len(q), tries, -1)
        z[..., cls.angles] = wrap(z[..., cls.angles])
        between = np.abs(z[:, :, None, :] - z[:, None, :, :])
        between[..., cls.angles] = np.minimum(between[..., cls.angles], 2 * np.pi - between[..., cls.angles])
        with np.errstate(invalid="ignore"):
            repeats = np.any(np.tril(np.all(between <= REPEAT * (1.0 + np.abs(z[:, None])), axis=3), k=-1), axis=2)
        last = np.where(np.isnan(z[..., -1]) | repeats, np.inf, z[..., -1])
        pick, rows = np.argmin(last, axis=1), np.arange(len(q))
        return np.where(np.isinf(last[rows, pick])[:, None], np.nan, z[rows, pick, -cls.n_out :])


def kth_real_root(c: np.ndarray, k: int, scale: float = 1.0) -> np.ndarray:
    """The k-th real root (n,) in ascending order of each row of c (highest degree first), NaN where there are
    fewer, by ``numpy.roots`` per row in the variable root / scale (as pkm's ``PolynomialRoots`` scales it)."""
    c = c * scale ** np.arange(c.shape[1] - 1, -1, -1)
    return scale * numpy_real_roots(c)[:, int(k)]


class FiveBar:
    """The symmetric 5R (Gao 1998; Lara-Molina 2016): O_i = (-+r3, 0), proximal r1, distal r2, P = (x, y)."""

    dynamic_index = "dynamic_dexterity"

    @staticmethod
    def angles(X: np.ndarray, d: Design, signs: Signs, *, distal: bool = True) -> list[tuple[np.ndarray, ...]]:
        """theta_i (and phi_i) of each chain: theta = atan2(y, x - ox) + sigma acos((r1^2 + rho^2 - r2^2) /
        (2 r1 rho)), phi the direction of the distal link."""
        r1, r2, r3 = d["r1"], d["r2"], d["r3"]
        x, y = X[:, 0], X[:, 1]
        out = []
        for ox, sigma in ((-r3, signs[0]), (r3, signs[1])):
            dx = x - ox
            rho2 = dx * dx + y * y
            theta = np.arctan2(y, dx) + sigma * np.arccos((r1 * r1 + rho2 - r2 * r2) / (2 * r1 * np.sqrt(rho2)))
            out.append((theta, np.arctan2(y - r1 * np.sin(theta), dx - r1 * np.cos(theta))) if distal else (theta,))
        return out

    @staticmethod
    def inverse_kinematics(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return np.stack([a[0] for a in FiveBar.angles(X, d, signs, distal=False)], axis=1)

    @staticmethod
    def forward_kinematics(q: np.ndarray, d: Design, sigma: float) -> np.ndarray:
        """P = the intersection of the circles of radius r2 about the elbows O_i + r1 e(theta_i)."""
        r1, r3 = d["r1"], d["r3"]
        a1 = np.stack([-r3 + r1 * np.cos(q[:, 0]), r1 * np.sin(q[:, 0])], axis=1)
        a2 = np.stack([r3 + r1 * np.cos(q[:, 1]), r1 * np.sin(q[:, 1])], axis=1)
        return circle_intersection(a1, a2, d["r2"], sigma)

    @staticmethod
    def jacobian(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_index(X, d, signs)[0]

    @staticmethod
    def inverse_condition_f(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_index(X, d, signs)[1]

    @staticmethod
    def dynamic(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_pipeline(X, d, signs)[2]

    @staticmethod
    def inertia_task(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_pipeline(X, d, signs)[1]

    @staticmethod
    def inverse_dynamics(X: np.ndarray, V: np.ndarray, A: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """Motor torques (n, 2) with rigid transmissions (pkm.dynamics.rigid.inverse_dynamics).

        Chain i in (theta, phi): the loop P = O + r1 e(theta) + r2 e(phi) differentiated once and twice gives
        theta_dot = e(phi).x_dot / (r1 S), phi_dot = -e(theta).x_dot / (r2 S), S = sin(phi - theta), and the
        accelerations from x_ddot + r1 theta_dot^2 e(theta) + r2 phi_dot^2 e(phi) alike. Lagrange on the chain's
        T = alpha theta_dot^2 / 2 + gamma cos(theta - phi) theta_dot phi_dot + beta phi_dot^2 / 2 (Lara-Molina
        eqs. 19-21) gives Q_theta, Q_phi; virtual work J^T tau_a = sum_i (Q_theta dtheta/dx + Q_phi dphi/dx)
        (eqs. 24-29); tau_m = tau_a + j theta_ddot + (fv + vm) theta_dot + fc sign(theta_dot) (eqs. 22-23).
        """
        r1, r2 = d["r1"], d["r2"]
        alpha = d["m1"] * r1 * r1 * (d["g1"] + d["c1"] ** 2) + d["m2"] * r1 * r1
        beta = d["m2"] * r2 * r2 * (d["g2"] + d["c2"] ** 2)
        gamma = d["m2"] * r1 * d["c2"] * r2
        force = np.zeros_like(X)
        rows, rates, accelerations = [], [], []
        for theta, phi in FiveBar.angles(X, d, signs):
            e_theta = np.stack([np.cos(theta), np.sin(theta)], axis=1)
            e_phi = np.stack([np.cos(phi), np.sin(phi)], axis=1)
            S = e_theta[:, 0] * e_phi[:, 1] - e_theta[:, 1] * e_phi[:, 0]
            d_theta, d_phi = e_phi / (r1 * S)[:, None], -e_theta / (r2 * S)[:, None]  # d(theta, phi)/dx
            theta_dot, phi_dot = np.einsum("ni,ni->n", d_theta, V), np.einsum("ni,ni->n", d_phi, V)
            bias = A + (r1 * theta_dot**2)[:, None] * e_theta + (r2 * phi_dot**2)[:, None] * e_phi
            theta_ddot, phi_ddot = np.einsum("ni,ni->n", d_theta, bias), np.einsum("ni,ni->n", d_phi, bias)
            cos = np.einsum("ni,ni->n", e_theta, e_phi)
            Q_theta = alpha * theta_ddot + gamma * (cos * phi_ddot - S * phi_dot**2)
            Q_phi = gamma * (cos * theta_ddot + S * theta_dot**2) + beta * phi_ddot
            force += Q_theta[:, None] * d_theta + Q_phi[:, None] * d_phi
            rows.append(d_theta)
            rates.append(theta_dot)
            accelerations.append(theta_ddot)
        (a, b), (c, e) = rows[0].T, rows[1].T
        det = a * e - b * c
        tau = np.stack([(e * force[:, 0] - c * force[:, 1]) / det, (a * force[:, 1] - b * force[:, 0]) / det], 1)
        rate, acceleration = np.stack(rates, axis=1), np.stack(accelerations, axis=1)
        return (tau + np.array([d["j1"], d["j2"]]) * acceleration + (d["fv"] + d["vm"]) * rate
                + d["fc"] * np.sign(rate))


class PassiveLeg:
    """Nam 2006: base revolutes B_i = (+-R, 0), links l_a, l_b, platform C +- r u(theta), theta = atan2(-x_c, y_c)."""

    dynamic_index = None

    @staticmethod
    def inverse_kinematics(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """phi_i of eq. 6 in the atan2 form of symbolic/mechanisms/passive_leg.py (the first loop of
        bench.passive_leg.numpy_ik_jacobian_index, without J)."""
        R, r, la, lb = d["R"], d["r"], d["l_a"], d["l_b"]
        xc, yc = x[:, 0], x[:, 1]
        norm = np.sqrt(xc * xc + yc * yc)
        c, s = yc / norm, -xc / norm  # cos and sin of theta = atan2(-x_c, y_c)
        phis = []
        for side, sign in ((1.0, signs[0]), (-1.0, signs[1])):
            alpha, beta = 2 * la * (xc + side * (r * c - R)), 2 * la * (yc + side * r * s)
            gamma = -(alpha**2 + beta**2) / (4 * la**2) + lb**2 - la**2
            root = np.sqrt(alpha**2 + beta**2 - gamma**2)
            phis.append(np.arctan2(-beta * gamma - sign * alpha * root, -alpha * gamma + sign * beta * root))
        return np.stack(phis, axis=1)

    @staticmethod
    def eq8(q: np.ndarray, d: Design) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(A_i, B_i, C_i) of eq. 8 as polynomials in l_c (coefficients (n, k), highest first)."""
        R, r, la, lb = d["R"], d["r"], d["l_a"], d["l_b"]
        out = []
        for phi, side in ((q[:, 0], 1.0), (q[:, 1], -1.0)):
            c, s = np.cos(phi), np.sin(phi)
            ones, zeros = np.ones_like(c), np.zeros_like(c)
            A = np.stack([ones, zeros, r * r + R * R + la * la - lb * lb + side * 2 * la * R * c], axis=1)
            B = np.stack([la * s, R * r + side * la * r * c], axis=1)
            C = np.stack([side * R + la * c, -side * la * r * s], axis=1)
            out.append((A, B, C))
        return out

    @staticmethod
    def forward_kinematics(q: np.ndarray, d: Design, k: int) -> np.ndarray:
        """Root k of (A1 B2 - A2 B1)^2 + (A2 C1 - A1 C2)^2 - 4 (B2 C1 - B1 C2)^2 (eq. 11 as derived, degree 6
        in l_c, solved in l_c / (l_a + l_b)); theta from the linear pair of eq. 8; C = l_c (-sin, cos)."""
        (A1, B1, C1), (A2, B2, C2) = PassiveLeg.eq8(q, d)
        mul = polynomial_product
        sine, cosine, det = mul(A1, B2) - mul(A2, B1), mul(A2, C1) - mul(A1, C2), mul(B2, C1) - mul(B1, C2)
        c = mul(sine, sine) + mul(cosine, cosine)
        c[:, 2:] -= 4 * mul(det, det)
        l_c = kth_real_root(c, k, d["l_a"] + d["l_b"])
        at = [np.polyval(p.T, l_c) for p in (sine, cosine, det)]
        theta = np.arctan2(-at[0] * np.sign(at[2]), at[1] * np.sign(at[2]))
        return l_c[:, None] * np.stack([-np.sin(theta), np.cos(theta)], axis=1)

    @staticmethod
    def jacobian(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_ik_jacobian_index(x, d, signs)[1]

    @staticmethod
    def inverse_condition_f(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return numpy_ik_jacobian_index(x, d, signs)[2]


class SliderGantry:
    """Wu 2008: link vectors A_i - B_i = (u_i, w_i), u_i = x +- d1, w_i = sigma_i sqrt(l^2 - u_i^2); J's row i
    is (tan(theta_i), 1) = (u_i / w_i, 1); sliders, counterweights and the links at B_i (mode ``below``)."""

    dynamic_index = "kappa_d"
    links = ((("m12", "I12", "s12"), ("m4", "I4", "s4")), (("m22", "I22", "s22"),))

    @staticmethod
    def tangents(X: np.ndarray, d: Design, signs: Signs) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """(u_i, w_i, tan(theta_i)) of both chains."""
        out = []
        for offset, sigma in ((d["d1"], signs[0]), (-d["d1"], signs[1])):
            u = X[:, 0] + offset
            w = sigma * np.sqrt(d["l"] ** 2 - u * u)
            out.append((u, w, u / w))
        return out

    @classmethod
    def inverse_kinematics(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """q_i = y - l2/2 - w_i (eq. 2)."""
        return np.stack([X[:, 1] - d["l2"] / 2 - w for _, w, _ in cls.tangents(X, d, signs)], axis=1)

    @staticmethod
    def forward_kinematics(q: np.ndarray, d: Design, sigma: float) -> np.ndarray:
        """O' = the intersection of the circles of radius l about (-+d1, q_i + l2/2)."""
        ones = np.ones(len(q))
        a1 = np.stack([-d["d1"] * ones, q[:, 0] + d["l2"] / 2], axis=1)
        a2 = np.stack([d["d1"] * ones, q[:, 1] + d["l2"] / 2], axis=1)
        return circle_intersection(a1, a2, d["l"], sigma)

    @classmethod
    def jacobian(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        J = np.ones((len(X), 2, 2))
        (_, _, J[:, 0, 0]), (_, _, J[:, 1, 0]) = cls.tangents(X, d, signs)
        return J

    @classmethod
    def inverse_condition_f(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """2 |t1 - t2| / (t1^2 + t2^2 + 2)."""
        (_, _, t1), (_, _, t2) = cls.tangents(X, d, signs)
        return 2 * np.abs(t1 - t2) / (t1 * t1 + t2 * t2 + 2)

    @classmethod
    def inertia_task(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """M of eq. 41 (the parts of bench.gantry.numpy_inverse_dynamics linear in x_ddot): per chain the mass
        m_i moving with the slider (slider, counterweight, links), the links' first moments S_i and inertias I_i
        about B_i; M = mN I + sum_i [[m_i t^2 - 2 S_i t^2 / l + I_i / w^2, t (m_i - S_i / l)], [., m_i]]."""
        M = np.zeros((len(X), 2, 2))
        M[:, 0, 0] = M[:, 1, 1] = d["mN"]
        for i, (_, w, t) in enumerate(cls.tangents(X, d, signs)):
            mass = d[f"m{i + 1}1"] + d[f"m{i + 1}3"] + sum(d[m] for m, _, _ in cls.links[i])
            first = sum(d[m] * d[s] for m, _, s in cls.links[i]) / d["l"]
            inertia = sum(d[j] for _, j, _ in cls.links[i])
            M[:, 0, 0] += (mass - 2 * first) * t * t + inertia / (w * w)
            M[:, 0, 1] += t * (mass - first)
            M[:, 1, 1] += mass
        M[:, 1, 0] = M[:, 0, 1]
        return M

    @classmethod
    def dynamic(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """kappa_D = sigma_max / sigma_min = sigma_max^2 / |det| of M_d = (J^T)^-1 M (Wu eqs. 42-43)."""
        M = cls.inertia_task(X, d, signs)
        (_, _, t1), (_, _, t2) = cls.tangents(X, d, signs)
        inverse = np.stack([np.ones_like(t1), -t2, -np.ones_like(t1), t1], axis=1).reshape(-1, 2, 2)
        M_d = inverse @ M / (t1 - t2)[:, None, None]
        frob2 = np.einsum("nij,nij->n", M_d, M_d)
        det = np.abs(M_d[:, 0, 0] * M_d[:, 1, 1] - M_d[:, 0, 1] * M_d[:, 1, 0])
        return (frob2 + np.sqrt(np.maximum(frob2 * frob2 - 4 * det * det, 0))) / (2 * det)

    @staticmethod
    def inverse_dynamics(X: np.ndarray, V: np.ndarray, A: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        if tuple(signs) != (1.0, 1.0):
            raise ValueError("bench.gantry.numpy_inverse_dynamics is written for mode below only")
        return numpy_inverse_dynamics(X, V, A, d)


class SliderGantrySymmetric(SliderGantry):
    """Wu section 6.3: link A4B4 (m5, I5, s5) beside A2B2 at the same angle."""

    links = (SliderGantry.links[0], (*SliderGantry.links[1], ("m5", "I5", "s5")))

    @staticmethod
    def inverse_dynamics(X: np.ndarray, V: np.ndarray, A: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """bench.gantry's inverse dynamics with links A2B2 and A4B4 lumped into one: at the same angle and
        pivot height (up to the constant l2) their terms add, with summed mass, inertia and first moment."""
        mass = d["m22"] + d["m5"]
        lumped = {**d, "m22": mass, "I22": d["I22"] + d["I5"], "s22": (d["m22"] * d["s22"] + d["m5"] * d["s5"]) / mass}
        return SliderGantry.inverse_dynamics(X, V, A, lumped, signs)


class UpsPu:
    """Zhao 2008: |T S_i - U_i|^2 = r^2 + R^2 + l0^2 + 2 l0 s_z - 2 U_i . s with s = Rx(theta1) Ry(theta2)
    r (cos a_i, sin a_i, 0), U_i = R (cos a_i, sin a_i, 0), a_1 = alpha, a_2 = beta."""

    dynamic_index = None

    @staticmethod
    def squared_lengths(x: np.ndarray, d: Design) -> list[tuple[np.ndarray, np.ndarray]]:
        """|T S_i - U_i|^2 of both UPS legs and its gradient (n, 3) in (l0, theta1, theta2)."""
        r, R = d["r"], d["R"]
        l0, t1, t2 = x.T
        c1, s1, c2, s2 = np.cos(t1), np.sin(t1), np.cos(t2), np.sin(t2)
        out = []
        for a in (d["alpha"], d["beta"]):
            ca, sa = np.cos(a), np.sin(a)
            s_z = r * (s1 * sa - c1 * s2 * ca)
            U_dot_s = R * r * (c2 * ca * ca + sa * (c1 * sa + s1 * s2 * ca))
            squared = r * r + R * R + l0 * l0 + 2 * l0 * s_z - 2 * U_dot_s
            grad = np.stack([
                2 * l0 + 2 * s_z,
                2 * l0 * r * (c1 * sa + s1 * s2 * ca) - 2 * R * r * sa * (c1 * s2 * ca - s1 * sa),
                -2 * l0 * r * c1 * c2 * ca - 2 * R * r * ca * (s1 * sa * c2 - s2 * ca),
            ], axis=1)
            out.append((squared, grad))
        return out

    @staticmethod
    def inverse_kinematics(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        del signs  # one solution per pose
        (sq1, _), (sq2, _) = UpsPu.squared_lengths(x, d)
        return np.stack([np.sqrt(sq1), np.sqrt(sq2), x[:, 0]], axis=1)

    @staticmethod
    def jacobian(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """J = dq/dx: row i of a UPS leg d|.|^2/dx / (2 l_i), row 3 (1, 0, 0) (eq. 7, columns in x's order)."""
        del signs
        J = np.zeros((len(x), 3, 3))
        for i, (squared, grad) in enumerate(UpsPu.squared_lengths(x, d)):
            J[:, i] = grad / (2 * np.sqrt(squared))[:, None]
        J[:, 2, 0] = 1.0
        return J

    @staticmethod
    def inverse_condition_f(x: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """1/kappa_f of J_n = J diag(1, 1/r, 1/r), the angles as arc lengths r theta (pkm.regions.pipeline)."""
        return inverse_condition_f(UpsPu.jacobian(x, d, signs) / np.array([1.0, d["r"], d["r"]]))

    @staticmethod
    def statics(x: np.ndarray, wrench: np.ndarray, d: Design) -> np.ndarray:
        return numpy_ik_jacobian_statics(x, wrench, d)[2]

    @staticmethod
    def linear_pairs(q: np.ndarray, d: Design) -> list[tuple[np.ndarray, ...]]:
        """(a_i, b_i, c_i) with a cos(theta1) + b sin(theta1) = c, each as (k0, kc, ks): k0 + kc cos(theta2)
        + ks sin(theta2), at l0 = q_3 (symbolic/mechanisms/ups_pu.py ``forward_polynomial``)."""
        r, R, l0 = d["r"], d["R"], q[:, 2]
        zero = np.zeros_like(l0)
        out = []
        for a, length in ((d["alpha"], q[:, 0]), (d["beta"], q[:, 1])):
            ca, sa = np.cos(a), np.sin(a)
            out.append((
                (zero - 2 * R * r * sa * sa, zero, -2 * l0 * r * ca),
                (2 * l0 * r * sa, zero, zero - 2 * R * r * sa * ca),
                (length * length - r * r - R * R - l0 * l0, zero + 2 * R * r * ca * ca, zero),
            ))
        return out

    @staticmethod
    def forward_kinematics(q: np.ndarray, d: Design, k: int) -> np.ndarray:
        """Root k of (C1 B2 - C2 B1)^2 + (A1 C2 - A2 C1)^2 - (A1 B2 - A2 B1)^2 in t = tan(theta2 / 2) (degree 8;
        A_i = a_i (1 + t^2) a quadratic in t); theta1 from the linear pair at theta2 = 2 atan(t)."""
        pairs = UpsPu.linear_pairs(q, d)
        (A1, B1, C1), (A2, B2, C2) = ([np.stack([k0 - kc, 2 * ks, k0 + kc], axis=1) for k0, kc, ks in leg]
                                      for leg in pairs)
        mul = polynomial_product
        det, cos1, sin1 = mul(A1, B2) - mul(A2, B1), mul(C1, B2) - mul(C2, B1), mul(A1, C2) - mul(A2, C1)
        t = kth_real_root(mul(cos1, cos1) + mul(sin1, sin1) - mul(det, det), k)
        theta2 = 2 * np.arctan(t)
        c2, s2 = np.cos(theta2), np.sin(theta2)
        (a1, b1, e1), (a2, b2, e2) = ([k0 + kc * c2 + ks * s2 for k0, kc, ks in leg] for leg in pairs)
        sign = np.sign(a1 * b2 - a2 * b1)
        theta1 = np.arctan2((a1 * e2 - a2 * e1) * sign, (e1 * b2 - e2 * b1) * sign)
        return np.stack([q[:, 2], theta1, theta2], axis=1)


class Rrr3(Seeded):
    """The symmetric planar 3-RRR (pkm/models/described/rrr3.toml): the working mode's signs are the oracle's
    elbow signs; the characteristic length is r_p."""

    dynamic_index = None
    angles = (0, 1, 2, 5)  # the distal links' angles and phi

    @staticmethod
    def inverse_kinematics(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return rrr3_ik(X, d, signs)

    @staticmethod
    def jacobian(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return rrr3_jacobian(X, d, signs)

    @staticmethod
    def inverse_condition_f(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """1/kappa_f of J_n = J diag(1, 1, 1/r_p): phi as the arc length r_p phi (pkm.regions.pipeline)."""
        return inverse_condition_f(rrr3_jacobian(X, d, signs) / np.array([1.0, 1.0, d["r_p"]]))

    @staticmethod
    def loop(z: np.ndarray, q: np.ndarray, d: Design) -> tuple[np.ndarray, np.ndarray]:
        """B_i + l2 e(phi_i) - C_i = 0 (two rows per leg) in z = (phi_1, phi_2, phi_3, x, y, phi), phi_i the
        distal links' angles: d/dphi_i = l2 e'(phi_i), d/d(x, y) = -I, d/dphi = -r_p e'(phi + a_i)."""
        n, phi, x = len(z), z[:, :3], z[:, 3:]
        _, C, rho = rrr3_points(x, d)
        h = rrr3_elbows(x, d, q) + d["l2"] * np.stack([np.cos(phi), np.sin(phi)], axis=-1) - C
        H = np.zeros((n, 3, 2, 6))
        legs = np.arange(3)
        H[:, legs, :, legs] = d["l2"] * np.stack([-np.sin(phi), np.cos(phi)], axis=-1).transpose(1, 0, 2)
        H[:, :, 0, 3] = H[:, :, 1, 4] = -1.0
        H[:, :, :, 5] = np.stack([rho[..., 1], -rho[..., 0]], axis=-1)
        return h.reshape(n, 6), H.reshape(n, 6, 6)

    @classmethod
    def signature(cls, z: np.ndarray, q: np.ndarray, d: Design) -> np.ndarray:
        """The elbow sides sin(phi_i - theta_i) and sign det dh/dz (pkm.spec.Seeds.signature)."""
        return np.hstack([np.sign(np.sin(z[:, :3] - q)), super().signature(z, q, d)])


class Delta(Seeded):
    """The Delta robot (pkm/models/described/delta.toml): the oracle's branch is minus the working mode's signs
    (its elbow_out, signs -1, is the oracle's branch +1); one unit in the pose, no characteristic length.

    Its bodies: per arm a rotor j_m, the arm a uniform bar (m_a at L_a/2, m_a L_a^2 / 12 about it) and half
    the rods' mass m_b at its tip, about the arm's axis I_a = j_m + m_a L_a^2 / 3 + m_b L_a^2 / 2; the
    platform m_p and the other halves of the rods, m_x = m_p + 3 m_b / 2, translating. The kinetic energy is
    (I_a |theta_dot|^2 + m_x |x_dot|^2) / 2, with constant coefficients (no Coriolis terms); gravity g along
    -z: V = g (m_x z - (m_a + m_b) L_a / 2 sum_i sin theta_i).
    """

    dynamic_index = "dynamic_dexterity"
    unknowns = 3  # the pose: its loop eliminates the parallelograms' angles
    GRAVITY = 9.81  # [m/s^2] delta.toml's gravity (0, 0, -9.81)

    @staticmethod
    def inertias(d: Design) -> tuple[float, float]:
        """I_a [kg m^2] and m_x [kg] (class docstring)."""
        arm = d["j_m"] + d["m_a"] * d["L_a"] ** 2 / 3 + d["m_b"] * d["L_a"] ** 2 / 2
        return arm, d["m_p"] + 3 * d["m_b"] / 2

    @classmethod
    def inertia_task(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """M_w = J^T M_t J = I_a J^T J + m_x I: M_t = I_a I + m_x J_f^T J_f (pkm.spec.composed_inertia)."""
        J = cls.jacobian(X, d, signs)
        arm, moving = cls.inertias(d)
        return arm * np.einsum("nki,nkj->nij", J, J) + moving * np.eye(3)

    @classmethod
    def dynamic(cls, X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """lambda_min / lambda_max of M_w, by ``numpy.linalg.eigvalsh``."""
        eigenvalues = np.linalg.eigvalsh(cls.inertia_task(X, d, signs))
        return eigenvalues[:, 0] / eigenvalues[:, -1]

    @classmethod
    def inverse_dynamics(cls, X: np.ndarray, V: np.ndarray, A: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """tau = I_a theta_ddot + dV/dtheta + J^-T (m_x x_ddot + dV/dx) (virtual work; Lagrange with constant
        coefficients). With w = P_i - E_i, E' and E'' the derivatives of the elbow in theta_i, the arm's
        closure differentiated twice: theta_ddot_i = (w . x_ddot + |x_dot - E' theta_dot_i|^2 - w . E''
        theta_dot_i^2) / (w . E'), theta_dot = J x_dot."""
        theta = delta_ik(X, d, -np.asarray(signs))
        _, H_x, H_q = delta_closure(X, d, theta)
        w, transmission, J = H_x / 2, -H_q / 2, -H_x / H_q[..., None]  # transmission = w . E'
        psi = DELTA_ARM_ANGLES
        radial = np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
        c, s = np.cos(theta)[..., None], np.sin(theta)[..., None]
        dE = -d["L_a"] * (s * radial + c * np.array([0.0, 0.0, 1.0]))
        ddE = -d["L_a"] * (c * radial - s * np.array([0.0, 0.0, 1.0]))
        rate = np.einsum("nij,nj->ni", J, V)
        relative = V[:, None, :] - dE * rate[..., None]
        acceleration = (np.einsum("nij,nj->ni", w, A) + np.einsum("nij,nij->ni", relative, relative)
                        - np.einsum("nij,nij->ni", w, ddE) * rate**2) / transmission
        arm, moving = cls.inertias(d)
        force = moving * (A + np.array([0.0, 0.0, cls.GRAVITY]))
        weight = -cls.GRAVITY * (d["m_a"] + d["m_b"]) * d["L_a"] / 2 * np.cos(theta)
        return arm * acceleration + weight + np.linalg.solve(J.transpose(0, 2, 1), force[..., None])[..., 0]

    @staticmethod
    def inverse_kinematics(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return delta_ik(X, d, -np.asarray(signs))

    @staticmethod
    def jacobian(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return delta_jacobian(X, d, -np.asarray(signs))

    @staticmethod
    def inverse_condition_f(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        return inverse_condition_f(delta_jacobian(X, d, -np.asarray(signs)))

    @staticmethod
    def loop(z: np.ndarray, q: np.ndarray, d: Design) -> tuple[np.ndarray, np.ndarray]:
        """The arms' closures |P_i - E_i|^2 - L_b^2 (z the pose: no passive joints)."""
        return delta_closure(z, d, q)[:2]


class Stewart(Seeded):
    """The 6-UPS Stewart-Gough platform (pkm/models/described/stewart.toml): one working mode; the
    characteristic length is r_p."""

    dynamic_index = None
    n_out = 6
    periodic = False
    angles = (3, 4, 5)

    @staticmethod
    def inverse_kinematics(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        del signs  # one solution per pose
        return sgp_ik(X, d)

    @staticmethod
    def jacobian(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        del signs
        return sgp_jacobian(X, d)

    @staticmethod
    def inverse_condition_f(X: np.ndarray, d: Design, signs: Signs) -> np.ndarray:
        """1/kappa_f of J_n = J diag(1, 1, 1, 1/r_p, 1/r_p, 1/r_p), the angles as arc lengths r_p theta."""
        del signs
        return inverse_condition_f(sgp_jacobian(X, d) / np.array([1.0, 1.0, 1.0, *3 * [d["r_p"]]]))

    @staticmethod
    def loop(z: np.ndarray, q: np.ndarray, d: Design) -> tuple[np.ndarray, np.ndarray]:
        """The legs' closures |s_k|^2 - l_k^2 (z the pose: no passive joints)."""
        return sgp_closure(z, d, q)[:2]


MODELS: dict[str, type] = {
    "five_bar": FiveBar,
    "passive_leg": PassiveLeg,
    "slider_gantry": SliderGantry,
    "slider_gantry_symmetric": SliderGantrySymmetric,
    "ups_pu": UpsPu,
    "rrr3": Rrr3,
    "delta": Delta,
    "stewart": Stewart,
}
ROOTS_PER_POSE = frozenset({"passive_leg", "ups_pu"})
SEEDED = frozenset({"rrr3", "delta", "stewart"})  # forward kinematics by Newton's method from pkm's seeds
