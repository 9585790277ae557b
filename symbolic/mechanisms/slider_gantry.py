"""Two-slider gantry with a parallelogram and counterweights (Wu, Wang, Wang and Shao 2008).

Frame: O on the base midway between the two vertical columns, x horizontal, y up. The columns stand at
x = -(d1 + d2) and x = d1 + d2; slider i (i = 1 left, 2 right) moves along its column at height q_i
(its lower joint B_i). The platform is a translating body of width 2 d2 and height l2 with its
reference point O' = (x, y) at its centre; its joints are A1 = (x - d2, y - l2/2), A3 = (x - d2,
y + l2/2) on the left and A2 = (x + d2, y - l2/2) on the right. Links A1B1, A3B3 and A2B2 have the same
length l; B3 = B1 + (0, l2) is the upper joint of slider 1, so that A1B1B3A3 is a parallelogram. The
symmetric variant (Wu section 6.3) adds the link A4B4, A4 = (x + d2, y + l2/2), B4 = B2 + (0, l2).

theta_i is the angle of link A_iB_i from the vertical, positive when A_i lies to the right of B_i:

    x + d1 - l sin(theta1) = 0,   y - l2/2 - q1 - l cos(theta1) = 0,
    x - d1 - l sin(theta2) = 0,   y - l2/2 - q2 - l cos(theta2) = 0,

which is Wu's eq. 1 with x_B1 = -d1, x_B2 = d1: the platform half-width d2 cancels, so d1 is the
column half-distance minus d2 (Wu eq. 15's d1 = (b + 2d)/2 then reproduces Table 1). Inverse
kinematics (eq. 2) with the branch sign sigma_i: q_i = y - l2/2 - sigma_i sqrt(l^2 - (x +- d1)^2);
Wu's machine uses sigma_i = +1 (each slider below its platform joint). The link A_iB_i is the vector
(u_i, w_i) = (x +- d1, sigma_i sqrt(l^2 - (x +- d1)^2)) = l (sin(theta_i), cos(theta_i)), so that the
first order, the inertia matrices and the inverse dynamics are also emitted from the pose with u_i / l and
w_i / l for the sine and cosine (``first_order_from_pose``, ``inertia_from_pose``,
``inverse_dynamics_from_pose``; J's row i is (u_i / w_i, 1)): no angle and no trigonometric call.

Elastic elements (pkm's stiffness, :mod:`pkm.spec.stiffness`): each slider's drive a spring k_s along its column,
each chain's link a steel square tube b_l x b_l x t_l clamped at its slider's joint (the parallelogram's two links
side by side), in the conventions of a described machine of two PRR legs (pkm/models/slider_gantry/legs.py).

Counterweight i hangs from a pulley on top of column i and moves opposite to slider i (its height is
-q_i up to a constant). Gravity g acts along -y. Bodies and masses follow Wu's Table 2.
"""

from __future__ import annotations

from functools import cache

import sympy as sp

from pkm.spec.vocabulary import MATERIALS
from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.described.elastic import add_hand_derived, beam_terms
from symbolic.kinematics import ForwardKinematics, InverseKinematics, add_from_pose, add_kinematics
from symbolic.lagrange import Body, Chain, chain_model, project, rate, stack
from symbolic.loops import LoopClosure
from symbolic.virtual_work import Motion, PivotBody, virtual_work

ell, d1, d2, l2 = sp.symbols("l d1 d2 l2", positive=True)
qs, ql = sp.symbols("qs ql", real=True)
theta_s, theta_l = sp.symbols("theta_s theta_l", positive=True)
m11, m21, m12, m22, m13, m23, m4, m_platform = sp.symbols("m11 m21 m12 m22 m13 m23 m4 mN", positive=True)
I12, I22, I4, s12, s22, s4 = sp.symbols("I12 I22 I4 s12 s22 s4", positive=True)
m5, I5, s5 = sp.symbols("m5 I5 s5", positive=True)
g = sp.Symbol("g", nonnegative=True)
b_l, t_l, k_s = sp.symbols("b_l t_l k_s", positive=True)
x, y = sp.symbols("x y", real=True)
q1, q2, theta1, theta2 = sp.symbols("q1 q2 theta1 theta2", real=True)
sigma1, sigma2, sigma = sp.symbols("sigma1 sigma2 sigma", real=True)
x_dot, y_dot = rate(x), rate(y)
x_ddot, y_ddot = sp.symbols("x_ddot y_ddot", real=True)

GEOMETRY = (ell, d1, d2, l2, qs, ql, theta_s, theta_l)
INERTIAL = (m11, m21, m12, m22, m13, m23, m4, m_platform, I12, I22, I4, s12, s22, s4)
EXTRA_LINK = (m5, I5, s5)
ELASTIC_DESIGN = (b_l, t_l, k_s)
LINKS = "steel"  # the links' material (pkm.spec.vocabulary.MATERIALS)

POSE = Port("x", (x, y), "platform reference point O' [m]")
JOINTS = Port("q", (q1, q2, theta1, theta2), "slider positions [m], then link angles from the vertical [rad]")
POSE_RATES = Port("x_dot", (x_dot, y_dot), "platform velocity [m/s]")
POSE_ACCELERATIONS = Port("x_ddot", (x_ddot, y_ddot), "platform acceleration [m/s^2]")
ACTUATED = Port("q_a", (q1, q2), "slider positions [m]")
MODE = Port("mode", (sigma1, sigma2), "branch of each chain: +1 slider below its platform joint, -1 above")
ASSEMBLY = Port("assembly", (sigma,), "+1 platform above the line through the links' slider ends, -1 below")

P = sp.Matrix([x, y])
GRAVITY = sp.Matrix([0, -g, 0])


def design_port(symmetric: bool) -> Port:
    symbols = GEOMETRY + INERTIAL + (EXTRA_LINK if symmetric else ()) + (g,) + ELASTIC_DESIGN
    extra = "; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4" if symmetric else ""
    return Port(
        "design",
        symbols,
        "l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; "
        f"I12, I22, I4 [kg m^2]; s12, s22, s4 [m]{extra}; g [m/s^2]; b_l, t_l [m]; k_s [N/m]",
    )


def loop_closure() -> LoopClosure:
    """The four loop-closure equations of the two chains (Wu eq. 1)."""
    h = [
        x + d1 - ell * sp.sin(theta1),
        y - l2 / 2 - q1 - ell * sp.cos(theta1),
        x - d1 - ell * sp.sin(theta2),
        y - l2 / 2 - q2 - ell * sp.cos(theta2),
    ]
    return LoopClosure.of(h, (q1, q2), (theta1, theta2), (x, y))


def inverse_kinematics() -> tuple[sp.Matrix, sp.Matrix, dict[sp.Expr, sp.Expr], dict[sp.Symbol, sp.Expr]]:
    """Slider positions (eq. 2) and link angles for the branch signs; reach and stroke margins; the
    cosine and sine of each link angle in the components of its position vector A_i - B_i = (u_i, w_i),
    with u_i = x +- d1 and w_i = sigma_i sqrt(l^2 - u_i^2), so that cos(theta_i) = w_i / l and
    sin(theta_i) = u_i / l (no trigonometric call)."""
    sliders, angles, reach, stroke, directions, vectors = [], [], [], [], {}, {}
    for i, (offset, s, th) in enumerate(((d1, sigma1, theta1), (-d1, sigma2, theta2)), 1):
        u = x + offset
        # Clamped so that a pose on the reach boundary keeps its (serial-singular) solution; the
        # reach margin flags the poses truly out of reach.
        w = s * sp.sqrt(sp.Max(0, ell**2 - u**2))
        q = y - l2 / 2 - w
        sliders.append(q)
        angles.append(sp.atan2(u, w))
        reach.append(ell**2 - u**2)
        stroke.append((q - qs) * (ql - q))
        u_i, w_i = sp.symbols(f"u{i} w{i}", real=True)
        directions.update({sp.cos(th): w_i / ell, sp.sin(th): u_i / ell})
        vectors.update({u_i: u, w_i: w})
    return sp.Matrix(sliders + angles), sp.Matrix(reach + stroke), directions, vectors


def forward_kinematics() -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """Platform position from the sliders: intersection of the circles of radius l about the link
    ends' images (-d1, q1 + l2/2) and (d1, q2 + l2/2); the assembly sign picks the side."""
    c1 = sp.Matrix([-d1, q1 + l2 / 2])
    c2 = sp.Matrix([d1, q2 + l2 / 2])
    u = c2 - c1
    dist2 = u[0] ** 2 + u[1] ** 2
    height2 = ell**2 - dist2 / 4
    normal = sp.Matrix([-u[1], u[0]]) / sp.sqrt(dist2)
    p = (c1 + c2) / 2 + sigma * sp.sqrt(sp.Max(0, height2)) * normal
    q = sp.Matrix(
        [q1, q2, sp.atan2(p[0] + d1, p[1] - l2 / 2 - q1), sp.atan2(p[0] - d1, p[1] - l2 / 2 - q2)]
    )
    return p, q, sp.Matrix([height2])


def task_rectangle() -> tuple[sp.Matrix, sp.Matrix]:
    """Centre and half-sizes of the task rectangle Q1Q2Q3Q4 of a design (Wu section 4.1, Fig. 2).

    The largest rectangle centred on x = 0 in which every link angle satisfies theta_s <= |theta_i|
    <= theta_l (margins from the singularities at theta_i = 0 and 90 deg) and both sliders stay within
    [qs, ql] in the working mode of Wu's machine: |x| <= w with w = min(l sin(theta_l) - d1,
    d1 - l sin(theta_s)); the bottom edge is where a slider at qs holds its link at the smallest angle
    (Q2, Q3), the top edge where a slider at ql holds its link at the largest (Q1, Q4).
    """
    w = sp.Min(ell * sp.sin(theta_l) - d1, d1 - ell * sp.sin(theta_s))
    bottom = qs + l2 / 2 + sp.sqrt(sp.Max(0, ell**2 - (d1 - w) ** 2))
    top = ql + l2 / 2 + sp.sqrt(sp.Max(0, ell**2 - (d1 + w) ** 2))
    return sp.Matrix([0, (bottom + top) / 2]), sp.Matrix([w, (top - bottom) / 2])


def _up(angle: sp.Expr) -> sp.Matrix:
    """Unit vector along a link from its slider end, at angle theta from the vertical."""
    return sp.Matrix([sp.sin(angle), sp.cos(angle)])


def _geometry(symmetric: bool):
    """Slider joints, link angles, link parameters and the counterweight heights of both chains."""
    column = d1 + d2
    B1, B2 = sp.Matrix([-column, q1]), sp.Matrix([column, q2])
    raise_l2 = sp.Matrix([0, l2])
    links = [
        ("link1", m12, I12, s12, B1, theta1, 1),
        ("link3", m4, I4, s4, B1 + raise_l2, theta1, 1),
        ("link2", m22, I22, s22, B2, theta2, 2),
    ]
    if symmetric:
        links.append(("link4", m5, I5, s5, B2 + raise_l2, theta2, 2))
    return B1, B2, links


def _translating_pivot_body(name: str, mass: sp.Symbol, pivot: sp.Matrix) -> PivotBody:
    """A body that only translates, with its centre of mass at its pivot."""
    return PivotBody.planar(name, mass, pivot=pivot, angle=sp.Integer(0), centre=sp.zeros(2, 1), inertia=sp.Integer(0))


def _translating_body(name: str, mass: sp.Symbol, centre: sp.Matrix) -> Body:
    """A body that only translates: its rotational inertia never enters the kinetic energy."""
    return Body.planar(name, mass, centre=centre, inertia=sp.Integer(0), angle=sp.Integer(0))


def pivot_bodies(symmetric: bool) -> list[PivotBody]:
    """Every moving body of Table 2 with the pivots of Wu section 5.1."""
    B1, B2, links = _geometry(symmetric)
    bodies = [
        _translating_pivot_body("slider1", m11, B1),
        _translating_pivot_body("slider2", m21, B2),
        _translating_pivot_body("counterweight1", m13, sp.Matrix([B1[0], -q1])),
        _translating_pivot_body("counterweight2", m23, sp.Matrix([B2[0], -q2])),
    ]
    for name, m, inertia, s, pivot, th, _ in links:
        angle = sp.pi / 2 - th
        bodies.append(PivotBody.planar(name, m, pivot=pivot, angle=angle, centre=s * _up(th), inertia=inertia))
    bodies.append(_translating_pivot_body("platform", m_platform, P))
    return bodies


def chains(symmetric: bool) -> tuple[Chain, Chain]:
    """The same bodies as two open chains in (q_i, theta_i) for the Lagrange derivation; the platform
    rides on chain 1 (its position from B1 and theta1), inertias about the centres of mass."""
    B1, B2, links = _geometry(symmetric)
    bodies: dict[int, list[Body]] = {1: [], 2: []}
    for i, (B, m_slider, m_counter) in ((1, (B1, m11, m13)), (2, (B2, m21, m23))):
        bodies[i] += [
            _translating_body(f"slider{i}", m_slider, B),
            _translating_body(f"counterweight{i}", m_counter, sp.Matrix([B[0], -B[1]])),
        ]
    for name, m, inertia, s, pivot, th, i in links:
        centre = pivot + s * _up(th)
        bodies[i].append(Body.planar(name, m, centre=centre, inertia=inertia - m * s**2, angle=sp.pi / 2 - th))
    platform = B1 + ell * _up(theta1) + sp.Matrix([d2, l2 / 2])
    bodies[1].append(_translating_body("platform", m_platform, platform))
    return (
        Chain("chain1", (q1, theta1), tuple(bodies[1]), gravity=GRAVITY),
        Chain("chain2", (q2, theta2), tuple(bodies[2]), gravity=GRAVITY),
    )


def module(symmetric: bool = False) -> ModuleSpec:
    """Every function pkm's ``slider_gantry`` (or ``slider_gantry_symmetric``) loads."""
    name = "slider_gantry_symmetric" if symmetric else "slider_gantry"
    variant = "with the fourth link A4B4 (Wu section 6.3)" if symmetric else "of Wu's Fig. 1"
    spec = ModuleSpec(name, "symbolic/mechanisms/slider_gantry.py", f"CasADi functions of the slider gantry {variant}.")
    design = design_port(symmetric)
    q, margins, directions, vectors = inverse_kinematics()
    p, q_fk, height2 = forward_kinematics()
    inverse = InverseKinematics(
        q,
        margins,
        doc="Closed-form inverse kinematics (Wu eq. 2) for the branch signs in mode, with the slider strokes.",
        q_doc="q1, q2 [m], theta1, theta2 [rad]",
        reach_doc="l^2 - (x +- d1)^2 [m^2] and (q_i - qs)(ql - q_i) [m^2]; >= 0 where reachable",
        directions=directions,
        vectors=vectors,
    )
    add_kinematics(
        spec,
        loop_closure(),
        pose=POSE,
        joints=JOINTS,
        actuated=ACTUATED,
        design=design,
        mode=MODE,
        inverse=inverse,
        forward=ForwardKinematics(
            p,
            q_fk,
            height2,
            doc="Closed-form forward kinematics: intersection of two circles of radius l.",
            x_doc="platform position [m]",
            q_doc="q1, q2 [m], theta1, theta2 [rad]",
            reach_doc="l^2 - |C1 C2|^2 / 4 [m^2]; >= 0 where the chains close",
        ),
        assembly=ASSEMBLY,
        units={"h": "m", "H_q": "-, m/rad", "H_x": "-", "J": "-", "J_f": "-", "psi": "-, rad/m", "det": "m^2"},
    )
    centre, half = task_rectangle()
    spec.add(
        "task_rectangle",
        (design,),
        (
            Output("centre", centre, "centre of the task rectangle [m]"),
            Output("half_size", half, "half width b/2 and half height h/2 [m]"),
        ),
        "Task rectangle Q1Q2Q3Q4 of the design within the angle margins and the strokes (Wu Fig. 2).",
    )
    _add_dynamics(spec, symmetric)
    _add_elastic(spec, symmetric)
    for name in ("inertia", "inverse_dynamics"):
        add_from_pose(spec, name, inverse=inverse, joints=JOINTS, pose=POSE, mode=MODE)
    return spec


def _add_elastic(spec: ModuleSpec, symmetric: bool) -> None:
    """The elastic elements of the two chains, in a described machine's conventions
    (:func:`symbolic.described.elastic.add_hand_derived`): each chain's column foot (-+(d1 + d2), 0), its
    slider's joint B_i and its platform joint A_i; each slider's drive a spring k_s along its column; each chain's
    link of length l a steel square tube b_l x b_l x t_l clamped at B_i, the parallelogram's A1B1 and A3B3 (and
    A2B2 and A4B4 in the symmetric variant) two such beams side by side."""
    points = []
    for side, q in ((-1, q1), (1, q2)):
        points += [sp.Matrix([side * (d1 + d2), 0]), sp.Matrix([side * (d1 + d2), q]),
                   P + sp.Matrix([side * d2, -l2 / 2])]
    young, shear, density = MATERIALS[LINKS]
    tube = {"material": {"E": young, "G": shear, "density": density},
            "section": {"shape": "rect_tube", "b": b_l, "h": b_l, "t": t_l}}
    add_hand_derived(spec, joints=JOINTS, pose=POSE, design=design_port(symmetric), points=points,
                     drives=[1 / k_s, 1 / k_s], passive=2,
                     terms=[beam_terms(tube, ell, sp.sympify, planar=True, count=count)
                            for count in (2, 2 if symmetric else 1)],
                     what="the links, chain by chain (a parallelogram's two side by side)")


@cache
def dynamic_models(symmetric: bool):
    """The virtual-work model (in q, x and the platform rates) and the Lagrange model projected onto
    the sliders, with the joint rates and velocity-product accelerations along the loop."""
    loop = loop_closure()
    q_dot, bias = loop.inverse_second_order(POSE_RATES.symbols)
    phi = loop.inverse_map()
    motion = Motion.of(JOINTS.symbols, POSE.symbols, phi, bias, POSE_RATES.symbols)
    vw = virtual_work(pivot_bodies(symmetric), motion, GRAVITY)
    joints = stack([chain_model(c) for c in chains(symmetric)], JOINTS.symbols)
    q_a_dot = sp.Matrix([rate(q1), rate(q2)])
    lagrange = project(joints, (q1, q2), loop.psi(), loop.psi_dot(list(q_a_dot)))
    return loop, q_dot, bias, vw, joints, lagrange


def _add_dynamics(spec: ModuleSpec, symmetric: bool) -> None:
    design = design_port(symmetric)
    loop, q_dot, bias, vw, joints, lagrange = dynamic_models(symmetric)
    J = loop.jacobian()
    J_T_inv = J.T.adjugate() / J.det(method="berkowitz")
    a = sp.Matrix(POSE_ACCELERATIONS.symbols)
    # Every body moves in the plane z = 0: only the x, y rows of H and the z row of G are non-zero.
    H = sp.Matrix.vstack(*(w.H[:2, :] for w in vw.wrenches))
    G = sp.Matrix.vstack(*(w.G[2, :] for w in vw.wrenches))
    spec.add(
        "partial_velocities",
        (JOINTS, POSE, design),
        (
            Output("H", H, "pivot partial velocities, 2 rows each [-]"),
            Output("G", G, "angular partial velocities, 1 row each [1/m]"),
        ),
        "Partial velocity and angular velocity matrices of every body (Wu eqs. 19-26), bodies in the order "
        "slider1, slider2, counterweight1, counterweight2, link1, link3, link2"
        + (", link4" if symmetric else "")
        + ", platform.",
    )
    spec.add(
        "virtual_work",
        (JOINTS, POSE, POSE_RATES, design),
        (
            Output("M", vw.M, "task-space mass matrix of eq. 41 [kg]"),
            Output("N", J_T_inv * vw.n, "velocity-product and gravity forces at the sliders (eq. 41) [N]"),
            Output("n", vw.n, "the same in the platform coordinates, J^T N [N]"),
        ),
        "Virtual-work dynamic model tau = (J^T)^-1 M x_ddot + N (Wu eqs. 40-41).",
    )
    spec.add(
        "inverse_dynamics",
        (JOINTS, POSE, POSE_RATES, POSE_ACCELERATIONS, design),
        (Output("tau", J_T_inv * (vw.M * a + vw.n), "slider driving forces F1, F2 [N]"),),
        "Driving forces of a platform motion by virtual work (Wu eq. 41).",
    )
    M_t = lagrange.M
    on_loop = dict(zip(lagrange.rates(), J * sp.Matrix(POSE_RATES.symbols), strict=True))
    q_a_ddot = J * a + bias[:2, :]
    C_t = lagrange.C.xreplace(on_loop)
    tau = M_t * q_a_ddot + C_t * J * sp.Matrix(POSE_RATES.symbols) + lagrange.g
    spec.add(
        "lagrange_dynamics",
        (JOINTS, POSE, POSE_RATES, POSE_ACCELERATIONS, design),
        (
            Output("tau", tau, "slider driving forces F1, F2 [N]"),
            Output("M_t", M_t, "slider-space mass matrix Psi^T M Psi [kg]"),
            Output("C_t", C_t, "Psi^T (M Psi_dot + C Psi) [kg/s]"),
            Output("g_t", lagrange.g, "gravity forces at the sliders [N]"),
        ),
        "Independent derivation: Lagrange equations of the two open chains projected onto the sliders.",
    )
    on_joints = dict(zip(joints.rates(), q_dot, strict=True))
    kinetic = sum((c.kinetic_energy() for c in chains(symmetric)), sp.Integer(0)).xreplace(on_joints)
    spec.add(
        "energy",
        (JOINTS, POSE, POSE_RATES, design),
        (
            Output("T", sp.Matrix([kinetic]), "kinetic energy of every body [J]"),
            Output("V", sp.Matrix([joints.potential]), "gravitational potential energy [J]"),
        ),
        "Kinetic and potential energy (for power balance: tau . q_a_dot = d(T + V)/dt).",
    )
    spec.add(
        "inertia",
        (JOINTS, POSE, design),
        (
            Output("M_t", J_T_inv * vw.M * J.adjugate() / J.det(method="berkowitz"), "slider-space mass matrix [kg]"),
            Output("M_w", vw.M, "task-space mass matrix M of eq. 41 [kg]"),
            Output("M_d", J_T_inv * vw.M, "Wu's inertia matrix (J^T)^-1 M of eq. 42: tau = M_d x_ddot [kg]"),
        ),
        "Inertia matrices of a posture (Wu eqs. 41-43).",
    )
