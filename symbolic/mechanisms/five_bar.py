"""Symmetric planar 5R mechanism (Gao 1998; Lara-Molina 2016).

Frame at the middle of the base. Base joints O1 = (-r3, 0) and O2 = (r3, 0) with r3 the half base;
proximal links of length r1 at absolute angles theta_i, distal links of length r2 at absolute angles
phi_i (from the elbow A_i towards the end effector P = (x, y)).

Loop closure (two chains, four equations)::

    P - O_i - r1 e(theta_i) - r2 e(phi_i) = 0,   e(a) = (cos a, sin a),   i = 1, 2.

Inverse kinematics of chain i with elbow sign sigma_i (Lara-Molina eqs. 4-5 solved for theta_i)::

    theta_i = atan2(P - O_i) + sigma_i acos((r1^2 + |P - O_i|^2 - r2^2) / (2 r1 |P - O_i|))

sigma_1 = +1 and sigma_2 = -1 put both elbows outside the chains' triangle O_i P (Gao's OABCD).
Forward kinematics intersects the circles of radius r2 about the elbows; the assembly sign chooses the
side of the directed line A1 -> A2 on which P lies.
"""

from __future__ import annotations

import sympy as sp

from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.loops import LoopClosure

r1, r2, r3 = sp.symbols("r1 r2 r3", positive=True)
x, y = sp.symbols("x y", real=True)
theta1, theta2, phi1, phi2 = sp.symbols("theta1 theta2 phi1 phi2", real=True)
sigma1, sigma2, sigma = sp.symbols("sigma1 sigma2 sigma", real=True)

DESIGN = Port("design", (r1, r2, r3), "proximal length, distal length, half base [m]")
POSE = Port("x", (x, y), "end-effector position [m]")
JOINTS = Port("q", (theta1, theta2, phi1, phi2), "actuated then passive absolute link angles [rad]")
ACTUATED = Port("q_a", (theta1, theta2), "actuated joint angles [rad]")
MODE = Port("mode", (sigma1, sigma2), "elbow signs of chains 1 and 2 (+1 or -1)")
ASSEMBLY = Port("assembly", (sigma,), "side of the line A1 -> A2 on which P lies (+1 left, -1 right)")


def _e(angle: sp.Expr) -> sp.Matrix:
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


BASES = (sp.Matrix([-r3, 0]), sp.Matrix([r3, 0]))
P = sp.Matrix([x, y])


def loop_closure() -> LoopClosure:
    """The four loop-closure equations of the two chains."""
    h = []
    for base, th, ph in zip(BASES, (theta1, theta2), (phi1, phi2), strict=True):
        h.extend(P - base - r1 * _e(th) - r2 * _e(ph))
    return LoopClosure.of(h, (theta1, theta2), (phi1, phi2), (x, y))


def inverse_kinematics() -> tuple[sp.Matrix, sp.Matrix]:
    """All joint angles of the pose P for the elbow signs (sigma1, sigma2), and the reach margins."""
    actuated, passive, margins = [], [], []
    for base, s in zip(BASES, (sigma1, sigma2), strict=True):
        d = P - base
        rho = sp.sqrt(d[0] ** 2 + d[1] ** 2)
        c = (r1**2 + rho**2 - r2**2) / (2 * r1 * rho)
        # Clamped so that a pose on the workspace boundary, where |c| exceeds 1 by round-off, keeps
        # its (serial-singular) solution; the reach margin flags the poses truly out of reach.
        th = sp.atan2(d[1], d[0]) + s * sp.acos(sp.Max(-1, sp.Min(1, c)))
        elbow = base + r1 * _e(th)
        actuated.append(th)
        passive.append(sp.atan2(y - elbow[1], x - elbow[0]))
        margins.append(1 - c**2)
    return sp.Matrix(actuated + passive), sp.Matrix(margins)


def forward_kinematics() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """End-effector position and all joint angles from the actuated angles; the assembly margin."""
    a1 = BASES[0] + r1 * _e(theta1)
    a2 = BASES[1] + r1 * _e(theta2)
    u = a2 - a1
    dist2 = u[0] ** 2 + u[1] ** 2
    height2 = r2**2 - dist2 / 4
    normal = sp.Matrix([-u[1], u[0]]) / sp.sqrt(dist2)
    p = (a1 + a2) / 2 + sigma * sp.sqrt(sp.Max(0, height2)) * normal
    q = sp.Matrix([theta1, theta2, sp.atan2(p[1] - a1[1], p[0] - a1[0]), sp.atan2(p[1] - a2[1], p[0] - a2[0])])
    return p, q, sp.Matrix([height2])


def module() -> ModuleSpec:
    """Every function pkm's ``five_bar`` loads."""
    spec = ModuleSpec("five_bar", "symbolic/mechanisms/five_bar.py", "CasADi functions of the symmetric 5R.")
    q, margins = inverse_kinematics()
    spec.add(
        "inverse_kinematics",
        (POSE, MODE, DESIGN),
        (
            Output("q", q, "theta1, theta2, phi1, phi2 [rad]"),
            Output("reach", margins, "1 - cos^2 of each elbow angle; >= 0 where reachable"),
        ),
        "Closed-form inverse kinematics of both chains for the elbow signs in mode.",
    )
    p, q_fk, height2 = forward_kinematics()
    spec.add(
        "forward_kinematics",
        (ACTUATED, ASSEMBLY, DESIGN),
        (
            Output("x", p, "end-effector position [m]"),
            Output("q", q_fk, "theta1, theta2, phi1, phi2 [rad]"),
            Output("reach", height2, "r2^2 - |A1 A2|^2 / 4; >= 0 where the chains close"),
        ),
        "Closed-form forward kinematics: intersection of the circles of radius r2 about the elbows.",
    )
    loop = loop_closure()
    spec.add(
        "constraint",
        (JOINTS, POSE, DESIGN),
        (
            Output("h", loop.h, "loop-closure residuals [m]"),
            Output("H_q", loop.H_a.row_join(loop.H_p), "dh/dq, actuated then passive [m/rad]"),
            Output("H_x", loop.H_x, "dh/dx [-]"),
        ),
        "Loop-closure residuals and their Jacobians.",
    )
    spec.add(
        "first_order",
        (JOINTS, POSE, DESIGN),
        (
            Output("J", loop.jacobian(), "q_a_dot = J x_dot [rad/m]"),
            Output("J_f", loop.forward_jacobian(), "x_dot = J_f q_a_dot [m/rad]"),
            Output("psi", loop.psi(), "q_dot = Psi q_a_dot, all joints from actuated [-]"),
            Output("det_type1", sp.Matrix([loop.det_type1()]), "serial singularity measure [m^2]"),
            Output("det_type2", sp.Matrix([loop.det_type2()]), "parallel singularity measure [m^2]"),
        ),
        "First-order kinematics by implicit differentiation of the loop closure.",
    )
    _add_mic(spec)
    return spec


def maximum_inscribed_circle() -> tuple[sp.Expr, sp.Expr]:
    """Centre height and radius of the MIC (Lara-Molina 2016 eqs. 10-12), r3 the half base.

    Case r1 + r3 < r2 (eq. 11): the annulus of each chain has width 2 r1 and the MIC, of radius
    min(r1, r2) = r1, touches its inner and outer circles with its centre at distance r2 from both
    bases. Otherwise (eq. 12): the MIC touches the outer circles and the parallel singularity at
    (0, y_col) where both distal links are horizontal; its radius is capped by the inner circles.
    """
    case_1 = r1 + r3 < r2
    # Each square root sees its own case's argument and 1 otherwise: both pieces are evaluated (and
    # differentiated) everywhere, and a NaN from the unused piece would poison the gradient.
    y_col = sp.sqrt(sp.Piecewise((1, case_1), (r1**2 - (r2 - r3) ** 2, True)))
    s = r1 + r2 + y_col
    y_mic_2 = (s**2 - r3**2) / (2 * s)
    # Eq. 12 ignores the inner circle of radius |r1 - r2| about each base, which its disc crosses when
    # r2 > r1 and r1 + r3 - r2 is small: the radius is capped so that the disc stays in both annuli.
    rad_2 = sp.Min(y_mic_2 - y_col, sp.sqrt(r3**2 + y_mic_2**2) - sp.Abs(r1 - r2))
    y_mic_1 = sp.sqrt(sp.Piecewise(((r1 + r2 + sp.Abs(r1 - r2)) ** 2 / 4 - r3**2, case_1), (1, True)))
    rad_1 = (r1 + r2 - sp.Abs(r1 - r2)) / 2
    return sp.Piecewise((y_mic_1, case_1), (y_mic_2, True)), sp.Piecewise((rad_1, case_1), (rad_2, True))


def _add_mic(spec: ModuleSpec) -> None:
    centre, radius = maximum_inscribed_circle()
    spec.add(
        "maximum_inscribed_circle",
        (DESIGN,),
        (
            Output("centre", sp.Matrix([0, centre]), "centre (0, y_MIC) of the MIC [m]"),
            Output("radius", sp.Matrix([radius]), "radius r_MIC of the MIC [m]"),
        ),
        "Maximum inscribed circle of the workspace of the out_out working mode (Lara-Molina eqs. 10-12).",
    )
