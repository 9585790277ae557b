# Generated from symbolic/mechanisms/slider_gantry.py (source sha256 309e42473438def0).
# Do not edit: regenerate with `make generate`.
# ruff: noqa
"""CasADi functions of the slider gantry with the fourth link A4B4 (Wu section 6.3)."""

import casadi as ca

SOURCE_HASH = "309e42473438def0"
FUNCTIONS = ("inverse_kinematics", "forward_kinematics", "constraint", "first_order", "first_order_from_pose", "task_rectangle", "partial_velocities", "virtual_work", "inverse_dynamics", "lagrange_dynamics", "energy", "inertia", "skeleton", "elastic", "leg_ends", "inertia_from_pose", "inverse_dynamics_from_pose", )
PARAMETERS = ("l", "d1", "d2", "l2", "qs", "ql", "theta_s", "theta_l", "m11", "m21", "m12", "m22", "m13", "m23", "m4", "mN", "I12", "I22", "I4", "s12", "s22", "s4", "m5", "I5", "s5", "g", "b_l", "t_l", "k_s", )
POSE = ("x", "y", )
ACTUATORS = ("q1", "q2", )


def inverse_kinematics():
    """Closed-form inverse kinematics (Wu eq. 2) for the branch signs in mode, with the slider strokes.

    Inputs:
        x (2): [x, y] platform reference point O' [m]
        mode (2): [sigma1, sigma2] branch of each chain: +1 slider below its platform joint, -1 above
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        q (4x1, column-major): q1, q2 [m], theta1, theta2 [rad]
        reach (4x1, column-major): l^2 - (x +- d1)^2 [m^2] and (q_i - qs)(ql - q_i) [m^2]; >= 0 where reachable
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 10 common subexpressions, 31 operations
    _t0 = design_0**2
    _t1 = design_1 + x_0
    _t2 = _t0 - _t1**2
    _t3 = mode_0*ca.sqrt(ca.fmax(0, _t2))
    _t4 = (1/2)*design_3 - x_1
    _t5 = _t3 + _t4
    _t6 = -design_1 + x_0
    _t7 = _t0 - _t6**2
    _t8 = mode_1*ca.sqrt(ca.fmax(0, _t7))
    _t9 = _t4 + _t8
    q = ca.reshape(ca.vertcat(-_t5, -_t9, ca.atan2(_t1, _t3), ca.atan2(_t6, _t8)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t2, _t7, (-_t5 - design_4)*(_t5 + design_5), (-_t9 - design_4)*(_t9 + design_5)), 4, 1)
    return ca.Function("inverse_kinematics", [x, mode, design], [q, reach], ["x", "mode", "design"], ["q", "reach"])


def forward_kinematics():
    """Closed-form forward kinematics: intersection of two circles of radius l.

    Inputs:
        q_a (2): [q1, q2] slider positions [m]
        assembly (1): [sigma] +1 platform above the line through the links' slider ends, -1 below
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        x (2x1, column-major): platform position [m]
        q (4x1, column-major): q1, q2 [m], theta1, theta2 [rad]
        reach (1x1, column-major): l^2 - |C1 C2|^2 / 4 [m^2]; >= 0 where the chains close
    """
    q_a = ca.SX.sym("q_a", 2)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    assembly = ca.SX.sym("assembly", 1)
    assembly_0 = assembly[0]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 12 common subexpressions, 36 operations
    _t0 = q_a_0 - q_a_1
    _t1 = design_1**2
    _t2 = _t0**2
    _t3 = 1/ca.sqrt(4*_t1 + _t2)
    _t4 = -_t1 - 1/4*_t2 + design_0**2
    _t5 = ca.sqrt(ca.fmax(0, _t4))
    _t6 = _t3*_t5*assembly_0
    _t7 = _t0*_t6
    _t8 = (1/2)*q_a_0
    _t9 = (1/2)*q_a_1
    _t10 = 2*_t6*design_1
    _t11 = _t10 + _t9
    x = ca.reshape(ca.vertcat(_t7, _t11 + _t8 + (1/2)*design_3), 2, 1)
    q = ca.reshape(ca.vertcat(q_a_0, q_a_1, ca.atan2(_t7 + design_1, _t11 - _t8), ca.atan2(_t0*_t3*_t5*assembly_0 - design_1, _t10 + _t8 - _t9)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t4), 1, 1)
    return ca.Function("forward_kinematics", [q_a, assembly, design], [x, q, reach], ["q_a", "assembly", "design"], ["x", "q", "reach"])


def constraint():
    """Loop-closure residuals and their Jacobians.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        h (4x1, column-major): loop-closure residuals [m]
        H_q (4x4, column-major): dh/dq, actuated then passive [-, m/rad]
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
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 5 common subexpressions, 24 operations
    _t0 = design_0*ca.sin(q_2)
    _t1 = design_0*ca.cos(q_2)
    _t2 = (1/2)*design_3 - x_1
    _t3 = design_0*ca.sin(q_3)
    _t4 = design_0*ca.cos(q_3)
    h = ca.reshape(ca.vertcat(-_t0 + design_1 + x_0, -_t1 - _t2 - q_0, -_t3 - design_1 + x_0, -_t2 - _t4 - q_1), 4, 1)
    H_q = ca.reshape(ca.vertcat(0, -1, 0, 0, 0, 0, 0, -1, -_t1, _t0, 0, 0, 0, 0, -_t4, _t3), 4, 4)
    H_x = ca.reshape(ca.vertcat(1, 0, 1, 0, 0, 1, 0, 1), 4, 2)
    return ca.Function("constraint", [q, x, design], [h, H_q, H_x], ["q", "x", "design"], ["h", "H_q", "H_x"])


def first_order():
    """First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        J (2x2, column-major): q_a_dot = J x_dot [-]
        J_f (2x2, column-major): x_dot = J_f q_a_dot [-]
        psi (4x2, column-major): q_dot = Psi q_a_dot, all joints from actuated [-, rad/m]
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
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 13 common subexpressions, 28 operations
    _t0 = ca.sin(q_2)
    _t1 = ca.cos(q_2)
    _t2 = ca.sin(q_3)
    _t3 = ca.cos(q_3)
    _t4 = _t0*_t3
    _t5 = _t1*_t2 - _t4
    _t6 = 1/_t5
    _t7 = _t3*_t6
    _t8 = _t1*_t7
    _t9 = 1/design_0
    _t10 = _t7*_t9
    _t11 = _t1/(_t5*design_0)
    _t12 = design_0**2
    J = ca.reshape(ca.vertcat(_t0/_t1, _t2/_t3, 1, 1), 2, 2)
    J_f = ca.reshape(ca.vertcat(-_t8, _t1*_t2*_t6, _t8, -_t4*_t6), 2, 2)
    psi = ca.reshape(ca.vertcat(1, 0, -_t10, -_t11, 0, 1, _t10, _t11), 4, 2)
    det_type1 = ca.reshape(ca.vertcat(-_t1*_t12*_t3), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(_t12*_t5), 1, 1)
    return ca.Function("first_order", [q, x, design], [J, J_f, psi, det_type1, det_type2], ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


def first_order_from_pose():
    """inverse_kinematics and first_order at its q, first_order with the cosine and sine of each joint angle from the position vectors of the links (no trigonometric call). first_order: First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        x (2): [x, y] platform reference point O' [m]
        mode (2): [sigma1, sigma2] branch of each chain: +1 slider below its platform joint, -1 above
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        q (4x1, column-major): q1, q2 [m], theta1, theta2 [rad]
        reach (4x1, column-major): l^2 - (x +- d1)^2 [m^2] and (q_i - qs)(ql - q_i) [m^2]; >= 0 where reachable
        J (2x2, column-major): q_a_dot = J x_dot [-]
        J_f (2x2, column-major): x_dot = J_f q_a_dot [-]
        psi (4x2, column-major): q_dot = Psi q_a_dot, all joints from actuated [-, rad/m]
        det_type1 (1x1, column-major): serial singularity measure [m^2]
        det_type2 (1x1, column-major): parallel singularity measure [m^2]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 17 common subexpressions, 49 operations
    _t0 = design_0**2
    _t1 = design_1 + x_0
    _t2 = _t0 - _t1**2
    _t3 = mode_0*ca.sqrt(ca.fmax(0, _t2))
    _t4 = (1/2)*design_3 - x_1
    _t5 = _t3 + _t4
    _t6 = -design_1 + x_0
    _t7 = _t0 - _t6**2
    _t8 = mode_1*ca.sqrt(ca.fmax(0, _t7))
    _t9 = _t4 + _t8
    _t10 = _t3
    _t11 = _t8
    _t12 = -_t1*_t11 + _t10*_t6
    _t13 = 1/_t12
    _t14 = _t10*_t11*_t13
    _t15 = _t10*_t13
    _t16 = _t11*_t13
    q = ca.reshape(ca.vertcat(-_t5, -_t9, ca.atan2(_t1, _t3), ca.atan2(_t6, _t8)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t2, _t7, (-_t5 - design_4)*(_t5 + design_5), (-_t9 - design_4)*(_t9 + design_5)), 4, 1)
    J = ca.reshape(ca.vertcat(_t1/_t10, _t6/_t11, 1, 1), 2, 2)
    J_f = ca.reshape(ca.vertcat(-_t14, _t15*_t6, _t14, -_t1*_t16), 2, 2)
    psi = ca.reshape(ca.vertcat(1, 0, -_t16, -_t15, 0, 1, _t16, _t15), 4, 2)
    det_type1 = ca.reshape(ca.vertcat(-_t10*_t11), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(_t12), 1, 1)
    return ca.Function("first_order_from_pose", [x, mode, design], [q, reach, J, J_f, psi, det_type1, det_type2], ["x", "mode", "design"], ["q", "reach", "J", "J_f", "psi", "det_type1", "det_type2"])


def task_rectangle():
    """Task rectangle Q1Q2Q3Q4 of the design within the angle margins and the strokes (Wu Fig. 2).

    Inputs:
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        centre (2x1, column-major): centre of the task rectangle [m]
        half_size (2x1, column-major): half width b/2 and half height h/2 [m]
    """
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 5 common subexpressions, 31 operations
    _t0 = (1/2)*design_4
    _t1 = design_0**2
    _t2 = ca.fmin(design_1 - design_0*ca.sin(design_6), -design_1 + design_0*ca.sin(design_7))
    _t3 = (1/2)*ca.sqrt(ca.fmax(0, _t1 - (-_t2 + design_1)**2))
    _t4 = (1/2)*design_5 + (1/2)*ca.sqrt(ca.fmax(0, _t1 - (_t2 + design_1)**2))
    centre = ca.reshape(ca.vertcat(0, _t0 + _t3 + _t4 + (1/2)*design_3), 2, 1)
    half_size = ca.reshape(ca.vertcat(_t2, -_t0 - _t3 + _t4), 2, 1)
    return ca.Function("task_rectangle", [design], [centre, half_size], ["design"], ["centre", "half_size"])


def partial_velocities():
    """Partial velocity and angular velocity matrices of every body (Wu eqs. 19-26), bodies in the order slider1, slider2, counterweight1, counterweight2, link1, link3, link2, link4, platform.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        H (18x2, column-major): pivot partial velocities, 2 rows each [-]
        G (9x2, column-major): angular partial velocities, 1 row each [1/m]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 7 common subexpressions, 21 operations
    _t0 = 1/ca.cos(q_2)
    _t1 = _t0*ca.sin(q_2)
    _t2 = 1/ca.cos(q_3)
    _t3 = _t2*ca.sin(q_3)
    _t4 = 1/design_0
    _t5 = -1/(design_0*ca.cos(q_2))
    _t6 = -1/(design_0*ca.cos(q_3))
    H = ca.reshape(ca.vertcat(0, _t1, 0, _t3, 0, -_t1, 0, -_t3, 0, _t1, 0, _t1, 0, _t3, 0, _t3, 1, 0, 0, 1, 0, 1, 0, -1, 0, -1, 0, 1, 0, 1, 0, 1, 0, 1, 0, 1), 18, 2)
    G = ca.reshape(ca.vertcat(0, 0, 0, 0, _t5, _t5, _t6, _t6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0), 9, 2)
    return ca.Function("partial_velocities", [q, x, design], [H, G], ["q", "x", "design"], ["H", "G"])


def virtual_work():
    """Virtual-work dynamic model tau = (J^T)^-1 M x_ddot + N (Wu eqs. 40-41).

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        x_dot (2): [x_dot, y_dot] platform velocity [m/s]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        M (2x2, column-major): task-space mass matrix of eq. 41 [kg]
        N (2x1, column-major): velocity-product and gravity forces at the sliders (eq. 41) [N]
        n (2x1, column-major): the same in the platform coordinates, J^T N [N]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    x_dot = ca.SX.sym("x_dot", 2)
    x_dot_0 = x_dot[0]
    x_dot_1 = x_dot[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 61 common subexpressions, 217 operations
    _t0 = ca.sin(q_2)
    _t1 = _t0**2
    _t2 = ca.cos(q_2)
    _t3 = _t1/_t2**2
    _t4 = ca.sin(q_3)
    _t5 = _t4**2
    _t6 = ca.cos(q_3)
    _t7 = _t5/_t6**2
    _t8 = 1/_t2
    _t9 = _t0*_t8
    _t10 = 1/design_0
    _t11 = _t10*_t9
    _t12 = design_10*(-_t11*design_19 + _t9)
    _t13 = 1/_t6
    _t14 = _t13*_t4
    _t15 = _t10*_t14
    _t16 = design_11*(_t14 - _t15*design_20)
    _t17 = design_14*(-_t11*design_21 + _t9)
    _t18 = design_22*(_t14 - _t15*design_24)
    _t19 = 1/(_t2*design_0)
    _t20 = _t1*_t8
    _t21 = design_10*design_19
    _t22 = 1/(_t6*design_0)
    _t23 = _t13*_t5
    _t24 = design_11*design_20
    _t25 = design_14*design_21
    _t26 = design_22*design_24
    _t27 = _t14*design_9 + _t14*design_13 + _t9*design_8 + _t9*design_12
    _t28 = _t9*design_10
    _t29 = _t14*design_11
    _t30 = _t9*design_14
    _t31 = _t14*design_22
    _t32 = 1/(-_t14 + _t9)
    _t33 = x_dot_0**2
    _t34 = _t19*_t33*(_t3 + 1)
    _t35 = _t34 + design_25
    _t36 = _t35*design_8
    _t37 = _t22*_t33*(_t7 + 1)
    _t38 = _t37 + design_25
    _t39 = _t38*design_9
    _t40 = design_12*(-_t34 + design_25)
    _t41 = design_13*(-_t37 + design_25)
    _t42 = _t33/design_0**2
    _t43 = _t42*_t8
    _t44 = _t42/_t2**3
    _t45 = _t1*_t44
    _t46 = design_10*(_t35 - _t43*design_19 - _t45*design_19)
    _t47 = _t13*_t42
    _t48 = _t42/_t6**3
    _t49 = _t48*_t5
    _t50 = design_11*(_t38 - _t47*design_20 - _t49*design_20)
    _t51 = design_14*(_t35 - _t43*design_21 - _t45*design_21)
    _t52 = design_22*(_t38 - _t47*design_24 - _t49*design_24)
    _t53 = _t36 + _t39 - _t40 - _t41 + _t46 + _t50 + _t51 + _t52 + design_25*design_15
    _t54 = _t32*_t53
    _t55 = _t0*_t44
    _t56 = _t0*_t35
    _t57 = _t4*_t48
    _t58 = _t38*_t4
    _t59 = _t14*_t39 - _t14*_t41 + _t14*_t50 + _t14*_t52 + _t19*(design_16*_t55 - _t21*_t56) + _t19*(design_18*_t55 - _t25*_t56) + _t22*(design_17*_t57 - _t24*_t58) + _t22*(design_23*_t57 - _t26*_t58) + _t36*_t9 - _t40*_t9 + _t46*_t9 + _t51*_t9
    _t60 = -_t32*_t59
    M = ca.reshape(ca.vertcat(_t12*_t9 + _t14*_t16 + _t14*_t18 + _t17*_t9 + _t19*(design_16*_t19 - _t20*_t21) + _t19*(design_18*_t19 - _t20*_t25) + _t22*(design_17*_t22 - _t23*_t24) + _t22*(design_23*_t22 - _t23*_t26) + _t3*design_8 + _t3*design_12 + _t7*design_9 + _t7*design_13 + design_15, _t12 + _t16 + _t17 + _t18 + _t27, -_t10*_t28*design_19 - _t10*_t29*design_20 - _t10*_t30*design_21 - _t10*_t31*design_24 + _t27 + _t28 + _t29 + _t30 + _t31, design_8 + design_10 + design_12 + design_9 + design_11 + design_13 + design_14 + design_22 + design_15), 2, 2)
    N = ca.reshape(ca.vertcat(-_t14*_t54 - _t60, _t54*_t9 + _t60), 2, 1)
    n = ca.reshape(ca.vertcat(_t59, _t53), 2, 1)
    return ca.Function("virtual_work", [q, x, x_dot, design], [M, N, n], ["q", "x", "x_dot", "design"], ["M", "N", "n"])


def inverse_dynamics():
    """Driving forces of a platform motion by virtual work (Wu eq. 41).

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        x_dot (2): [x_dot, y_dot] platform velocity [m/s]
        x_ddot (2): [x_ddot, y_ddot] platform acceleration [m/s^2]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        tau (2x1, column-major): slider driving forces F1, F2 [N]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    x_dot = ca.SX.sym("x_dot", 2)
    x_dot_0 = x_dot[0]
    x_dot_1 = x_dot[1]
    x_ddot = ca.SX.sym("x_ddot", 2)
    x_ddot_0 = x_ddot[0]
    x_ddot_1 = x_ddot[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 59 common subexpressions, 225 operations
    _t0 = ca.sin(q_3)
    _t1 = ca.cos(q_3)
    _t2 = 1/_t1
    _t3 = _t0*_t2
    _t4 = ca.sin(q_2)
    _t5 = ca.cos(q_2)
    _t6 = 1/_t5
    _t7 = _t4*_t6
    _t8 = 1/(-_t3 + _t7)
    _t9 = x_dot_0**2
    _t10 = _t4**2
    _t11 = _t10/_t5**2
    _t12 = 1/design_0
    _t13 = 1/(_t5*design_0)
    _t14 = _t13*_t9*(_t11 + 1)
    _t15 = _t14 + design_25
    _t16 = _t15*design_8
    _t17 = _t0**2
    _t18 = _t17/_t1**2
    _t19 = 1/(_t1*design_0)
    _t20 = _t19*_t9*(_t18 + 1)
    _t21 = _t20 + design_25
    _t22 = _t21*design_9
    _t23 = design_12*(-_t14 + design_25)
    _t24 = design_13*(-_t20 + design_25)
    _t25 = _t9/design_0**2
    _t26 = _t25*_t6
    _t27 = _t25/_t5**3
    _t28 = _t10*_t27
    _t29 = design_10*(_t15 - _t26*design_19 - _t28*design_19)
    _t30 = _t2*_t25
    _t31 = _t25/_t1**3
    _t32 = _t17*_t31
    _t33 = design_11*(_t21 - _t30*design_20 - _t32*design_20)
    _t34 = design_14*(_t15 - _t26*design_21 - _t28*design_21)
    _t35 = design_22*(_t21 - _t30*design_24 - _t32*design_24)
    _t36 = _t12*_t7
    _t37 = design_10*(-_t36*design_19 + _t7)
    _t38 = _t12*_t3
    _t39 = design_11*(_t3 - _t38*design_20)
    _t40 = design_14*(-_t36*design_21 + _t7)
    _t41 = design_22*(_t3 - _t38*design_24)
    _t42 = _t3*design_9 + _t3*design_13 + _t7*design_8 + _t7*design_12
    _t43 = _t8*(_t16 + _t22 - _t23 - _t24 + _t29 + _t33 + _t34 + _t35 + design_25*design_15 + x_ddot_0*(_t37 + _t39 + _t40 + _t41 + _t42) + x_ddot_1*(design_8 + design_10 + design_12 + design_9 + design_11 + design_13 + design_14 + design_22 + design_15))
    _t44 = _t27*_t4
    _t45 = design_10*design_19
    _t46 = _t15*_t4
    _t47 = _t0*_t31
    _t48 = design_11*design_20
    _t49 = _t0*_t21
    _t50 = design_14*design_21
    _t51 = design_22*design_24
    _t52 = _t7*design_10
    _t53 = _t3*design_11
    _t54 = _t7*design_14
    _t55 = _t3*design_22
    _t56 = _t10*_t6
    _t57 = _t17*_t2
    _t58 = -_t8*(_t13*(design_16*_t44 - _t45*_t46) + _t13*(design_18*_t44 - _t46*_t50) + _t16*_t7 + _t19*(design_17*_t47 - _t48*_t49) + _t19*(design_23*_t47 - _t49*_t51) + _t22*_t3 - _t23*_t7 - _t24*_t3 + _t29*_t7 + _t3*_t33 + _t3*_t35 + _t34*_t7 + x_ddot_0*(_t11*design_8 + _t11*design_12 + _t13*(design_16*_t13 - _t45*_t56) + _t13*(design_18*_t13 - _t50*_t56) + _t18*design_9 + _t18*design_13 + _t19*(design_17*_t19 - _t48*_t57) + _t19*(design_23*_t19 - _t51*_t57) + _t3*_t39 + _t3*_t41 + _t37*_t7 + _t40*_t7 + design_15) + x_ddot_1*(-_t12*_t52*design_19 - _t12*_t53*design_20 - _t12*_t54*design_21 - _t12*_t55*design_24 + _t42 + _t52 + _t53 + _t54 + _t55))
    tau = ca.reshape(ca.vertcat(-_t3*_t43 - _t58, _t43*_t7 + _t58), 2, 1)
    return ca.Function("inverse_dynamics", [q, x, x_dot, x_ddot, design], [tau], ["q", "x", "x_dot", "x_ddot", "design"], ["tau"])


def lagrange_dynamics():
    """Independent derivation: Lagrange equations of the two open chains projected onto the sliders.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        x_dot (2): [x_dot, y_dot] platform velocity [m/s]
        x_ddot (2): [x_ddot, y_ddot] platform acceleration [m/s^2]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        tau (2x1, column-major): slider driving forces F1, F2 [N]
        M_t (2x2, column-major): slider-space mass matrix Psi^T M Psi [kg]
        C_t (2x2, column-major): Psi^T (M Psi_dot + C Psi) [kg/s]
        g_t (2x1, column-major): gravity forces at the sliders [N]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    x_dot = ca.SX.sym("x_dot", 2)
    x_dot_0 = x_dot[0]
    x_dot_1 = x_dot[1]
    x_ddot = ca.SX.sym("x_ddot", 2)
    x_ddot_0 = x_ddot[0]
    x_ddot_1 = x_ddot[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 91 common subexpressions, 269 operations
    _t0 = ca.sin(q_2)
    _t1 = ca.cos(q_2)
    _t2 = 1/_t1
    _t3 = _t0*_t2
    _t4 = _t3*x_dot_0 + x_dot_1
    _t5 = ca.cos(q_3)
    _t6 = 1/design_0
    _t7 = ca.sin(q_3)
    _t8 = -_t0*_t5 + _t1*_t7
    _t9 = 1/_t8
    _t10 = 1/(_t8*design_0)
    _t11 = _t10*_t5
    _t12 = 1/_t5
    _t13 = _t12*_t7
    _t14 = _t13*x_dot_0 + x_dot_1
    _t15 = -_t11*_t4 + _t14*_t5/(_t8*design_0)
    _t16 = design_0*design_15
    _t17 = 2*_t1
    _t18 = design_10*design_19
    _t19 = design_14*design_21
    _t20 = (1/2)*_t11*_t15*(-_t16*_t17 - _t17*_t18 - _t17*_t19)
    _t21 = _t0*_t16 + _t0*_t18 + _t0*_t19
    _t22 = -_t21
    _t23 = _t0*_t7 + _t1*_t5
    _t24 = _t8**(-2)
    _t25 = _t24*_t6
    _t26 = _t25*_t5
    _t27 = _t15*_t23*_t26
    _t28 = -_t23
    _t29 = _t26*_t28 - _t7/(_t8*design_0)
    _t30 = _t1*_t10
    _t31 = _t1*_t14/(_t8*design_0) - _t30*_t4
    _t32 = _t27 + _t29*_t31
    _t33 = _t1*_t25
    _t34 = _t28*_t31*_t33
    _t35 = -_t0/(_t8*design_0) + _t23*_t33
    _t36 = _t15*_t35 + _t34
    _t37 = design_11*design_20**2
    _t38 = design_22*design_24**2
    _t39 = _t7**2
    _t40 = _t5**2
    _t41 = design_17 + design_23 + _t37*_t39 + _t37*_t40 - _t37 + _t38*_t39 + _t38*_t40 - _t38
    _t42 = _t30*_t41
    _t43 = _t36*_t42
    _t44 = design_10*design_19**2
    _t45 = design_14*design_21**2
    _t46 = _t0**2
    _t47 = design_0**2
    _t48 = _t47*design_15
    _t49 = _t1**2
    _t50 = design_16 + design_18 + _t44*_t46 + _t44*_t49 - _t44 + _t45*_t46 + _t45*_t49 - _t45 + _t46*_t48 + _t48*_t49
    _t51 = _t11*_t50
    _t52 = _t32*_t51
    _t53 = _t20 + _t22*_t32 - _t43 - _t52
    _t54 = -_t27 - _t29*_t31
    _t55 = -_t15*_t35 - _t34
    _t56 = _t42*_t55 + _t51*_t54
    _t57 = -_t22*_t54 + _t56
    _t58 = -_t20 - _t57
    _t59 = _t43 + _t52
    _t60 = _t6*x_dot_0**2
    _t61 = _t2*_t60*(_t46/_t49 + 1) + _t3*x_ddot_0 + x_ddot_1
    _t62 = -_t11*_t22
    _t63 = _t24/_t47
    _t64 = -_t11*(-_t21 - _t51) + _t41*_t49*_t63
    _t65 = _t62 + _t64 + design_8 + design_10 + design_12 + design_14 + design_15
    _t66 = _t12*_t60*(_t39/_t40 + 1) + _t13*x_ddot_0 + x_ddot_1
    _t67 = _t7*design_20
    _t68 = _t7*design_24
    _t69 = _t67*design_11 + _t68*design_22
    _t70 = -_t69
    _t71 = _t30*_t70
    _t72 = -_t64 - _t71
    _t73 = design_25*design_10
    _t74 = design_25*design_14
    _t75 = design_25*design_15
    _t76 = design_25*design_11
    _t77 = design_25*design_22
    _t78 = _t30*(-_t67*_t76 - _t68*_t77)
    _t79 = _t11*(-_t0*_t73*design_19 - _t0*_t74*design_21 - _t0*_t75*design_0)
    _t80 = _t73 + _t74 + _t75 - _t78 - _t79 + design_25*design_8 - design_25*design_12
    _t81 = 2*_t5
    _t82 = (1/2)*_t30*_t31*(-_t81*design_11*design_20 - _t81*design_22*design_24)
    _t83 = _t36*_t70 + _t59
    _t84 = _t82 + _t83
    _t85 = _t55*_t70 + _t56
    _t86 = -_t82 + _t85
    _t87 = _t30*(_t1*_t41/(_t8*design_0) - _t69) + _t40*_t50*_t63
    _t88 = -_t62 - _t87
    _t89 = _t71 + _t87 + design_9 + design_11 + design_13 + design_22
    _t90 = _t76 + _t77 + _t78 + _t79 + design_25*design_9 - design_25*design_13
    tau = ca.reshape(ca.vertcat(_t61*_t65 + _t66*_t72 + _t80 + x_dot_0*(_t13*_t53 + _t3*_t58) + x_dot_1*(_t22*_t32 - _t57 - _t59), _t61*_t88 + _t66*_t89 + _t90 + x_dot_0*(_t13*_t84 + _t3*_t86) + x_dot_1*(_t83 + _t85)), 2, 1)
    M_t = ca.reshape(ca.vertcat(_t65, _t88, _t72, _t89), 2, 2)
    C_t = ca.reshape(ca.vertcat(_t58, _t86, _t53, _t84), 2, 2)
    g_t = ca.reshape(ca.vertcat(_t80, _t90), 2, 1)
    return ca.Function("lagrange_dynamics", [q, x, x_dot, x_ddot, design], [tau, M_t, C_t, g_t], ["q", "x", "x_dot", "x_ddot", "design"], ["tau", "M_t", "C_t", "g_t"])


def energy():
    """Kinetic and potential energy (for power balance: tau . q_a_dot = d(T + V)/dt).

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        x_dot (2): [x_dot, y_dot] platform velocity [m/s]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        T (1x1, column-major): kinetic energy of every body [J]
        V (1x1, column-major): gravitational potential energy [J]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    x_dot = ca.SX.sym("x_dot", 2)
    x_dot_0 = x_dot[0]
    x_dot_1 = x_dot[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 22 common subexpressions, 127 operations
    _t0 = x_dot_0**2
    _t1 = ca.cos(q_2)
    _t2 = x_dot_0*ca.sin(q_2)/_t1
    _t3 = _t2 + x_dot_1
    _t4 = (1/2)*_t3**2
    _t5 = ca.cos(q_3)
    _t6 = x_dot_0*ca.sin(q_3)/_t5
    _t7 = _t6 + x_dot_1
    _t8 = (1/2)*_t7**2
    _t9 = design_19**2
    _t10 = _t0/design_0**2
    _t11 = (1/2)*_t10
    _t12 = _t11/_t1**2
    _t13 = design_20**2
    _t14 = _t11/_t5**2
    _t15 = design_21**2
    _t16 = design_24**2
    _t17 = 1/design_0
    _t18 = _t17*_t2
    _t19 = _t17*_t6
    _t20 = design_25*q_0
    _t21 = design_25*q_1
    T = ca.reshape(ca.vertcat(_t12*(design_16 - _t9*design_10) + _t12*(design_18 - _t15*design_14) + _t14*(design_17 - _t13*design_11) + _t14*(design_23 - _t16*design_22) + _t4*design_8 + _t4*design_12 + _t8*design_9 + _t8*design_13 + (1/2)*design_10*(_t10*_t9 + (-_t18*design_19 + _t3)**2) + (1/2)*design_11*(_t10*_t13 + (-_t19*design_20 + _t7)**2) + (1/2)*design_14*(_t10*_t15 + (-_t18*design_21 + _t3)**2) + (1/2)*design_22*(_t10*_t16 + (-_t19*design_24 + _t7)**2) + (1/2)*design_15*(_t0 + x_dot_1**2)), 1, 1)
    V = ca.reshape(ca.vertcat(_t20*design_8 - _t20*design_12 + _t21*design_9 - _t21*design_13 + design_25*design_10*(_t1*design_19 + q_0) + design_25*design_11*(_t5*design_20 + q_1) + design_25*design_14*(_t1*design_21 + design_3 + q_0) + design_25*design_22*(_t5*design_24 + design_3 + q_1) + design_25*design_15*(_t1*design_0 + (1/2)*design_3 + q_0)), 1, 1)
    return ca.Function("energy", [q, x, x_dot, design], [T, V], ["q", "x", "x_dot", "design"], ["T", "V"])


def inertia():
    """Inertia matrices of a posture (Wu eqs. 41-43).

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        M_t (2x2, column-major): slider-space mass matrix [kg]
        M_w (2x2, column-major): task-space mass matrix M of eq. 41 [kg]
        M_d (2x2, column-major): Wu's inertia matrix (J^T)^-1 M of eq. 42: tau = M_d x_ddot [kg]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 43 common subexpressions, 147 operations
    _t0 = ca.sin(q_2)
    _t1 = ca.cos(q_2)
    _t2 = 1/_t1
    _t3 = _t0*_t2
    _t4 = ca.sin(q_3)
    _t5 = ca.cos(q_3)
    _t6 = 1/_t5
    _t7 = _t4*_t6
    _t8 = 1/(_t3 - _t7)
    _t9 = design_8 + design_10 + design_12 + design_9 + design_11 + design_13 + design_14 + design_22 + design_15
    _t10 = _t7*_t8
    _t11 = _t3*design_10
    _t12 = _t7*design_11
    _t13 = _t3*design_14
    _t14 = _t7*design_22
    _t15 = 1/design_0
    _t16 = _t3*design_8 + _t3*design_12 + _t7*design_9 + _t7*design_13
    _t17 = -_t11*_t15*design_19 + _t11 - _t12*_t15*design_20 + _t12 - _t13*_t15*design_21 + _t13 - _t14*_t15*design_24 + _t14 + _t16
    _t18 = -_t17*_t8
    _t19 = -_t10*_t9 - _t18
    _t20 = _t15*_t3
    _t21 = design_10*(-_t20*design_19 + _t3)
    _t22 = _t15*_t7
    _t23 = design_11*(-_t22*design_20 + _t7)
    _t24 = design_14*(-_t20*design_21 + _t3)
    _t25 = design_22*(-_t22*design_24 + _t7)
    _t26 = _t16 + _t21 + _t23 + _t24 + _t25
    _t27 = _t0**2
    _t28 = _t27/_t1**2
    _t29 = _t4**2
    _t30 = _t29/_t5**2
    _t31 = 1/(_t1*design_0)
    _t32 = _t2*_t27
    _t33 = 1/(_t5*design_0)
    _t34 = _t29*_t6
    _t35 = _t21*_t3 + _t23*_t7 + _t24*_t3 + _t25*_t7 + _t28*design_8 + _t28*design_12 + _t30*design_9 + _t30*design_13 + _t31*(design_16*_t31 - _t32*design_10*design_19) + _t31*(design_18*_t31 - _t32*design_14*design_21) + _t33*(design_17*_t33 - _t34*design_11*design_20) + _t33*(design_23*_t33 - _t34*design_22*design_24) + design_15
    _t36 = _t35*_t8
    _t37 = -_t36
    _t38 = _t10*_t26 + _t37
    _t39 = _t3*_t8
    _t40 = _t18 + _t39*_t9
    _t41 = _t26*_t39
    _t42 = _t36 - _t41
    M_t = ca.reshape(ca.vertcat(_t8*(-_t19*_t7 - _t38), _t8*(-_t40*_t7 - _t42), _t8*(_t19*_t3 + _t38), _t8*(_t3*_t40 + _t42)), 2, 2)
    M_w = ca.reshape(ca.vertcat(_t35, _t26, _t17, _t9), 2, 2)
    M_d = ca.reshape(ca.vertcat(-_t38, _t37 + _t41, _t19, _t40), 2, 2)
    return ca.Function("inertia", [q, x, design], [M_t, M_w, M_d], ["q", "x", "design"], ["M_t", "M_w", "M_d"])


def skeleton():
    """The points of the joints, leg by leg, for drawing the linkage and for its elastic elements.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        points (6x2, column-major): each leg's joints, one row each [m]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 3 common subexpressions, 6 operations
    _t0 = design_1 + design_2
    _t1 = -_t0
    _t2 = -1/2*design_3 + x_1
    points = ca.reshape(ca.vertcat(_t1, _t1, -design_2 + x_0, _t0, _t0, design_2 + x_0, 0, q_0, _t2, 0, q_1, _t2), 6, 2)
    return ca.Function("skeleton", [q, x, design], [points], ["q", "x", "design"], ["points"])


def elastic():
    """The compliance of each leg's drive and of each of its beams.

    Inputs:
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        drives (2x1, column-major): each leg's drive compliance [rad/(N m), m/N]
        passive (2x1, column-major): each passive joint's compliance, 0: free [rad/(N m)]
        beams (2x5, column-major): the links, chain by chain (a parallelogram's two side by side): each beam's compliance terms at its end, clamped at its start: axial, bending_uu, bending_uphi, bending_phiphi, torsion [SI]
        bearings (2x1, column-major): the joints' bearings' compliance: rigid [m/N]
    """
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 8 common subexpressions, 25 operations
    _t0 = 1/design_28
    _t1 = design_26 - 2*design_27
    _t2 = design_0/(-420000000000.0*_t1**2 + 420000000000.0*design_26**2)
    _t3 = design_26**4
    _t4 = _t1**4
    _t5 = design_0**3/(105000000000.0*_t3 - 105000000000.0*_t4)
    _t6 = design_0**2/(70000000000.0*_t3 - 70000000000.0*_t4)
    _t7 = design_0/(35000000000.0*_t3 - 35000000000.0*_t4)
    drives = ca.reshape(ca.vertcat(_t0, _t0), 2, 1)
    passive = ca.reshape(ca.vertcat(0, 0), 2, 1)
    beams = ca.reshape(ca.vertcat(_t2, _t2, _t5, _t5, _t6, _t6, _t7, _t7, 0, 0), 2, 5)
    bearings = ca.reshape(ca.vertcat(0, 0), 2, 1)
    return ca.Function("elastic", [design], [drives, passive, beams, bearings], ["design"], ["drives", "passive", "beams", "bearings"])


def leg_ends():
    """The derivative of each leg's closure in its platform joint's point.

    Inputs:
        q (4): [q1, q2, theta1, theta2] slider positions [m], then link angles from the vertical [rad]
        x (2): [x, y] platform reference point O' [m]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        H_c (4x2, column-major): each leg's closure's derivative in its platform joint [-]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 0 common subexpressions, 0 operations
    H_c = ca.reshape(ca.vertcat(1, 0, 1, 0, 0, 1, 0, 1), 4, 2)
    return ca.Function("leg_ends", [q, x, design], [H_c], ["q", "x", "design"], ["H_c"])


def inertia_from_pose():
    """inverse_kinematics and inertia at its q, inertia with the cosine and sine of each joint angle from the position vectors of the links (no trigonometric call). inertia: Inertia matrices of a posture (Wu eqs. 41-43).

    Inputs:
        x (2): [x, y] platform reference point O' [m]
        mode (2): [sigma1, sigma2] branch of each chain: +1 slider below its platform joint, -1 above
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        q (4x1, column-major): q1, q2 [m], theta1, theta2 [rad]
        reach (4x1, column-major): l^2 - (x +- d1)^2 [m^2] and (q_i - qs)(ql - q_i) [m^2]; >= 0 where reachable
        M_t (2x2, column-major): slider-space mass matrix [kg]
        M_w (2x2, column-major): task-space mass matrix M of eq. 41 [kg]
        M_d (2x2, column-major): Wu's inertia matrix (J^T)^-1 M of eq. 42: tau = M_d x_ddot [kg]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 43 common subexpressions, 216 operations
    _t0 = design_0**2
    _t1 = design_1 + x_0
    _t2 = _t1**2
    _t3 = _t0 - _t2
    _t4 = mode_0*ca.sqrt(ca.fmax(0, _t3))
    _t5 = (1/2)*design_3 - x_1
    _t6 = _t4 + _t5
    _t7 = -design_1 + x_0
    _t8 = _t7**2
    _t9 = _t0 - _t8
    _t10 = mode_1*ca.sqrt(ca.fmax(0, _t9))
    _t11 = _t10 + _t5
    _t12 = 1/design_0
    _t13 = _t10
    _t14 = _t4
    _t15 = _t1*_t13 - _t14*_t7
    _t16 = _t15**(-2)
    _t17 = design_8 + design_10 + design_12 + design_9 + design_11 + design_13 + design_14 + design_22 + design_15
    _t18 = _t7*design_0
    _t19 = _t1*design_0
    _t20 = design_10*design_19
    _t21 = design_11*design_20
    _t22 = design_14*design_21
    _t23 = design_22*design_24
    _t24 = _t13*_t19*design_8 + _t13*_t19*design_12 + _t14*_t18*design_9 + _t14*_t18*design_13
    _t25 = -_t1*_t13*_t20 - _t1*_t13*_t22 + _t13*_t19*design_10 + _t13*_t19*design_14 + _t14*_t18*design_11 + _t14*_t18*design_22 - _t14*_t21*_t7 - _t14*_t23*_t7 + _t24
    _t26 = -_t14*_t17*_t18 + _t25
    _t27 = design_10*(design_0 - design_19)
    _t28 = design_11*(design_0 - design_20)
    _t29 = design_14*(design_0 - design_21)
    _t30 = design_22*(design_0 - design_24)
    _t31 = _t1*_t13*_t27 + _t1*_t13*_t29 + _t14*_t28*_t7 + _t14*_t30*_t7 + _t24
    _t32 = _t2*design_0
    _t33 = _t13**2
    _t34 = _t8*design_0
    _t35 = _t14**2
    _t36 = _t2*_t27*_t33 + _t2*_t29*_t33 + _t28*_t35*_t8 + _t30*_t35*_t8 + _t32*_t33*design_8 + _t32*_t33*design_12 + _t33*_t35*design_0*design_15 + _t33*(design_16*design_0 - _t2*_t20) + _t33*(design_18*design_0 - _t2*_t22) + _t34*_t35*design_9 + _t34*_t35*design_13 + _t35*(design_17*design_0 - _t21*_t8) + _t35*(design_23*design_0 - _t23*_t8)
    _t37 = -_t14*_t31*_t7 + _t36
    _t38 = _t1*_t13*_t17*design_0 - _t25
    _t39 = -_t1*_t13*_t31 + _t36
    _t40 = 1/_t14
    _t41 = 1/_t13
    _t42 = 1/_t15
    q = ca.reshape(ca.vertcat(-_t6, -_t11, ca.atan2(_t1, _t4), ca.atan2(_t7, _t10)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t3, _t9, (-_t6 - design_4)*(_t6 + design_5), (-_t11 - design_4)*(_t11 + design_5)), 4, 1)
    M_t = ca.reshape(ca.vertcat(_t12*_t16*(-_t14*_t26*_t7 + _t37), _t12*_t16*(-_t14*_t38*_t7 - _t39), _t12*_t16*(_t1*_t13*_t26 - _t37), _t12*_t16*(_t1*_t13*_t38 + _t39)), 2, 2)
    M_w = ca.reshape(ca.vertcat(_t12*_t36/(_t33*_t35), _t31/(_t13*_t14*design_0), _t25/(_t13*_t14*design_0), _t17), 2, 2)
    M_d = ca.reshape(ca.vertcat(_t37/(_t13*_t14*_t15*design_0), -_t39/(_t13*_t14*_t15*design_0), _t26/(_t15*design_0), _t38/(_t15*design_0)), 2, 2)
    return ca.Function("inertia_from_pose", [x, mode, design], [q, reach, M_t, M_w, M_d], ["x", "mode", "design"], ["q", "reach", "M_t", "M_w", "M_d"])


def inverse_dynamics_from_pose():
    """inverse_kinematics and inverse_dynamics at its q, inverse_dynamics with the cosine and sine of each joint angle from the position vectors of the links (no trigonometric call). inverse_dynamics: Driving forces of a platform motion by virtual work (Wu eq. 41).

    Inputs:
        x (2): [x, y] platform reference point O' [m]
        mode (2): [sigma1, sigma2] branch of each chain: +1 slider below its platform joint, -1 above
        x_dot (2): [x_dot, y_dot] platform velocity [m/s]
        x_ddot (2): [x_ddot, y_ddot] platform acceleration [m/s^2]
        design (29): [l, d1, d2, l2, qs, ql, theta_s, theta_l, m11, m21, m12, m22, m13, m23, m4, mN, I12, I22, I4, s12, s22, s4, m5, I5, s5, g, b_l, t_l, k_s] l, d1, d2, l2, qs, ql [m]; theta_s, theta_l [rad]; m11, m21, m12, m22, m13, m23, m4, mN [kg]; I12, I22, I4 [kg m^2]; s12, s22, s4 [m]; m5 [kg], I5 [kg m^2], s5 [m] of link A4B4; g [m/s^2]; b_l, t_l [m]; k_s [N/m]
    Outputs:
        q (4x1, column-major): q1, q2 [m], theta1, theta2 [rad]
        reach (4x1, column-major): l^2 - (x +- d1)^2 [m^2] and (q_i - qs)(ql - q_i) [m^2]; >= 0 where reachable
        tau (2x1, column-major): slider driving forces F1, F2 [N]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    x_dot = ca.SX.sym("x_dot", 2)
    x_dot_0 = x_dot[0]
    x_dot_1 = x_dot[1]
    x_ddot = ca.SX.sym("x_ddot", 2)
    x_ddot_0 = x_ddot[0]
    x_ddot_1 = x_ddot[1]
    design = ca.SX.sym("design", 29)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    design_5 = design[5]
    design_6 = design[6]
    design_7 = design[7]
    design_8 = design[8]
    design_9 = design[9]
    design_10 = design[10]
    design_11 = design[11]
    design_12 = design[12]
    design_13 = design[13]
    design_14 = design[14]
    design_15 = design[15]
    design_16 = design[16]
    design_17 = design[17]
    design_18 = design[18]
    design_19 = design[19]
    design_20 = design[20]
    design_21 = design[21]
    design_22 = design[22]
    design_23 = design[23]
    design_24 = design[24]
    design_25 = design[25]
    design_26 = design[26]
    design_27 = design[27]
    design_28 = design[28]
    # 71 common subexpressions, 315 operations
    _t0 = design_0**2
    _t1 = design_1 + x_0
    _t2 = _t1**2
    _t3 = _t0 - _t2
    _t4 = mode_0*ca.sqrt(ca.fmax(0, _t3))
    _t5 = (1/2)*design_3 - x_1
    _t6 = _t4 + _t5
    _t7 = -design_1 + x_0
    _t8 = _t7**2
    _t9 = _t0 - _t8
    _t10 = mode_1*ca.sqrt(ca.fmax(0, _t9))
    _t11 = _t10 + _t5
    _t12 = 1/design_0
    _t13 = _t4
    _t14 = _t13**3
    _t15 = 1/_t14
    _t16 = _t10
    _t17 = _t16**3
    _t18 = 1/_t17
    _t19 = 1/(_t1*_t16 - _t13*_t7)
    _t20 = design_25*design_0
    _t21 = _t14*_t17
    _t22 = design_0*design_8
    _t23 = _t14*design_25
    _t24 = x_dot_0**2
    _t25 = _t13**2
    _t26 = _t2 + _t25
    _t27 = _t24*_t26
    _t28 = _t23 + _t27
    _t29 = design_0*design_12
    _t30 = _t23 - _t27
    _t31 = design_0*design_9
    _t32 = _t17*design_25
    _t33 = _t16**2
    _t34 = _t33 + _t8
    _t35 = _t24*_t34
    _t36 = _t32 + _t35
    _t37 = design_0*design_13
    _t38 = _t32 - _t35
    _t39 = _t24*design_19
    _t40 = _t24*design_0
    _t41 = _t14*_t20 + _t26*_t40
    _t42 = -_t2*_t39 - _t25*_t39 + _t41
    _t43 = _t24*design_21
    _t44 = -_t2*_t43 - _t25*_t43 + _t41
    _t45 = _t24*design_20
    _t46 = _t17*_t20 + _t34*_t40
    _t47 = -_t33*_t45 - _t45*_t8 + _t46
    _t48 = _t24*design_24
    _t49 = -_t33*_t48 + _t46 - _t48*_t8
    _t50 = design_0 - design_19
    _t51 = _t1*design_10
    _t52 = design_0 - design_20
    _t53 = _t7*design_11
    _t54 = design_0 - design_21
    _t55 = _t1*design_14
    _t56 = design_0 - design_24
    _t57 = _t7*design_22
    _t58 = _t1*_t22
    _t59 = _t1*_t29
    _t60 = _t31*_t7
    _t61 = _t37*_t7
    _t62 = _t13*_t60 + _t13*_t61 + _t16*_t58 + _t16*_t59
    _t63 = _t14*_t31*_t36 - _t14*_t37*_t38 + _t14*_t47*design_11 + _t14*_t49*design_22 + _t17*_t22*_t28 - _t17*_t29*_t30 + _t17*_t42*design_10 + _t17*_t44*design_14 + _t20*_t21*design_15 + _t21*design_0*x_ddot_1*(design_8 + design_10 + design_12 + design_9 + design_11 + design_13 + design_14 + design_22 + design_15) + _t25*_t33*x_ddot_0*(_t13*_t52*_t53 + _t13*_t56*_t57 + _t16*_t50*_t51 + _t16*_t54*_t55 + _t62)
    _t64 = _t16**4
    _t65 = design_10*design_19
    _t66 = design_14*design_21
    _t67 = _t13**4
    _t68 = design_11*design_20
    _t69 = design_22*design_24
    _t70 = _t1*_t64*(design_16*_t40 - _t28*_t65) + _t1*_t64*(design_18*_t40 - _t28*_t66) + _t14*_t17*x_ddot_1*(-_t1*_t16*_t65 - _t1*_t16*_t66 + _t13*_t53*design_0 + _t13*_t57*design_0 - _t13*_t68*_t7 - _t13*_t69*_t7 + _t16*_t51*design_0 + _t16*_t55*design_0 + _t62) + _t25*_t33*x_ddot_0*(_t2*_t22*_t33 + _t2*_t29*_t33 + _t2*_t33*_t50*design_10 + _t2*_t33*_t54*design_14 + _t25*_t31*_t8 + _t25*_t33*design_0*design_15 + _t25*_t37*_t8 + _t25*_t52*_t8*design_11 + _t25*_t56*_t8*design_22 + _t25*(design_17*design_0 - _t68*_t8) + _t25*(design_23*design_0 - _t69*_t8) + _t33*(design_16*design_0 - _t2*_t65) + _t33*(design_18*design_0 - _t2*_t66)) + _t28*_t58*_t64 - _t30*_t59*_t64 + _t36*_t60*_t67 - _t38*_t61*_t67 + _t42*_t51*_t64 + _t44*_t55*_t64 + _t47*_t53*_t67 + _t49*_t57*_t67 + _t67*_t7*(design_17*_t40 - _t36*_t68) + _t67*_t7*(design_23*_t40 - _t36*_t69)
    q = ca.reshape(ca.vertcat(-_t6, -_t11, ca.atan2(_t1, _t4), ca.atan2(_t7, _t10)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t3, _t9, (-_t6 - design_4)*(_t6 + design_5), (-_t11 - design_4)*(_t11 + design_5)), 4, 1)
    tau = ca.reshape(ca.vertcat((-_t13*_t63*_t7 + _t70)/(_t14*_t17*design_0*(_t1*_t16 - _t13*_t7)), (_t1*_t16*_t63 - _t70)/(_t14*_t17*design_0*(_t1*_t16 - _t13*_t7))), 2, 1)
    return ca.Function("inverse_dynamics_from_pose", [x, mode, x_dot, x_ddot, design], [q, reach, tau], ["x", "mode", "x_dot", "x_ddot", "design"], ["q", "reach", "tau"])


def build():
    """All functions of this module by name."""
    return {name: globals()[name]() for name in FUNCTIONS}
