# Generated from symbolic/mechanisms/ups_pu.py (source sha256 c478a29f97ad3482).
# Do not edit: regenerate with `make generate`.
# ruff: noqa
"""CasADi functions of the 2-UPS-PU platform."""

import casadi as ca

SOURCE_HASH = "c478a29f97ad3482"
FUNCTIONS = ("inverse_kinematics", "constraint", "first_order", "forward_polynomial", "forward_from_root", "joint_positions", "statics", )
PARAMETERS = ("r", "R", "alpha", "beta", "l_min", "l_max", "l0_min", "l0_max", "theta_u_max", "theta_s_max", "D", "payload", "payload_height", "g", "task_tilt", "task_height", )
POSE = ("l0", "theta1", "theta2", )
ACTUATORS = ("l1", "l2", "l0_leg", )


def inverse_kinematics():
    """Leg lengths of Zhao eq. 4 (l1, l2) and the central stroke l0.

    Inputs:
        x (3): [l0, theta1, theta2] l0 [m], theta1, theta2 [rad]
        mode (1): [sigma] unused: the inverse kinematics has one solution (+1)
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        q (3x1, column-major): l1, l2, l0_leg [m]
        reach (3x1, column-major): the lengths themselves: every pose has an inverse kinematics
    """
    x = ca.SX.sym("x", 3)
    x_0 = x[0]
    x_1 = x[1]
    x_2 = x[2]
    mode = ca.SX.sym("mode", 1)
    mode_0 = mode[0]
    design = ca.SX.sym("design", 16)
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
    # 17 common subexpressions, 54 operations
    _t0 = ca.sin(x_1)
    _t1 = ca.sin(design_2)
    _t2 = _t1*design_0
    _t3 = ca.cos(x_1)
    _t4 = ca.cos(design_2)
    _t5 = design_0*ca.sin(x_2)
    _t6 = _t4*_t5
    _t7 = 2*x_0
    _t8 = 2*design_1
    _t9 = _t8*design_0*ca.cos(x_2)
    _t10 = design_1**2 + x_0**2 + design_0**2
    _t11 = ca.sqrt(-_t1*_t8*(_t0*_t6 + _t2*_t3) + _t10 - _t4**2*_t9 + _t7*(_t0*_t2 - _t3*_t6))
    _t12 = ca.sin(design_3)
    _t13 = _t12*design_0
    _t14 = ca.cos(design_3)
    _t15 = _t14*_t5
    _t16 = ca.sqrt(_t10 - _t12*_t8*(_t0*_t15 + _t13*_t3) - _t14**2*_t9 + _t7*(_t0*_t13 - _t15*_t3))
    q = ca.reshape(ca.vertcat(_t11, _t16, x_0), 3, 1)
    reach = ca.reshape(ca.vertcat(_t11, _t16, x_0), 3, 1)
    return ca.Function("inverse_kinematics", [x, mode, design], [q, reach], ["x", "mode", "design"], ["q", "reach"])


def constraint():
    """Loop-closure residuals and their Jacobians.

    Inputs:
        q (3): [l1, l2, l0_leg] UPS leg lengths l1, l2 and the PU leg's stroke l0 [m]
        x (3): [l0, theta1, theta2] l0 [m], theta1, theta2 [rad]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        h (3x1, column-major): loop-closure residuals [m^2, m]
        H_q (3x3, column-major): dh/dq, actuated then passive [m, -]
        H_x (3x3, column-major): dh/dx [m, m^2/rad]
    """
    q = ca.SX.sym("q", 3)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    x = ca.SX.sym("x", 3)
    x_0 = x[0]
    x_1 = x[1]
    x_2 = x[2]
    design = ca.SX.sym("design", 16)
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
    # 26 common subexpressions, 106 operations
    _t0 = ca.sin(x_1)
    _t1 = ca.sin(design_2)
    _t2 = _t1*design_0
    _t3 = _t0*_t2
    _t4 = ca.cos(x_1)
    _t5 = ca.cos(design_2)
    _t6 = ca.sin(x_2)
    _t7 = _t6*design_0
    _t8 = _t5*_t7
    _t9 = _t3 - _t4*_t8
    _t10 = 2*x_0
    _t11 = _t0*_t8 + _t2*_t4
    _t12 = ca.cos(x_2)
    _t13 = _t5**2
    _t14 = design_1**2 + x_0**2 + design_0**2
    _t15 = ca.sin(design_3)
    _t16 = _t15*design_0
    _t17 = _t0*_t16
    _t18 = ca.cos(design_3)
    _t19 = _t18*_t7
    _t20 = _t17 - _t19*_t4
    _t21 = _t0*_t19 + _t16*_t4
    _t22 = _t18**2
    _t23 = 2*design_1
    _t24 = _t10*_t12*_t4*design_0
    _t25 = _t12*_t23
    h = ca.reshape(ca.vertcat(2*design_1*_t1*_t11 + 2*design_1*_t12*_t13*design_0 - _t10*_t9 - _t14 + q_0**2, 2*design_1*_t12*_t22*design_0 + 2*design_1*_t15*_t21 - _t10*_t20 - _t14 + q_1**2, -x_0 + q_2), 3, 1)
    H_q = ca.reshape(ca.vertcat(2*q_0, 0, 0, 0, 2*q_1, 0, 0, 0, 1), 3, 3)
    H_x = ca.reshape(ca.vertcat(-_t10 - 2*_t3 + 2*_t4*_t5*_t6*design_0, -_t10 - 2*_t17 + 2*_t18*_t4*_t6*design_0, -1, -_t1*_t23*_t9 - _t10*_t11, -_t10*_t21 - _t15*_t20*_t23, 0, -_t13*_t23*_t7 + _t24*_t5 + _t25*_t3*_t5, _t17*_t18*_t25 + _t18*_t24 - _t22*_t23*_t7, 0), 3, 3)
    return ca.Function("constraint", [q, x, design], [h, H_q, H_x], ["q", "x", "design"], ["h", "H_q", "H_x"])


def first_order():
    """First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        q (3): [l1, l2, l0_leg] UPS leg lengths l1, l2 and the PU leg's stroke l0 [m]
        x (3): [l0, theta1, theta2] l0 [m], theta1, theta2 [rad]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        J (3x3, column-major): q_a_dot = J x_dot [-, m/rad]
        J_f (3x3, column-major): x_dot = J_f q_a_dot [-, rad/m]
        psi (3x3, column-major): q_dot = Psi q_a_dot, all joints from actuated [-]
        det_type1 (1x1, column-major): serial singularity measure [m^2]
        det_type2 (1x1, column-major): parallel singularity measure [m^2]
    """
    q = ca.SX.sym("q", 3)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    x = ca.SX.sym("x", 3)
    x_0 = x[0]
    x_1 = x[1]
    x_2 = x[2]
    design = ca.SX.sym("design", 16)
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
    # 61 common subexpressions, 363 operations
    _t0 = 1/q_0
    _t1 = ca.sin(design_2)
    _t2 = ca.sin(x_1)
    _t3 = _t2*design_0
    _t4 = _t1*_t3
    _t5 = ca.cos(design_2)
    _t6 = ca.sin(x_2)
    _t7 = _t5*_t6
    _t8 = ca.cos(x_1)
    _t9 = _t8*design_0
    _t10 = 1/q_1
    _t11 = ca.sin(design_3)
    _t12 = _t11*_t3
    _t13 = ca.cos(design_3)
    _t14 = _t13*_t6
    _t15 = _t8*x_0
    _t16 = _t1*_t15
    _t17 = _t1**2
    _t18 = design_1*_t2
    _t19 = _t17*_t18
    _t20 = _t2*x_0
    _t21 = design_1*_t6
    _t22 = _t21*_t5
    _t23 = _t1*_t8
    _t24 = _t16 + _t19 + _t20*_t7 - _t22*_t23
    _t25 = _t0*design_0
    _t26 = _t11*_t15
    _t27 = _t11**2
    _t28 = _t13*_t21
    _t29 = _t11*_t28*_t8
    _t30 = _t14*_t20 + _t18*_t27 + _t26 - _t29
    _t31 = _t10*design_0
    _t32 = ca.cos(x_2)
    _t33 = _t15*_t32
    _t34 = _t18*_t32
    _t35 = _t1*_t34
    _t36 = -design_1*_t5*_t6 + _t33 + _t35
    _t37 = _t11*_t34
    _t38 = _t13*(design_1*_t13*_t6 - _t33 - _t37)
    _t39 = _t5**2
    _t40 = x_0**2
    _t41 = _t13*_t32
    _t42 = _t8**2
    _t43 = _t1*_t42
    _t44 = _t13**2
    _t45 = _t6**2
    _t46 = _t13*_t39*_t45
    _t47 = design_1**2
    _t48 = _t2**2
    _t49 = _t22*x_0
    _t50 = _t11*_t42
    _t51 = _t45*_t5
    _t52 = _t11*_t17
    _t53 = -design_1*_t1*_t11*_t2*_t32*_t5*_t8*x_0 - design_1*_t1*_t13*_t32*_t42*_t5*_t6*x_0 - design_1*_t1*_t13*_t32*_t48*_t5*_t6*x_0 - design_1*_t1*_t44*_t6*_t8*x_0 - design_1*_t2*_t27*_t32*_t5*_t8*x_0 - design_1*_t2*_t44*_t45*_t5*x_0 - _t1*_t27*_t32*_t47*_t48*_t5 - _t11*_t13*_t39*_t45*_t47*_t8 - _t11*_t32*_t40*_t42*_t5 + _t11*_t41*_t48*_t49 + _t13*_t16*_t37 + _t13*_t19*_t33 - _t17*_t2*_t44*_t47*_t6 + _t18*_t46*x_0 + _t2*_t27*_t39*_t47*_t6 + _t21*_t26*_t39 + _t23*_t44*_t47*_t51 + _t40*_t41*_t43 + _t41*_t47*_t48*_t52 + _t41*_t49*_t50
    _t54 = -1/(_t53*design_0)
    _t55 = _t54*q_0
    _t56 = _t54*q_1
    _t57 = _t40*_t8
    _t58 = _t48*design_0
    _t59 = design_1*_t58
    _t60 = _t7*x_0
    J = ca.reshape(ca.vertcat(_t0*(_t4 - _t7*_t9 + x_0), _t10*(_t12 - _t14*_t9 + x_0), 1, _t24*_t25, _t30*_t31, 0, -_t25*_t36*_t5, _t31*_t38, 0), 3, 3)
    J_f = ca.reshape(ca.vertcat(0, _t38*_t55, -_t30*_t55, 0, _t36*_t5*_t56, _t24*_t56, 1, _t54*(design_1*_t1*_t11*_t13*_t32*_t48*design_0 + design_1*_t1*_t13*_t2*_t32*_t5*_t6*_t8*design_0 + design_1*_t11*_t13*_t2*_t32*x_0 + design_1*_t11*_t2*_t39*_t6*design_0 + design_1*_t39*_t6*x_0 + design_1*_t44*_t45*_t5*_t8*design_0 - design_1*_t46*_t9 - _t1*_t11*_t32*_t5*_t59 + _t1*_t13*_t2*_t32*_t8*x_0*design_0 - _t12*_t22*_t41*_t8 - _t12*_t33*_t5 + _t13*_t32*_t40*_t8 - _t21*_t4*_t44 - _t21*_t44*x_0 - _t32*_t5*_t57 - _t35*_t5*x_0), _t54*(design_1*_t1*_t11*_t2*_t5*_t6*_t8*design_0 + design_1*_t1*_t27*_t48*design_0 + design_1*_t1*_t5*_t6*_t8*x_0 + design_1*_t11*_t13*_t42*_t45*_t5*design_0 + design_1*_t13*_t17*_t2*_t6*_t8*design_0 - design_1*_t13*_t43*_t51*design_0 + design_1*_t2*_t27*x_0 + _t1*_t13*_t42*_t6*x_0*design_0 + _t1*_t13*_t48*_t6*x_0*design_0 - _t1*_t57 + _t11*_t40*_t8 - _t11*_t58*_t60 + _t13*_t2*_t40*_t6 - _t19*x_0 - _t2*_t40*_t7 - _t22*_t27*_t3*_t8 - _t26*_t28 - _t29*_t4 - _t50*_t60*design_0 - _t52*_t59)), 3, 3)
    psi = ca.reshape(ca.vertcat(1, 0, 0, 0, 1, 0, 0, 0, 1), 3, 3)
    det_type1 = ca.reshape(ca.vertcat(4*q_0*q_1), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(4*_t53*design_0**2), 1, 1)
    return ca.Function("first_order", [q, x, design], [J, J_f, psi, det_type1, det_type2], ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


def forward_polynomial():
    """Polynomial of degree 8 in t = tan(theta2 / 2) whose real roots are the assembly modes.

    Inputs:
        q_a (3): [l1, l2, l0_leg] actuated lengths [m]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        c (9x1, column-major): coefficients of t^8 ... t^0, t = tan(theta2 / 2) [m^8]
    """
    q_a = ca.SX.sym("q_a", 3)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    q_a_2 = q_a[2]
    design = ca.SX.sym("design", 16)
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
    # 61 common subexpressions, 206 operations
    _t0 = ca.sin(design_2)
    _t1 = design_0**2
    _t2 = ca.sin(design_3)
    _t3 = _t2**2
    _t4 = 4*q_a_2
    _t5 = _t0**2
    _t6 = _t1*_t2
    _t7 = _t5*_t6
    _t8 = 4*design_1*_t0*_t1*_t3*q_a_2 - design_1*_t4*_t7
    _t9 = _t8**2
    _t10 = -_t9
    _t11 = ca.cos(design_2)
    _t12 = 2*design_0
    _t13 = design_1*_t12
    _t14 = _t11**2*_t13
    _t15 = q_a_2**2
    _t16 = design_1**2
    _t17 = _t1 + _t15 + _t16
    _t18 = _t17 - q_a_0**2
    _t19 = -_t14 - _t18
    _t20 = _t12*q_a_2
    _t21 = _t2*_t20
    _t22 = ca.cos(design_3)
    _t23 = _t13*_t22**2
    _t24 = _t17 - q_a_1**2
    _t25 = -_t23 - _t24
    _t26 = -_t0*_t20*_t25 + _t19*_t21
    _t27 = _t13*_t3
    _t28 = _t13*_t5
    _t29 = _t19*_t27 - _t25*_t28
    _t30 = 8*_t15
    _t31 = _t0*_t1
    _t32 = _t22*_t31
    _t33 = 8*_t16
    _t34 = -_t11*_t3*_t31*_t33 - _t11*_t30*_t6 + _t22*_t33*_t7 + _t30*_t32
    _t35 = 2*_t8
    _t36 = -_t34*_t35
    _t37 = _t4*design_0
    _t38 = _t22*_t37
    _t39 = _t11*_t37
    _t40 = _t19*_t38 - _t25*_t39
    _t41 = 2*_t29
    _t42 = 4*design_1*_t2*_t22*design_0
    _t43 = 4*design_1*_t0*_t11*_t25*design_0 - _t19*_t42
    _t44 = 2*_t26
    _t45 = _t14 - _t18
    _t46 = _t23 - _t24
    _t47 = -_t0*_t20*_t46 + _t21*_t45
    _t48 = _t26 + _t47
    _t49 = _t27*_t45 - _t28*_t46
    _t50 = _t29 + _t49
    _t51 = _t34**2
    _t52 = 8*design_1*_t0*_t1*_t3*q_a_2 + 16*design_1*_t1*_t11*_t2*_t22*q_a_2 - 16*design_1*_t11*_t32*q_a_2 - 8*design_1*_t7*q_a_2
    _t53 = -_t35*_t52 - _t51
    _t54 = 2*_t40
    _t55 = _t38*_t45 - _t39*_t46
    _t56 = 4*design_1*_t0*_t11*_t46*design_0 - _t42*_t45
    _t57 = 2*_t43
    _t58 = -2*_t34*_t52 + _t36
    _t59 = 2*_t50
    _t60 = 2*_t48
    c = ca.reshape(ca.vertcat(_t10 + _t26**2 + _t29**2, _t36 + _t40*_t41 + _t43*_t44, _t40**2 + _t41*_t50 + _t43**2 + _t44*_t48 + _t53, _t41*_t55 + _t44*_t56 + _t48*_t57 + _t50*_t54 + _t58, _t41*_t49 + _t44*_t47 + _t48**2 + _t50**2 - 2*_t51 - _t52**2 + _t54*_t55 + _t56*_t57 - 2*_t9, _t47*_t57 + _t49*_t54 + _t55*_t59 + _t56*_t60 + _t58, _t47*_t60 + _t49*_t59 + _t53 + _t55**2 + _t56**2, _t36 + 2*_t47*_t56 + 2*_t49*_t55, _t10 + _t47**2 + _t49**2), 9, 1)
    return ca.Function("forward_polynomial", [q_a, design], [c], ["q_a", "design"], ["c"])


def forward_from_root():
    """Pose and joints from one real root of the forward polynomial.

    Inputs:
        root (1): [t] t = tan(theta2 / 2) [-]
        q_a (3): [l1, l2, l0_leg] actuated lengths [m]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        x (3x1, column-major): l0 [m], theta1, theta2 [rad]
        q (3x1, column-major): l1, l2, l0_leg [m]
        reach (4x1, column-major): 1e-9 (l1^2 + l2^2) - |leg residual|: >= 0 where the root closes the loop [m^2]
    """
    root = ca.SX.sym("root", 1)
    root_0 = root[0]
    q_a = ca.SX.sym("q_a", 3)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    q_a_2 = q_a[2]
    design = ca.SX.sym("design", 16)
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
    # 36 common subexpressions, 110 operations
    _t0 = ca.sin(design_2)
    _t1 = 2*design_1
    _t2 = _t1*design_0
    _t3 = ca.cos(design_2)
    _t4 = 2*ca.atan(root_0)
    _t5 = ca.sin(_t4)
    _t6 = 2*q_a_2
    _t7 = _t5*_t6*design_0
    _t8 = -_t0**2*_t2 - _t3*_t7
    _t9 = ca.sin(design_3)
    _t10 = ca.cos(design_3)
    _t11 = _t2*_t5
    _t12 = -_t10*_t11*_t9 + 2*_t9*q_a_2*design_0
    _t13 = -_t10*_t7 - _t2*_t9**2
    _t14 = -_t0*_t11*_t3 + 2*_t0*q_a_2*design_0
    _t15 = ca.sign(_t12*_t8 - _t13*_t14)
    _t16 = q_a_1**2
    _t17 = _t2*ca.cos(_t4)
    _t18 = design_1**2 + q_a_2**2 + design_0**2
    _t19 = -_t10**2*_t17 - _t16 + _t18
    _t20 = -_t19
    _t21 = q_a_0**2
    _t22 = -_t17*_t3**2 + _t18 - _t21
    _t23 = -_t22
    _t24 = -_t13*_t23 + _t20*_t8
    _t25 = _t15*_t24
    _t26 = _t12*_t23 - _t14*_t20
    _t27 = _t15*_t26
    _t28 = _t15**2
    _t29 = design_0/ca.sqrt(_t24**2*_t28 + _t26**2*_t28)
    _t30 = _t0*_t29
    _t31 = _t29*_t5
    _t32 = _t3*_t31
    _t33 = 1e-09*_t16 + 1e-09*_t21
    _t34 = _t29*_t9
    _t35 = _t10*_t31
    x = ca.reshape(ca.vertcat(q_a_2, ca.atan2(_t25, _t27), _t4), 3, 1)
    q = ca.reshape(ca.vertcat(q_a_0, q_a_1, q_a_2), 3, 1)
    reach = ca.reshape(ca.vertcat(_t33 - ca.fabs(-_t0*_t1*(_t25*_t32 + _t27*_t30) + _t22 + _t6*(_t25*_t30 - _t27*_t32)), _t33 - ca.fabs(-_t1*_t9*(_t25*_t35 + _t27*_t34) + _t19 + _t6*(_t25*_t34 - _t27*_t35)), q_a_0, q_a_1), 4, 1)
    return ca.Function("forward_from_root", [root, q_a, design], [x, q, reach], ["root", "q_a", "design"], ["x", "q", "reach"])


def joint_positions():
    """Positions of the joints U0, S1, S2, U1, U2 and the platform normal z_p.

    Inputs:
        x (3): [l0, theta1, theta2] l0 [m], theta1, theta2 [rad]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        U0 (3x1, column-major): U0 in the base frame [m]
        S1 (3x1, column-major): S1 in the base frame [m]
        S2 (3x1, column-major): S2 in the base frame [m]
        U1 (3x1, column-major): U1 in the base frame [m]
        U2 (3x1, column-major): U2 in the base frame [m]
        z_p (3x1, column-major): platform normal [-]
    """
    x = ca.SX.sym("x", 3)
    x_0 = x[0]
    x_1 = x[1]
    x_2 = x[2]
    design = ca.SX.sym("design", 16)
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
    # 14 common subexpressions, 37 operations
    _t0 = ca.cos(design_2)
    _t1 = ca.cos(x_2)
    _t2 = _t1*design_0
    _t3 = ca.cos(x_1)
    _t4 = ca.sin(design_2)
    _t5 = _t4*design_0
    _t6 = ca.sin(x_1)
    _t7 = ca.sin(x_2)
    _t8 = _t7*design_0
    _t9 = _t0*_t8
    _t10 = ca.cos(design_3)
    _t11 = ca.sin(design_3)
    _t12 = _t11*design_0
    _t13 = _t10*_t8
    U0 = ca.reshape(ca.vertcat(0, 0, x_0), 3, 1)
    S1 = ca.reshape(ca.vertcat(_t0*_t2, _t3*_t5 + _t6*_t9, -_t3*_t9 + _t5*_t6 + x_0), 3, 1)
    S2 = ca.reshape(ca.vertcat(_t10*_t2, _t12*_t3 + _t13*_t6, _t12*_t6 - _t13*_t3 + x_0), 3, 1)
    U1 = ca.reshape(ca.vertcat(design_1*_t0, design_1*_t4, 0), 3, 1)
    U2 = ca.reshape(ca.vertcat(design_1*_t10, design_1*_t11, 0), 3, 1)
    z_p = ca.reshape(ca.vertcat(_t7, -_t1*_t6, _t1*_t3), 3, 1)
    return ca.Function("joint_positions", [x, design], [U0, S1, S2, U1, U2, z_p], ["x", "design"], ["U0", "S1", "S2", "U1", "U2", "z_p"])


def statics():
    """Wrench matrices of the statics (Zhao eq. 8): physical, and as printed; the payload's wrench.

    Inputs:
        q (3): [l1, l2, l0_leg] UPS leg lengths l1, l2 and the PU leg's stroke l0 [m]
        x (3): [l0, theta1, theta2] l0 [m], theta1, theta2 [rad]
        design (16): [r, R, alpha, beta, l_min, l_max, l0_min, l0_max, theta_u_max, theta_s_max, D, payload, payload_height, g, task_tilt, task_height] r, R [m]; alpha, beta [rad]; l_min, l_max, l0_min, l0_max [m]; theta_u_max, theta_s_max [rad]; D [m]; payload [kg], payload_height [m], g [m/s^2]; task_tilt [rad], task_height [m]
    Outputs:
        W (6x6, column-major): (F, M) at U0 = W (f1, f2, f0, f_x, f_y, m_c) [-, m]
        W_printed (6x6, column-major): eq. 8 as printed: normalised moment axes, m_c about Z [-]
        w_load (6x1, column-major): the payload's wrench (F, M) at U0 [N, N m]
    """
    q = ca.SX.sym("q", 3)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    x = ca.SX.sym("x", 3)
    x_0 = x[0]
    x_1 = x[1]
    x_2 = x[2]
    design = ca.SX.sym("design", 16)
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
    # 44 common subexpressions, 133 operations
    _t0 = ca.cos(design_2)
    _t1 = ca.cos(x_2)
    _t2 = -design_1*_t0 + _t0*_t1*design_0
    _t3 = ca.sin(x_1)
    _t4 = ca.sin(design_2)
    _t5 = _t4*design_0
    _t6 = ca.cos(x_1)
    _t7 = ca.sin(x_2)
    _t8 = _t7*design_0
    _t9 = _t0*_t8
    _t10 = _t3*_t5 - _t6*_t9
    _t11 = _t10 + x_0
    _t12 = _t3*_t9 + _t5*_t6
    _t13 = -design_1*_t4 + _t12
    _t14 = 1/ca.sqrt(_t11**2 + _t13**2 + _t2**2)
    _t15 = _t14*_t2
    _t16 = _t13*_t14
    _t17 = _t11*_t14
    _t18 = _t1*design_0
    _t19 = _t0*_t18
    _t20 = ca.cos(design_3)
    _t21 = -design_1*_t20 + _t1*_t20*design_0
    _t22 = ca.sin(design_3)
    _t23 = _t22*design_0
    _t24 = _t20*_t8
    _t25 = _t23*_t3 - _t24*_t6
    _t26 = _t25 + x_0
    _t27 = _t23*_t6 + _t24*_t3
    _t28 = -design_1*_t22 + _t27
    _t29 = 1/ca.sqrt(_t21**2 + _t26**2 + _t28**2)
    _t30 = _t21*_t29
    _t31 = _t28*_t29
    _t32 = _t26*_t29
    _t33 = _t18*_t20
    _t34 = _t11*_t12 - _t11*_t13
    _t35 = -_t11*_t19 + _t11*_t2
    _t36 = -_t12*_t2 + _t13*_t19
    _t37 = 1/ca.sqrt(_t34**2 + _t35**2 + _t36**2)
    _t38 = _t26*_t27 - _t26*_t28
    _t39 = _t21*_t26 - _t26*_t33
    _t40 = -_t21*_t27 + _t28*_t33
    _t41 = 1/ca.sqrt(_t38**2 + _t39**2 + _t40**2)
    _t42 = design_13*design_11
    _t43 = _t42*design_12
    W = ca.reshape(ca.vertcat(_t15, _t16, _t17, -_t10*_t16 + _t11*_t12*_t14, _t10*_t14*_t2 - _t17*_t19, -_t12*_t15 + _t16*_t19, _t30, _t31, _t32, -_t25*_t31 + _t26*_t27*_t29, _t21*_t25*_t29 - _t32*_t33, -_t27*_t30 + _t31*_t33, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, -_t3, _t6), 6, 6)
    W_printed = ca.reshape(ca.vertcat(_t15, _t16, _t17, _t34*_t37, _t35*_t37, _t36*_t37, _t30, _t31, _t32, _t38*_t41, _t39*_t41, _t40*_t41, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1), 6, 6)
    w_load = ca.reshape(ca.vertcat(0, 0, -_t42, _t1*_t3*_t43, _t43*_t7, 0), 6, 1)
    return ca.Function("statics", [q, x, design], [W, W_printed, w_load], ["q", "x", "design"], ["W", "W_printed", "w_load"])


def build():
    """All functions of this module by name."""
    return {name: globals()[name]() for name in FUNCTIONS}
