"""End-effector trajectories x(t), evaluated alike on numbers and on CasADi expressions, and the
checks of the vectors, times and positive scalars that the dynamics take as input.

A trajectory whose acceleration jumps (the trapezoidal speed profile of Wu 2008, Table 3) knows its
switch times. Its derivatives at a switch are one-sided: :meth:`Trajectory.sample` gives the values
just after by default and just before with ``side="before"``, and :meth:`Trajectory.switches` gives
both at every switch with the jump between them. A derivative taken at the kink of max(u, 0) would be
neither (CasADi gives max's derivative 1/2 at the tie).
"""

from __future__ import annotations

import math
import numbers
import reprlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError
from pkm.kinematics import as_real

SIDES = ("after", "before")


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
# The ramp max(u, 0) as a branch: at u = 0 CasADi differentiates the branch taken, so the ramp's
# derivative there is 1 when the branch u >= 0 is closed at 0 (the slope just after) and 0 with u > 0
# (just before).
_SYMBOLIC = {
    side: _Operations(
        ca.cos,
        ca.sin,
        lambda u: ca.fmin(ca.fmax(u, 0), 1),
        (lambda u: ca.if_else(u >= 0, u, 0)) if side == "after" else (lambda u: ca.if_else(u > 0, u, 0)),
        lambda c: ca.vertcat(*c),
    )
    for side in SIDES
}


def _operations(t: Any, side: str = "after") -> tuple[Any, _Operations]:
    if isinstance(t, ca.SX | ca.MX | ca.DM):
        return t, _SYMBOLIC[side]
    return np.asarray(t, dtype=float), _NUMERIC


def _side(side: str) -> str:
    if side not in SIDES:
        raise PkmError(f"side = {side!r} must be one of {', '.join(SIDES)}")
    return side


def rest_to_rest(u: Any) -> Any:
    """s(u) = 126 u^5 - 420 u^6 + 540 u^7 - 315 u^8 + 70 u^9: s(0) = 0, s(1) = 1, and its derivatives
    of orders 1 to 4 vanish at u = 0 and u = 1.
    """
    return u**5 * (126 + u * (-420 + u * (540 + u * (-315 + 70 * u))))


def as_vector(values: Any, size: int | None, what: str) -> np.ndarray:
    """``values`` as a finite vector of shape (size,) (of any length for None); :class:`PkmError` naming
    ``what`` otherwise."""
    arr = as_real(values, what, "(n,)" if size is None else f"({size},)")
    if arr.ndim != 1 or (size is not None and arr.shape != (size,)):
        raise PkmError(f"{what} must have shape {'(n,)' if size is None else (size,)}; got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise PkmError(f"{what} contains non-finite values")
    return arr


def as_times(times: Any, *, increasing: bool) -> np.ndarray:
    """``times`` as a finite 1-D array: one or more values, or at least two strictly increasing ones."""
    t = as_real(times, "times", "(N,)")
    if t.ndim != 1 or len(t) < (2 if increasing else 1):
        raise PkmError(f"times must be a 1-D array of {'at least two' if increasing else 'one or more'} values")
    if not np.all(np.isfinite(t)):
        raise PkmError("times contains non-finite values")
    if increasing and not np.all(np.diff(t) > 0):
        raise PkmError("times must be strictly increasing")
    return t


def as_positive(value: float, what: str) -> float:
    """``value`` as a positive finite float; :class:`PkmError` naming ``what`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise PkmError(f"{what} = {reprlib.repr(value)} violates: a real number")
    try:
        value = float(value)
    except OverflowError:
        raise PkmError(f"{what} = an integer too large for a float violates: finite") from None
    if not (np.isfinite(value) and value > 0):
        raise PkmError(f"{what} = {value:g} must be positive and finite")
    return value


@dataclass(frozen=True)
class Switches:
    """A trajectory's states at its switch times, where its acceleration jumps.

    Position and velocity are continuous there; the acceleration has a limit from each side.

    Attributes
    ----------
    times : ndarray, shape (k,)
        The switch times [s], increasing.
    position, velocity : ndarray, shape (k, n_out)
        x and x_dot at the switches.
    acceleration_before, acceleration_after : ndarray, shape (k, n_out)
        x_ddot just before and just after each switch (its limits from the left and from the right).
    """

    times: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration_before: np.ndarray
    acceleration_after: np.ndarray

    @property
    def acceleration_jump(self) -> np.ndarray:
        """x_ddot after less x_ddot before each switch, shape (k, n_out)."""
        return self.acceleration_after - self.acceleration_before


@dataclass(frozen=True)
class Trajectory:
    """An end-effector motion x(t).

    Attributes
    ----------
    path : callable
        t -> x(t) for a float (returns shape (n_out,)), a numpy array of times (shape t.shape + (n_out,))
        or a casadi scalar (an n_out x 1 expression); built from arithmetic that CasADi differentiates.
        At a switch time its derivatives are the limits from the right (the phase that starts there).
    duration : float
        The time the motion lasts [s], from t = 0.
    dimension : int
        n_out, the number of end-effector coordinates.
    description : str
    switch_times : tuple of float
        The times in [0, duration], increasing, at which the acceleration jumps (position and velocity
        are continuous there); empty for a motion whose acceleration is continuous.
    path_before : callable or None
        The same motion as ``path``, with its derivatives at a switch time the limits from the left;
        required where there are switch times.
    """

    path: Callable[[Any], Any]
    duration: float
    dimension: int
    description: str
    switch_times: tuple[float, ...] = ()
    path_before: Callable[[Any], Any] | None = None

    def __post_init__(self) -> None:
        times = np.asarray(self.switch_times, dtype=float)
        if times.ndim != 1 or not np.all(np.isfinite(times)):
            raise PkmError("switch_times must be a sequence of finite times")
        if np.any(np.diff(times) <= 0) or np.any(times < 0) or np.any(times > self.duration):
            raise PkmError(f"switch_times must increase strictly within [0, duration = {self.duration:g}]")
        if times.size and self.path_before is None:
            raise PkmError("path_before is required where switch_times are given (the left limits at the switches)")

    @classmethod
    def point_to_point(cls, start: Any, end: Any, duration: float) -> Trajectory:
        """A straight rest-to-rest motion x = start + (end - start) s(t / duration).

        s is the degree-9 polynomial of :func:`rest_to_rest`: velocity, acceleration, jerk and snap
        vanish at both ends, so the motor torques of the flexible model (which need the fourth
        derivative of x) start and end continuously. The position holds outside [0, duration].
        """
        a = as_vector(start, None, "start")
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
        short to reach v_max (v_max^2 >= a_max |x1 - x0|) is triangular: T0 = sqrt(|x1 - x0| / a_max),
        T_f = 2 T0. The arc length is s(t) = a_max / 2 sum_k c_k r(t - t_k)^2 with r(u) = max(u, 0), the
        switch times t_k = (0, T0, T_f - T0, T_f) and c_k = (1, -1, -1, 1) ((0, T0, T_f) and (1, -2, 1)
        for a triangle). The acceleration a_max sum_k c_k [t >= t_k] jumps by c_k a_max at t_k: see
        :meth:`switches` for its values on both sides.
        """
        a = as_vector(start, None, "start")
        b = as_vector(end, a.size, "end")
        v_max = as_positive(v_max, "v_max")
        a_max = as_positive(a_max, "a_max")
        length = float(np.linalg.norm(b - a))
        if length == 0:
            raise PkmError("start and end of a trapezoidal move coincide")
        if v_max**2 >= a_max * length:
            t0 = math.sqrt(length / a_max)
            total = 2 * t0
            switches, coefficients = (0.0, t0, total), (1.0, -2.0, 1.0)
        else:
            t0 = v_max / a_max
            total = length / v_max + t0
            switches, coefficients = (0.0, t0, total - t0, total), (1.0, -1.0, -1.0, 1.0)
        direction = (b - a) / length

        def motion(t: Any, side: str) -> Any:
            t, ops = _operations(t, side)
            s = a_max / 2 * sum(c * ops.ramp(t - t_k) ** 2 for c, t_k in zip(coefficients, switches, strict=True))
            return ops.stack([float(a_k) + float(e_k) * s for a_k, e_k in zip(a, direction, strict=True)])

        return cls(
            lambda t: motion(t, "after"),
            total,
            a.size,
            f"trapezoidal move from {a.tolist()} to {b.tolist()}: v_max {v_max:g}, a_max {a_max:g}, "
            f"T0 {t0:.4g} s, T_f {total:.4g} s",
            switches,
            lambda t: motion(t, "before"),
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
    def _derivatives(self) -> dict[str, ca.Function]:
        t = ca.SX.sym("t")
        functions = {}
        for side, path in (("after", self.path), ("before", self.path_before or self.path)):
            x = path(t)
            x_dot = ca.jacobian(x, t)
            functions[side] = ca.Function(
                f"trajectory_{side}", [t], [x, x_dot, ca.jacobian(x_dot, t)], ["t"], ["x", "x_dot", "x_ddot"]
            )
        return functions

    def sample(self, times: Any, *, side: str = "after") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Position, velocity and acceleration, each (N, n_out), at the times (N,), by CasADi's AD.

        At a switch time the acceleration is its limit from the right (the phase that starts there; at
        the end of a move, rest) with ``side="after"``, from the left with ``side="before"``; elsewhere
        both sides agree.
        """
        t = as_times(times, increasing=False)
        return tuple(v[:, :, 0] for v in evaluate(self._derivatives[_side(side)], t[:, None]))

    def switches(self) -> Switches:
        """The states at the switch times with the acceleration on both sides of each (none: k = 0)."""
        times = np.asarray(self.switch_times, dtype=float)
        if not times.size:
            empty = np.zeros((0, self.dimension))
            return Switches(times, empty, empty, empty, empty)
        x, x_dot, after = self.sample(times)
        _, _, before = self.sample(times, side="before")
        return Switches(times, x, x_dot, before, after)
