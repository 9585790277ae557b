"""The spatial 2-UPS-PU platform (Zhao, Tang, Zhao 2008).

Base frame O-XYZ with Z up; the central PU leg slides along Z from O and carries the platform's
universal joint U0 = (0, 0, l0). The platform turns about the U joint's first axis, the base X axis,
by theta1, then about its second, the moving y_p axis, by theta2 (eq. 1): R = Rx(theta1) Ry(theta2);
the pose is x = (l0, theta1, theta2) and T = Trans_Z(l0) R (eq. 2). The UPS legs join the base U
joints U_i = R_b (cos a_i, sin a_i, 0) to the platform's spherical joints S_i = r (cos a_i, sin a_i, 0)
(platform frame) with a_1 = alpha, a_2 = beta (eq. 3); their lengths l1, l2 and the central stroke l0
are actuated.

Inverse kinematics (eq. 4): l_i = |T S_i - U_i|. The loop closure used for the first-order maps is
h = (l1^2 - |T S1 - U1|^2, l2^2 - |T S2 - U2|^2, l0_leg - l0), so that J = dq/dx with q = (l1, l2,
l0_leg), the paper's [q] of eq. 7 with its columns reordered to x = (l0, theta1, theta2).

Forward kinematics: with l0 = l0_leg known, each leg equation is linear in (cos theta1, sin theta1):
a_i(theta2) cos theta1 + b_i(theta2) sin theta1 = c_i(theta2) with a_i, b_i, c_i linear in
(cos theta2, sin theta2, 1). Solving the pair for (cos theta1, sin theta1) and imposing cos^2 + sin^2
= 1 gives one equation in theta2; with t = tan(theta2 / 2) it is a polynomial of degree 8 whose real
roots are the assembly modes. Eliminating theta1 rather than theta2 keeps the pair regular at
alpha = 90 deg, where the first leg does not depend on theta2 (the paper's closed form, eqs. 5-6);
the pair is singular where a1 b2 = a2 b1, e.g. at theta2 = 0 when alpha = 0.

Statics (eq. 8): a wrench (F, M) at U0 is balanced by the actuator forces f1, f2 along the UPS legs
(applied at S_i: moments (T S_i - U0) x s_i), f0 along Z (the PU leg's prismatic joint), the
constraint forces f_x, f_y of the PU leg along X and Y at U0, and its constraint torque m_c about the
common normal of the U joint's axes, X x Rx(theta1) Y = (0, -sin theta1, cos theta1).
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.kinematics import InverseKinematics, add_kinematics
from symbolic.loops import LoopClosure
from symbolic.polynomials import combine, multiply, subtract

r, R_b = sp.symbols("r R", positive=True)
alpha, beta = sp.symbols("alpha beta", real=True)
l_min, l_max, l0_min, l0_max = sp.symbols("l_min l_max l0_min l0_max", positive=True)
theta_u_max, theta_s_max, D = sp.symbols("theta_u_max theta_s_max D", positive=True)
payload, payload_height, gravity = sp.symbols("payload payload_height g", nonnegative=True)
task_tilt, task_height = sp.symbols("task_tilt task_height", positive=True)
l0, theta1, theta2 = sp.symbols("l0 theta1 theta2", real=True)
l1, l2, l0_leg = sp.symbols("l1 l2 l0_leg", real=True)
sigma, root = sp.symbols("sigma t", real=True)

DESIGN = Port(
    "design",
    (r, R_b, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height,
     gravity, task_tilt, task_height),
    "r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; "
    "payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]",
)
POSE = Port("x", (l0, theta1, theta2), "l0 [m], theta1, theta2 [rad]")
JOINTS = Port("q", (l1, l2, l0_leg), "UPS leg lengths l1, l2 and the PU leg's stroke l0 [m]")
ACTUATED = Port("q_a", (l1, l2, l0_leg), "actuated lengths [m]")
MODE = Port("mode", (sigma,), "unused: the inverse kinematics has one solution (+1)")
ROOT = Port("root", (root,), "t = tan(theta2 / 2) [-]")


def rotation(a: sp.Expr = theta1, b: sp.Expr = theta2) -> sp.Matrix:
    """R = Rx(theta1) Ry(theta2) (eq. 1)."""
    rx = sp.Matrix([[1, 0, 0], [0, sp.cos(a), -sp.sin(a)], [0, sp.sin(a), sp.cos(a)]])
    ry = sp.Matrix([[sp.cos(b), 0, sp.sin(b)], [0, 1, 0], [-sp.sin(b), 0, sp.cos(b)]])
    return rx * ry


def _on_circle(radius: sp.Expr, angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([radius * sp.cos(angle), radius * sp.sin(angle), 0])


def joints_in_space() -> dict[str, sp.Matrix]:
    """U0, S1, S2 (platform joints, base frame), U1, U2 (base joints) and the platform normal z_p."""
    rot = rotation()
    u0 = sp.Matrix([0, 0, l0])
    return {
        "U0": u0,
        "S1": u0 + rot * _on_circle(r, alpha),
        "S2": u0 + rot * _on_circle(r, beta),
        "U1": _on_circle(R_b, alpha),
        "U2": _on_circle(R_b, beta),
        "z_p": rot[:, 2],
    }


def leg_vectors() -> tuple[sp.Matrix, sp.Matrix]:
    p = joints_in_space()
    return p["S1"] - p["U1"], p["S2"] - p["U2"]


def squared_length(angle: sp.Expr) -> sp.Expr:
    """|T S - U|^2 for the leg at ``angle`` without squared trigonometric terms: with s = R S_local
    (|s| = r) and U in the base plane, r^2 + R^2 + l0^2 + 2 l0 s_z - 2 U . s."""
    s = rotation() * _on_circle(r, angle)
    u = _on_circle(R_b, angle)
    return r**2 + R_b**2 + l0**2 + 2 * l0 * s[2] - 2 * (u.T * s)[0]


def loop_closure() -> LoopClosure:
    h = [l1**2 - squared_length(alpha), l2**2 - squared_length(beta), l0_leg - l0]
    return LoopClosure.of(h, (l1, l2, l0_leg), (), (l0, theta1, theta2))


def inverse_kinematics() -> tuple[sp.Matrix, sp.Matrix]:
    """Leg lengths of eq. 4; every pose has them (the margins are the lengths themselves)."""
    q = sp.Matrix([sp.sqrt(squared_length(alpha)), sp.sqrt(squared_length(beta)), l0])
    return q, q


def _linear_in_theta1(leg: sp.Expr, length: sp.Expr) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(a, b, c) with a cos(theta1) + b sin(theta1) = c for |T S_i - U_i|^2 = length^2."""
    c1, s1 = sp.symbols("c1 s1", real=True)
    poly = sp.Poly(sp.expand(leg.subs({sp.cos(theta1): c1, sp.sin(theta1): s1}) - length**2), c1, s1)
    if poly.total_degree() > 1:
        raise ValueError(f"{leg} is not linear in cos(theta1), sin(theta1)")
    return poly.coeff_monomial(c1), poly.coeff_monomial(s1), -poly.coeff_monomial(1)


def _in_t(expr: sp.Expr) -> list[sp.Expr]:
    """An expression linear in (cos theta2, sin theta2, 1) times (1 + t^2), as a quadratic in
    t = tan(theta2 / 2) (highest degree first)."""
    c2, s2 = sp.symbols("c2 s2", real=True)
    poly = sp.Poly(sp.expand(expr.subs({sp.cos(theta2): c2, sp.sin(theta2): s2})), c2, s2)
    if poly.total_degree() > 1:
        raise ValueError(f"{expr} is not linear in cos(theta2), sin(theta2)")
    k0, kc, ks = poly.coeff_monomial(1), poly.coeff_monomial(c2), poly.coeff_monomial(s2)
    return [k0 - kc, 2 * ks, k0 + kc]


@cache
def forward_polynomial() -> tuple[sp.Matrix, tuple[sp.Expr, ...]]:
    """Coefficients (degree 8 first) of the polynomial in t = tan(theta2/2) and the (a_i, b_i, c_i).

    With A_i = a_i (1 + t^2) and so on (quadratics in t), the condition cos^2 + sin^2 = 1 on the
    solution of the linear pair reads (C1 B2 - C2 B1)^2 + (A1 C2 - A2 C1)^2 - (A1 B2 - A2 B1)^2 = 0,
    a polynomial of degree 8, built by multiplying coefficient lists (nothing is expanded).
    """
    at_l0 = {l0: l0_leg}
    a1, b1, c1 = _linear_in_theta1(sp.expand(squared_length(alpha)).subs(at_l0), l1)
    a2, b2, c2 = _linear_in_theta1(sp.expand(squared_length(beta)).subs(at_l0), l2)
    A1, B1, C1, A2, B2, C2 = (_in_t(e) for e in (a1, b1, c1, a2, b2, c2))
    det = subtract(multiply(A1, B2), multiply(A2, B1))
    cos2 = subtract(multiply(C1, B2), multiply(C2, B1))
    sin2 = subtract(multiply(A1, C2), multiply(A2, C1))
    residual = subtract(combine(multiply(cos2, cos2), multiply(sin2, sin2)), multiply(det, det))
    return sp.Matrix(residual), (a1, b1, c1, a2, b2, c2)


def forward_from_root() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Pose, joints and margins from a root t = tan(theta2 / 2): theta1 from the linear pair; the margins
    are the legs' closure residuals within tolerance and their lengths."""
    _, (a1, b1, c1, a2, b2, c2) = forward_polynomial()
    th2 = 2 * sp.atan(root)
    on_root = {theta2: th2}
    a1, b1, c1, a2, b2, c2 = (e.subs(on_root) for e in (a1, b1, c1, a2, b2, c2))
    det = a1 * b2 - a2 * b1
    th1 = sp.atan2((a1 * c2 - a2 * c1) * sp.sign(det), (c1 * b2 - c2 * b1) * sp.sign(det))
    x = sp.Matrix([l0_leg, th1, th2])
    back = {l0: l0_leg, theta1: th1, theta2: th2}
    residual1 = squared_length(alpha).subs(back) - l1**2
    residual2 = squared_length(beta).subs(back) - l2**2
    scale = l1**2 + l2**2
    tolerance = sp.Float(1e-9)
    # the polynomial knows the squared lengths only: a leg's length must also be one (>= 0)
    reach = sp.Matrix([tolerance * scale - sp.Abs(residual1), tolerance * scale - sp.Abs(residual2), l1, l2])
    return x, sp.Matrix([l1, l2, l0_leg]), reach


def load_wrench() -> sp.Matrix:
    """The wrench at U0 of a payload of mass ``payload`` whose centre of mass lies ``payload_height``
    above U0 along the platform normal z_p: F = (0, 0, -m g), M = (h z_p) x F."""
    force = sp.Matrix([0, 0, -payload * gravity])
    moment = (payload_height * joints_in_space()["z_p"]).cross(force)
    return force.col_join(moment)


def statics() -> tuple[sp.Matrix, sp.Matrix]:
    """The 6 x 6 wrench matrix W with (F, M) = W (f1, f2, f0, f_x, f_y, m_c), physical and as printed.

    Physical: actuator forces along the unit leg vectors s_i applied at S_i (moments (S_i - U0) x
    s_i), f0 along Z, f_x, f_y along X, Y at U0 and the U joint's constraint torque about
    (0, -sin theta1, cos theta1). Printed (eq. 8): moments S_0i = s_i' x s_i / |s_i' x s_i| with s_i'
    = T S_i taken as the position of S_i, and the constraint torque about Z.
    """
    p = joints_in_space()
    v1, v2 = leg_vectors()
    ex, ey, ez = sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0]), sp.Matrix([0, 0, 1])
    zero = sp.zeros(3, 1)
    normal = sp.Matrix([0, -sp.sin(theta1), sp.cos(theta1)])
    columns = []
    printed = []
    for v, key in ((v1, "S1"), (v2, "S2")):
        s = v / sp.sqrt((v.T * v)[0])
        arm = p[key] - p["U0"]
        columns.append(s.col_join(arm.cross(s)))
        m = p[key].cross(v)
        printed.append(s.col_join(m / sp.sqrt((m.T * m)[0])))
    for col in (ez, ex, ey):
        columns.append(col.col_join(zero))
        printed.append(col.col_join(zero))
    columns.append(zero.col_join(normal))
    printed.append(zero.col_join(ez))
    return sp.Matrix.hstack(*columns), sp.Matrix.hstack(*printed)


def module() -> ModuleSpec:
    """Every function pkm's ``ups_pu`` loads."""
    spec = ModuleSpec("ups_pu", "symbolic/mechanisms/ups_pu.py", "CasADi functions of the 2-UPS-PU platform.")
    q, margins = inverse_kinematics()
    x_fk, q_fk, reach_fk = forward_from_root()
    add_kinematics(
        spec,
        loop_closure(),
        pose=POSE,
        joints=JOINTS,
        actuated=ACTUATED,
        design=DESIGN,
        mode=MODE,
        inverse=InverseKinematics(
            q,
            margins,
            doc="Leg lengths of Zhao eq. 4 (l1, l2) and the central stroke l0.",
            q_doc="l1, l2, l0_leg [m]",
            reach_doc="the lengths themselves: every pose has an inverse kinematics",
        ),
        units={"h": "m^2, m", "H_q": "m, -", "H_x": "m, m^2/rad", "J": "-, m/rad", "J_f": "-, rad/m",
               "psi": "-", "det": "m^2"},
    )
    coefficients, _ = forward_polynomial()
    spec.add(
        "forward_polynomial",
        (ACTUATED, DESIGN),
        (Output("c", coefficients, "coefficients of t^8 ... t^0, t = tan(theta2 / 2) [m^8]"),),
        "Polynomial of degree 8 in t = tan(theta2 / 2) whose real roots are the assembly modes.",
    )
    spec.add(
        "forward_from_root",
        (ROOT, ACTUATED, DESIGN),
        (
            Output("x", x_fk, "l0 [m], theta1, theta2 [rad]"),
            Output("q", q_fk, "l1, l2, l0_leg [m]"),
            Output("reach", reach_fk, "1e-9 (l1^2 + l2^2) - |leg residual|: >= 0 where the root closes the loop [m^2]"),
        ),
        "Pose and joints from one real root of the forward polynomial.",
    )
    positions = joints_in_space()
    spec.add(
        "joint_positions",
        (POSE, DESIGN),
        tuple(Output(k, v, f"{k} in the base frame [m]" if k != "z_p" else "platform normal [-]")
              for k, v in positions.items()),
        "Positions of the joints U0, S1, S2, U1, U2 and the platform normal z_p.",
    )
    physical, printed = statics()
    spec.add(
        "statics",
        (JOINTS, POSE, DESIGN),
        (
            Output("W", physical, "(F, M) at U0 = W (f1, f2, f0, f_x, f_y, m_c) [-, m]"),
            Output("W_printed", printed, "eq. 8 as printed: normalised moment axes, m_c about Z [-]"),
            Output("w_load", load_wrench(), "the payload's wrench (F, M) at U0 [N, N m]"),
        ),
        "Wrench matrices of the statics (Zhao eq. 8): physical, and as printed; the payload's wrench.",
    )
    return spec
