"""Symmetric planar 5R mechanism (Gao 1998; Lara-Molina 2016).

Frame at the middle of the base. Base joints O1 = (-r3, 0) and O2 = (r3, 0) with r3 the half base;
proximal links of length r1 at absolute angles theta_i, distal links of length r2 at absolute angles
phi_i (from the elbow A_i towards the end effector P = (x, y)).

Loop closure (two chains, four equations)::

    P - O_i - r1 e(theta_i) - r2 e(phi_i) = 0,   e(a) = (cos a, sin a),   i = 1, 2.

Inverse kinematics of chain i with elbow sign sigma_i (Lara-Molina eqs. 4-5 solved for theta_i)::

    theta_i = atan2(P - O_i) + sigma_i acos((r1^2 + |P - O_i|^2 - r2^2) / (2 r1 |P - O_i|))

sigma_1 = +1 and sigma_2 = -1 put both elbows outside the chains' triangle O_i P (Gao's OABCD).
The links are found as position vectors first, by the intersection of two circles and without
trigonometric calls (:class:`ChainSolution`): with d = P - O_i and perp(d) = (-d_y, d_x)::

    k = (r1^2 + |d|^2 - r2^2) / 2,   h = sqrt(r1^2 |d|^2 - k^2),
    v_i = k d + sigma_i h perp(d) = r1 |d|^2 e(theta_i),   w_i = |d|^2 d - v_i = r2 |d|^2 e(phi_i),

so that the acos above is atan2(h, k) and phi_i = atan2(w_i). The first order (J = -H_q^-1 H_x of the
loop closure below, J_f, Psi and the determinants) is written in v_i, w_i and |d|^2: the cosine and
sine of each angle replaced by the components of v_i / (r1 |d|^2) and w_i / (r2 |d|^2), each entry
over one denominator. Row i of J, for instance, is |d_i|^2 w_i^T / (v_i x w_i) (x the planar cross product): the
same J as from the angles, to round-off, with no cos, sin, acos or atan2 (``first_order_from_pose``).
The inertia matrices are emitted from the pose the same way (``inertia_from_pose``), the cosines of
theta_i - phi_i in the mass matrix expanded into products of the vectors' components.

Forward kinematics intersects the circles of radius r2 about the elbows; the assembly sign chooses the
side of the directed line A1 -> A2 on which P lies.

Elastic elements (pkm's stiffness, the virtual joint method of :mod:`pkm.spec.stiffness`): each link an
aluminium square tube of outer side w_l and wall t_l (the 40 x 40 x 2 mm tube of the masses' defaults), an
Euler-Bernoulli beam clamped at its start (:func:`symbolic.described.elastic.beam_terms`), each drive the
transmission spring k_i, the elbows free: ``skeleton`` (the joints' points O_i, A_i, P, leg by leg),
``elastic`` and ``leg_ends`` (H_c = dh/dP = I per leg), in the conventions of a described machine of RR legs.

Dynamics (Lara-Molina 2016 section II.B): each chain carries its proximal link (mass m1, centre of mass
at c1 r1 from the base joint, moment of inertia g1 m1 r1^2 about it), its distal link (m2, c2 r2 from
the elbow, g2 m2 r2^2) and the motor rotor (inertia j_i, angle theta_mi) coupled to the proximal link
by a torsional spring k_i (eq. 13). Friction: viscous fv and Coulomb fc at the actuated joints (eq. 22),
viscous vm at the rotors. The plane is horizontal: no gravity.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import sympy as sp

from pkm.spec.vocabulary import MATERIALS
from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.described.elastic import add_hand_derived, beam_terms
from symbolic.kinematics import ForwardKinematics, InverseKinematics, add_from_pose, add_kinematics
from symbolic.lagrange import Body, Chain, Friction, Model, Spring, chain_model, project, rate, stack
from symbolic.loops import LoopClosure

r1, r2, r3 = sp.symbols("r1 r2 r3", positive=True)
m1, m2, c1, c2, g1, g2 = sp.symbols("m1 m2 c1 c2 g1 g2", positive=True)
k1, k2, j1, j2 = sp.symbols("k1 k2 j1 j2", positive=True)
fv, fc, vm = sp.symbols("fv fc vm", nonnegative=True)
w_l, t_l = sp.symbols("w_l t_l", positive=True)
x, y = sp.symbols("x y", real=True)
theta1, theta2, phi1, phi2 = sp.symbols("theta1 theta2 phi1 phi2", real=True)
sigma1, sigma2, sigma = sp.symbols("sigma1 sigma2 sigma", real=True)
theta_m1, theta_m2 = sp.symbols("theta_m1 theta_m2", real=True)
x_dot, y_dot = rate(x), rate(y)

DESIGN = Port(
    "design",
    (r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l),
    "r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], "
    "fc [N m], vm [N m s/rad]; w_l, t_l [m]",
)
POSE = Port("x", (x, y), "end-effector position [m]")
JOINTS = Port("q", (theta1, theta2, phi1, phi2), "actuated then passive absolute link angles [rad]")
JOINT_RATES = Port("q_dot", tuple(rate(s) for s in JOINTS.symbols), "rates of q [rad/s]")
ACTUATED_RATES = Port("q_a_dot", (rate(theta1), rate(theta2)), "actuated joint rates [rad/s]")
ELASTIC = Port("z", (theta1, theta2, theta_m1, theta_m2), "actuated joint then rotor angles [rad]")
ELASTIC_RATES = Port("z_dot", tuple(rate(s) for s in ELASTIC.symbols), "rates of z [rad/s]")
POSE_RATES = Port("x_dot", (x_dot, y_dot), "end-effector velocity [m/s]")
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


ROUNDOFF = sp.Rational(1, 2**50)  # 4 ulp of 1: the rounding error of a difference of two squares


@dataclass(frozen=True)
class ChainSolution:
    """Chain i solved for the pose P on the elbow sign sigma_i, its links as position vectors.

    With d = P - O_i, the elbow A_i is where the circles of radius r1 about O_i and r2 about P meet::

        k = (r1^2 + |d|^2 - r2^2) / 2,   h = sqrt(r1^2 |d|^2 - k^2),   perp(d) = (-d_y, d_x),
        v = k d + sigma_i h perp(d) = r1 |d|^2 e(theta_i),
        w = |d|^2 d - v = |d|^2 (P - A_i) = r2 |d|^2 e(phi_i),

    k and h being r1 |d| times the cosine and sine of the angle from d to the proximal link, which
    sigma_i turns by +-atan2(h, k). The reach margin is 1 - cos^2 = h^2 / (r1 |d|)^2. Where it is at
    most ROUNDOFF (a pose on the workspace boundary, up to the rounding of h^2) h is taken as 0, so that
    the solution there is serial-singular, as it is where the margin is below zero by round-off only.
    """

    d: sp.Matrix
    k: sp.Expr
    h: sp.Expr
    margin: sp.Expr
    v: sp.Matrix
    w: sp.Matrix
    rho2: sp.Expr

    @classmethod
    def of(cls, base: sp.Matrix, s: sp.Symbol) -> ChainSolution:
        d = P - base
        rho2 = d[0] ** 2 + d[1] ** 2
        k = (r1**2 + rho2 - r2**2) / 2
        h2 = r1**2 * rho2 - k**2
        margin = h2 / (r1**2 * rho2)
        h = sp.sqrt(sp.Piecewise((h2, margin > ROUNDOFF), (0, True)))
        v = k * d + s * h * sp.Matrix([-d[1], d[0]])
        return cls(d, k, h, margin, v, rho2 * d - v, rho2)


def inverse_kinematics() -> tuple[sp.Matrix, sp.Matrix, dict[sp.Expr, sp.Expr], dict[sp.Symbol, sp.Expr]]:
    """All joint angles of the pose P for the elbow signs (sigma1, sigma2), the reach margins, and the
    cosine and sine of every angle in the components of the links' position vectors, with those
    components as functions of the pose (:class:`ChainSolution`)."""
    actuated, passive, margins, directions, vectors = [], [], [], {}, {}
    for i, (base, s, th, ph) in enumerate(zip(BASES, (sigma1, sigma2), (theta1, theta2), (phi1, phi2), strict=True), 1):
        chain = ChainSolution.of(base, s)
        actuated.append(sp.atan2(chain.d[1], chain.d[0]) + s * sp.atan2(chain.h, chain.k))
        passive.append(sp.atan2(chain.w[1], chain.w[0]))
        margins.append(chain.margin)
        v = sp.symbols(f"v{i}_x v{i}_y", real=True)
        w = sp.symbols(f"w{i}_x w{i}_y", real=True)
        rho2 = sp.Symbol(f"rho{i}_sq", positive=True)
        directions.update({sp.cos(th): v[0] / (r1 * rho2), sp.sin(th): v[1] / (r1 * rho2),
                           sp.cos(ph): w[0] / (r2 * rho2), sp.sin(ph): w[1] / (r2 * rho2)})
        vectors.update(zip((*v, *w, rho2), (*chain.v, *chain.w, chain.rho2), strict=True))
    return sp.Matrix(actuated + passive), sp.Matrix(margins), directions, vectors


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
    q, margins, directions, vectors = inverse_kinematics()
    p, q_fk, height2 = forward_kinematics()
    loop = loop_closure()
    inverse = InverseKinematics(
        q,
        margins,
        doc="Closed-form inverse kinematics of both chains for the elbow signs in mode.",
        q_doc="theta1, theta2, phi1, phi2 [rad]",
        reach_doc="1 - cos^2 of each elbow angle; >= 0 where reachable",
        directions=directions,
        vectors=vectors,
    )
    add_kinematics(
        spec,
        loop,
        pose=POSE,
        joints=JOINTS,
        actuated=ACTUATED,
        design=DESIGN,
        mode=MODE,
        inverse=inverse,
        forward=ForwardKinematics(
            p,
            q_fk,
            height2,
            doc="Closed-form forward kinematics: intersection of the circles of radius r2 about the elbows.",
            x_doc="end-effector position [m]",
            q_doc="theta1, theta2, phi1, phi2 [rad]",
            reach_doc="r2^2 - |A1 A2|^2 / 4; >= 0 where the chains close",
        ),
        assembly=ASSEMBLY,
        units={"h": "m", "H_q": "m/rad", "H_x": "-", "J": "rad/m", "J_f": "m/rad", "psi": "-", "det": "m^2"},
    )
    _add_mic(spec)
    _add_elastic(spec)
    _add_dynamics(spec, loop)
    add_from_pose(spec, "inertia", inverse=inverse, joints=JOINTS, pose=POSE, mode=MODE)
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
    # On the case boundary r2 = r1 + r3 the argument is zero and round-off may make it negative.
    y_col = sp.sqrt(sp.Piecewise((1, case_1), (sp.Max(0, r1**2 - (r2 - r3) ** 2), True)))
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


LINKS = "aluminium"  # the links' material (pkm.spec.vocabulary.MATERIALS)


def _add_elastic(spec: ModuleSpec) -> None:
    """The joints' points, the elastic elements' compliances and the legs' closure derivative in P (module
    docstring)."""
    points = []
    for base, th in zip(BASES, (theta1, theta2), strict=True):
        points += [base, base + r1 * _e(th), P]
    young, shear, density = MATERIALS[LINKS]
    tube = {"material": {"E": young, "G": shear, "density": density},
            "section": {"shape": "rect_tube", "b": w_l, "h": w_l, "t": t_l}}
    add_hand_derived(spec, joints=JOINTS, pose=POSE, design=DESIGN, points=points, drives=[1 / k1, 1 / k2],
                     passive=2, terms=[beam_terms(tube, length, sp.sympify, planar=True, count=1) for _ in BASES
                                       for length in (r1, r2)],
                     what="the aluminium square tubes w_l x w_l x t_l, proximal then distal, chain by chain")


def chains() -> tuple[Chain, Chain]:
    """The two open chains with links, rotor, transmission spring and friction (eqs. 13-19, 22)."""
    out = []
    for i, (base, th, ph, tm, k, j) in enumerate(
        zip(BASES, (theta1, theta2), (phi1, phi2), (theta_m1, theta_m2), (k1, k2), (j1, j2), strict=True), 1
    ):
        elbow = base + r1 * _e(th)
        bodies = (
            Body.planar(f"proximal{i}", m1, centre=base + c1 * r1 * _e(th), inertia=g1 * m1 * r1**2, angle=th),
            Body.planar(f"distal{i}", m2, centre=elbow + c2 * r2 * _e(ph), inertia=g2 * m2 * r2**2, angle=ph),
            Body.planar(f"rotor{i}", sp.Integer(0), centre=base, inertia=j, angle=tm),
        )
        out.append(
            Chain(
                f"chain{i}",
                (th, ph, tm),
                bodies,
                springs=(Spring(k, th - tm),),
                friction=(Friction(th, fv, fc), Friction(tm, vm)),
            )
        )
    return tuple(out)


@cache
def joint_model() -> Model:
    """Both chains stacked in the order (theta1, theta2, phi1, phi2, theta_m1, theta_m2) (eq. 21)."""
    return stack([chain_model(c) for c in chains()], (theta1, theta2, phi1, phi2, theta_m1, theta_m2))


def elastic_model(loop: LoopClosure) -> Model:
    """The complete model of eq. 31 in z = (theta_a, theta_m): the loop eliminates phi1, phi2."""
    z = ELASTIC.symbols
    psi = sp.zeros(6, 4)
    psi[:4, :2] = loop.psi()
    psi[4:, 2:] = sp.eye(2)
    psi_dot = sp.zeros(6, 4)
    psi_dot[:4, :2] = loop.psi_dot(ACTUATED_RATES.symbols)
    return project(joint_model(), z, psi, psi_dot)


def _add_dynamics(spec: ModuleSpec, loop: LoopClosure) -> None:
    joints = joint_model()
    links = slice(0, 4)
    on_loop = dict(zip(joints.rates()[:4, :], JOINT_RATES.symbols, strict=True))
    spec.add(
        "joint_dynamics",
        (JOINTS, JOINT_RATES, DESIGN),
        (
            Output("M", joints.M[links, links], "mass matrix of the links in q (eq. 21) [kg m^2]"),
            Output("C", joints.C[links, links].xreplace(on_loop), "Christoffel Coriolis matrix in q [kg m^2/s]"),
        ),
        "Stacked chain dynamics of the links in the joint coordinates (Lara-Molina eqs. 20-21).",
    )
    model = elastic_model(loop)
    psi = loop.psi()
    on_actuated = dict(zip(joints.rates()[:4, :], psi * sp.Matrix(ACTUATED_RATES.symbols), strict=True))
    C4 = joints.C[links, links].xreplace(on_actuated)
    spec.add(
        "actuated_dynamics",
        (JOINTS, POSE, ACTUATED_RATES, DESIGN),
        (
            Output("M_t", model.M[:2, :2], "M_t = Psi^T M Psi [kg m^2]"),
            Output("C_t", model.C[:2, :2], "C_t = Psi^T (M Psi_dot + C Psi) [kg m^2/s]"),
            Output("C_t_paper", psi.T * C4 * psi, "Lara-Molina's Psi^T C Psi, without Psi_dot [kg m^2/s]"),
            Output("psi_dot", loop.psi_dot(ACTUATED_RATES.symbols), "time derivative of Psi [1/s]"),
        ),
        "Rigid-link dynamics projected onto the actuated joints (eq. 29, Psi_dot term included).",
    )
    spec.add(
        "elastic_dynamics",
        (JOINTS, POSE, ELASTIC_RATES, DESIGN),
        (
            Output("M_T", model.M, "blockdiag(M_t, diag(j1, j2)) (eq. 31) [kg m^2]"),
            Output("C_T", model.C, "blockdiag(C_t, 0) [kg m^2/s]"),
            Output("K_T", model.stiffness(), "joint stiffness matrix [N m/rad]"),
            Output("f_t", model.f, "friction torques (f_a, V theta_m_dot) (eqs. 22, 31) [N m]"),
        ),
        "Complete model of the manipulator with flexible actuated joints: M_T z_ddot + C_T z_dot + f_t + K_T z = u.",
    )
    M_t = model.M[:2, :2]
    J = loop.jacobian()
    K_half = sp.diag(sp.sqrt(k1), sp.sqrt(k2))
    M_t_inv = M_t.adjugate() / M_t.det(method="berkowitz")
    S = K_half * (M_t_inv + sp.diag(1 / j1, 1 / j2)) * K_half
    spec.add(
        "inertia",
        (JOINTS, POSE, DESIGN),
        (
            Output("M_t", M_t, "actuated-space inertia Psi^T M Psi [kg m^2]"),
            Output("M_w", J.T * M_t * J, "task-space inertia J^T M_t J (eq. 35) [kg]"),
            Output(
                "S_e",
                S,
                "K^1/2 (M_t^-1 + J_m^-1) K^1/2: its eigenvalues are the squared non-zero natural frequencies [1/s^2]",
            ),
        ),
        "Inertia matrices of a posture and the elastodynamic matrix of (K_T - lambda^2 M_T) z = 0 (eq. 37).",
    )
    q_dot, bias = loop.inverse_second_order(POSE_RATES.symbols)
    spec.add(
        "second_order",
        (JOINTS, POSE, POSE_RATES, DESIGN),
        (
            Output("q_dot", q_dot, "all joint rates [rad/s]"),
            Output("q_ddot_bias", bias, "joint accelerations at zero x_ddot: Phi_dot x_dot [rad/s^2]"),
        ),
        "Joint rates and velocity-product accelerations from the end-effector velocity.",
    )
