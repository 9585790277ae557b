"""Every real assembly of a mechanism at its actuated joints, none lost to naming: the complete forward
kinematics (issue 39).

A planar machine whose every leg, its actuated joint given, puts its platform joint on a circle (an RR's elbow
with its distal link, an RPR's base joint with its length, a PRR's slider with its link, a two-joint chain whose
passive joint is a revolute: about it) or on a line (a two-joint chain whose passive joint is a prismatic: the line
it slides along) assembles where the platform's joints P_i = P + R(phi) c_i (``platform_points``, c_i in its frame)
lie on those curves (the derived ``platform_loci``, :class:`Loci`):

    g_i(x, y, phi) = alpha_i |P_i|^2 + beta_i . P_i + gamma_i = 0,   P = (x, y),

alpha_i 1 for a circle (beta_i = -2 B_i, gamma_i = |B_i|^2 - r_i^2) and 0 for a line (beta_i its unit normal).

In the plane (three legs, a circle first where there is one), g_2 - alpha_2 g_1 and g_3 - alpha_3 g_1 are linear in
P: P = N(phi) / D(phi) by Cramer's rule, and g_1 at that P, times D^2 (times D for three lines, D then constant),
is a trigonometric polynomial f of degree 3 in phi (Gosselin, Sefrioui and Richard 1994, the 3-RPR's sextic;
lines leave the degree at 3 or lower). It is found exactly from 8 samples (a discrete Fourier transform: its
harmonics above the third vanish) and turned into the real sextic (1 + t^2)^3 f in t = tan(phi / 2)
(:data:`HALF_ANGLE`), whose real roots (the real companion matrices' eigenvalues, batched, the rows in blocks on
:data:`pkm.batch.THREADS` threads) are the real platform angles; phi = pi, where the sextic's degree drops, is
tried where it does. Each is taken back to P, polished by Newton's method on the three g_i and kept where it closes
them; at most 6. With a point pose in the plane (two legs), P is where two of the curves meet: at most 2; with a
point pose in space whose legs each put it on a sphere (an R_parallelogram's elbow with its rods, a UPS's base joint
with its length, a two-joint chain of those shapes: the derived ``platform_circles``), where three spheres meet: at
most 2. With a pose of six coordinates and six such legs (each a sphere about the base), the real ends of a
parameter homotopy's 40 paths (:mod:`pkm.homotopy`): at most 40, a path that did not arrive reported in
``failed``.

With ``certify``, each count is checked against a certified one (:func:`real_roots`): the sextic in t = tan(phi /
2), (1 + t^2)^3 f, in exact rational arithmetic from the inputs as the exact numbers they are (its values at seven
integer t, interpolated), its real roots isolated by python-flint (a real root's imaginary part exactly 0); a row
with a multiple real root (two assemblies meeting at a singularity) is not certified.

A mechanism with a closed form or a univariate polynomial of its own (:class:`pkm.kinematics.ClosedForm`,
:class:`pkm.kinematics.PolynomialRoots`) has every assembly among its named ones; the others (seeded Newton
continuation) are refused by name.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any, NamedTuple

import numpy as np

from pkm import batch, homotopy
from pkm.batch import evaluate
from pkm.errors import PkmError
from pkm.kinematics import ClosedForm, PolynomialRoots, as_batch

SAMPLES = 8  # samples of the degree-3 trigonometric polynomial (its harmonics 0 to 3, and 4 to check)
ON_CIRCLE = 1e-6  # a root t of the sextic whose imaginary part is this small (relative) is a real angle
NEWTON_STEPS = 2  # polishing steps on the circles' equations (from the sextic's roots, quadratic at once)
BLOCK_ROWS = 4096  # rows per thread at least
CLOSURE = 1e-9  # [m] a polished assembly closes every circle to this, relative to the machine's size
SAME = 1e-7  # two assemblies this close (pose, relative to the machine's size; angle in rad) are one
PARALLEL = 1e-6  # the sine of the angle below which the two lines of the circles' differences are parallel


@dataclass(frozen=True)
class Assemblies:
    """Every real assembly at each of N sets of actuated joints: ``poses`` (N, S, n_out), NaN beyond each
    row's ``counts`` (followed along a path, NaN where a column's assembly does not exist); ``residuals`` (N,
    S) the largest closure error of each [m]; ``bound`` the most there can be (the polynomial's degree, the
    homotopy's paths); ``failed`` (N,) the candidates that did not give an assembly (reported, not dropped), as
    ``failures`` says; ``method`` how they were found."""

    poses: np.ndarray
    residuals: np.ndarray
    counts: np.ndarray
    bound: int
    failed: np.ndarray
    method: str
    certified: np.ndarray | None = None  # (N,) whether the count equals the certified count (with ``certify``)
    failures: str = "real roots did not close"


def every_assembly(mech: Any, q_a: Any, design: Any = None, *, certify: bool = False, follow: bool = False,
                   designs: Any = None) -> Assemblies:
    """Every real assembly of ``mech`` at the actuated joints ``q_a`` (n_act,) or (N, n_act); with ``certify``
    each row's count checked against a certified count of the real roots (module docstring); with ``designs`` (a
    sequence of N designs, or an (N, n_p) array, in place of ``design``) row k at design k, the joints one row
    for all or one per design; with ``follow`` the rows are a path of the joints or of the design and each column
    of ``poses`` follows one configuration along it (:func:`followed`)."""
    if designs is None:
        found = _every_assembly(mech, q_a, design, certify=certify)
    else:
        found = _along_designs(mech, q_a, design, designs, certify=certify)
    return followed(found, mech) if follow else found


def _along_designs(mech: Any, q_a: Any, design: Any, designs: Any, *, certify: bool) -> Assemblies:
    """Every assembly of row k of the joints at design k, the rows stacked (NaN beyond a row's own)."""
    if design is not None:
        raise PkmError("design and designs violate: one of them (designs: one design per row of a path)")
    vectors = [mech.design_vector(d) for d in (designs if not isinstance(designs, np.ndarray) else list(designs))]
    qa, _ = as_batch(q_a, mech.n_act, "actuated joints")
    if not vectors or len(qa) not in (1, len(vectors)):
        raise PkmError(f"designs violate: a design per row of the actuated joints ({len(qa)} rows), or any number "
                       f"of designs for one row of them; got {len(vectors)}")
    rows = [_every_assembly(mech, qa[k if len(qa) > 1 else 0], d, certify=certify) for k, d in enumerate(vectors)]
    width = max(r.poses.shape[1] for r in rows)

    def padded(a: np.ndarray) -> np.ndarray:
        extra = [(0, 0), (0, width - a.shape[1]), *[(0, 0)] * (a.ndim - 2)]
        return np.pad(a, extra, constant_values=np.nan)

    certified = None if rows[0].certified is None else np.concatenate([r.certified for r in rows])
    return Assemblies(np.concatenate([padded(r.poses) for r in rows]), np.concatenate([padded(r.residuals)
                                                                                         for r in rows]),
                      np.concatenate([r.counts for r in rows]), max(r.bound for r in rows),
                      np.concatenate([r.failed for r in rows]), rows[0].method, certified, rows[0].failures)


def _every_assembly(mech: Any, q_a: Any, design: Any, *, certify: bool) -> Assemblies:
    qa, _ = as_batch(q_a, mech.n_act, "actuated joints")
    d = mech.design_vector(design)
    if "platform_loci" in mech.functions:
        alpha, beta, gamma = evaluate(mech.functions["platform_loci"], qa, d)
        (points,) = evaluate(mech.functions["platform_points"], d)
        loci = Loci(alpha[:, :, 0], beta, gamma[:, :, 0])
        order = np.argsort(-loci.alpha[0], kind="stable")  # a circle first where there is one: the pivot
        loci, points = loci.legs(order), points[0][order]
        scale = loci.scale(points)
        if mech.n_out == 2:
            _refuse_certify(certify, mech)
            return _two_loci(loci, points, scale)
        found = _three_loci(loci, points, scale)
        if not certify:
            return found
        counts = [real_roots(loci.rows(slice(k, k + 1)), points) for k in range(len(qa))]
        return replace(found, certified=np.array([n is not None and n == k for n, k in zip(
            counts, found.counts, strict=True)]))
    if "platform_circles" in mech.functions:
        (centres, radii) = evaluate(mech.functions["platform_circles"], qa, d)
        (points,) = evaluate(mech.functions["platform_points"], d)
        radii = np.abs(radii[:, :, 0])  # a signed length (a prismatic joint's) spans the same sphere
        scale = np.maximum.reduce([np.max(np.abs(centres), axis=(1, 2)), np.max(radii, axis=1),
                                   np.full(len(qa), np.max(np.abs(points)))])
        scale = np.where(scale > 0, scale, 1.0)
        _refuse_certify(certify, mech)
        if mech.n_out == 6:
            return _six_spheres(centres, radii, points[0], scale)
        return _three_spheres(centres, radii, points[0], scale)
    if isinstance(mech.forward, ClosedForm | PolynomialRoots):
        _refuse_certify(certify, mech)
        return _named(mech, qa, d)
    raise PkmError(f"mechanism {mech.name} violates: a mechanism whose complete forward kinematics pkm knows (a "
                   "closed form or a polynomial of its own, planar legs that each put the platform on a circle or "
                   "a line, or spatial ones on spheres); its forward_kinematics finds the assemblies its seeds "
                   "reach, not necessarily all")


def _refuse_certify(certify: bool, mech: Any) -> None:
    if certify:
        raise PkmError(f"certify violates: a planar machine of three legs on circles or lines, whose sextic's real "
                       f"roots are counted in ball arithmetic; {mech.name}'s assemblies come from another method")


def _named(mech: Any, qa: np.ndarray, design: np.ndarray) -> Assemblies:
    """Every assembly mode's pose, where it closes (a closed form's or a polynomial's modes name them all), its
    residual the largest of the loop closure h(q, x) at its joints."""
    poses, residuals = [], []
    for mode in mech.assembly_modes:
        x = mech.forward_kinematics(qa, design, assembly=mode.name)
        q = mech.forward_kinematics(qa, design, assembly=mode.name, passive=True)
        (h, *_) = evaluate(mech.functions["constraint"], q, x, design)
        poses.append(x)
        residuals.append(np.max(np.abs(h[:, :, 0]), axis=1))
    poses, residuals = np.stack(poses, axis=1), np.stack(residuals, axis=1)
    residuals[~np.all(np.isfinite(poses), axis=2)] = np.nan
    angles = np.array([u == "rad" for u in mech.pose_units])
    scale = np.maximum(np.nanmax(np.abs(np.where(angles, np.nan, poses)), axis=(1, 2), initial=0.0), 1e-300)
    poses, residuals = _distinct(poses, residuals, scale, angles)
    return Assemblies(poses, residuals, np.sum(np.isfinite(residuals), axis=1), len(mech.assembly_modes),
                      np.zeros(len(qa), int), f"{type(mech.forward).__name__}: every assembly mode")


class Loci(NamedTuple):
    """The curves on which N rows of k legs put their platform joints P_i in the plane, their actuated joints
    given (the derived ``platform_loci``): alpha |P_i|^2 + beta_i . P_i + gamma_i = 0, a circle (centre -beta / 2)
    where alpha is 1, a line (beta its unit normal) where it is 0."""

    alpha: np.ndarray  # (N, k)
    beta: np.ndarray  # (N, k, 2)
    gamma: np.ndarray  # (N, k)

    def rows(self, which: Any) -> Loci:
        return Loci(self.alpha[which], self.beta[which], self.gamma[which])

    def legs(self, order: np.ndarray) -> Loci:
        return Loci(self.alpha[:, order], self.beta[:, order], self.gamma[:, order])

    def radii(self) -> np.ndarray:
        """The circles' radii (N, k) (a line's a number of no meaning)."""
        return np.sqrt(np.maximum(np.sum(self.beta**2, axis=-1) / 4 - self.gamma, 0.0))

    def scale(self, points: np.ndarray) -> np.ndarray:
        """Each row's size: its circles' farthest reach from the origin, its lines' distances, the platform's
        joints'."""
        reach = np.where(self.alpha > 0, np.linalg.norm(self.beta, axis=-1) / 2 + self.radii(), np.abs(self.gamma))
        scale = np.maximum(np.max(reach, axis=1), np.max(np.abs(points)))
        return np.where(scale > 0, scale, 1.0)

    def residual(self, offset: np.ndarray) -> np.ndarray:
        """The distance of each platform joint from its curve (..., k) at its offsets P_i (..., k, 2) (the rows'
        axis first, broadcast)."""
        shape = (len(self.alpha),) + (1,) * (offset.ndim - 3) + (self.alpha.shape[1],)
        alpha, gamma = self.alpha.reshape(shape), self.gamma.reshape(shape)
        beta = self.beta.reshape(*shape, 2)
        radii = self.radii().reshape(shape)
        circle = np.abs(np.linalg.norm(offset + beta / 2, axis=-1) - radii)
        line = np.abs(np.sum(beta * offset, axis=-1) + gamma)
        return np.where(alpha > 0, circle, line)


def _two_loci(loci: Loci, points: np.ndarray, scale: np.ndarray) -> Assemblies:
    """P where P + c_1 and P + c_2 lie on their curves: two circles meet in 0, 1 or 2 points, a line and a
    circle too, two lines in one (none where they are parallel)."""
    if np.all(loci.alpha[0] > 0):
        return _two_circles(-loci.beta / 2, loci.radii(), points, loci, scale)
    line = 1 if loci.alpha[0, 0] > 0 else 0  # a circle first where there is one
    other = 1 - line
    normal = loci.beta[:, line]
    foot = -(loci.gamma[:, line] + normal @ points[line])[:, None] * normal
    along = np.stack([-normal[:, 1], normal[:, 0]], axis=1)
    q = foot + points[other]
    a = loci.alpha[:, other]
    b = 2 * a * np.sum(q * along, axis=1) + np.sum(loci.beta[:, other] * along, axis=1)
    c = a * np.sum(q**2, axis=1) + np.sum(loci.beta[:, other] * q, axis=1) + loci.gamma[:, other]
    with np.errstate(divide="ignore", invalid="ignore"):
        square = b**2 - 4 * a * c
        root = np.sqrt(np.where((square < 0) & (square >= -(SAME * scale) ** 2), 0.0, square))
        t = np.where(a[:, None] > 0, np.stack([(-b + root) / (2 * a), (-b - root) / (2 * a)], axis=1),
                     np.stack([-c / b, np.full_like(b, np.nan)], axis=1))
    poses = foot[:, None, :] + t[..., None] * along[:, None, :]
    poses[(a > 0) & (np.abs(root) <= SAME * scale), 1] = np.nan
    return _closing(poses, lambda p: np.max(loci.residual(p[:, None, :] + points), axis=1), scale,
                    method="two curves' intersection")


def _two_circles(centres: np.ndarray, radii: np.ndarray, points: np.ndarray, loci: Loci, scale: np.ndarray
                 ) -> Assemblies:
    """P where P + c_1 and P + c_2 lie on their circles: the circles about B_i - c_i meet in 0, 1 or 2
    points."""
    b = centres - points[None, :, :]
    d = b[:, 1] - b[:, 0]
    gap = np.linalg.norm(d, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        along = (radii[:, 0] ** 2 - radii[:, 1] ** 2 + gap**2) / (2 * gap)
        height = radii[:, 0] ** 2 - along**2
        across = np.sqrt(np.where((height < 0) & (height >= -(SAME * scale) ** 2), 0.0, height))  # tangent
        u = d / gap[:, None]
    normal = np.stack([-u[:, 1], u[:, 0]], axis=1)
    foot = b[:, 0] + along[:, None] * u
    poses = np.stack([foot + across[:, None] * normal, foot - across[:, None] * normal], axis=1)
    tangent = np.abs(across) <= SAME * scale
    poses[tangent, 1] = np.nan
    return _closing(poses, lambda p: np.max(loci.residual(p[:, None, :] + points), axis=1), scale,
                    method="two circles' intersection")


def _three_spheres(centres: np.ndarray, radii: np.ndarray, points: np.ndarray, scale: np.ndarray) -> Assemblies:
    """P where each P + c_i lies on its sphere (a point pose in space): the spheres about B_i - c_i meet in 0, 1
    or 2 points (trilateration in the frame of the three centres); none counted where the centres are on one
    line (a continuum or none)."""
    b = centres - points[None, :, :]
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.linalg.norm(b[:, 1] - b[:, 0], axis=1)
        ex = (b[:, 1] - b[:, 0]) / d[:, None]
        i = np.sum(ex * (b[:, 2] - b[:, 0]), axis=1)
        side = b[:, 2] - b[:, 0] - i[:, None] * ex
        j = np.linalg.norm(side, axis=1)
        ey = side / j[:, None]
        ez = np.cross(ex, ey)
        x = (radii[:, 0] ** 2 - radii[:, 1] ** 2 + d**2) / (2 * d)
        y = (radii[:, 0] ** 2 - radii[:, 2] ** 2 + i**2 + j**2 - 2 * i * x) / (2 * j)
        height = radii[:, 0] ** 2 - x**2 - y**2
        z = np.sqrt(np.where((height < 0) & (height >= -(SAME * scale) ** 2), 0.0, height))
    foot = b[:, 0] + x[:, None] * ex + y[:, None] * ey
    poses = np.stack([foot + z[:, None] * ez, foot - z[:, None] * ez], axis=1)
    poses[np.abs(z) <= SAME * scale, 1] = np.nan
    poses[j <= SAME * scale] = np.nan
    return _closing(poses, lambda p: _point_residual(p, centres, radii, points), scale,
                    method="three spheres' intersection")


SPATIAL_ANGLES = np.array([False, False, False, True, True, True])  # which coordinates of a spatial pose are angles


def _six_spheres(centres: np.ndarray, radii: np.ndarray, points: np.ndarray, scale: np.ndarray) -> Assemblies:
    """The poses (x, y, z, roll, pitch, yaw; R = Rz(yaw) Ry(pitch) Rx(roll), pitch within +-pi/2) where each of
    the platform's six joints lies on its sphere: the real ends of the parameter homotopy's 40 paths
    (:mod:`pkm.homotopy`), kept where they close every sphere to CLOSURE of the row's size; the paths that did
    not arrive counted in ``failed``."""
    n = len(centres)
    z, arrived = homotopy.solve(centres, np.broadcast_to(points, (n, 6, 3)), radii**2)
    rotation, t, real = homotopy.real_poses(z, arrived)
    residuals = homotopy.pose_residual(rotation, t, centres[:, None], points, radii[:, None])
    closed = real & (residuals <= CLOSURE * scale[:, None])
    angles = np.stack([np.arctan2(rotation[..., 2, 1], rotation[..., 2, 2]),
                       np.arcsin(np.clip(-rotation[..., 2, 0], -1.0, 1.0)),
                       np.arctan2(rotation[..., 1, 0], rotation[..., 0, 0])], axis=-1)
    poses = np.where(closed[..., None], np.concatenate([t, angles], axis=-1), np.nan)
    poses, residuals = _distinct(poses, np.where(closed, residuals, np.nan), scale, SPATIAL_ANGLES)
    return Assemblies(poses, residuals, np.sum(np.isfinite(residuals), axis=1), homotopy.PATHS,
                      np.sum(~arrived, axis=1), "a parameter homotopy in Study's coordinates, 40 paths",
                      failures="paths did not arrive (their ends at infinity or at a singular point)")


def _closing(poses: np.ndarray, residual: Any, scale: np.ndarray, *, method: str) -> Assemblies:
    """A point pose's two candidates (N, 2, dim) kept where they close every leg (``residual(p)`` (N,) at the
    candidates p (N, dim)) to CLOSURE of the row's size."""
    residuals = np.stack([residual(poses[:, s]) for s in range(2)], axis=1)
    open_ = ~(residuals <= CLOSURE * scale[:, None])
    poses[open_] = np.nan
    residuals[open_] = np.nan
    closed = np.all(np.isfinite(poses), axis=2)
    return Assemblies(poses, residuals, closed.sum(axis=1), 2, np.zeros(len(poses), int), method)


def _point_residual(p: np.ndarray, centres: np.ndarray, radii: np.ndarray, points: np.ndarray) -> np.ndarray:
    return np.max(np.abs(np.linalg.norm(p[:, None, :] + points[None] - centres, axis=2) - radii), axis=1)


def _turned(phi: np.ndarray, points: np.ndarray) -> np.ndarray:
    """The platform joints (k, 2) turned by the platform angles phi (...): (..., k, 2)."""
    cos, sin = np.cos(phi)[..., None], np.sin(phi)[..., None]
    return np.stack([cos * points[:, 0] - sin * points[:, 1], sin * points[:, 0] + cos * points[:, 1]], axis=-1)


def _terms(phi: np.ndarray, loci: Loci, points: np.ndarray) -> tuple[np.ndarray, ...]:
    """At platform angles phi (N, M), with w_i = R(phi) c_i and each curve g_i = alpha_i |P + w_i|^2 + beta_i . (P
    + w_i) + gamma_i = alpha_i |P|^2 + P . grad_i + const_i: the linear system m P = rhs of g_2 and g_3 less
    alpha_i g_1 (the first curve a circle where there is one; its rows (N, M, 2, 2), its right side (N, M, 2))
    whose solution by Cramer's rule is N / D, and f = D^2 g_1(N / D) = alpha_1 |N|^2 + D N . grad_1 + D^2 const_1
    (for lines alone D g_1(N / D): D is then constant); returns f, N (N, M, 2), D (N, M), grad (N, M, 3, 2),
    const (N, M, 3), m and rhs."""
    w = _turned(phi, points)
    alpha, gamma = loci.alpha[:, None, :], loci.gamma[:, None, :]
    beta = loci.beta[:, None]
    u, v = w[..., 0], w[..., 1]  # the sums over two coordinates written out: numpy's reductions cost more
    const = alpha * (u * u + v * v) + beta[..., 0] * u + beta[..., 1] * v + gamma
    grad = 2 * alpha[..., None] * w + beta
    m = grad[..., 1:, :] - alpha[..., 1:, None] * grad[..., :1, :]
    rhs = -(const[..., 1:] - alpha[..., 1:] * const[..., :1])
    det = m[..., 0, 0] * m[..., 1, 1] - m[..., 0, 1] * m[..., 1, 0]
    nx = m[..., 1, 1] * rhs[..., 0] - m[..., 0, 1] * rhs[..., 1]
    ny = m[..., 0, 0] * rhs[..., 1] - m[..., 1, 0] * rhs[..., 0]
    first = alpha[..., 0]  # 1 where the first curve is a circle; 0 where all are lines, then f = g_1(N / D) D
    f = first * (nx * nx + ny * ny) + (first * det + 1 - first) * (nx * grad[..., 0, 0] + ny * grad[..., 0, 1]
                                                                   + det * const[..., 0])
    return f, np.stack([nx, ny], axis=-1), det, grad, const, m, rhs


def _half_angle_matrix() -> np.ndarray:
    """T (7, 7) with T @ a the coefficients (t^0 .. t^6) of (1 + t^2)^3 f for f = sum a_k e^(i k phi), k = -3..3:
    e^(i k phi) (1 + t^2)^3 = (1 + i t)^(3 + k) (1 - i t)^(3 - k) at t = tan(phi / 2)."""
    columns = []
    for k in range(-3, 4):
        product = np.polynomial.polynomial.polymul(np.polynomial.polynomial.polypow([1, 1j], 3 + k),
                                                   np.polynomial.polynomial.polypow([1, -1j], 3 - k))
        columns.append(np.pad(product, (0, 7 - len(product))))
    return np.array(columns).T


HALF_ANGLE = _half_angle_matrix()


def _roots(coefficients: np.ndarray) -> np.ndarray:
    """The real roots t (N, 6) of the real polynomials c_0 + c_1 t + ... + c_6 t^6 (N, 7), NaN for the others;
    where the degree drops (a root at t = infinity: phi = pi), pi's t, a large number, stands in its place."""
    out = np.full((len(coefficients), 6), np.nan + 0j)
    lead = coefficients[:, 6]
    full = np.abs(lead) > 1e-13 * np.max(np.abs(coefficients), axis=1)
    if full.any():
        companion = np.zeros((int(full.sum()), 6, 6))
        companion[:, 1:, :-1] = np.eye(5)
        companion[:, :, -1] = -coefficients[full, :6] / lead[full, None]
        out[full] = np.linalg.eigvals(companion)
    for row in np.flatnonzero(~full):
        found = np.roots(np.trim_zeros(coefficients[row, 5::-1], "f"))
        out[row, : len(found)] = found
        out[row, len(found)] = np.tan(np.pi / 2 * (1 - 1e-12))
    real = np.abs(out.imag) <= ON_CIRCLE * (1 + np.abs(out.real))
    return np.where(real, out.real, np.nan)


def _three_loci(loci: Loci, points: np.ndarray, scale: np.ndarray) -> Assemblies:
    """Every (x, y, phi) that puts each platform joint on its curve (module docstring), the rows in blocks on
    :data:`pkm.batch.THREADS` threads where there are BLOCK_ROWS of them at least (numpy's loops and LAPACK
    release Python's lock)."""
    blocks = min(batch.THREADS, max(1, len(scale) // BLOCK_ROWS))
    if blocks == 1:
        return _three_loci_block(loci, points, scale)
    edges = np.linspace(0, len(scale), blocks + 1).astype(int)
    with ThreadPoolExecutor(blocks) as pool:
        parts = list(pool.map(lambda k: _three_loci_block(loci.rows(slice(edges[k], edges[k + 1])), points,
                                                          scale[edges[k]:edges[k + 1]]), range(blocks)))
    return Assemblies(*(np.concatenate([getattr(part, name) for part in parts]) for name in
                        ("poses", "residuals", "counts")), parts[0].bound,
                      np.concatenate([part.failed for part in parts]), parts[0].method)


def _three_loci_block(loci: Loci, points: np.ndarray, scale: np.ndarray) -> Assemblies:
    n = len(scale)
    samples = 2 * np.pi * np.arange(SAMPLES) / SAMPLES
    f, *_ = _terms(np.broadcast_to(samples, (n, SAMPLES)), loci, points)
    harmonics = np.fft.fft(f, axis=1) / SAMPLES
    coefficients = (harmonics[:, [k % SAMPLES for k in range(-3, 4)]] @ HALF_ANGLE.T).real  # of t^0 .. t^6
    with np.errstate(divide="ignore", invalid="ignore"):
        phi = 2 * np.arctan(_roots(coefficients))
        first, second = _positions(phi, loci, points)
        poses, residuals, closed = _polished(first, loci, points, scale)
        mirrored = np.flatnonzero(np.any(np.isfinite(second[..., 0]), axis=1))
        if len(mirrored):  # rows with two assemblies at one angle: both candidates of each such root
            both = np.concatenate([first[mirrored], second[mirrored]], axis=1)
            more, more_residuals, more_closed = _polished(both, loci.rows(mirrored), points, scale[mirrored])
            poses[mirrored], residuals[mirrored] = more[:, :6], more_residuals[:, :6]
            closed[mirrored] = np.any(more_closed.reshape(len(mirrored), 2, -1), axis=1)
    failed = np.sum(np.isfinite(phi) & ~closed, axis=1)
    return Assemblies(poses, residuals, np.sum(np.isfinite(residuals), axis=1), 6, failed,
                      "the sextic in the platform angle (Gosselin-Sefrioui-Richard), its roots polished")


def _polished(x: np.ndarray, loci: Loci, points: np.ndarray, scale: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Candidate poses (N, S, 3) polished by Newton's method; the distinct closed ones and their residuals, and
    which candidates closed."""
    for _ in range(NEWTON_STEPS):
        x = _newton_step(x, loci, points)
    offset, _ = _offsets(x, points)
    residual = np.max(loci.residual(offset), axis=-1)
    closed = residual <= CLOSURE * scale[:, None]
    poses, residuals = _distinct(np.where(closed[..., None], x, np.nan), np.where(closed, residual, np.nan), scale,
                                 ANGLE)
    return poses, residuals, closed


def _positions(phi: np.ndarray, loci: Loci, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Candidate poses (N, 6, 3) for the platform angles phi (N, 6): the position by Cramer's rule, and NaN; where
    the system's two lines are nearly parallel (D(phi) near 0: two mirror assemblies at one angle), the two
    points where the better of the two lines meets the first curve, a circle, instead (where the curves are all
    lines, a continuum or none: no candidate)."""
    _, num, det, grad, const, m, rhs = _terms(phi, loci, points)
    lengths = np.linalg.norm(m, axis=-1)
    parallel = np.abs(det) <= PARALLEL * np.prod(lengths, axis=-1)
    first = np.concatenate([num / det[..., None], phi[..., None]], axis=-1)
    second = np.full_like(first, np.nan)
    circle = np.broadcast_to(loci.alpha[:, None, 0] > 0, parallel.shape)
    first[parallel & ~circle] = np.nan
    parallel &= circle
    if parallel.any():
        # the first circle about -v with radius r: |P + v|^2 = r^2, v = w_1 + beta_1 / 2
        v = (grad[..., 0, :] / 2)[parallel]
        r2 = (np.sum(grad[..., 0, :] ** 2, axis=-1) / 4 - const[..., 0])[parallel]
        m, rhs, lengths = m[parallel], rhs[parallel], lengths[parallel]
        best = np.argmax(lengths, axis=-1)
        n = m[np.arange(len(m)), best]
        d = rhs[np.arange(len(m)), best]
        norm2 = np.sum(n**2, axis=-1)
        foot = -v + ((d + np.sum(n * v, axis=-1)) / norm2)[:, None] * n
        half = np.sqrt(np.maximum(r2 - np.sum((foot + v) ** 2, axis=-1), 0.0) / norm2)
        across = np.stack([-n[:, 1], n[:, 0]], axis=-1) * half[:, None]
        first[parallel, :2], second[parallel, :2] = foot + across, foot - across
        second[parallel, 2] = phi[parallel]
    return first, second


def _offsets(x: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The platform joints P_i at the poses x (N, S, 3): (N, S, 3, 2), and their derivative in phi."""
    turned = _turned(x[..., 2], points)
    return x[..., None, :2] + turned, np.stack([-turned[..., 1], turned[..., 0]], axis=-1)


def _newton_step(x: np.ndarray, loci: Loci, points: np.ndarray) -> np.ndarray:
    """One Newton step on the curves' g_i = alpha_i |P_i|^2 + beta_i . P_i + gamma_i in (x, y, phi); a singular
    step leaves the row."""
    offset, turning = _offsets(x, points)
    alpha, gamma = loci.alpha[:, None, :], loci.gamma[:, None, :]
    beta = loci.beta[:, None]
    u, v = offset[..., 0], offset[..., 1]
    g = alpha * (u * u + v * v) + beta[..., 0] * u + beta[..., 1] * v + gamma
    grad = 2 * alpha[..., None] * offset + beta
    turns = grad[..., 0] * turning[..., 0] + grad[..., 1] * turning[..., 1]
    jacobian = np.concatenate([grad, turns[..., None]], axis=-1)
    finite = np.all(np.isfinite(jacobian), axis=(-2, -1)) & (np.abs(np.linalg.det(
        np.where(np.isfinite(jacobian), jacobian, 0.0))) > 0)
    step = np.zeros_like(x)
    step[finite] = np.linalg.solve(jacobian[finite], g[finite][..., None])[..., 0]
    return x - step


ANGLE = np.array([False, False, True])  # which coordinates of a planar pose are angles


def _distinct(poses: np.ndarray, residuals: np.ndarray, scale: np.ndarray, angles: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """Each row's assemblies once (a double root found twice is one: an assembly within SAME of an earlier one
    of its row, its lengths relative to the row's ``scale``, its angles wrapped, is dropped), the closed first in
    the order of the last coordinate; NaN beyond them."""
    poses = poses.copy()
    poses[..., angles] = np.angle(np.exp(1j * poses[..., angles]))
    gap = np.abs(poses[:, :, None, :] - poses[:, None, :, :])
    gap[..., angles] = np.abs(np.angle(np.exp(1j * gap[..., angles])))
    tolerance = np.where(angles, SAME, SAME * scale[:, None, None, None])
    near = np.all(gap <= tolerance, axis=-1)
    earlier = np.tril(np.ones(near.shape[1:], dtype=bool), -1)
    repeated = np.any(near & earlier, axis=2)
    poses[repeated] = np.nan
    residuals = np.where(repeated, np.nan, residuals)
    key = np.where(np.isfinite(residuals), poses[..., -1], np.inf)
    order = np.argsort(key, axis=1, kind="stable")
    return np.take_along_axis(poses, order[..., None], axis=1), np.take_along_axis(residuals, order, axis=1)


INTERPOLATION = tuple(range(-3, 4))  # the t = tan(phi / 2) the sextic is interpolated through


def real_roots(loci: Loci, points: np.ndarray) -> int | None:
    """The certified number of real platform angles at which three platform joints ``points`` (3, 2) lie on their
    curves (one row of ``loci``), the inputs taken as the exact numbers they are: the sextic (1 + t^2)^3 f(phi(t))
    in exact rational arithmetic (its values at seven integer t, interpolated), its real roots isolated by
    python-flint (``fmpz_poly.complex_roots``: a real root's imaginary part exactly 0), and phi = pi where its
    degree drops by one; None where a real root is multiple (assemblies meeting at a singularity) or the sextic
    vanishes."""
    try:
        import flint
    except ImportError:
        raise PkmError("certify violates: python-flint installed (pip install python-flint), whose exact "
                       "arithmetic certifies the count") from None

    def exact(value: float) -> Any:
        ratio = Fraction(float(value))
        return flint.fmpq(ratio.numerator, ratio.denominator)

    rows = Loci(*(np.vectorize(exact, otypes=[object])(v) for v in loci.rows(0)))
    corners = np.vectorize(exact, otypes=[object])(points)
    values = [_sextic_at(flint.fmpq(t), rows, corners) for t in INTERPOLATION]
    sextic = flint.fmpq_poly(0)
    for k, (t, value) in enumerate(zip(INTERPOLATION, values, strict=True)):
        term = flint.fmpq_poly([value])
        for j, other in enumerate(INTERPOLATION):
            if j != k:
                term *= flint.fmpq_poly([-other, 1]) / (t - other)
        sextic += term
    if sextic.is_zero():
        return None
    dropped = 6 - sextic.degree()  # phi = pi a root of this multiplicity
    roots = [m for root, m in sextic.numer().complex_roots() if root.imag == 0]
    if dropped > 1 or any(m > 1 for m in roots):
        return None
    return len(roots) + dropped


def _sextic_at(t: Any, loci: Loci, points: np.ndarray) -> Any:
    """(1 + t^2)^3 f at t, exactly (:func:`_terms`): cos and sin of phi(t) rational in t, f by Cramer's rule; t,
    one row of ``loci`` and ``points`` exact rationals (python-flint's fmpq)."""
    cos, sin = (1 - t * t) / (1 + t * t), 2 * t / (1 + t * t)
    alpha, beta = loci.alpha, loci.beta
    w = [(cos * c[0] - sin * c[1], sin * c[0] + cos * c[1]) for c in points]
    const = [a * (u * u + v * v) + b[0] * u + b[1] * v + g
             for a, b, (u, v), g in zip(alpha, beta, w, loci.gamma, strict=True)]
    grad = [(2 * a * u + b[0], 2 * a * v + b[1]) for a, b, (u, v) in zip(alpha, beta, w, strict=True)]
    m = [[grad[k][0] - alpha[k] * grad[0][0], grad[k][1] - alpha[k] * grad[0][1]] for k in (1, 2)]
    rhs = [-(const[k] - alpha[k] * const[0]) for k in (1, 2)]
    det = m[0][0] * m[1][1] - m[0][1] * m[1][0]
    nx, ny = m[1][1] * rhs[0] - m[0][1] * rhs[1], m[0][0] * rhs[1] - m[1][0] * rhs[0]
    f = alpha[0] * (nx * nx + ny * ny) + (alpha[0] * det + 1 - alpha[0]) * (nx * grad[0][0] + ny * grad[0][1]
                                                                           + det * const[0])
    return f * (1 + t * t) ** 3


def followed(found: Assemblies, mech: Any) -> Assemblies:
    """The assemblies of a path of actuated joints or of designs (consecutive rows) in columns that each follow one
    configuration: each row's assemblies go to the columns whose configurations, continued along their last
    step, are nearest (nearest pairs first; angles wrapped), one born where assemblies meet at a singularity
    to a column free there; so that column k names one assembly along the path, not a rank."""
    angles = np.array([u == "rad" for u in mech.pose_units])
    poses, residuals = found.poses.copy(), found.residuals.copy()
    for row in range(1, len(poses)):
        before, now = poses[row - 1], found.poses[row]
        if row > 1:  # each column's next configuration predicted along its last step, where it has one
            step = poses[row - 1] - poses[row - 2]
            step[:, angles] = np.angle(np.exp(1j * step[:, angles]))
            before = np.where(np.isfinite(step), before + step, before)
        gap = now[:, None, :] - before[None, :, :]
        gap[..., angles] = np.angle(np.exp(1j * gap[..., angles]))
        distance = np.linalg.norm(gap, axis=-1)
        distance[~np.isfinite(distance)] = np.inf
        placed = np.full(len(now), -1)
        free = np.ones(len(now), dtype=bool)
        for flat in np.argsort(distance, axis=None):
            i, j = divmod(int(flat), len(now))
            if np.isfinite(distance[i, j]) and placed[i] < 0 and free[j]:
                placed[i], free[j] = j, False
        for i in np.flatnonzero((placed < 0) & np.all(np.isfinite(now), axis=1)):
            j = int(np.flatnonzero(free)[0])
            placed[i], free[j] = j, False
        poses[row] = np.nan
        residuals[row] = np.nan
        for i, j in enumerate(placed):
            if j >= 0:
                poses[row, j], residuals[row, j] = now[i], found.residuals[row, i]
    return replace(found, poses=poses, residuals=residuals, method=found.method + ", followed along the path")
