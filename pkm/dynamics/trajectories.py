"""End-effector trajectories x(t), evaluated alike on numbers and on CasADi expressions, and the
checks of the vectors, times and positive scalars that the dynamics take as input.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError


@dataclass(frozen=True)
class _Operations:
    cos: Callable[[Any], Any]
    sin: Callable[[Any], Any]
    clip: Callable[[Any], Any]
    ramp: Callable[[Any], Any]
    stack: Callable[[list[Any]], Any]


_NUMERIC = _Operations(
    np.cos, np.sin, lambda u: np.clip(u, 0.0, 1.0), lambda u: np.maximum(u, 0.0), lambda c: np.stack(c, axis=-1)
)
_SYMBOLIC = _Operations(
    ca.cos, ca.sin, lambda u: ca.fmin(ca.fmax(u, 0), 1), lambda u: ca.fmax(u, 0), lambda c: ca.vertcat(*c)
)


def _operations(t: Any) -> tuple[Any, _Operations]:
    if isinstance(t, ca.SX | ca.MX | ca.DM):
        return t, _SYMBOLIC
    return np.asarray(t, dtype=float), _NUMERIC


def rest_to_rest(u: Any) -> Any:
    """s(u) = 126 u^5 - 420 u^6 + 540 u^7 - 315 u^8 + 70 u^9: s(0) = 0, s(1) = 1, and its derivatives
    of orders 1 to 4 vanish at u = 0 and u = 1.
    """
    return u**5 * (126 + u * (-420 + u * (540 + u * (-315 + 70 * u))))


def as_vector(values: Any, size: int, what: str) -> np.ndarray:
    """``values`` as a finite vector of shape (size,); :class:`PkmError` naming ``what`` otherwise."""
    arr = np.asarray(values, dtype=float)
    if arr.shape != (size,):
        raise PkmError(f"{what} must have shape ({size},); got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise PkmError(f"{what} contains non-finite values")
    return arr


def as_times(times: Any, *, increasing: bool) -> np.ndarray:
    """``times`` as a finite 1-D array: one or more values, or at least two strictly increasing ones."""
    t = np.asarray(times, dtype=float)
    if t.ndim != 1 or len(t) < (2 if increasing else 1):
        raise PkmError(f"times must be a 1-D array of {'at least two' if increasing else 'one or more'} values")
    if not np.all(np.isfinite(t)):
        raise PkmError("times contains non-finite values")
    if increasing and not np.all(np.diff(t) > 0):
        raise PkmError("times must be strictly increasing")
    return t


def as_positive(value: float, what: str) -> float:
    """``value`` as a positive finite float; :class:`PkmError` naming ``what`` otherwise."""
    value = float(value)
    if not (np.isfinite(value) and value > 0):
        raise PkmError(f"{what} = {value:g} must be positive and finite")
    return value


@dataclass(frozen=True)
class Trajectory:
    """An end-effector motion x(t).

    Attributes
    ----------
    path : callable
        t -> x(t) for a float (returns shape (n_out,)), a numpy array of times (shape t.shape + (n_out,))
        or a casadi scalar (an n_out x 1 expression); built from arithmetic that CasADi differentiates.
    duration : float
        The time the motion lasts [s], from t = 0.
    dimension : int
        n_out, the number of end-effector coordinates.
    description : str
    """

    path: Callable[[Any], Any]
    duration: float
    dimension: int
    description: str

    @classmethod
    def point_to_point(cls, start: Any, end: Any, duration: float) -> Trajectory:
        """A straight rest-to-rest motion x = start + (end - start) s(t / duration).

        s is the degree-9 polynomial of :func:`rest_to_rest`: velocity, acceleration, jerk and snap
        vanish at both ends, so the motor torques of the flexible model (which need the fourth
        derivative of x) start and end continuously. The position holds outside [0, duration].
        """
        a = as_vector(start, np.size(start), "start")
        b = as_vector(end, a.size, "end")
        duration = as_positive(duration, "duration")

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            s = rest_to_rest(ops.clip(t / duration))
            return ops.stack([float(a_k) + float(b_k - a_k) * s for a_k, b_k in zip(a, b, strict=True)])

        return cls(path, duration, a.size, f"rest-to-rest from {a.tolist()} to {b.tolist()} in {duration:g} s")

    @classmethod
    def trapezoidal(cls, start: Any, end: Any, v_max: float, a_max: float) -> Trajectory:
        """A straight move with a trapezoidal speed profile (Wu 2008 section 6.2, Table 3).

        Equal accelerating and decelerating times T0 = v_max / a_max at +-a_max, cruising at v_max in
        between; the total time T_f satisfies Wu's eq. 45, T0 = T_f - |x1 - x0| / v_max. A move too
        short to reach v_max is triangular (T0 = sqrt(|x1 - x0| / a_max)). The arc length is
        s(t) = a_max / 2 (r(t)^2 - r(t - T0)^2 - r(t - T_f + T0)^2 + r(t - T_f)^2), r(u) = max(u, 0);
        the acceleration jumps at the phase changes.
        """
        a = as_vector(start, np.size(start), "start")
        b = as_vector(end, a.size, "end")
        v_max = as_positive(v_max, "v_max")
        a_max = as_positive(a_max, "a_max")
        length = float(np.linalg.norm(b - a))
        if length == 0:
            raise PkmError("start and end of a trapezoidal move coincide")
        t0 = min(v_max / a_max, math.sqrt(length / a_max))
        total = length / (a_max * t0) + t0
        direction = (b - a) / length

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            r = ops.ramp
            s = a_max / 2 * (r(t) ** 2 - r(t - t0) ** 2 - r(t - total + t0) ** 2 + r(t - total) ** 2)
            return ops.stack([float(a_k) + float(e_k) * s for a_k, e_k in zip(a, direction, strict=True)])

        return cls(
            path,
            total,
            a.size,
            f"trapezoidal move from {a.tolist()} to {b.tolist()}: v_max {v_max:g}, a_max {a_max:g}, "
            f"T0 {t0:.4g} s, T_f {total:.4g} s",
        )

    @classmethod
    def circle(cls, centre: Any, radius: float, period: float, turns: float = 1.0) -> Trajectory:
        """A planar circle at constant speed, x = centre + radius (cos w t, sin w t) with w = 2 pi / period.

        It starts at centre + (radius, 0) and lasts ``turns`` periods; the motion continues outside
        [0, duration] (it has no rest at its ends).
        """
        c = as_vector(centre, 2, "centre")
        radius = as_positive(radius, "radius")
        period = as_positive(period, "period")
        turns = as_positive(turns, "turns")
        omega = 2 * np.pi / period

        def path(t: Any) -> Any:
            t, ops = _operations(t)
            angle = omega * t
            return ops.stack([c[0] + radius * ops.cos(angle), c[1] + radius * ops.sin(angle)])

        return cls(path, turns * period, 2, f"circle about {c.tolist()}, radius {radius:g}, period {period:g} s")

    def position(self, t: Any) -> Any:
        """x(t) for a float, a numpy array of times or a casadi scalar (see :attr:`path`)."""
        return self.path(t)

    @cached_property
    def _derivatives(self) -> ca.Function:
        t = ca.SX.sym("t")
        x = self.path(t)
        x_dot = ca.jacobian(x, t)
        return ca.Function("trajectory", [t], [x, x_dot, ca.jacobian(x_dot, t)], ["t"], ["x", "x_dot", "x_ddot"])

    def sample(self, times: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration, each (N, n_out), at the times (N,), by CasADi's AD."""
        t = as_times(times, increasing=False)
        return tuple(v[:, :, 0] for v in evaluate(self._derivatives, t[:, None]))
