"""Workspace-based synthesis of the slider gantry (Wu 2008 section 4): the paper's own procedure.

Wu's two steps: for a task rectangle b x h and the smallest link angle theta_1S, eqs. 10-16 give the
link length l, the half distance d1 and the slider stroke with the input/output ratio y_d1 : b = 1 : 1
of eq. 13 (theta_1S + theta_2L = 90 deg); then theta_1S is chosen for the velocity ratio k_av
(eqs. 6-7). :func:`workspace_synthesis` is the first step, :func:`two_step_design` turns its result into
a complete pkm design with the task rectangle at a chosen height.

pkm's IPOPT synthesis over the same model is :mod:`pkm.models.slider_gantry.problems`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from pkm import registry
from pkm.errors import DesignError, check_real

DEG = math.pi / 180


def _positive(name: str, value: float, unit: str = "m", *, closed: bool = False) -> float:
    value = check_real(name, value, f"a finite number {'>=' if closed else '>'} 0 [{unit}]", DesignError)
    ok = value >= 0 if closed else value > 0
    if not ok:
        raise DesignError(f"{name} = {value:g} {unit} violates {name} {'>=' if closed else '>'} 0")
    return value


@dataclass(frozen=True)
class WorkspaceSynthesis:
    """Wu's first step (eqs. 10-16) for a task rectangle b x h [m] and the smallest link angle theta_1S.

    Attributes: ``d`` [m] the horizontal offset of link 1 at Q2 (eq. 14), ``theta_2l`` [rad] the
    largest link angle (pi/2 - theta_1S, eq. 13), ``length`` (Wu's l) and ``d1`` [m] (eq. 15), ``y_d1`` [m] the slider
    travel from Q2 to Q3 (eq. 12, equal to b) and ``stroke`` [m] |q_iL - q_iS| (eq. 16).
    """

    b: float
    h: float
    theta_1s: float
    d: float
    theta_2l: float
    length: float
    d1: float
    y_d1: float
    stroke: float


def workspace_synthesis(b: float, h: float, theta_1s: float) -> WorkspaceSynthesis:
    """Wu eqs. 10-16: l, d1 and the stroke for the task rectangle b x h [m] and theta_1S [rad].

    theta_1S must lie in (0, 45 deg): eq. 14's d = b tan(theta_1S) / (1 - tan(theta_1S)) is positive
    only there (at 45 deg the two angle limits meet and l is unbounded).
    """
    b = _positive("b", b)
    h = _positive("h", h)
    theta_1s = check_real("theta_1S", theta_1s, "a number in (0, 45 deg) [rad]", DesignError)
    if not 0 < theta_1s < math.pi / 4:
        raise DesignError(
            f"theta_1S = {theta_1s:g} rad ({theta_1s / DEG:g} deg) violates 0 < theta_1S < 45 deg (Wu eq. 14)"
        )
    t = math.tan(theta_1s)
    d = b * t / (1 - t)
    theta_2l = math.pi / 2 - theta_1s
    length = (b + d) / math.sin(theta_2l)
    y_d1 = length * (math.cos(theta_1s) - math.sin(math.pi / 2 - theta_2l))
    return WorkspaceSynthesis(
        b=b,
        h=h,
        theta_1s=theta_1s,
        d=d,
        theta_2l=theta_2l,
        length=length,
        d1=(b + 2 * d) / 2,
        y_d1=y_d1,
        stroke=y_d1 + h,
    )


def placement(length: float, d1: float, b: float, h: float, *, l2: float, centre_y: float) -> tuple[float, float]:
    """Stroke limits (qs, ql) [m] that put the bottom of a b x h rectangle centred at (0, centre_y) on
    the lower stroke limit (Q2, Q3 of Wu Fig. 2) and its top on the upper one (Q1, Q4)."""
    qs = centre_y - h / 2 - l2 / 2 - math.sqrt(length**2 - (d1 - b / 2) ** 2)
    ql = centre_y + h / 2 - l2 / 2 - math.sqrt(length**2 - (d1 + b / 2) ** 2)
    return qs, ql


REFERENCE_LENGTH = 0.6164  # [m] Table 1's l, at which Table 2's link inertias hold
SCALED_INERTIAS = ("I12", "I22", "I4", "I5")
HALF_LENGTH_OFFSETS = ("s12", "s22", "s4", "s5")


def scaled_links(base: dict[str, Any], length: Any) -> dict[str, Any]:
    """Table 2's link parameters for links of length ``length`` (a number or CasADi): each link keeps its
    mass, its centre of mass at s = l/2 and its inertia about the pivot scaled as l^2 from Table 2's (at
    Table 1's l); the parameters of ``base`` the mechanism has."""
    scale = (length / REFERENCE_LENGTH) ** 2
    out = {name: base[name] * scale for name in SCALED_INERTIAS if name in base}
    out.update({name: length / 2 for name in HALF_LENGTH_OFFSETS if name in base})
    return out


def two_step_design(
    b: float,
    h: float,
    theta_1s: float,
    *,
    d2: float,
    l2: float,
    centre_y: float = 0.5,
    mechanism: str = "slider_gantry",
    **inertial: float,
) -> dict[str, float]:
    """A complete design from Wu's first step, the task rectangle centred at (0, centre_y) [m].

    The angle margins are theta_s = theta_1S and theta_l = theta_2L; the strokes put the rectangle's
    bottom and top on the slider limits (:func:`placement`). The links' inertias and centres of mass
    follow their length (:func:`scaled_links`, as the synthesis problems scale them); ``inertial``
    overrides Table 2's values.
    """
    first = workspace_synthesis(b, h, theta_1s)
    d2 = _positive("d2", d2, closed=True)
    l2 = _positive("l2", l2)
    qs, ql = placement(first.length, first.d1, b, h, l2=l2, centre_y=centre_y)
    values = {
        "l": first.length,
        "d1": first.d1,
        "d2": d2,
        "l2": l2,
        "qs": qs,
        "ql": ql,
        "theta_s": first.theta_1s,
        "theta_l": first.theta_2l,
    }
    mech = registry.mechanism(mechanism)
    values.update({**scaled_links(dict(mech.design()), first.length), **inertial})
    return dict(mech.design(values))


def k_av_closed_form(length: float, d1: float, b: float) -> float:
    """Wu eq. 7 in closed form: the mean of k_v = cot(theta_1) = sqrt(l^2 - u^2) / u over u = x + d1,
    x in [-b/2, b/2]; an antiderivative of sqrt(l^2 - u^2) / u is sqrt(l^2 - u^2) - l artanh(sqrt(l^2 -
    u^2) / l)."""

    def antiderivative(u: float) -> float:
        s = math.sqrt(length**2 - u**2)
        return s - length * math.atanh(s / length)

    length, d1, b = (_positive(name, value) for name, value in (("l", length), ("d1", d1), ("b", b)))
    lo, hi = d1 - b / 2, d1 + b / 2
    if not (lo > 0 and hi <= length):
        raise DesignError(f"k_av needs 0 < d1 - b/2 and d1 + b/2 <= l; got d1 = {d1:g}, b = {b:g}, l = {length:g}")
    return (antiderivative(hi) - antiderivative(lo)) / b


def required_stroke(length, d1, b: float, h: float):
    """Slider stroke [m] that a b x h rectangle centred on x = 0 needs: h plus the rise between the
    links' extreme angles (Wu eq. 16 with y_d1 = l (cos theta_min - cos theta_max))."""
    return h + sqrt(length**2 - (d1 - b / 2) ** 2) - sqrt(length**2 - (d1 + b / 2) ** 2)


def sqrt(value: Any) -> Any:
    """Square root of a float, an array or a CasADi expression."""
    return ca.sqrt(value) if isinstance(value, ca.MX | ca.SX) else np.sqrt(value)


def asin(value: Any) -> Any:
    """Arcsine of a float, an array or a CasADi expression."""
    return ca.asin(value) if isinstance(value, ca.MX | ca.SX) else np.arcsin(value)


def two_step_angles(theta_s: float, samples: int) -> np.ndarray:
    """theta_1S of Wu's two-step family from the margin theta_s up to 44.9 deg (eq. 14 needs < 45)."""
    return np.linspace(theta_s, 44.9 * DEG, samples)


def two_step_points(b: float, h: float, angles: np.ndarray) -> np.ndarray:
    """(l, d1) [m] of Wu's eqs. 14-15 along the two-step family for the angles theta_1S."""
    out = [workspace_synthesis(b, h, t) for t in angles]
    return np.array([[w.length, w.d1] for w in out])
