"""The planar 2-DOF manipulator with revolute actuators and a passive constraining leg (Nam, Park 2006).

Base frame O-xy: the actuated base revolutes B1 = (R, 0) and B2 = (-R, 0); the lower links B_i d_i
(length l_a) at angles phi_i from the x axis; the upper links d_i b_i (length l_b) at angles psi_i; the
platform of half-width r with centre C = (x_c, y_c) and orientation theta, b1 = C + r u, b2 = C - r u,
u = (cos theta, sin theta). The passive RP leg joins O to C perpendicularly to the platform:
x_c cos theta + y_c sin theta = 0 (eq. 1), so C = l_c (-sin theta, cos theta) (eq. 7) with l_c the
leg's length. The pose is x = (x_c, y_c) with y_c > 0 (theta in (-pi/2, pi/2), section 4).

Inverse kinematics (eqs. 2-6): alpha_i cos phi_i + beta_i sin phi_i + gamma_i = 0 with alpha_i,
beta_i, gamma_i of eq. 5; the paper's sign s_i of eq. 6 picks the root. The emitted form is
phi_i = atan2(-beta_i gamma_i - s_i alpha_i sqrt(Delta_i), -alpha_i gamma_i + s_i beta_i sqrt(Delta_i)),
Delta_i = alpha_i^2 + beta_i^2 - gamma_i^2: the same angle as eq. 6's 2 arctan(t_i), defined also where
gamma_i = alpha_i. The elbow d_i lies on the side of the line B_i b_i given by sign((b_i - B_i) x
(d_i - B_i)) = -s_i.

Forward kinematics (eqs. 8-11): with C = l_c (-sin theta, cos theta) the leg equations read
A_i - 2 B_i cos theta + 2 C_i sin theta = 0 (eq. 8), linear in (cos theta, sin theta). Solving the pair
and imposing cos^2 + sin^2 = 1 gives (A_1 B_2 - A_2 B_1)^2 + (A_2 C_1 - A_1 C_2)^2
- 4 (B_2 C_1 - B_1 C_2)^2 = 0, a polynomial of degree 6 in l_c (eq. 11 has no factor 4).

The loop closure used for the first-order maps joins every link: h = (d_i + l_b e(psi_i) - b_i for
i = 1, 2; x_c cos theta + y_c sin theta; l_c - (y_c cos theta - x_c sin theta)) with the joints
q = (phi1, phi2, theta, psi1, psi2, l_c); its J equals the paper's J = J_q^-1 J_x (eqs. 18-21).
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.kinematics import InverseKinematics, add_kinematics
from symbolic.loops import LoopClosure
from symbolic.polynomials import combine, multiply, subtract

R, r, l_a, l_b = sp.symbols("R r l_a l_b", positive=True)
theta_max = sp.symbols("theta_max", positive=True)
x_c, y_c = sp.symbols("x_c y_c", real=True)
phi1, phi2, theta, psi1, psi2, l_c = sp.symbols("phi1 phi2 theta psi1 psi2 l_c", real=True)
s1, s2 = sp.symbols("s1 s2", real=True)
lc_root = sp.symbols("l_c_root", real=True)
w_theta, w_lc = sp.symbols("w_theta w_lc", real=True)

DESIGN = Port("design", (R, r, l_a, l_b, theta_max), "R, r, l_a, l_b [m]; theta_max [rad]")
POSE = Port("x", (x_c, y_c), "x_c, y_c: centre C of the platform [m]")
JOINTS = Port("q", (phi1, phi2, theta, psi1, psi2, l_c),
              "phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]")
ACTUATED = Port("q_a", (phi1, phi2), "actuated base angles phi1, phi2 [rad]")
MODE = Port("mode", (s1, s2), "the signs of eq. 6 for legs 1 and 2 (+1 or -1)")
ROOT = Port("root", (lc_root,), "l_c: a real root of the forward polynomial [m]")
POLAR = Port("y", (w_theta, w_lc), "theta [rad], l_c [m]: the platform's angle and the passive leg's length")
ANGLE = Port("a", (w_theta,), "theta [rad]: the abscissa of the workspace region")

FLOOR = sp.Float(1e-30)
ORIGIN_CLEARANCE = sp.Float(1e-3)


def _e(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def platform_points(centre: sp.Matrix, angle: sp.Expr) -> tuple[sp.Matrix, sp.Matrix]:
    """b1, b2 for the platform centre and angle."""
    u = _e(angle)
    return centre + r * u, centre - r * u


def base_points() -> tuple[sp.Matrix, sp.Matrix]:
    return sp.Matrix([R, 0]), sp.Matrix([-R, 0])


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[1] - a[1] * b[0]


def pose_angle() -> sp.Expr:
    """theta of eq. 1 with theta in (-pi/2, pi/2): atan2(-x_c, y_c) for y_c > 0."""
    return sp.atan2(-x_c, y_c)


def eq5_coefficients(centre: sp.Matrix, angle: sp.Expr) -> tuple[tuple[sp.Expr, sp.Expr, sp.Expr], ...]:
    """(alpha_i, beta_i, gamma_i) of eq. 5 for both legs."""
    out = []
    for b, base in zip(platform_points(centre, angle), base_points(), strict=True):
        p = b - base
        alpha, beta = 2 * l_a * p[0], 2 * l_a * p[1]
        gamma = -(alpha**2 + beta**2) / (4 * l_a**2) + l_b**2 - l_a**2
        out.append((alpha, beta, gamma))
    return tuple(out)


def inverse_kinematics() -> tuple[sp.Matrix, sp.Matrix]:
    """All joints on the branch of the signs (s1, s2) and the reach margins (Delta_1, Delta_2, y_c)."""
    centre = sp.Matrix([x_c, y_c])
    th = pose_angle()
    phis, deltas = [], []
    for (alpha, beta, gamma), s in zip(eq5_coefficients(centre, th), (s1, s2), strict=True):
        delta = alpha**2 + beta**2 - gamma**2
        root = sp.sqrt(delta)
        phis.append(sp.atan2(-beta * gamma - s * alpha * root, -alpha * gamma + s * beta * root))
        deltas.append(delta / (4 * l_a**2 * (l_a + l_b) ** 2))
    psis = passive_joints(centre, th, phis)
    q = sp.Matrix([phis[0], phis[1], th, psis[0], psis[1], sp.sqrt(x_c**2 + y_c**2)])
    return q, sp.Matrix([deltas[0], deltas[1], y_c])


def eq6(printed: bool) -> sp.Matrix:
    """phi_i of eq. 6, 2 arctan((-beta_i +- sqrt(Delta_i)) / (gamma_i - alpha_i)), or as printed with
    r - alpha_i in the denominator."""
    centre = sp.Matrix([x_c, y_c])
    out = []
    for (alpha, beta, gamma), s in zip(eq5_coefficients(centre, pose_angle()), (s1, s2), strict=True):
        denominator = (r if printed else gamma) - alpha
        out.append(2 * sp.atan((-beta + s * sp.sqrt(alpha**2 + beta**2 - gamma**2)) / denominator))
    return sp.Matrix(out)


def loop_closure() -> LoopClosure:
    centre = sp.Matrix([x_c, y_c])
    h = []
    for phi, psi, b, base in zip((phi1, phi2), (psi1, psi2), platform_points(centre, theta), base_points(),
                                 strict=True):
        h.extend(base + l_a * _e(phi) + l_b * _e(psi) - b)
    h.append(x_c * sp.cos(theta) + y_c * sp.sin(theta))
    h.append(l_c - (y_c * sp.cos(theta) - x_c * sp.sin(theta)))
    return LoopClosure.of(h, (phi1, phi2), (theta, psi1, psi2, l_c), (x_c, y_c))


def eq8_coefficients(length: sp.Expr) -> tuple[tuple[sp.Expr, sp.Expr, sp.Expr], ...]:
    """(A_i, B_i, C_i) of eq. 8 for both legs at the passive leg's length ``length``, as derived."""
    A1 = length**2 + r**2 + R**2 + l_a**2 - l_b**2 + 2 * l_a * R * sp.cos(phi1)
    B1 = R * r + l_a * r * sp.cos(phi1) + length * l_a * sp.sin(phi1)
    C1 = length * R + length * l_a * sp.cos(phi1) - l_a * r * sp.sin(phi1)
    A2 = length**2 + r**2 + R**2 + l_a**2 - l_b**2 - 2 * l_a * R * sp.cos(phi2)
    B2 = R * r - l_a * r * sp.cos(phi2) + length * l_a * sp.sin(phi2)
    C2 = -length * R + length * l_a * sp.cos(phi2) + l_a * r * sp.sin(phi2)
    return (A1, B1, C1), (A2, B2, C2)


def leg_equations(length: sp.Expr, angle: sp.Expr) -> sp.Matrix:
    """Eqs. 2-3 (|b_i - d_i|^2 - l_b^2) at C = length (-sin angle, cos angle)."""
    centre = length * sp.Matrix([-sp.sin(angle), sp.cos(angle)])
    out = []
    for phi, b, base in zip((phi1, phi2), platform_points(centre, angle), base_points(), strict=True):
        v = b - base - l_a * _e(phi)
        out.append(v[0] ** 2 + v[1] ** 2 - l_b**2)
    return sp.Matrix(out)


def _in_length(expr: sp.Expr) -> list[sp.Expr]:
    """Coefficients in l_c (highest first) of an expression polynomial in l_c."""
    return sp.Poly(sp.expand(expr), lc_root).all_coeffs()


@cache
def forward_polynomial() -> sp.Matrix:
    """Coefficients (degree 6 first) of (A1 B2 - A2 B1)^2 + (A2 C1 - A1 C2)^2 - 4 (B2 C1 - B1 C2)^2."""
    (A1, B1, C1), (A2, B2, C2) = (tuple(_in_length(e) for e in leg) for leg in eq8_coefficients(lc_root))
    sine = subtract(multiply(A1, B2), multiply(A2, B1))
    cosine = subtract(multiply(A2, C1), multiply(A1, C2))
    det = subtract(multiply(B2, C1), multiply(B1, C2))
    return sp.Matrix(combine(combine(multiply(sine, sine), multiply(cosine, cosine)), multiply(det, det), -4))


def eq11(printed: bool) -> sp.Expr:
    """The left side of eq. 11 in l_c (as derived, or as printed without the factor 4)."""
    (A1, B1, C1), (A2, B2, C2) = eq8_coefficients(l_c)
    factor = 1 if printed else 4
    return (A1 * B2 - A2 * B1) ** 2 + (A2 * C1 - A1 * C2) ** 2 - factor * (B2 * C1 - B1 * C2) ** 2


def angle_from_length(length: sp.Expr) -> sp.Expr:
    """theta from the linear pair of eq. 8 at the passive leg's length."""
    (A1, B1, C1), (A2, B2, C2) = eq8_coefficients(length)
    det = B2 * C1 - B1 * C2
    return sp.atan2((A2 * B1 - A1 * B2) * sp.sign(det), (A2 * C1 - A1 * C2) * sp.sign(det))


def passive_joints(centre: sp.Matrix, angle: sp.Expr, phis: tuple[sp.Expr, ...] = (phi1, phi2)) -> list[sp.Expr]:
    """psi1, psi2 of the upper links at the actuated angles ``phis``."""
    out = []
    for phi, b, base in zip(phis, platform_points(centre, angle), base_points(), strict=True):
        upper = b - base - l_a * _e(phi)
        out.append(sp.atan2(upper[1], upper[0]))
    return out


def forward_from_root() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Pose, joints and closure margins from a root l_c of the forward polynomial."""
    th = angle_from_length(lc_root)
    centre = lc_root * sp.Matrix([-sp.sin(th), sp.cos(th)])
    psi = passive_joints(centre, th)
    q = sp.Matrix([phi1, phi2, th, psi[0], psi[1], lc_root])
    residual = leg_equations(lc_root, th)
    tolerance = sp.Float(1e-9) * (l_a + l_b) ** 2
    reach = sp.Matrix([tolerance - sp.Abs(residual[0]), tolerance - sp.Abs(residual[1])])
    return centre, q, reach


def joint_points() -> dict[str, sp.Matrix]:
    """B1, d1, b1, C, b2, d2, B2 from the joints and the pose."""
    centre = sp.Matrix([x_c, y_c])
    b1, b2 = platform_points(centre, theta)
    B1, B2 = base_points()
    return {"B1": B1, "d1": B1 + l_a * _e(phi1), "b1": b1, "C": centre, "b2": b2, "d2": B2 + l_a * _e(phi2),
            "B2": B2}


def joint_angle_sines() -> sp.Matrix:
    """sin of the joint angles of section 4, each in (0, pi) on Fig. 1's branch: angle d_i = b_i d_i B_i
    and angle b_i = d_i b_i C, leg 1 counter-clockwise and leg 2 clockwise (mirror images)."""
    p = joint_points()
    out = []
    for k, orientation in (("1", 1), ("2", -1)):
        d, b, base, c = p[f"d{k}"], p[f"b{k}"], p[f"B{k}"], p["C"]
        out.append(orientation * cross(b - d, base - d) / (l_a * l_b))
    for k, orientation in (("1", 1), ("2", -1)):
        d, b, c = p[f"d{k}"], p[f"b{k}"], p["C"]
        out.append(orientation * cross(c - b, d - b) / (r * l_b))
    return sp.Matrix(out)


def elbow_signs() -> sp.Matrix:
    """The signs s_i of eq. 6 of a configuration: s_i = -sign((b_i - B_i) x (d_i - B_i))."""
    p = joint_points()
    return sp.Matrix([-sp.sign(cross(p[f"b{k}"] - p[f"B{k}"], p[f"d{k}"] - p[f"B{k}"])) for k in ("1", "2")])


def paper_jacobians() -> dict[str, sp.Matrix]:
    """J_q, J_x of eqs. 18-20 and the type-2 measures of eq. 24, from the joints and the pose."""
    p = joint_points()
    c, s = sp.cos(theta), sp.sin(theta)
    X = [p["b1"][0] - p["d1"][0], p["b2"][0] - p["d2"][0]]
    Y = [p["b1"][1] - p["d1"][1], p["b2"][1] - p["d2"][1]]
    den = x_c * s - y_c * c
    Z = [r * (-X[i] * s + Y[i] * c) / den for i in range(2)]
    Jq = sp.diag(*[l_a * (-X[i] * sp.sin(q) + Y[i] * sp.cos(q)) for i, q in enumerate((phi1, phi2))])
    Jx = sp.Matrix([[X[0] + Z[0] * c, Y[0] + Z[0] * s], [X[1] - Z[1] * c, Y[1] - Z[1] * s]])
    upper_cross = X[0] * Y[1] - X[1] * Y[0]
    normal = [X[i] * s - Y[i] * c for i in range(2)]
    length = y_c * c - x_c * s
    return {
        "J_q": Jq,
        "J_x": Jx,
        "det_J_x": sp.Matrix([-2 * length * Jx.det()]),
        "eq24": sp.Matrix([-2 * length * upper_cross + 2 * r * normal[0] * normal[1]]),
        "eq25": sp.Matrix([upper_cross, normal[0], normal[1]]),
    }


def boundary(angle: sp.Expr) -> dict[str, sp.Expr]:
    """The outer and inner boundaries l_CM, l_cm (eqs. 12-13) as derived and as printed, and the
    radicands of eqs. 14-15; a boundary is real where its radicand is >= 0 (its root is taken of the
    radicand floored at 0)."""
    sin, cos = sp.sin(angle), sp.cos(angle)
    radicand_outer = R**2 * sin**2 - R**2 - r**2 + 2 * r * R * cos + (l_a + l_b) ** 2
    radicand_inner = R**2 * sin**2 - R**2 - (r + l_b) ** 2 + 2 * (r + l_b) * R * cos + l_a**2
    side = R * sp.Abs(sin)
    outer = sp.sqrt(sp.Max(radicand_outer, FLOOR * (l_a + l_b) ** 2))
    inner = sp.sqrt(sp.Max(radicand_inner, FLOOR * (l_a + l_b) ** 2))
    return {
        "l_CM": -side + outer,
        "l_cm": side + inner,
        "l_CM_printed": (-side + outer) / 2,
        "l_cm_printed": (side + inner) / 2,
        "eq14": radicand_outer,
        "eq15": radicand_inner,
    }


def region_curves() -> tuple[sp.Expr, sp.Expr]:
    """The workspace in (theta, l_c) at one theta: from the inner boundary (the x axis where l_cm is
    not real) to the outer boundary, leaving out l_c < ORIGIN_CLEARANCE (l_a + l_b) around the origin:
    the architecture singularity of the family l_b - l_a = R - r, where the joint angles b_i and det J_x
    tend to limits that depend on the direction of approach."""
    b = boundary(w_theta)
    clearance = ORIGIN_CLEARANCE * (l_a + l_b)
    lower = sp.Piecewise((sp.Max(clearance, b["l_cm"]), b["eq15"] > 0), (clearance, True))
    return lower, b["l_CM"]


def region_range() -> sp.Matrix:
    """(-theta_hi, theta_hi): theta_max, or less where l_CM <= 0, i.e. where (l_a + l_b)^2 <= R^2 + r^2
    - 2 r R cos(theta): theta_hi = acos(max(cos_reach, cos(theta_max))), finite in its derivative as
    long as eq. 14 holds (cos_reach < 1)."""
    cos_reach = (R**2 + r**2 - (l_a + l_b) ** 2) / (2 * r * R)
    hi = sp.acos(sp.Max(cos_reach, sp.cos(theta_max)))
    return sp.Matrix([-hi, hi])


def footprint() -> sp.Expr:
    """S = (r + R) sqrt((l_a + l_b)^2 - (R - r)^2) of eq. 30: the mechanism's size with both legs
    stretched."""
    return (r + R) * sp.sqrt((l_a + l_b) ** 2 - (R - r) ** 2)


def module() -> ModuleSpec:
    """Every function pkm's ``passive_leg`` loads."""
    spec = ModuleSpec("passive_leg", "symbolic/mechanisms/passive_leg.py",
                      "CasADi functions of the 2-DOF manipulator with a passive constraining leg.")
    q, reach = inverse_kinematics()
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
            reach,
            doc="Joints on the branch of eq. 6's signs (s1, s2); theta = atan2(-x_c, y_c), l_c = |C|.",
            q_doc="phi1, phi2, theta, psi1, psi2 [rad], l_c [m]",
            reach_doc="Delta_1, Delta_2 of eq. 6 over 4 l_a^2 (l_a + l_b)^2 [-] and y_c [m]: >= 0 where reachable",
        ),
        units={"h": "m, -, m", "H_q": "m", "H_x": "-", "J": "rad/m", "J_f": "m/rad", "psi": "-", "det": "m^5"},
    )
    spec.add(
        "forward_polynomial",
        (ACTUATED, DESIGN),
        (Output("c", forward_polynomial(), "coefficients of l_c^6 ... l_c^0 [m^(8 - k)]"),),
        "Polynomial of degree 6 in l_c whose real roots are the assembly modes (eq. 11 as derived).",
    )
    x_fk, q_fk, reach_fk = forward_from_root()
    spec.add(
        "forward_from_root",
        (ROOT, ACTUATED, DESIGN),
        (
            Output("x", x_fk, "x_c, y_c [m]"),
            Output("q", q_fk, "phi1, phi2, theta, psi1, psi2 [rad], l_c [m]"),
            Output("reach", reach_fk, "1e-9 (l_a + l_b)^2 - |eqs. 2-3 residual| [m^2]: >= 0 where the root closes"),
        ),
        "Pose and joints from one real root l_c of the forward polynomial, theta from eq. 8.",
    )
    spec.add(
        "paper_inverse",
        (POSE, MODE, DESIGN),
        (Output("phi", eq6(False), "eq. 6 with gamma_i - alpha_i in the denominator [rad]"),
         Output("phi_printed", eq6(True), "eq. 6 as printed, r - alpha_i in the denominator [rad]")),
        "The actuated angles by eq. 6 in the paper's own form.",
    )
    spec.add(
        "paper_forward",
        (JOINTS, DESIGN),
        (
            Output("eq8", leg_equations(l_c, theta), "eqs. 2-3 at C = l_c (-sin theta, cos theta) [m^2]"),
            Output("eq11", sp.Matrix([eq11(False)]), "eq. 11 as derived (factor 4) [m^8]"),
            Output("eq11_printed", sp.Matrix([eq11(True)]), "eq. 11 as printed [m^8]"),
            Output("eq9", _eq9(False), "(A_i + 2 B_i) s^2 + 4 C_i s + (A_i - 2 B_i), s = tan(theta/2) [m^2]"),
            Output("eq9_printed", _eq9(True), "(A_i - B_i) s^2 + 2 C_i s + (A_i + B_i) as printed [m^2]"),
        ),
        "Eqs. 8, 9 and 11 evaluated at the joints q (l_c and theta) for the actuated angles phi.",
    )
    jac = paper_jacobians()
    spec.add(
        "paper_first_order",
        (JOINTS, POSE, DESIGN),
        (
            Output("J_q", jac["J_q"], "eq. 19 [m^2]"),
            Output("J_x", jac["J_x"], "eq. 20 [m]"),
            Output("det_J_x", jac["det_J_x"], "-2 l_c det J_x [m^3]"),
            Output("eq24", jac["eq24"], "eq. 24 as printed [m^3]"),
            Output("eq25", jac["eq25"], "X1 Y2 - X2 Y1 [m^2], X_i sin theta - Y_i cos theta [m] (eq. 25)"),
        ),
        "The paper's J_q and J_x (eqs. 16-20) and the type-2 condition of eqs. 24-25.",
    )
    spec.add(
        "joint_angles",
        (JOINTS, POSE, DESIGN),
        (
            Output("margins", joint_angle_sines(), "sin of angle d1, d2, b1, b2 (section 4) [-]"),
            Output("signs", elbow_signs(), "the signs s1, s2 of eq. 6 of the configuration [-]"),
        ),
        "The section-4 joint angles (>= 0 inside their ranges) and the working mode of a configuration.",
    )
    points = joint_points()
    spec.add(
        "joint_positions",
        (JOINTS, POSE, DESIGN),
        tuple(Output(k, v, f"{k} [m]") for k, v in points.items()),
        "Positions of the joints B1, d1, b1, C, b2, d2, B2.",
    )
    b = boundary(w_theta)
    spec.add(
        "workspace_boundary",
        (ANGLE, DESIGN),
        tuple(Output(k, sp.Matrix([v]), f"{k} [m{'^2' if k.startswith('eq') else ''}]") for k, v in b.items()),
        "l_CM, l_cm of eqs. 12-13 as derived and as printed, and the radicands of eqs. 14-15.",
    )
    lower, upper = region_curves()
    zero = sp.Matrix([0])
    spec.add("workspace_range_negative", (DESIGN,), (
        Output("lo", region_range()[0:1, :], "-theta_hi [rad]"),
        Output("hi", zero, "0 [rad]"),
    ), "The workspace's theta range below 0 (the boundaries have a kink at theta = 0).")
    spec.add("workspace_range_positive", (DESIGN,), (
        Output("lo", zero, "0 [rad]"),
        Output("hi", region_range()[1:2, :], "theta_hi [rad]: theta_max, or less where l_CM <= 0"),
    ), "The workspace's theta range above 0.")
    spec.add("workspace_curves", (ANGLE, DESIGN), (
        Output("lower", sp.Matrix([lower]), "inner boundary l_c [m]"),
        Output("upper", sp.Matrix([upper]), "outer boundary l_CM [m]"),
    ), "The workspace at one theta: l_c from the inner to the outer boundary.")
    spec.add("polar_to_pose", (POLAR, DESIGN), (
        Output("x", w_lc * sp.Matrix([-sp.sin(w_theta), sp.cos(w_theta)]), "x_c, y_c [m] (eq. 7)"),
    ), "The pose of a platform angle and passive-leg length (eq. 7).")
    spec.add("polar_area", (POLAR, DESIGN), (
        Output("element", sp.Matrix([w_lc]), "dx_c dy_c / (dtheta dl_c) = l_c [m]"),
    ), "The area element of eq. 7's map.")
    spec.add("footprint", (DESIGN,), (Output("S", sp.Matrix([footprint()]), "S of eq. 30 [m^2]"),),
             "The mechanism's size with both legs stretched (eq. 30).")
    return spec


def _eq9(printed: bool) -> sp.Matrix:
    """Eq. 9 in s = tan(theta/2) at the joints' theta, as derived from eq. 8 or as printed."""
    half = sp.tan(theta / 2)
    out = []
    for A, B, C in eq8_coefficients(l_c):
        if printed:
            out.append((A - B) * half**2 + 2 * C * half + (A + B))
        else:
            out.append((A + 2 * B) * half**2 + 4 * C * half + (A - 2 * B))
    return sp.Matrix(out)
