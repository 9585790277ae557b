"""Every pose of a rigid body whose six points each lie on a sphere: a parameter homotopy in Study's soma
coordinates, for the complete forward kinematics of a spatial machine of six legs (:mod:`pkm.assemblies`).

A pose (R, t) is the Study point z = (e, g) in C^8, e the rotation's quaternion and g = t e / 2 (t a pure
quaternion), on the Study quadric e . g = 0, up to scale; point b_i of the body on the sphere (a_i, r_i),
|R b_i + t - a_i|^2 = r_i^2, is, times e . e, the quadratic form (Husty 1996; Wampler 1996)

    F_i(z) = (|a_i|^2 + |b_i|^2 - r_i^2) e.e + 4 g.g + 4 (e b_i).g - 2 (e b_i e*).a_i - 4 (g e*).a_i = 0

(quaternion products; dots of four components). With the quadric and a random linear patch c . e = 1 (which
leaves out e = 0, where the forms have a spurious component), the eight equations have 40 solutions for generic
points and radii, complex and real, and never more isolated ones (Raghavan 1993; Dietmaier 1998 found a
geometry with all 40 real).

The 40 solutions at one generic complex instance (random points, radii and patch) are found once by monodromy (known
solutions tracked around loops of random complex instances until 40 are known; Sommese and Wampler, 2005) and kept
in the kernel cache (its folder ``homotopy``). Every instance is then reached from it by the straight parameter path
p(s) = (1 - s) p_start + s p (complex start: the path misses the instances with fewer solutions with probability
one), each of the 40 paths tracked by a predictor-corrector (a Runge-Kutta step of dz/ds = -F_z^-1 F_s, Newton's
corrections, the step halved where they do not converge and grown where they do; a path that did not arrive tracked
again with steps of at most RETRY_STEP). The paths run in pkm/_track.c, a kernel pkm writes in C (each path a row
with steps of its own, its 8 x 8 complex solves by Gaussian elimination with partial pivoting, the rows on pkm's
threads through the kernel runner), compiled into the kernel cache at first use; where the compiled path is off,
:func:`track` steps all of them at once in numpy (batches of small complex solves), the same steps to rounding.
The monodromy's loops between complex instances run in numpy. Each path ends at a solution, or is reported failed
(it met a singular point or ran out of steps), never dropped.

F_i is quadratic in the parameters along the path, so dF_i/ds is exact in closed form from the parameters' change
(:func:`_terms`).
"""

from __future__ import annotations

import contextlib
import hashlib
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from pkm import batch, compiled
from pkm.compiled.cache import location
from pkm.errors import ComputationError
from pkm.io import atomic_write

PATHS = 40  # the solutions of the generic instance (Raghavan 1993)
SEED = 39  # the generic start instance's random draw
VERSION = 1  # of the start instance's file in the cache
MAX_STEPS = 400  # predictor-corrector steps per path at most
FIRST_STEP = 0.05  # of s
MAX_STEP = 0.25  # of s
RETRY_STEP = 0.01  # of s: the largest step of a path tracked again where it did not arrive
GROWTH = 1.25  # the step's factor after a step whose corrections converged (halved where they did not)
LEAST_STEP = 1e-7  # a path whose step falls below this has met a singular point: failed
CORRECTIONS = 3  # Newton corrections after each predictor step
CONVERGED = 1e-9  # a correction this small (relative to |z|) closes a step
END_STEPS = 4  # Newton steps at s = 1
REAL = 1e-8  # a solution whose imaginary part (relative) is this small is real
LOOPS = 30  # monodromy loops at most


Quaternion = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


def _times(p: Quaternion, q: Quaternion) -> Quaternion:
    """Quaternion products, component by component (w, x, y, z): Hamilton's."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz, pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx, pw * qz + px * qy - py * qx + pz * qw)


def _dot(p: Quaternion, q: Quaternion) -> np.ndarray:
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3] * q[3]


def _parts(v: np.ndarray) -> Quaternion:
    """The pure quaternions of vectors (..., 3)."""
    return (np.zeros(v.shape[:-1], dtype=v.dtype), v[..., 0], v[..., 1], v[..., 2])


def _terms(z: np.ndarray, a: np.ndarray, b: np.ndarray, radii2: np.ndarray, change: tuple[np.ndarray, ...] | None = None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """F_i (R, 6) and its gradient in z (R, 6, 8) at Study points z (R, 8) for the instances (a (R, 6, 3), b
    (R, 6, 3), radii2 (R, 6)), and with ``change`` (da, db, dradii2) the derivative of F_i along it (R, 6): with
    k_i = |a_i|^2 + |b_i|^2 - r_i^2 and a_i, b_i pure quaternions, grad_e F_i = 2 k_i e + 4 g b_i* + 4 a_i e b_i
    + 4 a_i g and grad_g F_i = 8 g + 4 e b_i - 4 a_i e."""
    e = tuple(z[:, k, None] for k in range(4))
    g = tuple(z[:, k, None] for k in range(4, 8))
    pa, pb = _parts(a), _parts(b)
    eb, ae = _times(e, pb), _times(pa, e)
    k = np.sum(a * a, axis=-1) + np.sum(b * b, axis=-1) - radii2
    f = k * _dot(e, e) + 4 * _dot(g, g) + 4 * _dot(eb, g) - 2 * _dot(eb, ae) - 4 * _dot(g, ae)
    gb = _times(g, (pb[0], -pb[1], -pb[2], -pb[3]))
    aeb, ag = _times(ae, pb), _times(pa, g)
    gradient = np.stack([*(2 * k * e[i] + 4 * (gb[i] + aeb[i] + ag[i]) for i in range(4)),
                         *(8 * g[i] + 4 * (eb[i] - ae[i]) for i in range(4))], axis=-1)
    if change is None:
        return f, gradient, None
    da, db, dradii2 = change
    qa, qb = _parts(da), _parts(db)
    edb, dae = _times(e, qb), _times(qa, e)
    dk = 2 * np.sum(a * da, axis=-1) + 2 * np.sum(b * db, axis=-1) - dradii2
    df = (dk * _dot(e, e) + 4 * _dot(edb, g) - 2 * (_dot(edb, ae) + _dot(eb, dae)) - 4 * _dot(g, dae))
    return f, gradient, df


def _system(z: np.ndarray, start: tuple[np.ndarray, ...], change: tuple[np.ndarray, ...], s: np.ndarray,
            c: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """H (R, 8), H_z (R, 8, 8) and H_s (R, 8) at Study points z (R, 8) and path times s (R,) on the paths
    p(s) = start + s change of their instances (per row) with the patch c (8,)."""
    now = tuple(p + s.reshape(-1, *(1,) * (p.ndim - 1)) * d for p, d in zip(start, change, strict=True))
    f, gradient, df = _terms(z, *now, change=change)
    e, g = z[:, :4], z[:, 4:]
    h = np.concatenate([f, np.sum(e * g, axis=-1, keepdims=True), (z @ c - 1)[:, None]], axis=-1)
    h_z = np.concatenate([gradient, np.concatenate([g, e], axis=-1)[:, None], np.broadcast_to(c, z.shape)[:, None]],
                         axis=1)
    return h, h_z, np.concatenate([df, np.zeros((len(z), 2), dtype=z.dtype)], axis=-1)


def _velocity(z: np.ndarray, start: tuple[np.ndarray, ...], change: tuple[np.ndarray, ...], s: np.ndarray,
              c: np.ndarray) -> np.ndarray:
    _, h_z, h_s = _system(z, start, change, s, c)
    return -_solved(h_z, h_s)


def _solved(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a^-1 b of each row (a (R, 8, 8), b (R, 8)); NaN in a row whose matrix is singular (its path fails there)."""
    try:
        return np.linalg.solve(a, b[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.full(b.shape, np.nan, dtype=np.result_type(a, b))
        for k in range(len(a)):
            with contextlib.suppress(np.linalg.LinAlgError):
                out[k] = np.linalg.solve(a[k], b[k])
        return out


def _corrected(z: np.ndarray, start: tuple[np.ndarray, ...], change: tuple[np.ndarray, ...], s: np.ndarray,
               c: np.ndarray, *, steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Newton's corrections at fixed s; the points and whether the last correction was below CONVERGED."""
    size = np.ones(len(z))
    for _ in range(steps):
        h, h_z, _ = _system(z, start, change, s, c)
        step = _solved(h_z, h)
        z = z - step
        size = np.linalg.norm(step, axis=-1) / np.maximum(np.linalg.norm(z, axis=-1), 1.0)
    return z, size <= CONVERGED


def track(z: np.ndarray, start: tuple[np.ndarray, ...], target: tuple[np.ndarray, ...], c: np.ndarray, *,
          largest: float = MAX_STEP) -> tuple[np.ndarray, np.ndarray]:
    """Paths from the Study points z (R, 8) at s = 0 to s = 1, each along p(s) = (1 - s) start + s target of its
    row (a (R, 6, 3), b (R, 6, 3), radii2 (R, 6) each): the end points, and whether each path arrived (its last
    corrections converged at s = 1), each step at most ``largest``. Only the paths still going are stepped."""
    z = z.astype(complex)
    start = tuple(p.astype(complex) for p in start)
    change = tuple(t - p for p, t in zip(start, target, strict=True))
    s, step = np.zeros(len(z)), np.full(len(z), min(FIRST_STEP, largest))
    rows = np.arange(len(z))
    with np.errstate(all="ignore"):
        for _ in range(MAX_STEPS):
            if not len(rows):
                break
            zr, sr = z[rows], s[rows]
            p0, dp = tuple(p[rows] for p in start), tuple(d[rows] for d in change)
            h = np.minimum(step[rows], 1 - sr)
            k1 = _velocity(zr, p0, dp, sr, c)
            k2 = _velocity(zr + h[:, None] / 2 * k1, p0, dp, sr + h / 2, c)
            k3 = _velocity(zr + h[:, None] / 2 * k2, p0, dp, sr + h / 2, c)
            k4 = _velocity(zr + h[:, None] * k3, p0, dp, sr + h, c)
            guess = zr + h[:, None] / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            new, ok = _corrected(np.where(np.isfinite(guess), guess, zr), p0, dp, sr + h, c, steps=CORRECTIONS)
            ok &= np.all(np.isfinite(new), axis=-1)
            z[rows[ok]], s[rows[ok]] = new[ok], sr[ok] + h[ok]
            step[rows] = np.where(ok, np.minimum(GROWTH * step[rows], largest), step[rows] / 2)
            rows = rows[(s[rows] < 1) & (step[rows] >= LEAST_STEP)]
        z, arrived = _corrected(z, start, change, np.ones(len(z)), c, steps=END_STEPS)
    return z, arrived & (s >= 1) & np.all(np.isfinite(z), axis=-1)


def _random_instance(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    complex_normal = lambda *shape: rng.normal(size=shape) + 1j * rng.normal(size=shape)  # noqa: E731
    return complex_normal(6, 3), complex_normal(6, 3), complex_normal(6)


def _start() -> tuple[tuple[np.ndarray, ...], np.ndarray, np.ndarray]:
    """The generic start instance (a, b, radii2), its patch c and its 40 solutions (40, 8), from the cache or by
    monodromy (module docstring)."""
    path = location() / "homotopy" / f"study-{VERSION}-{SEED}-{_digest()}.npz"
    try:
        with np.load(path) as kept:
            return (kept["a"], kept["b"], kept["radii2"]), kept["c"], kept["z"]
    except (OSError, KeyError, ValueError):
        pass
    start, c, z = _monodromy(np.random.default_rng(SEED))
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(path, lambda tmp: np.savez(tmp, a=start[0], b=start[1], radii2=start[2], c=c, z=z))
    return start, c, z


def _digest() -> str:
    """What the start instance depends on: this module's text."""
    return hashlib.sha256(Path(__file__).read_bytes()).hexdigest()[:12]


def _monodromy(rng: np.random.Generator) -> tuple[tuple[np.ndarray, ...], np.ndarray, np.ndarray]:
    """A random complex instance through a random Study point, and its 40 solutions by monodromy loops."""
    c = rng.normal(size=8) + 1j * rng.normal(size=8)
    e = rng.normal(size=4) + 1j * rng.normal(size=4)
    t = rng.normal(size=3) + 1j * rng.normal(size=3)
    z0 = np.concatenate([e, np.array(_times(_parts(t), tuple(e))) / 2])
    z0 = z0 / (z0 @ c)
    a, b, _ = _random_instance(rng)
    rest = _terms(z0[None], a[None], b[None], np.zeros((1, 6)))[0][0]
    start = (a, b, rest / np.sum(z0[:4] ** 2))  # F_i(z0) = 0: r_i^2 e.e is the rest of the form
    known = z0[None, :]
    for _ in range(LOOPS):
        first, second = _random_instance(rng), _random_instance(rng)
        z = known
        for source, target in ((start, first), (first, second), (second, start)):
            rows = len(z)
            z, arrived = track(z, tuple(np.broadcast_to(p, (rows, *p.shape)) for p in source),
                               tuple(np.broadcast_to(p, (rows, *p.shape)) for p in target), c)
            z = z[arrived]
        known = _union(known, z)
        if len(known) >= PATHS:
            break
    if len(known) != PATHS:
        raise ComputationError(f"the monodromy found {len(known)} of the {PATHS} solutions of the start instance")
    return start, c, known


def _union(known: np.ndarray, found: np.ndarray) -> np.ndarray:
    for z in found:
        if np.min(np.linalg.norm(known - z, axis=1)) > 1e-6 * max(1.0, np.linalg.norm(z)):
            known = np.vstack([known, z])
    return known


def solve(a: np.ndarray, b: np.ndarray, radii2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every solution (N, 40, 8) of the instances (a (N, 6, 3), b (N, 6, 3), radii2 (N, 6)), real or complex, each
    path's end and whether it arrived (N, 40). The paths are tracked by the compiled tracker (pkm/_track.c, a
    row per path, on :data:`pkm.batch.THREADS` threads) where the compiled path is on, else by :func:`track` in
    numpy on as many threads (numpy's loops and LAPACK release the interpreter's lock)."""
    start, c, z = _start()
    n = len(a)
    target = tuple(np.repeat(np.asarray(p, dtype=float), PATHS, axis=0) for p in (a, b, radii2))
    points = np.tile(z, (n, 1))
    ends, arrived = _tracked(points, start, target, c, MAX_STEP)
    again = np.flatnonzero(~arrived)
    if len(again):
        ends[again], arrived[again] = _tracked(points[again], start, tuple(p[again] for p in target), c, RETRY_STEP)
    return ends.reshape(n, PATHS, 8), arrived.reshape(n, PATHS)


TRACKER = Path(__file__).with_name("_track.c")
CHUNK_PATHS = 40  # paths a thread takes at a time from the compiled tracker's batch


def _tracked(z: np.ndarray, start: tuple[np.ndarray, ...], target: tuple[np.ndarray, ...], c: np.ndarray,
             largest: float) -> tuple[np.ndarray, np.ndarray]:
    """The paths from z (R, 8) on the start instance (one, complex) to the target instances (real, a row each):
    their ends and whether they arrived, compiled where it can be."""
    rows = len(z)
    if rows == 0:
        return np.zeros((0, 8), complex), np.zeros(0, bool)
    run, _ = compiled.written_kernel(TRACKER)
    if run is None:
        return _tracked_in_numpy(z, start, target, c, largest)
    starts = np.concatenate([p.reshape(-1) for p in start]).astype(complex)
    inputs = [np.ascontiguousarray(np.concatenate([z.real, z.imag], axis=1)),
              np.ascontiguousarray(np.concatenate([p.reshape(rows, -1) for p in target], axis=1)),
              np.concatenate([starts.real, starts.imag]), np.concatenate([c.real, c.imag]),
              np.array([MAX_STEPS, FIRST_STEP, largest, GROWTH, LEAST_STEP, CORRECTIONS, CONVERGED, END_STEPS],
                       dtype=float)]
    ends, arrived = np.zeros((rows, 16)), np.zeros((rows, 1))
    chunks = [([inputs[0][k : k + CHUNK_PATHS], inputs[1][k : k + CHUNK_PATHS], *inputs[2:]],
               [ends[k : k + CHUNK_PATHS], arrived[k : k + CHUNK_PATHS], np.zeros((1, 1))],
               min(CHUNK_PATHS, rows - k), min(CHUNK_PATHS, rows - k)) for k in range(0, rows, CHUNK_PATHS)]
    run([16, 42, 0, 0, 0], chunks, batch.THREADS)
    return ends[:, :8] + 1j * ends[:, 8:], arrived[:, 0] > 0


def _tracked_in_numpy(z: np.ndarray, start: tuple[np.ndarray, ...], target: tuple[np.ndarray, ...], c: np.ndarray,
                      largest: float) -> tuple[np.ndarray, np.ndarray]:
    blocks = np.array_split(np.arange(len(z)), min(batch.THREADS, len(z)))

    def block(rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        begin = tuple(np.broadcast_to(p, (len(rows), *p.shape)) for p in start)
        return track(z[rows], begin, tuple(p[rows] for p in target), c, largest=largest)

    with ThreadPoolExecutor(len(blocks)) as pool:
        parts = list(pool.map(block, blocks))
    return np.concatenate([e for e, _ in parts]), np.concatenate([r for _, r in parts])


def real_poses(z: np.ndarray, arrived: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The real ones among Study points (..., 8): the rotations (..., 3, 3), the translations (..., 3), and
    which are real (arrived, and imaginary parts below REAL once scaled by their largest rotation entry)."""
    e = z[..., :4]
    largest = np.take_along_axis(e, np.argmax(np.abs(e), axis=-1)[..., None], axis=-1)
    with np.errstate(all="ignore"):
        w = z / largest
    real = arrived & np.all(np.abs(w.imag) <= REAL * np.maximum(np.abs(w), 1.0), axis=-1)
    e, g = w.real[..., :4], w.real[..., 4:]
    norm = np.sum(e * e, axis=-1, keepdims=True)
    t = 2 * np.stack(_times(tuple(np.moveaxis(g, -1, 0)), tuple(np.moveaxis(e * [1, -1, -1, -1], -1, 0)))[1:],
                     axis=-1) / norm
    u = e / np.sqrt(norm)
    w0, x, y, zz = np.moveaxis(u, -1, 0)
    rotation = np.stack([
        np.stack([1 - 2 * (y * y + zz * zz), 2 * (x * y - w0 * zz), 2 * (x * zz + w0 * y)], axis=-1),
        np.stack([2 * (x * y + w0 * zz), 1 - 2 * (x * x + zz * zz), 2 * (y * zz - w0 * x)], axis=-1),
        np.stack([2 * (x * zz - w0 * y), 2 * (y * zz + w0 * x), 1 - 2 * (x * x + y * y)], axis=-1)], axis=-2)
    return rotation, t, real


def pose_residual(rotation: np.ndarray, t: np.ndarray, a: np.ndarray, b: np.ndarray, r: np.ndarray,
                  ) -> np.ndarray:
    """The largest | |R b_i + t - a_i| - r_i | of each pose [m]."""
    ends = np.einsum("...ij,...kj->...ki", rotation, b) + t[..., None, :]
    return np.max(np.abs(np.linalg.norm(ends - a, axis=-1) - r), axis=-1)

