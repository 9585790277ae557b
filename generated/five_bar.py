# Generated from symbolic/mechanisms/five_bar.py (source sha256 f84aad74511c1b8c).
# Do not edit: regenerate with `make generate`.
# ruff: noqa
"""CasADi functions of the symmetric 5R."""

import casadi as ca

SOURCE_HASH = "f84aad74511c1b8c"
FUNCTIONS = ("inverse_kinematics", "forward_kinematics", "constraint", "first_order", "first_order_from_pose", "maximum_inscribed_circle", "skeleton", "elastic", "leg_ends", "joint_dynamics", "actuated_dynamics", "elastic_dynamics", "inertia", "second_order", "inertia_from_pose", )
PARAMETERS = ("r1", "r2", "r3", "m1", "m2", "c1", "c2", "g1", "g2", "k1", "k2", "j1", "j2", "fv", "fc", "vm", "w_l", "t_l", )
POSE = ("x", "y", )
ACTUATORS = ("theta1", "theta2", )


def inverse_kinematics():
    """Closed-form inverse kinematics of both chains for the elbow signs in mode.

    Inputs:
        x (2): [x, y] end-effector position [m]
        mode (2): [sigma1, sigma2] elbow signs of chains 1 and 2 (+1 or -1)
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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
    # 20 common subexpressions, 69 operations
    _t0 = design_2 + x_0
    _t1 = design_0**2
    _t2 = x_1**2
    _t3 = _t0**2
    _t4 = _t2 + _t3
    _t5 = (1/2)*_t1 + (1/2)*_t2 - 1/2*design_1**2
    _t6 = (1/2)*_t3 + _t5
    _t7 = _t1*_t4 - _t6**2
    _t8 = 1/_t1
    _t9 = _t7*_t8/_t4
    _t10 = ca.if_else((_t9 > 1/1125899906842624), ca.sqrt(_t7), 0)
    _t11 = -design_2 + x_0
    _t12 = _t11**2
    _t13 = _t12 + _t2
    _t14 = (1/2)*_t12 + _t5
    _t15 = _t1*_t13 - _t14**2
    _t16 = _t15*_t8/_t13
    _t17 = ca.if_else((_t16 > 1/1125899906842624), ca.sqrt(_t15), 0)
    _t18 = _t10*mode_0
    _t19 = _t17*mode_1
    q = ca.reshape(ca.vertcat(mode_0*ca.atan2(_t10, _t6) + ca.atan2(x_1, _t0), mode_1*ca.atan2(_t17, _t14) + ca.atan2(x_1, _t11), ca.atan2(-_t0*_t18 + _t4*x_1 - _t6*x_1, _t0*_t4 - _t0*_t6 + _t18*x_1), ca.atan2(-_t11*_t19 + _t13*x_1 - _t14*x_1, _t11*_t13 - _t11*_t14 + _t19*x_1)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t9, _t16), 2, 1)
    return ca.Function("inverse_kinematics", [x, mode, design], [q, reach], ["x", "mode", "design"], ["q", "reach"])


def forward_kinematics():
    """Closed-form forward kinematics: intersection of the circles of radius r2 about the elbows.

    Inputs:
        q_a (2): [theta1, theta2] actuated joint angles [rad]
        assembly (1): [sigma] side of the line A1 -> A2 on which P lies (+1 left, -1 right)
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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


def first_order_from_pose():
    """inverse_kinematics and first_order at its q, first_order with the cosine and sine of each joint angle from the position vectors of the links (no trigonometric call). first_order: First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        x (2): [x, y] end-effector position [m]
        mode (2): [sigma1, sigma2] elbow signs of chains 1 and 2 (+1 or -1)
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        q (4x1, column-major): theta1, theta2, phi1, phi2 [rad]
        reach (2x1, column-major): 1 - cos^2 of each elbow angle; >= 0 where reachable
        J (2x2, column-major): q_a_dot = J x_dot [rad/m]
        J_f (2x2, column-major): x_dot = J_f q_a_dot [m/rad]
        psi (4x2, column-major): q_dot = Psi q_a_dot, all joints from actuated [-]
        det_type1 (1x1, column-major): serial singularity measure [m^2]
        det_type2 (1x1, column-major): parallel singularity measure [m^2]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 18)
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
    # 46 common subexpressions, 137 operations
    _t0 = design_2 + x_0
    _t1 = design_0**2
    _t2 = x_1**2
    _t3 = _t0**2
    _t4 = _t2 + _t3
    _t5 = (1/2)*_t1 + (1/2)*_t2 - 1/2*design_1**2
    _t6 = (1/2)*_t3 + _t5
    _t7 = _t1*_t4 - _t6**2
    _t8 = 1/_t1
    _t9 = 1/_t4
    _t10 = _t7/(_t1*_t4)
    _t11 = ca.if_else((_t10 > 1/1125899906842624), ca.sqrt(_t7), 0)
    _t12 = -design_2 + x_0
    _t13 = _t12**2
    _t14 = _t13 + _t2
    _t15 = (1/2)*_t13 + _t5
    _t16 = _t1*_t14 - _t15**2
    _t17 = 1/_t14
    _t18 = _t16/(_t1*_t14)
    _t19 = ca.if_else((_t18 > 1/1125899906842624), ca.sqrt(_t16), 0)
    _t20 = _t11*mode_0
    _t21 = _t0*_t20 + _t6*x_1
    _t22 = -_t21 + _t4*x_1
    _t23 = -_t0*_t6 + _t20*x_1
    _t24 = _t0*_t4 + _t23
    _t25 = _t19*mode_1
    _t26 = _t12*_t25 + _t15*x_1
    _t27 = _t14*x_1 - _t26
    _t28 = -_t12*_t15 + _t25*x_1
    _t29 = _t12*_t14 + _t28
    _t30 = -_t23
    _t31 = _t22*_t30
    _t32 = -_t21*_t24 + _t31
    _t33 = -_t32
    _t34 = _t4/_t33
    _t35 = -_t28
    _t36 = _t27*_t35
    _t37 = -_t26*_t29 + _t36
    _t38 = -_t37
    _t39 = _t14/_t38
    _t40 = -_t22*_t29 + _t24*_t27
    _t41 = 1/_t40
    _t42 = 1/(_t4*_t40)
    _t43 = _t33*_t42
    _t44 = 1/(_t14*_t40)
    _t45 = _t37*_t44
    q = ca.reshape(ca.vertcat(mode_0*ca.atan2(_t11, _t6) + ca.atan2(x_1, _t0), mode_1*ca.atan2(_t19, _t15) + ca.atan2(x_1, _t12), ca.atan2(_t22, _t24), ca.atan2(_t27, _t29)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t10, _t18), 2, 1)
    J = ca.reshape(ca.vertcat(-_t24*_t34, -_t29*_t39, -_t22*_t34, -_t27*_t39), 2, 2)
    J_f = ca.reshape(ca.vertcat(_t27*_t32*_t42, _t29*_t43, _t22*_t38*_t44, _t24*_t45), 2, 2)
    psi = ca.reshape(ca.vertcat(1, 0, _t41*(_t21*_t29 - _t27*_t30), _t14*_t43, 0, 1, _t4*_t45, _t41*(_t22*_t35 - _t24*_t26)), 4, 2)
    det_type1 = ca.reshape(ca.vertcat((-_t21*_t24*_t26*_t29 + _t21*_t24*_t27*_t35 + _t22*_t26*_t29*_t30 - _t31*_t36)/(_t14**2*_t4**2)), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(-_t40/(_t14*_t4)), 1, 1)
    return ca.Function("first_order_from_pose", [x, mode, design], [q, reach, J, J_f, psi, det_type1, det_type2], ["x", "mode", "design"], ["q", "reach", "J", "J_f", "psi", "det_type1", "det_type2"])


def maximum_inscribed_circle():
    """Maximum inscribed circle of the workspace of the out_out working mode (Lara-Molina eqs. 10-12).

    Inputs:
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        centre (2x1, column-major): centre (0, y_MIC) of the MIC [m]
        radius (1x1, column-major): radius r_MIC of the MIC [m]
    """
    design = ca.SX.sym("design", 18)
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
    # 8 common subexpressions, 45 operations
    _t0 = design_2**2
    _t1 = ca.fabs(design_0 - design_1)
    _t2 = design_0 + design_1
    _t3 = (design_1 > design_0 + design_2)
    _t4 = ca.if_else(_t3, 1, ca.sqrt(ca.fmax(0, design_0**2 - (design_1 - design_2)**2)))
    _t5 = -_t0 + (_t2 + _t4)**2
    _t6 = 2*_t4 + 2*design_0 + 2*design_1
    _t7 = _t5/_t6
    centre = ca.reshape(ca.vertcat(0, ca.if_else(_t3, ca.sqrt(-_t0 + (1/4)*(_t1 + _t2)**2), _t7)), 2, 1)
    radius = ca.reshape(ca.vertcat(ca.if_else(_t3, -1/2*_t1 + (1/2)*design_0 + (1/2)*design_1, ca.fmin(-_t4 + _t7, -_t1 + ca.sqrt(_t0 + _t5**2/_t6**2)))), 1, 1)
    return ca.Function("maximum_inscribed_circle", [design], [centre, radius], ["design"], ["centre", "radius"])


def skeleton():
    """The points of the joints, leg by leg, for drawing the linkage and for its elastic elements.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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
    # 1 common subexpressions, 11 operations
    _t0 = -design_2
    points = ca.reshape(ca.vertcat(_t0, _t0 + design_0*ca.cos(q_0), x_0, design_2, design_0*ca.cos(q_1) + design_2, x_0, 0, design_0*ca.sin(q_0), x_1, 0, design_0*ca.sin(q_1), x_1), 6, 2)
    return ca.Function("skeleton", [q, x, design], [points], ["q", "x", "design"], ["points"])


def elastic():
    """The compliance of each leg's drive and of each of its beams.

    Inputs:
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        drives (2x1, column-major): each leg's drive compliance [rad/(N m), m/N]
        passive (2x1, column-major): each passive joint's compliance, 0: free [rad/(N m)]
        beams (4x5, column-major): the aluminium square tubes w_l x w_l x t_l, proximal then distal, chain by chain: each beam's compliance terms at its end, clamped at its start: axial, bending_uu, bending_uphi, bending_phiphi, torsion [SI]
        bearings (2x1, column-major): the joints' bearings' compliance: rigid [m/N]
    """
    design = ca.SX.sym("design", 18)
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
    # 15 common subexpressions, 36 operations
    _t0 = -2*design_17 + design_16
    _t1 = 1/(-70000000000.0*_t0**2 + 70000000000.0*design_16**2)
    _t2 = _t1*design_0
    _t3 = _t1*design_1
    _t4 = design_16**4
    _t5 = _t0**4
    _t6 = 1/(17500000000.0*_t4 - 17500000000.0*_t5)
    _t7 = _t6*design_0**3
    _t8 = _t6*design_1**3
    _t9 = 1/(11666666666.666666*_t4 - 11666666666.666666*_t5)
    _t10 = _t9*design_0**2
    _t11 = _t9*design_1**2
    _t12 = 1/(5833333333.333333*_t4 - 5833333333.333333*_t5)
    _t13 = _t12*design_0
    _t14 = _t12*design_1
    drives = ca.reshape(ca.vertcat(1/design_9, 1/design_10), 2, 1)
    passive = ca.reshape(ca.vertcat(0, 0), 2, 1)
    beams = ca.reshape(ca.vertcat(_t2, _t3, _t2, _t3, _t7, _t8, _t7, _t8, _t10, _t11, _t10, _t11, _t13, _t14, _t13, _t14, 0, 0, 0, 0), 4, 5)
    bearings = ca.reshape(ca.vertcat(0, 0), 2, 1)
    return ca.Function("elastic", [design], [drives, passive, beams, bearings], ["design"], ["drives", "passive", "beams", "bearings"])


def leg_ends():
    """The derivative of each leg's closure in its platform joint's point.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
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
    design = ca.SX.sym("design", 18)
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
    # 0 common subexpressions, 0 operations
    H_c = ca.reshape(ca.vertcat(1, 0, 1, 0, 0, 1, 0, 1), 4, 2)
    return ca.Function("leg_ends", [q, x, design], [H_c], ["q", "x", "design"], ["H_c"])


def joint_dynamics():
    """Stacked chain dynamics of the links in the joint coordinates (Lara-Molina eqs. 20-21).

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        q_dot (4): [theta1_dot, theta2_dot, phi1_dot, phi2_dot] rates of q [rad/s]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        M (4x4, column-major): mass matrix of the links in q (eq. 21) [kg m^2]
        C (4x4, column-major): Christoffel Coriolis matrix in q [kg m^2/s]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_dot = ca.SX.sym("q_dot", 4)
    q_dot_0 = q_dot[0]
    q_dot_1 = q_dot[1]
    q_dot_2 = q_dot[2]
    q_dot_3 = q_dot[3]
    design = ca.SX.sym("design", 18)
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
    # 29 common subexpressions, 84 operations
    _t0 = design_0**2
    _t1 = _t0*design_3
    _t2 = _t1*design_7
    _t3 = ca.sin(q_0)
    _t4 = _t3**2
    _t5 = _t0*design_4
    _t6 = ca.cos(q_0)
    _t7 = _t6**2
    _t8 = _t1*design_5**2
    _t9 = ca.sin(q_2)
    _t10 = design_6*design_4*design_0*design_1
    _t11 = _t10*_t9
    _t12 = ca.cos(q_2)
    _t13 = _t10*_t12
    _t14 = _t11*_t3 + _t13*_t6
    _t15 = ca.sin(q_1)
    _t16 = _t15**2
    _t17 = ca.cos(q_1)
    _t18 = _t17**2
    _t19 = ca.sin(q_3)
    _t20 = _t10*_t19
    _t21 = ca.cos(q_3)
    _t22 = _t10*_t21
    _t23 = _t15*_t20 + _t17*_t22
    _t24 = design_4*design_1**2
    _t25 = _t24*design_8
    _t26 = _t24*design_6**2
    _t27 = 2*_t11*_t6 - 2*_t13*_t3
    _t28 = -2*_t15*_t22 + 2*_t17*_t20
    M = ca.reshape(ca.vertcat(_t2 + _t4*_t5 + _t4*_t8 + _t5*_t7 + _t7*_t8, 0, _t14, 0, 0, _t16*_t5 + _t16*_t8 + _t18*_t5 + _t18*_t8 + _t2, 0, _t23, _t14, 0, _t12**2*_t26 + _t25 + _t26*_t9**2, 0, 0, _t23, 0, _t19**2*_t26 + _t21**2*_t26 + _t25), 4, 4)
    C = ca.reshape(ca.vertcat(0, 0, (1/2)*_t27*q_dot_0, 0, 0, 0, 0, (1/2)*_t28*q_dot_1, -1/2*_t27*q_dot_2, 0, 0, 0, 0, -1/2*_t28*q_dot_3, 0, 0), 4, 4)
    return ca.Function("joint_dynamics", [q, q_dot, design], [M, C], ["q", "q_dot", "design"], ["M", "C"])


def actuated_dynamics():
    """Rigid-link dynamics projected onto the actuated joints (eq. 29, Psi_dot term included).

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        q_a_dot (2): [theta1_dot, theta2_dot] actuated joint rates [rad/s]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        M_t (2x2, column-major): M_t = Psi^T M Psi [kg m^2]
        C_t (2x2, column-major): C_t = Psi^T (M Psi_dot + C Psi) [kg m^2/s]
        C_t_paper (2x2, column-major): Lara-Molina's Psi^T C Psi, without Psi_dot [kg m^2/s]
        psi_dot (4x2, column-major): time derivative of Psi [1/s]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    q_a_dot = ca.SX.sym("q_a_dot", 2)
    q_a_dot_0 = q_a_dot[0]
    q_a_dot_1 = q_a_dot[1]
    design = ca.SX.sym("design", 18)
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
    # 82 common subexpressions, 243 operations
    _t0 = design_0**2
    _t1 = _t0*design_3
    _t2 = _t1*design_7
    _t3 = ca.sin(q_0)
    _t4 = _t3**2
    _t5 = _t0*design_4
    _t6 = ca.cos(q_0)
    _t7 = _t6**2
    _t8 = _t1*design_5**2
    _t9 = ca.sin(q_2)
    _t10 = _t3*_t9
    _t11 = design_6*design_4*design_0*design_1
    _t12 = ca.cos(q_2)
    _t13 = _t12*_t6
    _t14 = _t10*_t11 + _t11*_t13
    _t15 = ca.sin(q_3)
    _t16 = ca.cos(q_3)
    _t17 = -_t15*_t6 + _t16*_t3
    _t18 = _t12*_t15 - _t16*_t9
    _t19 = design_0/design_1
    _t20 = _t19/_t18
    _t21 = _t17*_t20
    _t22 = _t6*_t9
    _t23 = _t12*_t3 - _t22
    _t24 = design_1**2
    _t25 = _t24*design_4
    _t26 = _t25*design_8
    _t27 = _t25*design_6**2
    _t28 = _t15**2*_t27 + _t16**2*_t27 + _t26
    _t29 = _t18**(-2)
    _t30 = _t0*_t29/_t24
    _t31 = _t28*_t30
    _t32 = _t12**2*_t27 + _t26 + _t27*_t9**2
    _t33 = _t21*_t32
    _t34 = _t14 + _t33
    _t35 = ca.cos(q_1)
    _t36 = _t15*_t35
    _t37 = ca.sin(q_1)
    _t38 = -_t16*_t37 + _t36
    _t39 = _t20*_t38
    _t40 = _t30*_t32
    _t41 = -_t12*_t37 + _t35*_t9
    _t42 = _t20*_t41
    _t43 = _t28*_t42
    _t44 = _t15*_t37
    _t45 = _t16*_t35
    _t46 = _t11*_t44 + _t11*_t45
    _t47 = _t43 + _t46
    _t48 = _t20*_t23
    _t49 = _t37**2
    _t50 = _t35**2
    _t51 = _t21*q_a_dot_0 + _t39*q_a_dot_1
    _t52 = 2*_t11
    _t53 = -_t12*_t3*_t52 + _t22*_t52
    _t54 = -1/2*_t51*_t53
    _t55 = _t21*_t54
    _t56 = _t15*_t3 + _t16*_t6
    _t57 = _t20*q_a_dot_0
    _t58 = _t12*_t16 + _t15*_t9
    _t59 = _t19*_t29
    _t60 = _t58*_t59
    _t61 = _t51*_t60
    _t62 = _t42*q_a_dot_1 + _t48*q_a_dot_0
    _t63 = -_t58*_t59
    _t64 = _t17*_t61 + _t56*_t57 + _t62*(_t17*_t63 - _t20*_t56)
    _t65 = _t10 + _t13
    _t66 = _t62*_t63
    _t67 = _t23*_t66 + _t51*(-_t20*_t65 + _t23*_t60) + _t57*_t65
    _t68 = (1/2)*_t53*q_a_dot_0
    _t69 = _t32*_t64 + _t68
    _t70 = -2*_t16*_t37*design_6*design_4*design_0*design_1 + _t36*_t52
    _t71 = -1/2*_t62*_t70
    _t72 = _t48*_t71
    _t73 = _t39*_t54
    _t74 = _t44 + _t45
    _t75 = _t20*q_a_dot_1
    _t76 = _t38*_t61 + _t62*(_t20*_t74 + _t38*_t63) - _t74*_t75
    _t77 = (1/2)*_t70*q_a_dot_1
    _t78 = _t12*_t35 + _t37*_t9
    _t79 = _t41*_t66 + _t51*(_t20*_t78 + _t41*_t60) - _t75*_t78
    _t80 = _t28*_t79 + _t77
    _t81 = _t42*_t71
    M_t = ca.reshape(ca.vertcat(_t14*_t21 + _t2 + _t21*_t34 + _t23**2*_t31 + _t4*_t5 + _t4*_t8 + _t5*_t7 + _t7*_t8, _t14*_t39 + _t17*_t38*_t40 + _t47*_t48, _t23*_t31*_t41 + _t34*_t39 + _t46*_t48, _t2 + _t38**2*_t40 + _t42*_t46 + _t42*_t47 + _t49*_t5 + _t49*_t8 + _t5*_t50 + _t50*_t8), 2, 2)
    C_t = ca.reshape(ca.vertcat(_t14*_t64 + _t21*_t69 + _t28*_t48*_t67 + _t55, _t39*_t69 + _t43*_t67 + _t46*_t67 + _t72, _t14*_t76 + _t33*_t76 + _t48*_t80 + _t73, _t32*_t39*_t76 + _t42*_t80 + _t46*_t79 + _t81), 2, 2)
    C_t_paper = ca.reshape(ca.vertcat(_t21*_t68 + _t55, _t39*_t68 + _t72, _t48*_t77 + _t73, _t42*_t77 + _t81), 2, 2)
    psi_dot = ca.reshape(ca.vertcat(0, 0, _t64, _t67, 0, 0, _t76, _t79), 4, 2)
    return ca.Function("actuated_dynamics", [q, x, q_a_dot, design], [M_t, C_t, C_t_paper, psi_dot], ["q", "x", "q_a_dot", "design"], ["M_t", "C_t", "C_t_paper", "psi_dot"])


def elastic_dynamics():
    """Complete model of the manipulator with flexible actuated joints: M_T z_ddot + C_T z_dot + f_t + K_T z = u.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        z_dot (4): [theta1_dot, theta2_dot, theta_m1_dot, theta_m2_dot] rates of z [rad/s]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        M_T (4x4, column-major): blockdiag(M_t, diag(j1, j2)) (eq. 31) [kg m^2]
        C_T (4x4, column-major): blockdiag(C_t, 0) [kg m^2/s]
        K_T (4x4, column-major): joint stiffness matrix [N m/rad]
        f_t (4x1, column-major): friction torques (f_a, V theta_m_dot) (eqs. 22, 31) [N m]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    z_dot = ca.SX.sym("z_dot", 4)
    z_dot_0 = z_dot[0]
    z_dot_1 = z_dot[1]
    z_dot_2 = z_dot[2]
    z_dot_3 = z_dot[3]
    design = ca.SX.sym("design", 18)
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
    # 78 common subexpressions, 247 operations
    _t0 = design_0**2
    _t1 = _t0*design_3
    _t2 = _t1*design_7
    _t3 = ca.sin(q_0)
    _t4 = _t3**2
    _t5 = _t0*design_4
    _t6 = ca.cos(q_0)
    _t7 = _t6**2
    _t8 = _t1*design_5**2
    _t9 = ca.sin(q_2)
    _t10 = _t3*_t9
    _t11 = design_6*design_4*design_0*design_1
    _t12 = ca.cos(q_2)
    _t13 = _t12*_t6
    _t14 = _t10*_t11 + _t11*_t13
    _t15 = ca.sin(q_3)
    _t16 = ca.cos(q_3)
    _t17 = -_t15*_t6 + _t16*_t3
    _t18 = _t12*_t15 - _t16*_t9
    _t19 = design_0/design_1
    _t20 = _t19/_t18
    _t21 = _t17*_t20
    _t22 = _t6*_t9
    _t23 = _t12*_t3 - _t22
    _t24 = design_1**2
    _t25 = _t24*design_4
    _t26 = _t25*design_8
    _t27 = _t25*design_6**2
    _t28 = _t15**2*_t27 + _t16**2*_t27 + _t26
    _t29 = _t18**(-2)
    _t30 = _t0*_t29/_t24
    _t31 = _t28*_t30
    _t32 = _t12**2*_t27 + _t26 + _t27*_t9**2
    _t33 = _t21*_t32
    _t34 = _t14 + _t33
    _t35 = ca.cos(q_1)
    _t36 = _t15*_t35
    _t37 = ca.sin(q_1)
    _t38 = -_t16*_t37 + _t36
    _t39 = _t20*_t38
    _t40 = _t30*_t32
    _t41 = -_t12*_t37 + _t35*_t9
    _t42 = _t20*_t41
    _t43 = _t28*_t42
    _t44 = _t15*_t37
    _t45 = _t16*_t35
    _t46 = _t11*_t44 + _t11*_t45
    _t47 = _t43 + _t46
    _t48 = _t20*_t23
    _t49 = _t37**2
    _t50 = _t35**2
    _t51 = _t21*z_dot_0 + _t39*z_dot_1
    _t52 = 2*_t11
    _t53 = -_t12*_t3*_t52 + _t22*_t52
    _t54 = -1/2*_t51*_t53
    _t55 = _t15*_t3 + _t16*_t6
    _t56 = _t20*z_dot_0
    _t57 = _t12*_t16 + _t15*_t9
    _t58 = _t19*_t29
    _t59 = _t57*_t58
    _t60 = _t51*_t59
    _t61 = _t42*z_dot_1 + _t48*z_dot_0
    _t62 = -_t57*_t58
    _t63 = _t17*_t60 + _t55*_t56 + _t61*(_t17*_t62 - _t20*_t55)
    _t64 = _t10 + _t13
    _t65 = _t61*_t62
    _t66 = _t23*_t65 + _t51*(-_t20*_t64 + _t23*_t59) + _t56*_t64
    _t67 = _t32*_t63 + (1/2)*_t53*z_dot_0
    _t68 = -2*_t16*_t37*design_6*design_4*design_0*design_1 + _t36*_t52
    _t69 = -1/2*_t61*_t68
    _t70 = _t44 + _t45
    _t71 = _t20*z_dot_1
    _t72 = _t38*_t60 + _t61*(_t20*_t70 + _t38*_t62) - _t70*_t71
    _t73 = _t12*_t35 + _t37*_t9
    _t74 = _t41*_t65 + _t51*(_t20*_t73 + _t41*_t59) - _t71*_t73
    _t75 = _t28*_t74 + (1/2)*_t68*z_dot_1
    _t76 = -design_9
    _t77 = -design_10
    M_T = ca.reshape(ca.vertcat(_t14*_t21 + _t2 + _t21*_t34 + _t23**2*_t31 + _t4*_t5 + _t4*_t8 + _t5*_t7 + _t7*_t8, _t14*_t39 + _t17*_t38*_t40 + _t47*_t48, 0, 0, _t23*_t31*_t41 + _t34*_t39 + _t46*_t48, _t2 + _t38**2*_t40 + _t42*_t46 + _t42*_t47 + _t49*_t5 + _t49*_t8 + _t5*_t50 + _t50*_t8, 0, 0, 0, 0, design_11, 0, 0, 0, 0, design_12), 4, 4)
    C_T = ca.reshape(ca.vertcat(_t14*_t63 + _t21*_t54 + _t21*_t67 + _t28*_t48*_t66, _t39*_t67 + _t43*_t66 + _t46*_t66 + _t48*_t69, 0, 0, _t14*_t72 + _t33*_t72 + _t39*_t54 + _t48*_t75, _t32*_t39*_t72 + _t42*_t69 + _t42*_t75 + _t46*_t74, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0), 4, 4)
    K_T = ca.reshape(ca.vertcat(design_9, 0, _t76, 0, 0, design_10, 0, _t77, _t76, 0, design_9, 0, 0, _t77, 0, design_10), 4, 4)
    f_t = ca.reshape(ca.vertcat(design_14*ca.sign(z_dot_0) + design_13*z_dot_0, design_14*ca.sign(z_dot_1) + design_13*z_dot_1, z_dot_2*design_15, z_dot_3*design_15), 4, 1)
    return ca.Function("elastic_dynamics", [q, x, z_dot, design], [M_T, C_T, K_T, f_t], ["q", "x", "z_dot", "design"], ["M_T", "C_T", "K_T", "f_t"])


def inertia():
    """Inertia matrices of a posture and the elastodynamic matrix of (K_T - lambda^2 M_T) z = 0 (eq. 37).

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        M_t (2x2, column-major): actuated-space inertia Psi^T M Psi [kg m^2]
        M_w (2x2, column-major): task-space inertia J^T M_t J (eq. 35) [kg]
        S_e (2x2, column-major): K^1/2 (M_t^-1 + J_m^-1) K^1/2: its eigenvalues are the squared non-zero natural frequencies [1/s^2]
    """
    q = ca.SX.sym("q", 4)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 18)
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
    # 290 common subexpressions, 1065 operations
    _t0 = design_0**2
    _t1 = _t0*design_3
    _t2 = _t1*design_7
    _t3 = ca.sin(q_0)
    _t4 = _t3**2
    _t5 = _t0*design_4
    _t6 = ca.cos(q_0)
    _t7 = _t6**2
    _t8 = design_5**2
    _t9 = _t1*_t8
    _t10 = ca.sin(q_2)
    _t11 = design_6*design_4
    _t12 = _t11*design_0*design_1
    _t13 = ca.cos(q_2)
    _t14 = _t10*_t12*_t3 + _t12*_t13*_t6
    _t15 = ca.sin(q_3)
    _t16 = _t15*_t6
    _t17 = ca.cos(q_3)
    _t18 = -_t16 + _t17*_t3
    _t19 = _t10*_t17
    _t20 = _t13*_t15 - _t19
    _t21 = design_0/(_t20*design_1)
    _t22 = _t18*_t21
    _t23 = _t10*_t6
    _t24 = _t13*_t3 - _t23
    _t25 = design_1**2
    _t26 = _t25*design_4
    _t27 = _t26*design_8
    _t28 = _t15**2
    _t29 = design_6**2
    _t30 = _t26*_t29
    _t31 = _t17**2
    _t32 = _t27 + _t28*_t30 + _t30*_t31
    _t33 = _t0/(_t20**2*_t25)
    _t34 = _t32*_t33
    _t35 = _t10**2
    _t36 = _t13**2
    _t37 = _t27 + _t30*_t35 + _t30*_t36
    _t38 = _t14 + _t22*_t37
    _t39 = _t14*_t22 + _t2 + _t22*_t38 + _t24**2*_t34 + _t4*_t5 + _t4*_t9 + _t5*_t7 + _t7*_t9
    _t40 = ca.cos(q_1)
    _t41 = _t15*_t40
    _t42 = ca.sin(q_1)
    _t43 = _t17*_t42
    _t44 = _t41 - _t43
    _t45 = _t21*_t44
    _t46 = _t33*_t37
    _t47 = _t10*_t40
    _t48 = _t13*_t42
    _t49 = _t47 - _t48
    _t50 = _t21*_t49
    _t51 = _t12*_t15*_t42 + _t12*_t17*_t40
    _t52 = _t32*_t50 + _t51
    _t53 = _t21*_t24
    _t54 = _t14*_t45 + _t18*_t44*_t46 + _t52*_t53
    _t55 = _t24*_t34*_t49 + _t38*_t45 + _t51*_t53
    _t56 = _t42**2
    _t57 = _t40**2
    _t58 = _t2 + _t44**2*_t46 + _t5*_t56 + _t5*_t57 + _t50*_t51 + _t50*_t52 + _t56*_t9 + _t57*_t9
    _t59 = 1/design_0
    _t60 = -_t59/_t44
    _t61 = _t17*_t60
    _t62 = _t59/_t24
    _t63 = _t13*_t62
    _t64 = -_t39*_t63 - _t54*_t61
    _t65 = -_t55*_t63 - _t58*_t61
    _t66 = _t15*_t60
    _t67 = _t10*_t62
    _t68 = -_t39*_t67 - _t54*_t66
    _t69 = -_t55*_t67 - _t58*_t66
    _t70 = design_3*design_4
    _t71 = _t70*design_8
    _t72 = design_0**4
    _t73 = _t72*design_7
    _t74 = _t71*_t73
    _t75 = _t35*_t7
    _t76 = _t35*_t57
    _t77 = _t28*_t74
    _t78 = _t4*design_7
    _t79 = _t72*_t78
    _t80 = _t36*_t71
    _t81 = _t31*_t71
    _t82 = _t56*_t73
    _t83 = _t13*_t23*_t3
    _t84 = 2*_t74
    _t85 = _t47*_t48
    _t86 = _t16*_t17*_t3
    _t87 = _t41*_t43
    _t88 = design_3**2
    _t89 = _t88*design_7**2
    _t90 = _t31*_t35
    _t91 = _t72*_t90
    _t92 = _t28*_t36
    _t93 = _t72*_t92
    _t94 = design_4**2
    _t95 = _t72*_t94
    _t96 = _t95*design_8**2
    _t97 = _t4*_t57
    _t98 = _t56*_t7
    _t99 = _t70*_t91
    _t100 = _t78*_t99
    _t101 = _t99*design_7
    _t102 = _t101*_t56
    _t103 = _t7*design_7
    _t104 = _t103*_t99
    _t105 = _t101*_t57
    _t106 = _t70*_t93
    _t107 = _t106*_t78
    _t108 = _t106*design_7
    _t109 = _t108*_t56
    _t110 = _t103*_t106
    _t111 = _t108*_t57
    _t112 = _t13*_t15*_t19
    _t113 = 2*_t112
    _t114 = _t113*_t72
    _t115 = _t3*_t40*_t42*_t6
    _t116 = 2*_t115
    _t117 = _t95*design_8
    _t118 = _t117*_t97
    _t119 = _t118*_t35
    _t120 = _t117*_t98
    _t121 = _t120*_t35
    _t122 = _t118*_t28
    _t123 = _t120*_t28
    _t124 = _t118*_t36
    _t125 = _t118*_t31
    _t126 = _t36*_t98
    _t127 = _t117*_t126
    _t128 = _t120*_t31
    _t129 = _t113*_t70
    _t130 = _t129*_t73
    _t131 = _t57*_t7
    _t132 = 2*_t117
    _t133 = _t131*_t132
    _t134 = _t4*_t56
    _t135 = _t134*_t36
    _t136 = _t134*_t31
    _t137 = _t11*design_3
    _t138 = 2*_t137
    _t139 = _t138*_t91
    _t140 = _t57*design_7
    _t141 = _t56*design_7
    _t142 = _t138*_t93
    _t143 = _t103*_t93
    _t144 = _t132*_t56
    _t145 = _t144*_t83
    _t146 = _t132*_t57
    _t147 = _t146*_t83
    _t148 = _t132*_t4
    _t149 = _t148*_t85
    _t150 = _t132*_t7
    _t151 = _t150*_t85
    _t152 = _t144*_t86
    _t153 = _t146*_t86
    _t154 = _t148*_t87
    _t155 = _t150*_t87
    _t156 = _t113*_t137
    _t157 = _t156*_t73
    _t158 = _t28*_t73
    _t159 = _t138*_t158
    _t160 = _t138*_t73
    _t161 = _t31*_t83
    _t162 = _t31*_t85
    _t163 = _t35*_t86
    _t164 = _t160*_t87
    _t165 = _t36*_t86
    _t166 = 2*design_6
    _t167 = _t72*_t8
    _t168 = _t167*_t71
    _t169 = _t168*_t97
    _t170 = _t168*_t98
    _t171 = _t167*_t97
    _t172 = _t167*_t98
    _t173 = _t115*_t132
    _t174 = _t173*design_6
    _t175 = _t91*_t94
    _t176 = _t134*_t175
    _t177 = _t175*_t97
    _t178 = _t175*_t98
    _t179 = _t131*_t175
    _t180 = _t93*_t94
    _t181 = _t134*_t180
    _t182 = _t180*_t97
    _t183 = _t180*_t98
    _t184 = _t131*_t180
    _t185 = _t8*_t88
    _t186 = _t185*_t91
    _t187 = _t185*_t93
    _t188 = 2*_t168
    _t189 = _t131*_t188
    _t190 = 2*_t29
    _t191 = _t190*_t70
    _t192 = _t191*_t75
    _t193 = _t158*_t191
    _t194 = _t31*_t36
    _t195 = _t191*_t194
    _t196 = _t56*_t83
    _t197 = _t57*_t83
    _t198 = _t4*_t85
    _t199 = _t7*_t85
    _t200 = _t56*_t86
    _t201 = _t57*_t86
    _t202 = _t4*_t87
    _t203 = _t7*_t87
    _t204 = _t191*_t73
    _t205 = _t204*_t87
    _t206 = _t113*_t95
    _t207 = _t113*_t185
    _t208 = _t207*_t73
    _t209 = _t173*_t29
    _t210 = 4*design_6
    _t211 = _t210*_t95
    _t212 = _t112*_t211
    _t213 = _t112*_t131
    _t214 = _t166*_t95
    _t215 = _t214*_t28
    _t216 = _t214*_t31
    _t217 = _t200*_t35
    _t218 = _t76*_t86
    _t219 = _t202*_t35
    _t220 = _t75*_t87
    _t221 = _t214*_t36
    _t222 = _t88*design_5**4
    _t223 = _t222*_t91
    _t224 = _t222*_t93
    _t225 = _t131*_t93
    _t226 = _t29*_t95
    _t227 = _t28*_t35
    _t228 = _t227*_t97
    _t229 = _t226*_t98
    _t230 = _t226*_t31
    _t231 = _t36*_t97
    _t232 = design_6**4
    _t233 = _t232*_t95
    _t234 = _t227*_t98
    _t235 = _t231*_t31
    _t236 = _t126*_t31
    _t237 = 2*_t8
    _t238 = _t237*_t99
    _t239 = _t106*_t237
    _t240 = _t167*_t70
    _t241 = 4*_t240
    _t242 = _t112*_t134
    _t243 = 4*_t70
    _t244 = _t112*_t171
    _t245 = _t112*_t172
    _t246 = 4*_t226
    _t247 = _t131*_t227
    _t248 = 6*_t29
    _t249 = 4*_t230
    _t250 = design_6**3
    _t251 = _t250*_t95
    _t252 = 2*_t251
    _t253 = 4*_t250
    _t254 = 2*_t236
    _t255 = _t134*_t8
    _t256 = 4*_t137
    _t257 = _t8*_t97
    _t258 = _t131*_t8
    _t259 = _t8*_t98
    _t260 = _t114*_t222
    _t261 = _t113*_t226
    _t262 = _t246*_t28
    _t263 = _t249*_t85
    _t264 = _t116*_t227
    _t265 = _t116*_t29
    _t266 = _t246*_t36
    _t267 = _t252*_t28
    _t268 = _t252*_t31
    _t269 = _t115*_t253
    _t270 = _t269*_t95
    _t271 = _t252*_t36
    _t272 = _t116*_t232
    _t273 = _t167*_t256
    _t274 = _t138*_t167
    _t275 = _t274*_t28
    _t276 = _t274*_t31
    _t277 = _t274*_t36
    _t278 = _t202*_t36
    _t279 = _t203*_t36
    _t280 = _t167*_t191
    _t281 = _t240*_t29
    _t282 = 4*_t281
    _t283 = _t190*_t99
    _t284 = _t106*_t190
    _t285 = _t28*_t280
    _t286 = _t280*_t31
    _t287 = _t280*_t36
    _t288 = (-_t113 + _t90 + _t92)/(_t100*_t29 + _t100 + _t102*_t29 + _t102 + _t103*_t186 + _t104*_t29 + _t104 + _t105*_t29 + _t105 + _t107*_t29 + _t107 + _t109*_t29 + _t109 + _t110*_t29 + _t110 + _t111*_t29 + _t111 + 16*_t112*_t115*_t226 - _t113*_t229 - _t114*_t89 - _t116*_t194*_t233 - _t116*_t230*_t36 - _t116*_t96 - _t119*_t166 + _t119*_t29 + _t119 + _t121*_t29 + _t121 + _t122*_t29 + _t122 - _t123*_t166 + _t123*_t29 + _t123 + _t124*_t29 + _t124 - _t125*_t166 + _t125*_t29 + _t125 + _t126*_t168 + _t126*_t230 - _t127*_t166 + _t127*_t29 + _t127 + _t128*_t29 + _t128 - _t129*_t79 - _t129*_t82 - _t130*_t57 - _t130*_t7 - _t131*_t206 + _t131*_t223 + _t131*_t238 + _t131*_t239 - _t131*_t260 - _t131*_t261 + _t132*_t135 + _t132*_t136 + _t133*_t28 + _t133*_t35 - _t134*_t206 + _t134*_t212 + _t134*_t223 + _t134*_t224 + _t134*_t238 + _t134*_t239 - _t134*_t260 - _t134*_t261 + _t135*_t188 + _t135*_t249 + _t135*_t282*_t31 + _t136*_t188 - _t138*_t143 - _t138*_t225*_t8 - _t139*_t140 - _t139*_t255 - _t139*_t258 - _t139*_t78 + _t140*_t186 + _t140*_t187 - _t141*_t142 + _t141*_t186 + _t141*_t187 - _t142*_t255 + _t143*_t185 - _t145*design_6 - _t145 - _t147*design_6 - _t147 + _t149*design_6 - _t149 + _t151*design_6 - _t151 + _t152*design_6 - _t152 + _t153*design_6 - _t153 - _t154*design_6 - _t154 - _t155*design_6 - _t155 + _t156*_t79 + _t156*_t82 + _t157*_t57 + _t157*_t7 + _t158*_t192 - _t159*_t83 + _t159*_t85 - _t160*_t161 + _t160*_t162 + _t160*_t163 + _t160*_t165 - _t161*_t204 - _t162*_t204 - _t163*_t204 - _t164*_t35 - _t164*_t36 - _t165*_t204 - _t166*_t176 - _t166*_t179 - _t166*_t181 - _t166*_t184 - _t167*_t192*_t87 + _t169*_t28 + _t169*_t35 + _t170*_t28 + _t170*_t35 + _t171*_t80 + _t171*_t81 + _t172*_t81 + _t174*_t28 + _t174*_t31 + _t174*_t35 + _t174*_t36 - _t175*_t265 + _t175*_t269 - _t175*_t272 + _t176*_t29 + _t176 - _t177*_t210 + _t177*_t232 + _t177*_t248 - _t177*_t253 + _t177 + _t178*_t190 + _t178*_t232 + _t178 + _t179*_t29 + _t179 - _t180*_t265 + _t180*_t269 - _t180*_t272 + _t181*_t29 + _t181 + _t182*_t190 + _t182*_t232 + _t182 - _t183*_t210 + _t183*_t232 + _t183*_t248 - _t183*_t253 + _t183 + _t184*_t29 + _t184 + _t186*_t78 + _t187*_t78 - _t188*_t196 - _t188*_t197 - _t188*_t198 - _t188*_t199 - _t188*_t200 - _t188*_t201 - _t188*_t202 - _t188*_t203 + _t189*_t28 + _t189*_t35 + _t193*_t76 - _t193*_t83 - _t193*_t85 + _t194*_t270 + _t195*_t79 + _t195*_t82 - _t196*_t215 - _t196*_t216 - _t196*_t249 + _t196*_t262 - _t196*_t267 - _t196*_t268 - _t196*_t275 - _t196*_t276 - _t196*_t285 - _t196*_t286 - _t197*_t215 - _t197*_t216 + _t197*_t249 - _t197*_t262 - _t197*_t267 - _t197*_t268 - _t197*_t275 - _t197*_t276 - _t197*_t285 - _t197*_t286 + _t198*_t215 + _t198*_t216 - _t198*_t262 + _t198*_t267 + _t198*_t268 + _t198*_t275 + _t198*_t276 - _t198*_t285 - _t198*_t286 + _t199*_t215 + _t199*_t216 - _t199*_t262 + _t199*_t267 + _t199*_t268 + _t199*_t275 + _t199*_t276 - _t199*_t285 - _t199*_t286 + _t200*_t221 - _t200*_t266 + _t200*_t271 + _t200*_t277 - _t200*_t287 + _t201*_t221 - _t201*_t266 + _t201*_t271 + _t201*_t277 - _t201*_t287 - _t202*_t221 - _t202*_t266 - _t202*_t271 - _t203*_t221 + _t203*_t266 - _t203*_t271 - _t205*_t35 - _t205*_t36 - _t206*_t97 - _t206*_t98 - _t207*_t79 - _t207*_t82 - _t208*_t57 - _t208*_t7 - _t209*_t28 - _t209*_t31 - _t209*_t35 - _t209*_t36 + _t211*_t213 + _t212*_t97 + _t212*_t98 - _t213*_t241 + _t213*_t273 + _t214*_t217 + _t214*_t218 - _t214*_t219 - _t214*_t220 - _t217*_t246 + _t217*_t252 + _t217*_t274 - _t217*_t280 - _t218*_t246 + _t218*_t252 + _t218*_t274 - _t218*_t280 + _t219*_t246 - _t219*_t252 - _t219*_t274 - _t219*_t280 - _t220*_t246 - _t220*_t252 - _t220*_t274 + _t222*_t225 + _t223*_t97 + _t223*_t98 + _t224*_t97 + _t224*_t98 + _t226*_t228 - _t226*_t264 + _t227*_t229 + _t227*_t270 + _t228*_t233 - _t228*_t252 + _t228*_t280 + _t230*_t231 + _t233*_t234 + _t233*_t235 + _t233*_t236 - _t233*_t264 - _t234*_t252 + _t234*_t280 - _t235*_t252 + _t235*_t280 + _t238*_t97 + _t238*_t98 + _t239*_t97 + _t239*_t98 - _t241*_t242 + _t242*_t273 - _t243*_t244 - _t243*_t245 + _t244*_t256 + _t245*_t256 + _t246*_t247 + _t247*_t282 - _t251*_t254 + _t254*_t281 + _t255*_t283 + _t255*_t284 - _t256*_t257*_t91 - _t256*_t259*_t93 + _t257*_t283 + _t257*_t284 + _t258*_t283 + _t258*_t284 + _t259*_t283 + _t259*_t284 - _t260*_t97 - _t260*_t98 - _t261*_t97 - _t263*_t4 - _t263*_t7 - _t274*_t278 - _t274*_t279 - _t278*_t280 - _t279*_t280 + _t57*_t77 + _t7*_t77 + _t74*_t75 + _t74*_t76 + _t79*_t80 + _t79*_t81 + _t80*_t82 + _t81*_t82 - _t83*_t84 - _t84*_t85 - _t84*_t86 - _t84*_t87 + _t89*_t91 + _t89*_t93 + _t96*_t97 + _t96*_t98)
    _t289 = _t288*ca.sqrt(design_9)*ca.sqrt(design_10)
    M_t = ca.reshape(ca.vertcat(_t39, _t54, _t55, _t58), 2, 2)
    M_w = ca.reshape(ca.vertcat(-_t61*_t65 - _t63*_t64, -_t61*_t69 - _t63*_t68, -_t64*_t67 - _t65*_t66, -_t66*_t69 - _t67*_t68), 2, 2)
    S_e = ca.reshape(ca.vertcat(design_9*(_t288*_t58 + 1/design_11), -_t289*_t54, -_t289*_t55, design_10*(_t288*_t39 + 1/design_12)), 2, 2)
    return ca.Function("inertia", [q, x, design], [M_t, M_w, S_e], ["q", "x", "design"], ["M_t", "M_w", "S_e"])


def second_order():
    """Joint rates and velocity-product accelerations from the end-effector velocity.

    Inputs:
        q (4): [theta1, theta2, phi1, phi2] actuated then passive absolute link angles [rad]
        x (2): [x, y] end-effector position [m]
        x_dot (2): [x_dot, y_dot] end-effector velocity [m/s]
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        q_dot (4x1, column-major): all joint rates [rad/s]
        q_ddot_bias (4x1, column-major): joint accelerations at zero x_ddot: Phi_dot x_dot [rad/s^2]
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
    design = ca.SX.sym("design", 18)
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
    # 46 common subexpressions, 134 operations
    _t0 = ca.cos(q_2)
    _t1 = 1/design_0
    _t2 = ca.sin(q_2)
    _t3 = ca.cos(q_0)
    _t4 = ca.sin(q_0)
    _t5 = _t0*_t4 - _t2*_t3
    _t6 = 1/_t5
    _t7 = 1/(_t5*design_0)
    _t8 = _t0*_t7
    _t9 = -_t2*_t7*x_dot_1 - _t8*x_dot_0
    _t10 = ca.cos(q_3)
    _t11 = ca.sin(q_3)
    _t12 = ca.cos(q_1)
    _t13 = ca.sin(q_1)
    _t14 = _t10*_t13 - _t11*_t12
    _t15 = 1/_t14
    _t16 = 1/(_t14*design_0)
    _t17 = _t10*_t16
    _t18 = -_t11*_t16*x_dot_1 - _t17*x_dot_0
    _t19 = 1/design_1
    _t20 = 1/(_t5*design_1)
    _t21 = _t20*_t3
    _t22 = _t20*_t4
    _t23 = _t21*x_dot_0 + _t22*x_dot_1
    _t24 = 1/(_t14*design_1)
    _t25 = _t12*_t24
    _t26 = _t13*_t24
    _t27 = _t25*x_dot_0 + _t26*x_dot_1
    _t28 = _t0*_t3 + _t2*_t4
    _t29 = -_t28
    _t30 = _t5**(-2)
    _t31 = _t1*_t30
    _t32 = _t29*_t31*_t9
    _t33 = _t28*_t31
    _t34 = _t10*_t12 + _t11*_t13
    _t35 = -_t34
    _t36 = _t14**(-2)
    _t37 = _t1*_t36
    _t38 = _t18*_t35*_t37
    _t39 = _t34*_t37
    _t40 = _t19*_t30
    _t41 = _t23*_t28*_t40
    _t42 = _t29*_t40
    _t43 = _t19*_t36
    _t44 = _t27*_t34*_t43
    _t45 = _t35*_t43
    q_dot = ca.reshape(ca.vertcat(_t9, _t18, _t23, _t27), 4, 1)
    q_ddot_bias = ca.reshape(ca.vertcat(x_dot_0*(-_t0*_t32 + _t23*(-_t0*_t33 + _t2/(_t5*design_0))) + x_dot_1*(-_t2*_t32 + _t23*(-_t2*_t33 - _t8)), x_dot_0*(-_t10*_t38 + _t27*(-_t10*_t39 + _t11/(_t14*design_0))) + x_dot_1*(-_t11*_t38 + _t27*(-_t11*_t39 - _t17)), x_dot_0*(_t3*_t41 + _t9*(-_t22 + _t3*_t42)) + x_dot_1*(_t4*_t41 + _t9*(_t21 + _t4*_t42)), x_dot_0*(_t12*_t44 + _t18*(_t12*_t45 - _t26)) + x_dot_1*(_t13*_t44 + _t18*(_t13*_t45 + _t25))), 4, 1)
    return ca.Function("second_order", [q, x, x_dot, design], [q_dot, q_ddot_bias], ["q", "x", "x_dot", "design"], ["q_dot", "q_ddot_bias"])


def inertia_from_pose():
    """inverse_kinematics and inertia at its q, inertia with the cosine and sine of each joint angle from the position vectors of the links (no trigonometric call). inertia: Inertia matrices of a posture and the elastodynamic matrix of (K_T - lambda^2 M_T) z = 0 (eq. 37).

    Inputs:
        x (2): [x, y] end-effector position [m]
        mode (2): [sigma1, sigma2] elbow signs of chains 1 and 2 (+1 or -1)
        design (18): [r1, r2, r3, m1, m2, c1, c2, g1, g2, k1, k2, j1, j2, fv, fc, vm, w_l, t_l] r1, r2, r3 [m]; m1, m2 [kg]; c1, c2, g1, g2 [-]; k1, k2 [N m/rad]; j1, j2 [kg m^2]; fv [N m s/rad], fc [N m], vm [N m s/rad]; w_l, t_l [m]
    Outputs:
        q (4x1, column-major): theta1, theta2, phi1, phi2 [rad]
        reach (2x1, column-major): 1 - cos^2 of each elbow angle; >= 0 where reachable
        M_t (2x2, column-major): actuated-space inertia Psi^T M Psi [kg m^2]
        M_w (2x2, column-major): task-space inertia J^T M_t J (eq. 35) [kg]
        S_e (2x2, column-major): K^1/2 (M_t^-1 + J_m^-1) K^1/2: its eigenvalues are the squared non-zero natural frequencies [1/s^2]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 18)
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
    # 336 common subexpressions, 1185 operations
    _t0 = design_2 + x_0
    _t1 = design_0**2
    _t2 = x_1**2
    _t3 = _t0**2
    _t4 = _t2 + _t3
    _t5 = design_1**2
    _t6 = (1/2)*_t1 + (1/2)*_t2 - 1/2*_t5
    _t7 = (1/2)*_t3 + _t6
    _t8 = _t1*_t4 - _t7**2
    _t9 = 1/_t1
    _t10 = 1/_t4
    _t11 = _t8/(_t1*_t4)
    _t12 = ca.if_else((_t11 > 1/1125899906842624), ca.sqrt(_t8), 0)
    _t13 = -design_2 + x_0
    _t14 = _t13**2
    _t15 = _t14 + _t2
    _t16 = (1/2)*_t14 + _t6
    _t17 = _t1*_t15 - _t16**2
    _t18 = 1/_t15
    _t19 = _t17/(_t1*_t15)
    _t20 = ca.if_else((_t19 > 1/1125899906842624), ca.sqrt(_t17), 0)
    _t21 = _t12*mode_0
    _t22 = _t0*_t21 + _t7*x_1
    _t23 = -_t22 + _t4*x_1
    _t24 = -_t0*_t7 + _t21*x_1
    _t25 = _t0*_t4 + _t24
    _t26 = _t20*mode_1
    _t27 = _t13*_t26 + _t16*x_1
    _t28 = _t15*x_1 - _t27
    _t29 = -_t13*_t16 + _t26*x_1
    _t30 = _t13*_t15 + _t29
    _t31 = _t4**2
    _t32 = _t25*_t28
    _t33 = _t23*_t30
    _t34 = _t32 - _t33
    _t35 = _t34**2
    _t36 = 1/_t35
    _t37 = _t35*design_3
    _t38 = _t1*design_7
    _t39 = _t37*_t38
    _t40 = _t22**2
    _t41 = _t35*design_4
    _t42 = -_t24
    _t43 = _t42**2
    _t44 = design_5**2
    _t45 = _t40*_t44
    _t46 = _t37*_t44
    _t47 = _t15**2
    _t48 = _t5*design_8
    _t49 = _t47*_t48
    _t50 = design_6**2
    _t51 = _t28**2
    _t52 = _t50*_t51
    _t53 = _t30**2
    _t54 = _t50*_t53
    _t55 = _t49 + _t52 + _t54
    _t56 = _t23*_t42
    _t57 = _t22*_t25 - _t56
    _t58 = _t57**2
    _t59 = _t28*_t42
    _t60 = _t22*_t30 - _t59
    _t61 = _t60*design_4
    _t62 = _t22*_t23
    _t63 = _t25*_t42
    _t64 = _t34*design_6
    _t65 = _t64*(_t62 + _t63)
    _t66 = _t31*_t48
    _t67 = _t23**2
    _t68 = _t50*_t67
    _t69 = _t25**2
    _t70 = _t50*_t69
    _t71 = _t66 + _t68 + _t70
    _t72 = _t60*_t71
    _t73 = _t62*_t64 + _t63*_t64 + _t72
    _t74 = _t31*_t39 + _t37*_t45 + _t40*_t41 + _t41*_t43 + _t43*_t46 + _t55*_t58*design_4 + _t61*_t65 + _t61*_t73
    _t75 = -_t29
    _t76 = _t28*_t75
    _t77 = _t27*_t30
    _t78 = _t76 - _t77
    _t79 = _t27*_t28
    _t80 = _t30*_t75
    _t81 = _t23*_t75
    _t82 = _t25*_t27
    _t83 = _t81 - _t82
    _t84 = _t55*_t83
    _t85 = _t64*_t79 + _t64*_t80 + _t84
    _t86 = _t57*_t85 + _t65*_t78 + _t72*_t78
    _t87 = _t86*design_4
    _t88 = 1/(_t15*_t35*_t4)
    _t89 = _t64*(_t79 + _t80)
    _t90 = _t57*_t84 + _t57*_t89 + _t73*_t78
    _t91 = _t90*design_4
    _t92 = _t27**2
    _t93 = _t75**2
    _t94 = _t83*design_4
    _t95 = _t39*_t47 + _t41*_t92 + _t41*_t93 + _t46*_t92 + _t46*_t93 + _t71*_t78**2*design_4 + _t85*_t94 + _t89*_t94
    _t96 = _t30*_t57
    _t97 = -_t78
    _t98 = _t25*_t97
    _t99 = -_t74*_t98 - _t87*_t96
    _t100 = -_t91*_t98 - _t95*_t96
    _t101 = _t36/(_t58*_t97**2)
    _t102 = _t28*_t57
    _t103 = _t23*_t97
    _t104 = -_t102*_t87 - _t103*_t74
    _t105 = -_t102*_t95 - _t103*_t91
    _t106 = _t51*_t69
    _t107 = _t53*_t67
    _t108 = _t32*_t33
    _t109 = 2*_t108
    _t110 = _t106 + _t107 - _t109
    _t111 = _t15**4
    _t112 = design_3*design_4
    _t113 = _t112*_t38
    _t114 = _t113*_t48
    _t115 = _t111*_t114
    _t116 = design_4**2
    _t117 = _t116*_t43
    _t118 = _t117*_t92
    _t119 = _t31*_t47
    _t120 = _t119*design_8**2*design_1**4
    _t121 = _t116*_t40
    _t122 = _t121*_t93
    _t123 = _t113*_t31
    _t124 = _t123*_t93
    _t125 = _t123*_t92
    _t126 = _t123*_t49
    _t127 = _t4**4
    _t128 = _t114*_t127
    _t129 = _t51*_t93
    _t130 = _t53*_t92
    _t131 = _t119*design_7**2*design_0**4
    _t132 = design_3**2
    _t133 = _t106*_t132
    _t134 = _t107*_t132
    _t135 = _t118*_t49
    _t136 = _t122*_t49
    _t137 = _t136*_t67
    _t138 = _t135*_t69
    _t139 = _t121*_t92
    _t140 = 2*_t49
    _t141 = _t140*_t69
    _t142 = _t117*_t93
    _t143 = _t140*_t67
    _t144 = 2*design_6
    _t145 = _t43*_t44
    _t146 = _t112*_t145
    _t147 = _t146*_t92
    _t148 = _t147*_t49
    _t149 = _t112*_t45
    _t150 = _t149*_t93
    _t151 = _t150*_t49
    _t152 = _t149*_t92
    _t153 = _t146*_t93
    _t154 = _t118*_t66
    _t155 = _t154*_t51
    _t156 = _t122*_t66
    _t157 = _t113*_t47
    _t158 = _t157*_t40
    _t159 = _t157*_t43
    _t160 = _t106*_t159
    _t161 = 2*_t66
    _t162 = _t161*_t51
    _t163 = _t107*_t158
    _t164 = _t147*_t66
    _t165 = _t150*_t66
    _t166 = _t156*_t53
    _t167 = _t161*_t53
    _t168 = _t52*_t69
    _t169 = _t38*_t47
    _t170 = _t169*_t45
    _t171 = _t52*_t67
    _t172 = 2*_t112
    _t173 = _t172*_t43
    _t174 = _t133*_t44
    _t175 = _t169*_t43
    _t176 = _t54*_t67
    _t177 = _t175*_t44
    _t178 = _t54*_t69
    _t179 = _t172*_t178
    _t180 = _t106*_t92
    _t181 = _t123*_t180
    _t182 = _t106*_t93
    _t183 = _t107*_t92
    _t184 = _t107*_t93
    _t185 = _t123*_t184
    _t186 = _t31*_t38
    _t187 = _t186*_t92
    _t188 = _t186*_t93
    _t189 = _t183*_t44
    _t190 = _t132*_t186
    _t191 = _t184*_t44
    _t192 = _t38*_t48
    _t193 = _t22*_t25*_t56
    _t194 = _t172*_t193
    _t195 = _t116*_t22*_t27*_t42*_t75
    _t196 = 2*_t195
    _t197 = _t106*_t121
    _t198 = _t197*_t92
    _t199 = _t106*_t117
    _t200 = _t199*_t92
    _t201 = _t197*_t93
    _t202 = _t199*_t93
    _t203 = _t121*_t183
    _t204 = _t117*_t183
    _t205 = _t121*_t184
    _t206 = _t132*design_5**4
    _t207 = _t206*_t40
    _t208 = _t106*_t207
    _t209 = 4*design_6
    _t210 = _t51*_t67
    _t211 = design_6**4
    _t212 = _t118*_t211
    _t213 = _t122*_t211
    _t214 = _t172*_t45
    _t215 = _t106*_t214
    _t216 = _t117*_t184
    _t217 = _t206*_t43
    _t218 = _t106*_t217
    _t219 = design_6**3
    _t220 = 2*_t219
    _t221 = _t118*_t220
    _t222 = _t122*_t220
    _t223 = _t173*_t44
    _t224 = _t112*_t144
    _t225 = _t224*_t45
    _t226 = 4*_t171
    _t227 = 2*_t168
    _t228 = 4*_t219
    _t229 = _t112*_t209
    _t230 = _t145*_t229
    _t231 = _t145*_t224
    _t232 = _t223*_t92
    _t233 = _t214*_t93
    _t234 = 2*_t176
    _t235 = 4*_t178
    _t236 = _t53*_t69
    _t237 = _t229*_t45
    _t238 = _t81*_t82
    _t239 = _t140*_t238
    _t240 = _t22*_t30*_t59
    _t241 = _t76*_t77
    _t242 = _t172*_t241
    _t243 = _t109*_t132
    _t244 = _t116*_t92
    _t245 = _t140*_t193
    _t246 = _t116*_t93
    _t247 = _t144*_t193
    _t248 = _t244*_t247
    _t249 = _t144*_t67
    _t250 = _t195*_t49
    _t251 = _t246*_t247
    _t252 = _t44*_t92
    _t253 = _t112*_t252
    _t254 = _t144*_t69
    _t255 = _t44*_t93
    _t256 = _t112*_t255
    _t257 = _t140*_t195
    _t258 = _t144*_t238
    _t259 = _t121*_t258
    _t260 = _t157*_t247
    _t261 = _t117*_t258
    _t262 = _t144*_t66
    _t263 = _t195*_t262
    _t264 = _t169*_t194
    _t265 = _t161*_t195
    _t266 = _t240*_t244
    _t267 = _t240*_t246
    _t268 = _t157*_t240
    _t269 = _t161*_t240
    _t270 = _t169*_t172*_t240
    _t271 = _t123*_t258
    _t272 = _t238*_t52
    _t273 = _t172*_t186
    _t274 = _t109*_t158
    _t275 = _t121*_t241
    _t276 = _t109*_t159
    _t277 = _t238*_t54
    _t278 = _t117*_t241
    _t279 = _t161*_t241
    _t280 = _t109*_t125
    _t281 = _t109*_t124
    _t282 = _t123*_t241
    _t283 = _t109*_t190
    _t284 = _t186*_t242
    _t285 = 4*_t193
    _t286 = _t244*_t285
    _t287 = _t193*_t220
    _t288 = _t244*_t287
    _t289 = _t193*_t224
    _t290 = _t246*_t285
    _t291 = _t195*_t228
    _t292 = _t246*_t287
    _t293 = _t196*_t211
    _t294 = _t289*_t44
    _t295 = _t172*_t252
    _t296 = _t193*_t295
    _t297 = _t172*_t255
    _t298 = _t193*_t297
    _t299 = 4*_t121
    _t300 = _t220*_t238
    _t301 = _t121*_t300
    _t302 = _t225*_t238
    _t303 = 4*_t117
    _t304 = _t117*_t300
    _t305 = _t231*_t238
    _t306 = 4*_t68
    _t307 = _t220*_t266
    _t308 = _t224*_t240
    _t309 = _t252*_t308
    _t310 = 4*_t70
    _t311 = _t220*_t267
    _t312 = _t255*_t308
    _t313 = _t240*_t295
    _t314 = _t240*_t297
    _t315 = _t109*_t139
    _t316 = _t109*_t118
    _t317 = _t109*_t122
    _t318 = _t108*_t209
    _t319 = _t109*_t142
    _t320 = 4*_t108
    _t321 = _t109*_t207
    _t322 = _t108*_t237
    _t323 = _t109*_t217
    _t324 = _t241*_t299
    _t325 = _t220*_t275
    _t326 = _t108*_t230
    _t327 = _t225*_t241
    _t328 = _t220*_t278
    _t329 = _t231*_t241
    _t330 = _t214*_t241
    _t331 = _t223*_t241
    _t332 = _t106*_t158 + _t106*_t291 - _t106*_t293 + _t107*_t159 + _t107*_t291 - _t107*_t293 + 16*_t108*_t195*_t50 - _t111*_t192*_t194 + _t115*_t40*_t69 + _t115*_t43*_t67 - _t117*_t239 + _t118*_t120 + 6*_t118*_t168 + _t118*_t171 + _t118*_t178 + _t118*_t234 + _t118*_t318 + _t120*_t122 - _t120*_t196 - _t121*_t239 + _t122*_t171 + 6*_t122*_t176 + _t122*_t178 + _t122*_t227 + _t122*_t318 - _t123*_t140*_t240 + _t123*_t182 + _t123*_t183 - _t123*_t239 + _t124*_t168 + _t124*_t176 + _t124*_t49*_t67 + _t125*_t168 + _t125*_t176 + _t125*_t49*_t69 + _t126*_t40*_t53 + _t126*_t43*_t51 - _t127*_t192*_t242 + _t128*_t129 + _t128*_t130 - _t129*_t294 - _t130*_t294 + _t131*_t133 + _t131*_t134 - _t131*_t243 + _t133*_t170 + _t134*_t170 + _t134*_t177 + _t135*_t67 + _t135*_t68 + _t135*_t70 + _t136*_t68 + _t136*_t69 + _t136*_t70 - _t137*_t144 + _t137 - _t138*_t144 + _t138 + _t139*_t141 + _t139*_t167 + _t139*_t168 + _t139*_t176 + _t139*_t235 + _t139*_t318 + _t141*_t152 + _t142*_t143 + _t142*_t162 + _t142*_t168 + _t142*_t176 + _t142*_t226 + _t142*_t318 + _t143*_t153 - _t144*_t155 - _t144*_t160 - _t144*_t163 - _t144*_t166 - _t144*_t181 - _t144*_t185 - _t144*_t198 - _t144*_t202 - _t144*_t203 - _t144*_t216 - _t146*_t239 - _t146*_t279 + _t147*_t227 + _t147*_t234 - _t147*_t320 + _t148*_t67 + _t148*_t69 - _t149*_t239 - _t149*_t279 + _t150*_t227 + _t150*_t234 - _t150*_t320 + _t151*_t67 + _t151*_t69 + _t152*_t167 + _t152*_t227 + _t152*_t234 + _t152*_t235 - _t152*_t320 + _t153*_t162 + _t153*_t226 + _t153*_t227 + _t153*_t234 - _t153*_t320 + _t154*_t52 + _t154*_t53 + _t154*_t54 + _t155 + _t156*_t51 + _t156*_t52 + _t156*_t54 + _t158*_t168 + _t158*_t176 + _t159*_t168 + _t159*_t176 + _t160 - _t161*_t266 - _t161*_t267 - _t161*_t275 - _t161*_t278 + _t163 + _t164*_t51 + _t164*_t53 + _t165*_t51 + _t165*_t53 + _t166 + _t169*_t171*_t173 + _t169*_t179*_t40 - _t170*_t243 + _t171*_t172*_t188 - _t171*_t196 + _t171*_t232 + _t171*_t233 + _t173*_t189 + _t174*_t175 + _t174*_t187 + _t174*_t188 - _t177*_t243 - _t178*_t196 + _t178*_t232 + _t178*_t233 + _t179*_t187 + _t180*_t223 - _t180*_t225 - _t180*_t230 + _t181 + _t182*_t223 - _t182*_t231 + _t183*_t207 + _t183*_t214 + _t183*_t217 - _t183*_t225 + _t184*_t207 + _t184*_t214 + _t184*_t217 + _t184*_t223 - _t184*_t237 + _t185 + _t189*_t190 + _t190*_t191 - _t191*_t224*_t43 - _t195*_t227 - _t195*_t234 + _t198 - _t200*_t209 + _t200*_t211 - _t200*_t228 + _t200 + _t201*_t211 + _t201 + _t202 + _t203 + _t204*_t211 + _t204 - _t205*_t209 + _t205*_t211 - _t205*_t228 + _t205 + _t208*_t92 + _t208*_t93 + _t210*_t212 + _t210*_t213 - _t210*_t221 - _t210*_t222 + _t210*_t291 - _t210*_t293 + _t212*_t236 + _t213*_t236 - _t214*_t272 - _t214*_t277 + _t215*_t92 + _t215*_t93 + _t216 + _t218*_t92 + _t218*_t93 - _t221*_t236 - _t222*_t236 - _t223*_t272 - _t223*_t277 + _t236*_t291 - _t236*_t293 - _t244*_t245 - _t245*_t246 - _t245*_t253 - _t245*_t256 - _t248*_t49 - _t248*_t51 - _t248*_t53 + _t249*_t250 + _t249*_t266 + _t249*_t267 + _t249*_t268 - _t249*_t275 - _t249*_t278 - _t249*_t282 + _t250*_t254 - _t251*_t49 - _t251*_t51 - _t251*_t53 - _t252*_t283 - _t252*_t289*_t51 - _t253*_t269 + _t254*_t266 + _t254*_t267 + _t254*_t268 - _t254*_t275 - _t254*_t278 - _t254*_t282 - _t255*_t283 - _t256*_t269 - _t257*_t68 - _t257*_t70 + _t259*_t49 + _t259*_t51 + _t259*_t53 - _t260*_t51 - _t260*_t53 + _t261*_t49 + _t261*_t51 + _t261*_t53 + _t262*_t266 + _t262*_t267 - _t262*_t275 - _t262*_t278 + _t263*_t51 + _t263*_t53 - _t264*_t52 - _t264*_t54 - _t265*_t52 - _t265*_t54 - _t266*_t306 - _t266*_t310 - _t267*_t306 - _t267*_t310 - _t270*_t68 - _t270*_t70 + _t271*_t51 + _t271*_t53 - _t272*_t273 - _t272*_t299 - _t272*_t303 - _t273*_t277 + _t274*design_6 - _t274 + _t276*design_6 - _t276 - _t277*_t299 - _t277*_t303 - _t278*_t306 + _t278*_t310 + _t280*design_6 - _t280 + _t281*design_6 - _t281 - _t284*_t68 - _t284*_t70 + _t286*_t52 - _t286*_t54 - _t288*_t51 - _t288*_t53 - _t290*_t52 + _t290*_t54 - _t292*_t51 - _t292*_t53 - _t294*_t53*_t93 - _t296*_t52 - _t296*_t54 - _t298*_t52 - _t298*_t54 + _t301*_t51 + _t301*_t53 + _t302*_t51 + _t302*_t53 + _t304*_t51 + _t304*_t53 + _t305*_t51 + _t305*_t53 + _t307*_t67 + _t307*_t69 + _t309*_t67 + _t309*_t69 + _t311*_t67 + _t311*_t69 + _t312*_t67 + _t312*_t69 - _t313*_t68 - _t313*_t70 - _t314*_t68 - _t314*_t70 - _t315*_t50 - _t315 - _t316*_t50 - _t316 - _t317*_t50 - _t317 - _t319*_t50 - _t319 - _t321*_t92 - _t321*_t93 + _t322*_t92 + _t322*_t93 - _t323*_t92 - _t323*_t93 + _t324*_t68 - _t324*_t70 - _t325*_t67 - _t325*_t69 + _t326*_t92 + _t326*_t93 - _t327*_t67 - _t327*_t69 - _t328*_t67 - _t328*_t69 - _t329*_t67 - _t329*_t69 - _t330*_t68 - _t330*_t70 - _t331*_t68 - _t331*_t70
    _t333 = _t332*_t35
    _t334 = _t36/_t332
    _t335 = _t110*_t15*_t334*_t4*ca.sqrt(design_9)*ca.sqrt(design_10)*design_4
    q = ca.reshape(ca.vertcat(mode_0*ca.atan2(_t12, _t7) + ca.atan2(x_1, _t0), mode_1*ca.atan2(_t20, _t16) + ca.atan2(x_1, _t13), ca.atan2(_t23, _t25), ca.atan2(_t28, _t30)), 4, 1)
    reach = ca.reshape(ca.vertcat(_t11, _t19), 2, 1)
    M_t = ca.reshape(ca.vertcat(_t36*_t74/_t31, _t87*_t88, _t88*_t91, _t36*_t95/_t47), 2, 2)
    M_w = ca.reshape(ca.vertcat(_t101*(-_t100*_t96 - _t98*_t99), _t101*(-_t104*_t98 - _t105*_t96), _t101*(-_t100*_t102 - _t103*_t99), _t101*(-_t102*_t105 - _t103*_t104)), 2, 2)
    S_e = ca.reshape(ca.vertcat(_t334*design_9*(_t110*_t31*_t95*design_11 + _t333)/design_11, -_t335*_t86, -_t335*_t90, _t334*design_10*(_t110*_t47*_t74*design_12 + _t333)/design_12), 2, 2)
    return ca.Function("inertia_from_pose", [x, mode, design], [q, reach, M_t, M_w, S_e], ["x", "mode", "design"], ["q", "reach", "M_t", "M_w", "S_e"])


def build():
    """All functions of this module by name."""
    return {name: globals()[name]() for name in FUNCTIONS}
