"""The workspace of the 2-UPS-PU under the four mechanical constraints of Zhao section 5, and the
prescribed task cylinder of section 6.

Each constraint is a margin, >= 0 where it holds, smooth where it can be (for IPOPT) and a boolean mask
when compared with 0 (for sampling), all in one CasADi function ``workspace_margins(q, x, design)``
composed from the generated ``first_order`` and ``joint_positions``:

* ``jacobian_sign``: det(J_n) times the sign of det(J_n) at the home orientation theta1 = theta2 = 0
  of the same l0, J_n = J diag(1, 1/r, 1/r). Eq. 9 as printed, |q| > 0, fails at the home pose of the
  paper's own Fig. 3 design (pkm: det < 0 there); the reading that makes sense is that the workspace
  does not cross the singular surface, so the determinant keeps its home sign.
* strokes (eq. 10): ``l1 - l_min``, ``l_max - l1``, the same for l2, ``l0 - l0_min``, ``l0_max - l0``.
* joint ranges (eqs. 11-12): cos(misalignment) - cos(limit) for the base universal joints U1, U2 (leg
  axis against the base normal Z), the spherical joints S1, S2 (leg axis against the platform normal
  z_p) and the platform universal joint U0 (z_p against Z).
* link interference (eq. 13): the least distance between the segments U1S1, U2S2 and OU0, pairwise,
  less the leg diameter D (closest points of two segments, clamped to the segments; continuous and
  piecewise smooth): the legs as capsules of radius D / 2, also the machine's ``collision(q, x, design) ->
  margins`` (:data:`COLLISIONS`) and ``capsules(design) -> radii``, so that the collision margin index, its maps
  and its region extremes in syntheses read them like a described machine's.
* the angles' range of eq. 6: pi/2 - |theta_i|, so that an angle is one turn of the platform, not an
  equivalent one several turns away (a tilt typed in degrees where radians go is out of reach).

The mechanism's inverse kinematics holds these margins in its reach (:func:`pkm.kinematics.within_limits`).

The task cylinder lives in (l0, gamma cos phi, gamma sin phi), phi and gamma the polar angle and tilt
of the platform normal (eq. 14): ``task_cylinder(design)`` places it (axis along l0 from l0_min,
radius task_tilt, height task_height) and ``tilt_to_pose`` maps its points to (l0, theta1, theta2)
by eq. 15.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate

MARGINS = (
    "jacobian_sign",
    "l1_min", "l1_max", "l2_min", "l2_max", "l0_min", "l0_max",
    "u1_range", "u2_range", "s1_range", "s2_range", "u0_range",
    "legs_1_2", "legs_1_0", "legs_2_0",
    "theta1_range", "theta2_range",
)
COLLISIONS = ("legs_1_2", "legs_1_0", "legs_2_0")  # the legs' capsules (diameter D) pairwise: the collision margins
PARALLEL = 1e-12  # [m^4] below this, two segments count as parallel
DEG = math.pi / 180
SMALL_TILT = 1e-6  # [rad] below this sin(gamma) / gamma is its Taylor polynomial


def segment_distance(p1: ca.SX, q1: ca.SX, p2: ca.SX, q2: ca.SX) -> ca.SX:
    """Least distance between the segments p1q1 and p2q2 (closest points, Ericson 2005 section 5.1.9)."""
    d1, d2, w = q1 - p1, q2 - p2, p1 - p2
    a, e = ca.dot(d1, d1), ca.dot(d2, d2)
    b, c, f = ca.dot(d1, d2), ca.dot(d1, w), ca.dot(d2, w)
    denominator = a * e - b**2
    s = ca.if_else(denominator > PARALLEL, ca.fmin(ca.fmax((b * f - c * e) / denominator, 0), 1), 0)
    t = (b * s + f) / e
    s = ca.if_else(t < 0, ca.fmin(ca.fmax(-c / a, 0), 1), ca.if_else(t > 1, ca.fmin(ca.fmax((b - c) / a, 0), 1), s))
    t = ca.fmin(ca.fmax(t, 0), 1)
    return ca.norm_2(p1 + s * d1 - (p2 + t * d2))


def functions(generated: Mapping[str, ca.Function], parameters: Sequence[str]) -> dict[str, ca.Function]:
    """``workspace_margins(q, x, design) -> margins`` (in the order of :data:`MARGINS`), the design
    vector's entries named by ``parameters``."""
    first_order, positions = generated["first_order"], generated["joint_positions"]
    q = ca.SX.sym("q", 3)
    x = ca.SX.sym("x", 3)
    d = ca.SX.sym("design", first_order.numel_in(2))
    value = {name: d[k] for k, name in enumerate(parameters)}
    r, l_min, l_max, l0_min, l0_max = (value[n] for n in ("r", "l_min", "l_max", "l0_min", "l0_max"))
    u_max, s_max, diameter = value["theta_u_max"], value["theta_s_max"], value["D"]
    scale = ca.diag(ca.vertcat(1, 1 / r, 1 / r))
    det = ca.det(first_order(q, x, d)[0] @ scale)
    home = ca.vertcat(x[0], 0, 0)
    home_q = generated["inverse_kinematics"](home, ca.DM([1.0]), d)[0]
    det_home = ca.det(first_order(home_q, home, d)[0] @ scale)
    u0, s1, s2, u1, u2, z_p = positions(x, d)
    a1 = (s1 - u1) / ca.norm_2(s1 - u1)
    a2 = (s2 - u2) / ca.norm_2(s2 - u2)
    origin = ca.DM.zeros(3)
    margins = ca.vertcat(
        det * ca.sign(det_home),
        q[0] - l_min, l_max - q[0], q[1] - l_min, l_max - q[1], x[0] - l0_min, l0_max - x[0],
        a1[2] - ca.cos(u_max), a2[2] - ca.cos(u_max),
        ca.dot(a1, z_p) - ca.cos(s_max), ca.dot(a2, z_p) - ca.cos(s_max),
        z_p[2] - ca.cos(u_max),
        segment_distance(u1, s1, u2, s2) - diameter,
        segment_distance(u1, s1, origin, u0) - diameter,
        segment_distance(u2, s2, origin, u0) - diameter,
        math.pi / 2 - ca.fabs(x[1]), math.pi / 2 - ca.fabs(x[2]),
    )
    y = ca.SX.sym("y", 3)
    gamma = ca.sqrt(y[1] ** 2 + y[2] ** 2)
    # sin(gamma) / gamma, continued at gamma = 0 (the cylinder's axis holds nodes of every extreme)
    sinc = ca.if_else(gamma > SMALL_TILT, ca.sin(gamma) / gamma, 1 - gamma**2 / 6)
    theta2 = ca.asin(sinc * y[1])
    theta1 = -ca.asin(sinc * y[2] / ca.cos(theta2))
    height = value["task_height"]
    legs = (margins[MARGINS.index(name)] for name in COLLISIONS)
    return {
        "workspace_margins": ca.Function(
            "workspace_margins", [q, x, d], [margins], ["q", "x", "design"], ["margins"]
        ),
        "collision": ca.Function("collision", [q, x, d], [ca.vertcat(*legs)], ["q", "x", "design"], ["margins"]),
        "capsules": ca.Function("capsules", [d], [ca.vertcat(*[diameter / 2] * 3)], ["design"], ["radii"]),
        "tilt_to_pose": ca.Function("tilt_to_pose", [y, d], [ca.vertcat(y[0], theta1, theta2)], ["y", "design"], ["x"]),
        "task_cylinder": ca.Function(
            "task_cylinder",
            [d],
            [ca.vertcat(l0_min + height / 2, 0, 0), ca.vertcat(value["task_tilt"], height / 2)],
            ["design"],
            ["centre", "size"],
        ),
    }


def tilt_to_angles(phi: np.ndarray, gamma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(theta1, theta2) of the platform normal at polar angle phi and tilt gamma (Zhao eqs. 14-15)."""
    theta2 = np.arcsin(np.sin(gamma) * np.cos(phi))
    theta1 = -np.arcsin(np.sin(gamma) * np.sin(phi) / np.cos(theta2))
    return theta1, theta2


def inside(mech: Any, x: np.ndarray, design: np.ndarray) -> np.ndarray:
    """Mask (N,) of the poses that satisfy every constraint."""
    q = mech.inverse_kinematics(x, design, limits=False)
    (margins,) = evaluate(mech.functions["workspace_margins"], q, x, design)
    return np.all(margins[:, :, 0] >= 0, axis=1)


@dataclass(frozen=True)
class Section:
    """The workspace at one l0: its area in the (theta1, theta2) plane [rad^2] by dense sampling and by
    the paper's ray search, the ray search's boundary (theta1, theta2), the sampled mask, and the rays
    along which the workspace re-enters after the first violation (where it is not star-shaped)."""

    l0: float
    sampled_area: float
    ray_area: float
    boundary: np.ndarray
    grid: np.ndarray
    mask: np.ndarray
    reentrant_rays: int


def section(mech: Any, design: np.ndarray, l0: float, *, resolution: int = 200, rays: int = 360,
            step: float = 0.25 * DEG) -> Section:
    """The workspace section at ``l0``: sampled on a resolution^2 grid over theta1, theta2 in
    [-90, 90] deg, and by the ray search of Zhao section 5.3 (step 5): along ``rays`` polar angles
    phi, the tilt gamma grows by ``step`` from the home orientation until a constraint fails. The ray
    search assumes the section is star-shaped about the home orientation in (phi, gamma); where it is
    not, the two areas differ."""
    axis = -math.pi / 2 + math.pi * (np.arange(resolution) + 0.5) / resolution
    T1, T2 = np.meshgrid(axis, axis, indexing="ij")
    grid = np.stack([np.full(T1.size, l0), T1.ravel(), T2.ravel()], axis=1)
    mask = inside(mech, grid, design)
    cell = (math.pi / resolution) ** 2
    phi = 2 * math.pi * np.arange(rays) / rays
    reach, reentrant = ray_reach(mech, design, l0, phi, step)
    b1, b2 = tilt_to_angles(phi, reach)
    boundary = np.stack([b1, b2], axis=1)
    ray_area = 0.5 * abs(np.dot(b1, np.roll(b2, -1)) - np.dot(b2, np.roll(b1, -1)))
    return Section(
        l0, float(mask.sum() * cell), float(ray_area), boundary, grid[:, 1:], mask.reshape(T1.shape), reentrant
    )


def ray_reach(mech: Any, design: np.ndarray, l0: float, phi: np.ndarray, step: float) -> tuple[np.ndarray, int]:
    """Zhao's ray search at ``l0`` (section 5.3, step 5): along each polar angle phi the tilt gamma grows
    by ``step`` from the home orientation until a constraint fails; the last tilt inside (phi.shape) and
    the number of rays along which the workspace re-enters beyond it."""
    gammas = np.arange(1, int(math.pi / 2 / step)) * step
    P, G = np.meshgrid(phi, gammas, indexing="ij")
    t1, t2 = tilt_to_angles(P.ravel(), G.ravel())
    ok = inside(mech, np.stack([np.full(t1.size, l0), t1, t2], axis=1), design).reshape(P.shape)
    first_out = np.where(ok.all(axis=1), len(gammas), np.argmin(ok, axis=1))
    beyond = np.arange(len(gammas))[None, :] > first_out[:, None]
    reentrant = int(np.any(ok & beyond, axis=1).sum())
    return np.where(first_out > 0, gammas[np.maximum(first_out - 1, 0)], 0.0), reentrant


def least_tilt(mech: Any, design: np.ndarray, levels: np.ndarray, *, rays: int = 360,
               step: float = 0.1 * DEG) -> np.ndarray:
    """Zhao's Fig. 9: at each l0 of ``levels``, the least over ``rays`` polar angles of the tilt the ray
    search reaches (:func:`ray_reach`); the workspace contains a task cylinder of tilt radius gamma_u over
    those levels where every value is at least gamma_u."""
    phi = 2 * math.pi * np.arange(rays) / rays
    return np.array([ray_reach(mech, design, float(l0), phi, step)[0].min() for l0 in levels])


def volume(mech: Any, design: np.ndarray, *, planes: int = 10, resolution: int = 200, rays: int = 360,
           step: float = 0.25 * DEG) -> dict[str, Any]:
    """The workspace volume [m rad^2] over the l0 stroke by the midpoint rule over ``planes`` sections
    (:func:`section`): by dense sampling and by the ray search, with the sections themselves."""
    d = mech.design_dict(design)
    height = (d["l0_max"] - d["l0_min"]) / planes
    levels = d["l0_min"] + height * (np.arange(planes) + 0.5)
    cuts = [section(mech, design, float(l0), resolution=resolution, rays=rays, step=step) for l0 in levels]
    return {
        "sampled": float(sum(c.sampled_area for c in cuts) * height),
        "ray_search": float(sum(c.ray_area for c in cuts) * height),
        "reentrant_rays": int(sum(c.reentrant_rays for c in cuts)),
        "sections": cuts,
    }
