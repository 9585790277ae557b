"""Independent numpy oracles for the three machines of issue 24: inverse kinematics and Jacobian of the
symmetric planar 3-RRR, the Delta robot and the 6-UPS Stewart-Gough platform, written by hand from the
geometry and in pkm's conventions, so that the descriptions pkm derives can be checked against them.

Conventions shared by all three:

- ``pose`` is (n,) or (N, n); every result keeps that leading shape: q is (n_act,) or (N, n_act) and J is
  (n_act, n) or (N, n_act, n).
- ``design`` is a dict of the named parameters (lengths in m, angles in rad).
- ``J`` maps the time derivative of the pose coordinates as listed (rates of the angles, not the angular
  velocity) to the actuator rates: ``q_dot = J x_dot``. It is formed in closed form from each leg's closure
  ``h_i(x, q_i) = 0``: ``J_i = -(dh_i/dq_i)^-1 dh_i/dx``, never by finite differences.
- ``*_closure(pose, design, q)`` gives each leg's closure h_i, dh/dx and dh_i/dq_i at any actuated joints q:
  the Jacobians above and, for the Delta and the 6-UPS, the loops of bench/numpy_models.py's forward
  kinematics by Newton's method (the 3-RRR's there is in its distal angles too, as pkm states it).
- A pose out of reach gives NaN in the legs that cannot close (``arccos`` of a number beyond +-1).

3-RRR (pose ``(x, y, phi)``, design ``R_b, r_p, l1, l2``). Leg i = 0, 1, 2 at ``a_i = pi/2 + 2 pi i / 3``:
base joint ``A_i = R_b e(a_i)``, platform joint ``C_i = (x, y) + r_p e(phi + a_i)`` with
``e(t) = (cos t, sin t)``, elbow ``B_i = A_i + l1 e(theta_i)``, distal link ``|C_i - B_i| = l2``. With
``d = C_i - A_i`` and the elbow sign ``s_i``::

    theta_i = atan2(d_y, d_x) + s_i acos((l1^2 + |d|^2 - l2^2) / (2 l1 |d|))      (not wrapped)

so that ``s_i = +1`` puts the elbow counter-clockwise of the line A_i -> C_i. From
``h_i = |C_i - B_i|^2 - l2^2`` with ``w = C_i - B_i`` and ``rho = C_i - (x, y)``::

    dh_i/dx = 2 [w_x, w_y, rho_x w_y - rho_y w_x],  dh_i/dtheta_i = -2 l1 (w_y cos theta_i - w_x sin theta_i)
    J_i = [w_x, w_y, rho_x w_y - rho_y w_x] / (l1 (w_y cos theta_i - w_x sin theta_i))

Delta (pose ``(x, y, z)``, z up, platform below the base; design ``R, r, L_a, L_b``). Arm i at
``psi_i = 2 pi i / 3``: radial ``e_i = (cos psi_i, sin psi_i, 0)``, base joint ``R e_i`` with axis
``(-sin psi_i, cos psi_i, 0)``, elbow ``E_i = (R + L_a cos theta_i) e_i - L_a sin theta_i e_z`` (theta_i from
the horizontal outward direction, positive downward), platform joint ``P_i = (x, y, z) + r e_i``,
forearm ``|P_i - E_i| = L_b``. With ``d = P_i - R e_i`` the closure reads ``a cos theta + b sin theta = c``,
``a = 2 L_a d.e_i``, ``b = -2 L_a d_z``, ``c = |d|^2 + L_a^2 - L_b^2``, and::

    theta_i = atan2(b, a) - branch_i acos(c / sqrt(a^2 + b^2))                     (not wrapped)

``atan2(b, a)`` is the direction, in the arm's plane (outward, downward), of the projection of P_i seen from
the base joint. Branch +1 is the solution whose angle is below that direction, i.e. whose elbow lies on the
outer-upper side of the line from the base joint to P_i's projection: the usual "elbow out" configuration
(knee outside the base circle, ``cos theta_i > 0``, over the usual working range below the base); it is
always the smaller of the two theta_i. Branch -1 is the elbow folded inward. From
``h_i = |P_i - E_i|^2 - L_b^2`` with ``w = P_i - E_i``::

    dh_i/dx = 2 w^T,  dh_i/dtheta_i = -2 w . dE_i/dtheta_i,  dE_i/dtheta_i = -L_a (sin theta_i e_i + cos theta_i e_z)
    J_i = w^T / (w . dE_i/dtheta_i)

6-UPS Stewart-Gough (pose ``(x, y, z, alpha, beta, gamma)``, ``R = Rz(gamma) Ry(beta) Rx(alpha)``; design
``R_b, r_p, theta_b, theta_p``). Leg k = 0..5 joins base point k to platform point k::

    b_k = R_b (cos u_k, sin u_k, 0),  u_k = 2 pi floor(k/2) / 3 + (-1)^(k+1) theta_b / 2
    p_k = r_p (cos v_k, sin v_k, 0),  v_k = 2 pi floor(k/2) / 3 + (-1)^(k+1) (pi/3 - theta_p / 2)

The base pairs (legs 0-1, 2-3, 4-5) are centred at 0, 120 and 240 deg with half-separation theta_b / 2; the
platform pairs, centred at 300, 60 and 180 deg with half-separation theta_p / 2, are (5, 0), (1, 2) and
(3, 4): leg 2j goes from the base pair at 120 j deg to the platform pair at 120 j - 60 deg, leg 2j + 1 to
the one at 120 j + 60 deg, so each platform pair joins two different base pairs (the classic 6-6 platform;
its two points nearest to their base points). The actuated leg length is ``l_k = |(x, y, z) + R p_k - b_k|``
and, from ``h_k = |s_k|^2 - l_k^2`` with the leg vector ``s_k = (x, y, z) + R p_k - b_k`` and the unit leg
vector ``n_k = s_k / l_k``::

    dh_k/dx = 2 [s_k^T, ((R p_k) x s_k)^T E],  dh_k/dl_k = -2 l_k
    J_k = [n_k^T, ((R p_k) x n_k)^T E(alpha, beta, gamma)],
    omega = E [alpha_dot, beta_dot, gamma_dot],
    E = [[cos gamma cos beta, -sin gamma, 0], [sin gamma cos beta, cos gamma, 0], [-sin beta, 0, 1]]

(``omega = gamma_dot e_z + beta_dot Rz(gamma) e_y + alpha_dot Rz(gamma) Ry(beta) e_x`` in the base frame).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

__all__ = [
    "delta_closure",
    "delta_elbows",
    "delta_ik",
    "delta_jacobian",
    "rrr3_closure",
    "rrr3_elbows",
    "rrr3_ik",
    "rrr3_jacobian",
    "rrr3_leg_angles",
    "rrr3_points",
    "sgp_angular_rate_map",
    "sgp_attachment_angles",
    "sgp_closure",
    "sgp_ik",
    "sgp_jacobian",
    "sgp_rotation",
]

Design = Mapping[str, float]
Signs = int | Sequence[int] | np.ndarray


def _batch(pose: np.ndarray | Sequence[float], n: int) -> tuple[np.ndarray, bool]:
    """The poses as (N, n) and whether one pose (n,) was given."""
    x = np.asarray(pose, dtype=float)
    if x.shape[-1] != n or x.ndim not in (1, 2):
        raise ValueError(f"pose must be ({n},) or (N, {n}), got shape {x.shape}")
    return np.atleast_2d(x), x.ndim == 1


def _signs(signs: Signs, count: int) -> np.ndarray:
    """Branch signs broadcast to (count,), each +1 or -1."""
    s = np.broadcast_to(np.asarray(signs, dtype=float), (count,))
    if not np.all(np.abs(s) == 1):
        raise ValueError(f"branch signs must be +1 or -1, got {s}")
    return s


def _out(value: np.ndarray, single: bool) -> np.ndarray:
    return value[0] if single else value


# --- 3-RRR ---------------------------------------------------------------------------------------------

RRR3_LEG_ANGLES = np.pi / 2 + 2 * np.pi * np.arange(3) / 3


def rrr3_leg_angles() -> np.ndarray:
    """(3,) the angles a_i = pi/2 + 2 pi i / 3 of the base and platform joints."""
    return RRR3_LEG_ANGLES.copy()


def rrr3_points(x: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Base joints A (3, 2), platform joints C (N, 3, 2) and platform vectors rho = C - (x, y) (N, 3, 2) at
    the poses x (N, 3)."""
    a = RRR3_LEG_ANGLES
    A = design["R_b"] * np.stack([np.cos(a), np.sin(a)], axis=-1)
    t = x[:, 2:3] + a
    rho = design["r_p"] * np.stack([np.cos(t), np.sin(t)], axis=-1)
    return A, x[:, None, :2] + rho, rho


def rrr3_ik(pose: np.ndarray | Sequence[float], design: Design, signs: Signs) -> np.ndarray:
    """Actuated absolute angles theta (3,) or (N, 3) of the 3-RRR at ``pose`` (x, y, phi) for the elbow
    signs ``signs`` (+1 or -1, one per leg or one for all); NaN where a leg cannot close."""
    x, single = _batch(pose, 3)
    s = _signs(signs, 3)
    A, C, _ = rrr3_points(x, design)
    d = C - A
    dist = np.hypot(d[..., 0], d[..., 1])
    l1, l2 = design["l1"], design["l2"]
    with np.errstate(invalid="ignore"):
        opening = np.arccos((l1**2 + dist**2 - l2**2) / (2 * l1 * dist))
    return _out(np.arctan2(d[..., 1], d[..., 0]) + s * opening, single)


def rrr3_elbows(pose: np.ndarray | Sequence[float], design: Design, theta: np.ndarray) -> np.ndarray:
    """Elbows B_i = A_i + l1 e(theta_i), (3, 2) or (N, 3, 2), for the actuated angles ``theta``."""
    single = np.ndim(pose) == 1
    th = np.atleast_2d(theta)
    A, _, _ = rrr3_points(_batch(pose, 3)[0], design)
    return _out(A + design["l1"] * np.stack([np.cos(th), np.sin(th)], axis=-1), single)


def rrr3_closure(
    pose: np.ndarray | Sequence[float], design: Design, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each leg's closure h_i = |C_i - B_i|^2 - l2^2 at the actuated angles ``theta`` (3,) or (N, 3), with
    dh/dx (3, 3) or (N, 3, 3) and dh_i/dtheta_i (3,) or (N, 3) (module docstring)."""
    x, single = _batch(pose, 3)
    th = np.atleast_2d(theta)
    _, C, rho = rrr3_points(x, design)
    w = C - rrr3_elbows(x, design, th)
    wx, wy = w[..., 0], w[..., 1]
    h = wx * wx + wy * wy - design["l2"] ** 2
    H_x = 2 * np.stack([wx, wy, rho[..., 0] * wy - rho[..., 1] * wx], axis=-1)
    H_q = -2 * design["l1"] * (wy * np.cos(th) - wx * np.sin(th))
    return _out(h, single), _out(H_x, single), _out(H_q, single)


def rrr3_jacobian(pose: np.ndarray | Sequence[float], design: Design, signs: Signs) -> np.ndarray:
    """J (3, 3) or (N, 3, 3) of the 3-RRR, ``theta_dot = J (x_dot, y_dot, phi_dot)``, from each leg's
    closure |C_i - B_i|^2 = l2^2 (module docstring)."""
    x, single = _batch(pose, 3)
    _, H_x, H_q = rrr3_closure(x, design, rrr3_ik(x, design, signs))
    return _out(-H_x / H_q[..., None], single)


# --- Delta ---------------------------------------------------------------------------------------------

DELTA_ARM_ANGLES = 2 * np.pi * np.arange(3) / 3


def _delta_frames() -> tuple[np.ndarray, np.ndarray]:
    """Radial unit vectors e_i (3, 3) and e_z (3,)."""
    psi = DELTA_ARM_ANGLES
    radial = np.stack([np.cos(psi), np.sin(psi), np.zeros(3)], axis=-1)
    return radial, np.array([0.0, 0.0, 1.0])


def _delta_platform_joints(x: np.ndarray, design: Design) -> np.ndarray:
    radial, _ = _delta_frames()
    return x[:, None, :] + design["r"] * radial


def delta_ik(pose: np.ndarray | Sequence[float], design: Design, branch: Signs) -> np.ndarray:
    """Actuated arm angles theta (3,) or (N, 3) of the Delta at ``pose`` (x, y, z) on ``branch`` (+1 elbow
    out, -1 elbow in; one per arm or one for all); NaN where an arm cannot close."""
    x, single = _batch(pose, 3)
    s = _signs(branch, 3)
    radial, _ = _delta_frames()
    d = _delta_platform_joints(x, design) - design["R"] * radial
    La, Lb = design["L_a"], design["L_b"]
    a = 2 * La * np.einsum("nij,ij->ni", d, radial)
    b = -2 * La * d[..., 2]
    c = np.einsum("nij,nij->ni", d, d) + La**2 - Lb**2
    with np.errstate(invalid="ignore"):
        opening = np.arccos(c / np.hypot(a, b))
    return _out(np.arctan2(b, a) - s * opening, single)


def delta_elbows(pose: np.ndarray | Sequence[float], design: Design, theta: np.ndarray) -> np.ndarray:
    """Elbows E_i (3, 3) or (N, 3, 3) for the arm angles ``theta``."""
    single = np.ndim(pose) == 1
    th = np.atleast_2d(theta)[..., None]
    radial, ez = _delta_frames()
    elbows = (design["R"] + design["L_a"] * np.cos(th)) * radial - design["L_a"] * np.sin(th) * ez
    return _out(elbows, single)


def delta_closure(
    pose: np.ndarray | Sequence[float], design: Design, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each arm's closure h_i = |P_i - E_i|^2 - L_b^2 at the arm angles ``theta`` (3,) or (N, 3), with dh/dx
    (3, 3) or (N, 3, 3) and dh_i/dtheta_i (3,) or (N, 3) (module docstring)."""
    x, single = _batch(pose, 3)
    th = np.atleast_2d(theta)
    radial, ez = _delta_frames()
    w = _delta_platform_joints(x, design) - delta_elbows(x, design, th)
    dE = -design["L_a"] * (np.sin(th[..., None]) * radial + np.cos(th[..., None]) * ez)
    h = np.einsum("nij,nij->ni", w, w) - design["L_b"] ** 2
    return _out(h, single), _out(2 * w, single), _out(-2 * np.einsum("nij,nij->ni", w, dE), single)


def delta_jacobian(pose: np.ndarray | Sequence[float], design: Design, branch: Signs) -> np.ndarray:
    """J (3, 3) or (N, 3, 3) of the Delta, ``theta_dot = J (x_dot, y_dot, z_dot)``, from each arm's closure
    |P_i - E_i|^2 = L_b^2 (module docstring)."""
    x, single = _batch(pose, 3)
    _, H_x, H_q = delta_closure(x, design, delta_ik(x, design, branch))
    return _out(-H_x / H_q[..., None], single)


# --- 6-UPS Stewart-Gough platform ------------------------------------------------------------------------


def sgp_attachment_angles(design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Polar angles (u_k, v_k), each (6,), of the base and platform points (module docstring)."""
    k = np.arange(6)
    centre = 2 * np.pi * (k // 2) / 3
    side = (-1.0) ** (k + 1)
    return centre + side * design["theta_b"] / 2, centre + side * (np.pi / 3 - design["theta_p"] / 2)


def _sgp_points(design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Base points b_k and platform points p_k (platform frame), each (6, 3)."""
    u, v = sgp_attachment_angles(design)
    base = design["R_b"] * np.stack([np.cos(u), np.sin(u), np.zeros(6)], axis=-1)
    platform = design["r_p"] * np.stack([np.cos(v), np.sin(v), np.zeros(6)], axis=-1)
    return base, platform


def sgp_rotation(angles: np.ndarray) -> np.ndarray:
    """R = Rz(gamma) Ry(beta) Rx(alpha), (..., 3, 3), for ``angles`` (..., 3) = (alpha, beta, gamma)."""
    ang = np.asarray(angles, dtype=float)
    ca, sa = np.cos(ang[..., 0]), np.sin(ang[..., 0])
    cb, sb = np.cos(ang[..., 1]), np.sin(ang[..., 1])
    cg, sg = np.cos(ang[..., 2]), np.sin(ang[..., 2])
    rows = [
        [cg * cb, cg * sb * sa - sg * ca, cg * sb * ca + sg * sa],
        [sg * cb, sg * sb * sa + cg * ca, sg * sb * ca - cg * sa],
        [-sb, cb * sa, cb * ca],
    ]
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def sgp_angular_rate_map(angles: np.ndarray) -> np.ndarray:
    """E (..., 3, 3) with omega = E (alpha_dot, beta_dot, gamma_dot), omega in the base frame."""
    ang = np.asarray(angles, dtype=float)
    cb, sb = np.cos(ang[..., 1]), np.sin(ang[..., 1])
    cg, sg = np.cos(ang[..., 2]), np.sin(ang[..., 2])
    zero, one = np.zeros_like(cb), np.ones_like(cb)
    rows = [[cg * cb, -sg, zero], [sg * cb, cg, zero], [-sb, zero, one]]
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2)


def _sgp_legs(x: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Leg vectors s_k = (x, y, z) + R p_k - b_k and rotated platform points R p_k, each (N, 6, 3)."""
    base, platform = _sgp_points(design)
    rotated = np.einsum("nij,kj->nki", sgp_rotation(x[:, 3:]), platform)
    return x[:, None, :3] + rotated - base, rotated


def sgp_ik(pose: np.ndarray | Sequence[float], design: Design) -> np.ndarray:
    """Leg lengths l (6,) or (N, 6) of the 6-UPS at ``pose`` (x, y, z, alpha, beta, gamma)."""
    x, single = _batch(pose, 6)
    legs, _ = _sgp_legs(x, design)
    return _out(np.linalg.norm(legs, axis=-1), single)


def sgp_closure(
    pose: np.ndarray | Sequence[float], design: Design, lengths: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each leg's closure h_k = |s_k|^2 - l_k^2 at the leg lengths ``lengths`` (6,) or (N, 6), with dh/dx
    (6, 6) or (N, 6, 6) and dh_k/dl_k (6,) or (N, 6) (module docstring)."""
    x, single = _batch(pose, 6)
    length = np.atleast_2d(lengths)
    legs, rotated = _sgp_legs(x, design)
    moment = np.einsum("nkj,nji->nki", np.cross(rotated, legs), sgp_angular_rate_map(x[:, 3:]))
    h = np.einsum("nkj,nkj->nk", legs, legs) - length * length
    return _out(h, single), _out(2 * np.concatenate([legs, moment], axis=-1), single), _out(-2 * length, single)


def sgp_jacobian(pose: np.ndarray | Sequence[float], design: Design) -> np.ndarray:
    """J (6, 6) or (N, 6, 6) of the 6-UPS, ``l_dot = J x_dot`` with x_dot the rates of the pose
    coordinates: rows [n_k^T, ((R p_k) x n_k)^T E] (module docstring)."""
    x, single = _batch(pose, 6)
    _, H_x, H_q = sgp_closure(x, design, sgp_ik(x, design))
    return _out(-H_x / H_q[..., None], single)
