# Generated from symbolic/mechanisms/five_bar.py (source sha256 e8fe5ea5c727bd20).
# Do not edit: regenerate with `make generate`.
# ruff: noqa
"""CasADi functions of the symmetric 5R."""

import casadi as ca

SOURCE_HASH = "e8fe5ea5c727bd20"
FUNCTIONS = ("inverse_kinematics", "forward_kinematics", "constraint", "first_order", "maximum_inscribed_circle", )


def inverse_kinematics():
    """Closed-form inverse kinematics of both chains for the elbow signs in mode.

    Inputs:
        x (2): [x, y] end-effector position [m]
        mode (2): [sigma1, sigma2] elbow signs of chains 1 and 2 (+1 or -1)
        design (3): [r1, r2, r3] proximal length, distal length, half base [m]
    Outputs:
        q (4x1, column-major): theta1, theta2, phi1, phi2 [rad]
        reach (2x1, column-major): 1 - cos^2 of each elbow angle; >= 0 where reachable
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 3)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    # 15 common subexpressions, 65 operations
    _t0 = design_2 + x_0
    _t1 = x_1**2
    _t2 = _t0**2 + _t1
    _t3 = design_0**2
    _t4 = _t3 - design_1**2
    _t5 = _t2 + _t4
    _t6 = (1/2)/design_0
    _t7 = mode_0*ca.acos(ca.fmax(-1, ca.fmin(1, _t5*_t6/ca.sqrt(_t2)))) + ca.atan2(x_1, _t0)
    _t8 = design_2 - x_0
    _t9 = -_t8
    _t10 = _t1 + _t9**2
    _t11 = _t10 + _t4
    _t12 = mode_1*ca.acos(ca.fmax(-1, ca.fmin(1, _t11*_t6/ca.sqrt(_t10)))) + ca.atan2(x_1, _t9)
    _t13 = -x_1
    _t14 = (1/4)/_t3
    q = ca.reshape(ca.vertcat(_t7, _t12, ca.atan2(-_t13 - design_0*ca.sin(_t7), _t0 - design_0*ca.cos(_t7)), ca.atan2(-_t13 - design_0*ca.sin(_t12), -_t8 - design_0*ca.cos(_t12))), 4, 1)
    reach = ca.reshape(ca.vertcat(-_t14*_t5**2/_t2 + 1, 1 - _t11**2*_t14/_t10), 2, 1)
    return ca.Function("inverse_kinematics", [x, mode, design], [q, reach], ["x", "mode", "design"], ["q", "reach"])


def forward_kinematics():
    """Closed-form forward kinematics: intersection of the circles of radius r2 about the elbows.

    Inputs:
        q_a (2): [theta1, theta2] actuated joint angles [rad]
        assembly (1): [sigma] side of the line A1 -> A2 on which P lies (+1 left, -1 right)
        design (3): [r1, r2, r3] proximal length, distal length, half base [m]
    Outputs:
        x (2x1, column-major): end-effector position [m]
        q (4x1, column-major): theta1, theta2, phi1, phi2 [rad]
        reach (1x1, column-major): r2^2 - |A1 A2|^2 / 4; >= 0 where the chains close
    """
    q_a = ca.SX.sym("q_a", 2)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    assembly = ca.SX.sym("assembly", 1)
    assembly_0 = assembly[0]
    design = ca.SX.sym("design", 3)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    # 18 common subexpressions, 48 operations
    _t0 = design_0*ca.cos(q_a_0)
    _t1 = (1/2)*_t0
    _t2 = design_0*ca.cos(q_a_1)
    _t3 = (1/2)*_t2
    _t4 = design_0*ca.sin(q_a_0)
    _t5 = ca.sin(q_a_1)
    _t6 = _t4 - _t5*design_0
    _t7 = _t6**2
    _t8 = -_t0 + _t2 + 2*design_2
    _t9 = _t8**2
    _t10 = -1/4*_t7 - 1/4*_t9 + design_1**2
    _t11 = assembly_0*ca.sqrt(ca.fmax(0, _t10))/ca.sqrt(_t7 + _t9)
    _t12 = _t11*_t6
    _t13 = _t12 + _t3
    _t14 = (1/2)*_t4
    _t15 = (1/2)*_t5*design_0
    _t16 = _t11*_t8
    _t17 = _t15 + _t16
    x = ca.reshape(ca.vertcat(_t1 + _t13, _t14 + _t17), 2, 1)
    q = ca.reshape(ca.vertcat(q_a_0, q_a_1, ca.atan2(-_t14 + _t17, -_t1 + _t13 + design_2), ca.atan2(_t14 - _t15 + _t16, _t1 + _t12 - _t3 - design_2)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t10), 1, 1)
    return ca.Function("forward_kinematics", [q_a, assembly, design], [x, q, reach], ["q_a", "assembly", "design"], ["x", "q", "reach"])


def constraint():
    """Loop-closure residuals and their Jacobians.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        design (3): [r1, r2, r3] proximal length, distal length, half base [m]
    Outputs:
        h (4x1, column-major): loop-closure residuals [m]
        H_q (4x4, column-major): dh/dq, actuated then passive [m/rad]
        H_x (4x2, column-major): dh/dx [-]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 3)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    # 10 common subexpressions, 35 operations
    _t0 = -x_0
    _t1 = design_0*ca.cos(q_0)
    _t2 = design_1*ca.cos(q_2)
    _t3 = -x_1
    _t4 = design_0*ca.sin(q_0)
    _t5 = design_1*ca.sin(q_2)
    _t6 = design_0*ca.cos(q_1)
    _t7 = design_1*ca.cos(q_3)
    _t8 = design_0*ca.sin(q_1)
    _t9 = design_1*ca.sin(q_3)
    h = ca.reshape(ca.vertcat(-_t0 - _t1 - _t2 + design_2, -_t3 - _t4 - _t5, -_t0 - _t6 - _t7 - design_2, -_t3 - _t8 - _t9), 4, 1)
    H_q = ca.reshape(ca.vertcat(_t4, -_t1, 0, 0, 0, 0, _t8, -_t6, _t5, -_t2, 0, 0, 0, 0, _t9, -_t7), 4, 4)
    H_x = ca.reshape(ca.vertcat(1, 0, 1, 0, 0, 1, 0, 1), 4, 2)
    return ca.Function("constraint", [q, x, design], [h, H_q, H_x], ["q", "x", "design"], ["h", "H_q", "H_x"])


def first_order():
    """First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        design (3): [r1, r2, r3] proximal length, distal length, half base [m]
    Outputs:
        J (2x2, column-major): q_a_dot = J x_dot [rad/m]
        J_f (2x2, column-major): x_dot = J_f q_a_dot [m/rad]
        psi (4x2, column-major): q_dot = Psi q_a_dot, all joints from actuated [-]
        det_type1 (1x1, column-major): serial singularity measure [m^2]
        det_type2 (1x1, column-major): parallel singularity measure [m^2]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 3)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    # 24 common subexpressions, 70 operations
    _t0 = ca.cos(q_2)
    _t1 = 1/design_0
    _t2 = ca.sin(q_2)
    _t3 = ca.cos(q_0)
    _t4 = _t2*_t3
    _t5 = ca.sin(q_0)
    _t6 = -_t0*_t5 + _t4
    _t7 = -_t6
    _t8 = _t1/_t7
    _t9 = ca.cos(q_3)
    _t10 = ca.sin(q_3)
    _t11 = ca.cos(q_1)
    _t12 = _t10*_t11
    _t13 = ca.sin(q_1)
    _t14 = _t12 - _t13*_t9
    _t15 = -_t14
    _t16 = _t1/_t15
    _t17 = -_t0*_t10 + _t2*_t9
    _t18 = -design_0/_t17
    _t19 = _t18*_t7
    _t20 = _t14*_t18
    _t21 = 1/design_1
    _t22 = _t18*_t21
    _t23 = design_1**2
    J = ca.reshape(ca.vertcat(-_t0*_t8, -_t16*_t9, -_t2*_t8, -_t10*_t16), 2, 2)
    J_f = ca.reshape(ca.vertcat(_t10*_t18*_t6, _t19*_t9, _t15*_t18*_t2, _t0*_t20), 2, 2)
    psi = ca.reshape(ca.vertcat(1, 0, _t22*(-_t10*_t3 + _t5*_t9), _t19*_t21, 0, 1, _t20*_t21, _t22*(-_t0*_t13 + _t11*_t2)), 4, 2)
    det_type1 = ca.reshape(ca.vertcat(_t23*design_0**2*(_t0*_t10*_t11*_t5 - _t0*_t13*_t5*_t9 - _t12*_t4 + _t13*_t2*_t3*_t9)), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(_t17*_t23), 1, 1)
    return ca.Function("first_order", [q, x, design], [J, J_f, psi, det_type1, det_type2], ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


def maximum_inscribed_circle():
    """Maximum inscribed circle of the workspace of the out_out working mode (Lara-Molina eqs. 10-12).

    Inputs:
        design (3): [r1, r2, r3] proximal length, distal length, half base [m]
    Outputs:
        centre (2x1, column-major): centre (0, y_MIC) of the MIC [m]
        radius (1x1, column-major): radius r_MIC of the MIC [m]
    """
    design = ca.SX.sym("design", 3)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    # 8 common subexpressions, 44 operations
    _t0 = design_2**2
    _t1 = ca.fabs(design_0 - design_1)
    _t2 = design_0 + design_1
    _t3 = (design_1 > design_0 + design_2)
    _t4 = ca.if_else(_t3, 1, ca.sqrt(design_0**2 - (design_1 - design_2)**2))
    _t5 = -_t0 + (_t2 + _t4)**2
    _t6 = 2*_t4 + 2*design_0 + 2*design_1
    _t7 = _t5/_t6
    centre = ca.reshape(ca.vertcat(0, ca.if_else(_t3, ca.sqrt(-_t0 + (1/4)*(_t1 + _t2)**2), _t7)), 2, 1)
    radius = ca.reshape(ca.vertcat(ca.if_else(_t3, -1/2*_t1 + (1/2)*design_0 + (1/2)*design_1, ca.fmin(-_t4 + _t7, -_t1 + ca.sqrt(_t0 + _t5**2/_t6**2)))), 1, 1)
    return ca.Function("maximum_inscribed_circle", [design], [centre, radius], ["design"], ["centre", "radius"])


def build():
    """All functions of this module by name."""
    return {name: globals()[name]() for name in FUNCTIONS}
