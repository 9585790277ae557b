# Generated from symbolic/mechanisms/passive_leg.py (source sha256 5bbdedf5e80aa934).
# Do not edit: regenerate with `make generate`.
# ruff: noqa
"""CasADi functions of the 2-DOF manipulator with a passive constraining leg."""

import casadi as ca

SOURCE_HASH = "5bbdedf5e80aa934"
FUNCTIONS = ("inverse_kinematics", "constraint", "first_order", "forward_polynomial", "forward_from_root", "paper_inverse", "paper_forward", "paper_first_order", "joint_angles", "joint_positions", "workspace_boundary", "workspace_range_negative", "workspace_range_positive", "workspace_curves", "polar_to_pose", "polar_area", "footprint", )
PARAMETERS = ("R", "r", "l_a", "l_b", "theta_max", )
POSE = ("x_c", "y_c", )
ACTUATORS = ("phi1", "phi2", )


def inverse_kinematics():
    """Joints on the branch of eq. 6's signs (s1, s2); theta = atan2(-x_c, y_c), l_c = |C|.

    Inputs:
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        mode (2): [s1, s2] the signs of eq. 6 for legs 1 and 2 (+1 or -1)
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        q (6x1, column-major): phi1, phi2, theta, psi1, psi2 [rad], l_c [m]
        reach (3x1, column-major): Delta_1, Delta_2 of eq. 6 over 4 l_a^2 (l_a + l_b)^2 [-] and y_c [m]: >= 0 where reachable
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 33 common subexpressions, 98 operations
    _t0 = ca.sqrt(x_0**2 + x_1**2)
    _t1 = design_1/_t0
    _t2 = _t1*x_0
    _t3 = _t2 - x_1
    _t4 = -_t3
    _t5 = design_2**2
    _t6 = 4*_t5
    _t7 = _t1*x_1
    _t8 = -design_0 + _t7 + x_0
    _t9 = _t4**2*_t6 + _t6*_t8**2
    _t10 = (1/4)/_t5
    _t11 = -_t5 + design_3**2
    _t12 = -_t10*_t9 + _t11
    _t13 = 2*design_2
    _t14 = _t12*_t13
    _t15 = -_t12**2 + _t9
    _t16 = _t13*ca.sqrt(_t15)*mode_0
    _t17 = -_t14*_t4 - _t16*_t8
    _t18 = -_t14*_t8 + _t16*_t4
    _t19 = _t2 + x_1
    _t20 = design_0 - _t7
    _t21 = _t20 + x_0
    _t22 = _t19**2*_t6 + _t21**2*_t6
    _t23 = -_t10*_t22 + _t11
    _t24 = _t13*_t23
    _t25 = _t22 - _t23**2
    _t26 = _t13*ca.sqrt(_t25)*mode_1
    _t27 = -_t19*_t24 - _t21*_t26
    _t28 = _t19*_t26 - _t21*_t24
    _t29 = -x_0
    _t30 = design_2/ca.sqrt(_t17**2 + _t18**2)
    _t31 = design_2/ca.sqrt(_t27**2 + _t28**2)
    _t32 = _t10/(design_2 + design_3)**2
    q = ca.reshape(ca.vertcat(ca.atan2(_t17, _t18), ca.atan2(_t27, _t28), ca.atan2(_t29, x_1), ca.atan2(-_t17*_t30 - _t3, -_t18*_t30 - _t20 - _t29), ca.atan2(_t19 - _t27*_t31, _t21 - _t28*_t31), _t0), 6, 1)
    reach = ca.reshape(ca.vertcat(_t15*_t32, _t25*_t32, x_1), 3, 1)
    return ca.Function("inverse_kinematics", [x, mode, design], [q, reach], ["x", "mode", "design"], ["q", "reach"])


def constraint():
    """Loop-closure residuals and their Jacobians.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        h (6x1, column-major): loop-closure residuals [m, -, m]
        H_q (6x6, column-major): dh/dq, actuated then passive [m]
        H_x (6x2, column-major): dh/dx [-]
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 18 common subexpressions, 55 operations
    _t0 = -x_0
    _t1 = design_2*ca.cos(q_0)
    _t2 = design_3*ca.cos(q_3)
    _t3 = ca.cos(q_2)
    _t4 = _t3*design_1
    _t5 = -_t4
    _t6 = -x_1
    _t7 = design_2*ca.sin(q_0)
    _t8 = design_3*ca.sin(q_3)
    _t9 = ca.sin(q_2)
    _t10 = _t9*design_1
    _t11 = -_t10
    _t12 = design_2*ca.cos(q_1)
    _t13 = design_3*ca.cos(q_4)
    _t14 = design_2*ca.sin(q_1)
    _t15 = design_3*ca.sin(q_4)
    _t16 = _t3*x_0 + _t9*x_1
    _t17 = -_t3*x_1 + _t9*x_0
    h = ca.reshape(ca.vertcat(design_0 + _t0 + _t1 + _t2 + _t5, _t11 + _t6 + _t7 + _t8, -design_0 + _t0 + _t12 + _t13 + _t4, _t10 + _t14 + _t15 + _t6, _t16, _t17 + q_5), 6, 1)
    H_q = ca.reshape(ca.vertcat(-_t7, _t1, 0, 0, 0, 0, 0, 0, -_t14, _t12, 0, 0, _t10, _t5, _t11, _t4, -_t17, _t16, -_t8, _t2, 0, 0, 0, 0, 0, 0, -_t15, _t13, 0, 0, 0, 0, 0, 0, 0, 1), 6, 6)
    H_x = ca.reshape(ca.vertcat(-1, 0, -1, 0, _t3, _t9, 0, -1, 0, -1, _t9, -_t3), 6, 2)
    return ca.Function("constraint", [q, x, design], [h, H_q, H_x], ["q", "x", "design"], ["h", "H_q", "H_x"])


def first_order():
    """First-order kinematics by implicit differentiation of the loop closure.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        J (2x2, column-major): q_a_dot = J x_dot [rad/m]
        J_f (2x2, column-major): x_dot = J_f q_a_dot [m/rad]
        psi (6x2, column-major): q_dot = Psi q_a_dot, all joints from actuated [-]
        det_type1 (1x1, column-major): serial singularity measure [m^5]
        det_type2 (1x1, column-major): parallel singularity measure [m^5]
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 68 common subexpressions, 439 operations
    _t0 = ca.cos(q_3)
    _t1 = ca.sin(q_2)
    _t2 = _t1*x_0
    _t3 = _t0*_t2
    _t4 = ca.cos(q_2)
    _t5 = ca.sin(q_3)
    _t6 = _t4**2
    _t7 = _t6*design_1
    _t8 = _t5*_t7
    _t9 = 1/design_2
    _t10 = ca.sin(q_0)
    _t11 = _t10*_t3
    _t12 = ca.cos(q_0)
    _t13 = _t4*x_1
    _t14 = _t13*_t5
    _t15 = _t12*_t14
    _t16 = _t2*_t5
    _t17 = _t12*_t16
    _t18 = _t0*_t13
    _t19 = _t10*_t18
    _t20 = _t11 + _t15 - _t17 - _t19
    _t21 = _t9/_t20
    _t22 = ca.cos(q_4)
    _t23 = _t13*_t22
    _t24 = _t2*_t22
    _t25 = ca.sin(q_4)
    _t26 = _t25*_t7
    _t27 = _t4*design_1
    _t28 = _t1*_t27
    _t29 = _t22*_t28
    _t30 = ca.sin(q_1)
    _t31 = _t24*_t30
    _t32 = ca.cos(q_1)
    _t33 = _t13*_t25
    _t34 = _t2*_t25
    _t35 = _t23*_t30
    _t36 = _t31 + _t32*_t33 - _t32*_t34 - _t35
    _t37 = _t9/_t36
    _t38 = _t28*_t5
    _t39 = _t1**2
    _t40 = _t39*design_1
    _t41 = _t22*_t40
    _t42 = _t12*_t5
    _t43 = _t0*_t1
    _t44 = _t27*_t43
    _t45 = _t25*_t44
    _t46 = _t0*_t40
    _t47 = _t22*_t46
    _t48 = _t24*_t5
    _t49 = _t18*_t25
    _t50 = _t29*_t5
    _t51 = _t23*_t5 + _t25*_t3 + 2*_t25*_t8 - 2*_t45 + 2*_t47 - _t48 - _t49 - 2*_t50
    _t52 = design_2/_t51
    _t53 = _t0*_t10
    _t54 = _t25*_t32
    _t55 = _t22*_t30
    _t56 = _t25*_t4
    _t57 = _t22*_t42
    _t58 = _t52/design_3
    _t59 = _t4**3
    _t60 = _t59*design_1
    _t61 = _t1**3
    _t62 = _t61*design_1
    _t63 = _t25*x_0
    _t64 = _t39*x_1
    _t65 = _t5*_t55
    _t66 = _t0*_t54
    _t67 = design_3**2
    J = ca.reshape(ca.vertcat(_t21*(_t0*_t1*_t4*design_1 + _t0*_t4*x_1 - _t3 - _t8), _t37*(_t23 - _t24 + _t26 - _t29), _t21*(_t0*_t39*design_1 - _t16 - _t38 + _t4*_t5*x_1), _t37*(_t25*_t28 + _t33 - _t34 - _t41)), 2, 2)
    J_f = ca.reshape(ca.vertcat(_t52*(_t10*_t45 - _t10*_t47 - _t11*_t25 - _t12*_t25*_t38 - _t15*_t25 + _t17*_t25 + _t19*_t25 + _t41*_t42), _t52*(_t0*_t1*_t10*_t22*_t4*design_1 + _t0*_t1*_t10*_t22*x_0 + _t12*_t22*_t4*_t5*x_1 + _t12*_t25*_t5*_t6*design_1 - _t12*_t48 - _t19*_t22 - _t26*_t53 - _t29*_t42), _t52*(_t14*_t54 - _t16*_t54 + _t30*_t50 + _t31*_t5 - _t35*_t5 - _t38*_t54 + _t46*_t54 - _t46*_t55), _t52*(_t0*_t1*_t22*_t30*_t4*design_1 + _t0*_t1*_t25*_t32*x_0 + _t0*_t22*_t30*_t4*x_1 + _t25*_t32*_t5*_t6*design_1 - _t3*_t55 - _t32*_t49 - _t44*_t54 - _t55*_t8)), 2, 2)
    psi = ca.reshape(ca.vertcat(1, 0, _t52*(_t0*_t1*_t10*_t22 - _t1*_t57 + _t12*_t25*_t4*_t5 - _t53*_t56), _t58*(2*_t1*_t10*_t22*_t4*design_1 + _t1*_t10*_t22*x_0 + 2*_t1*_t12*_t25*_t4*design_1 - _t10*_t23 - 2*_t10*_t26 + _t12*_t25*_t4*x_1 - _t12*_t34 - 2*_t12*_t41), _t20*_t58, _t52*(_t0*_t1*_t10*_t22*_t6*design_1 + _t0*_t10*_t22*_t61*design_1 + _t0*_t10*_t25*_t39*x_0 + _t0*_t10*_t25*_t6*x_0 - _t1*_t12*_t22*_t8 - _t10*_t46*_t56 + _t12*_t22*_t39*_t5*x_1 + _t12*_t22*_t5*_t6*x_1 + _t12*_t25*_t39*_t4*_t5*design_1 + _t12*_t25*_t5*_t59*design_1 - _t22*_t53*_t6*x_1 - _t22*_t53*_t64 - _t25*_t53*_t60 - _t39*_t42*_t63 - _t42*_t6*_t63 - _t57*_t62), 0, 1, _t52*(-_t22*_t30*_t43 - _t32*_t5*_t56 + _t4*_t65 + _t43*_t54), -_t36*_t58, _t58*(2*_t0*_t1*_t30*_t4*design_1 + _t0*_t30*_t4*x_1 + 2*_t1*_t32*_t4*_t5*design_1 + _t1*_t32*_t5*x_0 - _t14*_t32 - _t3*_t30 - 2*_t30*_t8 - 2*_t32*_t46), _t52*(_t0*_t1*_t22*_t30*_t6*design_1 + _t0*_t22*_t30*_t39*x_1 + _t0*_t22*_t30*_t6*x_1 + _t0*_t22*_t30*_t61*design_1 + _t25*_t32*_t39*_t4*_t5*design_1 + _t25*_t32*_t39*_t5*x_0 + _t25*_t32*_t5*_t59*design_1 + _t25*_t32*_t5*_t6*x_0 - _t26*_t32*_t43 - _t30*_t4*_t41*_t5 - _t39*_t65*x_0 - _t6*_t65*x_0 - _t6*_t66*x_1 - _t60*_t65 - _t62*_t66 - _t64*_t66)), 6, 2)
    det_type1 = ca.reshape(ca.vertcat(_t67*design_2**2*(-_t11*_t54 + _t11*_t55 - _t15*_t54 + _t17*_t54 + _t19*_t54 - _t19*_t55 - _t31*_t42 + _t35*_t42)), 1, 1)
    det_type2 = ca.reshape(ca.vertcat(_t51*_t67), 1, 1)
    return ca.Function("first_order", [q, x, design], [J, J_f, psi, det_type1, det_type2], ["q", "x", "design"], ["J", "J_f", "psi", "det_type1", "det_type2"])


def forward_polynomial():
    """Polynomial of degree 6 in l_c whose real roots are the assembly modes (eq. 11 as derived).

    Inputs:
        q_a (2): [phi1, phi2] actuated base angles phi1, phi2 [rad]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        c (7x1, column-major): coefficients of l_c^6 ... l_c^0 [m^(8 - k)]
    """
    q_a = ca.SX.sym("q_a", 2)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 37 common subexpressions, 124 operations
    _t0 = ca.sin(q_a_0)
    _t1 = _t0*design_2
    _t2 = ca.sin(q_a_1)
    _t3 = -_t1 + _t2*design_2
    _t4 = 2*design_0
    _t5 = design_2*ca.cos(q_a_0)
    _t6 = design_2*ca.cos(q_a_1)
    _t7 = -_t6
    _t8 = _t4 + _t5 + _t7
    _t9 = _t5*design_1
    _t10 = _t6*design_1
    _t11 = -_t10 - _t9
    _t12 = 2*_t3
    _t13 = _t1*design_1
    _t14 = _t2*design_2
    _t15 = _t14*design_1
    _t16 = -_t13 - _t15
    _t17 = 2*_t8
    _t18 = design_0 + _t5
    _t19 = -design_0 - _t7
    _t20 = -_t1*_t19 + _t18*_t2*design_2
    _t21 = design_2**2
    _t22 = design_0**2 + _t21 - design_3**2 + design_1**2
    _t23 = _t22 + _t4*_t5
    _t24 = _t22 - _t4*_t6
    _t25 = -_t1*_t24 + _t14*_t23
    _t26 = _t18*_t24 - _t19*_t23
    _t27 = 2*_t11
    _t28 = -_t13*_t24 - _t15*_t23
    _t29 = design_0*design_1
    _t30 = _t29 + _t9
    _t31 = -_t10 + _t29
    _t32 = -2*_t0*_t2*_t21*design_1 + _t18*_t31 - _t19*_t30
    _t33 = 8*_t20
    _t34 = 2*_t16
    _t35 = _t23*_t31 - _t24*_t30
    _t36 = -_t13*_t31 - _t15*_t30
    c = ca.reshape(ca.vertcat(_t3**2 + _t8**2, _t11*_t12 + _t16*_t17, _t11**2 + _t12*_t25 + _t16**2 + _t17*_t26 - 4*_t20**2, _t12*_t35 + _t17*_t28 + _t25*_t27 + _t26*_t34 - _t32*_t33, _t25**2 + _t26**2 + _t27*_t35 + _t28*_t34 - 4*_t32**2 - _t33*_t36, 2*_t25*_t35 + 2*_t26*_t28 - 8*_t32*_t36, _t28**2 + _t35**2 - 4*_t36**2), 7, 1)
    return ca.Function("forward_polynomial", [q_a, design], [c], ["q_a", "design"], ["c"])


def forward_from_root():
    """Pose and joints from one real root l_c of the forward polynomial, theta from eq. 8.

    Inputs:
        root (1): [l_c_root] l_c: a real root of the forward polynomial [m]
        q_a (2): [phi1, phi2] actuated base angles phi1, phi2 [rad]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        x (2x1, column-major): x_c, y_c [m]
        q (6x1, column-major): phi1, phi2, theta, psi1, psi2 [rad], l_c [m]
        reach (2x1, column-major): 1e-9 (l_a + l_b)^2 - |eqs. 2-3 residual| [m^2]: >= 0 where the root closes
    """
    root = ca.SX.sym("root", 1)
    root_0 = root[0]
    q_a = ca.SX.sym("q_a", 2)
    q_a_0 = q_a[0]
    q_a_1 = q_a[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 33 common subexpressions, 100 operations
    _t0 = design_0*design_1
    _t1 = design_2*ca.sin(q_a_0)
    _t2 = design_2*ca.cos(q_a_0)
    _t3 = _t0 + _t1*root_0 + _t2*design_1
    _t4 = design_0*root_0
    _t5 = design_2*ca.cos(q_a_1)
    _t6 = design_2*ca.sin(q_a_1)
    _t7 = -_t4 + _t5*root_0 + _t6*design_1
    _t8 = -_t1*design_1 + _t2*root_0 + _t4
    _t9 = _t0 - _t5*design_1 + _t6*root_0
    _t10 = ca.sign(-_t3*_t7 + _t8*_t9)
    _t11 = 2*design_0
    _t12 = -design_3**2
    _t13 = design_0**2 + _t12 + design_2**2 + root_0**2 + design_1**2
    _t14 = -_t11*_t5 + _t13
    _t15 = _t11*_t2 + _t13
    _t16 = _t14*_t3 - _t15*_t9
    _t17 = _t10*_t16
    _t18 = _t10**2
    _t19 = _t14*_t8 - _t15*_t7
    _t20 = 1/ca.sqrt(_t16**2*_t18 + _t18*_t19**2)
    _t21 = _t20*root_0
    _t22 = _t17*_t21
    _t23 = _t10*_t19
    _t24 = _t21*_t23
    _t25 = _t20*design_1
    _t26 = _t17*_t25
    _t27 = -_t1 + _t24 + _t26
    _t28 = _t23*_t25
    _t29 = -design_0 - _t2 - _t22 + _t28
    _t30 = _t10*_t19*_t20*root_0 - _t26 - _t6
    _t31 = design_0 - _t22 - _t28 - _t5
    _t32 = 1e-09*(design_2 + design_3)**2
    x = ca.reshape(ca.vertcat(-_t22, _t24), 2, 1)
    q = ca.reshape(ca.vertcat(q_a_0, q_a_1, ca.atan2(_t17, _t23), ca.atan2(_t27, _t29), ca.atan2(_t30, _t31), root_0), 6, 1)
    reach = ca.reshape(ca.vertcat(_t32 - ca.fabs(_t12 + _t27**2 + _t29**2), _t32 - ca.fabs(_t12 + _t30**2 + _t31**2)), 2, 1)
    return ca.Function("forward_from_root", [root, q_a, design], [x, q, reach], ["root", "q_a", "design"], ["x", "q", "reach"])


def paper_inverse():
    """The actuated angles by eq. 6 in the paper's own form.

    Inputs:
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        mode (2): [s1, s2] the signs of eq. 6 for legs 1 and 2 (+1 or -1)
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        phi (2x1, column-major): eq. 6 with gamma_i - alpha_i in the denominator [rad]
        phi_printed (2x1, column-major): eq. 6 as printed, r - alpha_i in the denominator [rad]
    """
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    mode = ca.SX.sym("mode", 2)
    mode_0 = mode[0]
    mode_1 = mode[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 24 common subexpressions, 79 operations
    _t0 = design_1/ca.sqrt(x_0**2 + x_1**2)
    _t1 = _t0*x_1
    _t2 = -design_0 + _t1 + x_0
    _t3 = 2*design_2
    _t4 = _t2*_t3
    _t5 = design_2**2
    _t6 = 1/_t5
    _t7 = _t0*x_0
    _t8 = -_t7 + x_1
    _t9 = 4*_t5
    _t10 = _t2**2*_t9 + _t8**2*_t9
    _t11 = -_t10
    _t12 = design_3**2
    _t13 = -_t12 + _t5
    _t14 = (1/4)*_t6
    _t15 = _t12 - _t5
    _t16 = -_t3*_t8 + mode_0*ca.sqrt(_t10 - (_t11*_t14 + _t15)**2)
    _t17 = design_0 - _t1 + x_0
    _t18 = _t17*_t3
    _t19 = _t7 + x_1
    _t20 = _t17**2*_t9 + _t19**2*_t9
    _t21 = -_t20
    _t22 = -_t19*_t3 + mode_1*ca.sqrt(_t20 - (_t14*_t21 + _t15)**2)
    _t23 = -design_1
    phi = ca.reshape(ca.vertcat(2*ca.atan(_t16/((1/4)*_t11*_t6 - _t13 - _t4)), 2*ca.atan(_t22/(-_t13 - _t18 + (1/4)*_t21*_t6))), 2, 1)
    phi_printed = ca.reshape(ca.vertcat(2*ca.atan(_t16/(-_t23 - _t4)), 2*ca.atan(_t22/(-_t18 - _t23))), 2, 1)
    return ca.Function("paper_inverse", [x, mode, design], [phi, phi_printed], ["x", "mode", "design"], ["phi", "phi_printed"])


def paper_forward():
    """Eqs. 8, 9 and 11 evaluated at the joints q (l_c and theta) for the actuated angles phi.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        eq8 (2x1, column-major): eqs. 2-3 at C = l_c (-sin theta, cos theta) [m^2]
        eq11 (1x1, column-major): eq. 11 as derived (factor 4) [m^8]
        eq11_printed (1x1, column-major): eq. 11 as printed [m^8]
        eq9 (2x1, column-major): (A_i + 2 B_i) s^2 + 4 C_i s + (A_i - 2 B_i), s = tan(theta/2) [m^2]
        eq9_printed (2x1, column-major): (A_i - B_i) s^2 + 2 C_i s + (A_i + B_i) as printed [m^2]
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 41 common subexpressions, 146 operations
    _t0 = -design_3**2
    _t1 = ca.cos(q_2)
    _t2 = ca.sin(q_2)
    _t3 = _t2*design_1
    _t4 = design_2*ca.sin(q_0)
    _t5 = design_2*ca.cos(q_0)
    _t6 = _t2*q_5
    _t7 = _t1*design_1
    _t8 = design_2*ca.sin(q_1)
    _t9 = design_2*ca.cos(q_1)
    _t10 = design_0*design_1
    _t11 = _t4*q_5
    _t12 = _t5*design_1
    _t13 = _t10 + _t11 + _t12
    _t14 = design_0*q_5
    _t15 = _t9*q_5
    _t16 = _t8*design_1
    _t17 = -_t14 + _t15 + _t16
    _t18 = _t5*q_5
    _t19 = _t4*design_1
    _t20 = _t14 + _t18 - _t19
    _t21 = _t8*q_5
    _t22 = _t9*design_1
    _t23 = _t10 + _t21 - _t22
    _t24 = (-_t13*_t17 + _t20*_t23)**2
    _t25 = 2*design_0
    _t26 = design_0**2 + _t0 + design_2**2 + q_5**2 + design_1**2
    _t27 = _t25*_t5 + _t26
    _t28 = -_t25*_t9 + _t26
    _t29 = (-_t13*_t28 + _t23*_t27)**2 + (-_t17*_t27 + _t20*_t28)**2
    _t30 = ca.tan((1/2)*q_2)
    _t31 = _t30**2
    _t32 = 2*_t10
    _t33 = 2*_t11
    _t34 = 2*_t12
    _t35 = 4*_t14
    _t36 = -_t32
    _t37 = 2*_t22
    _t38 = 2*_t21
    _t39 = -_t10
    _t40 = 2*_t14
    eq8 = ca.reshape(ca.vertcat(_t0 + (_t1*q_5 + _t3 - _t4)**2 + (-design_0 - _t5 - _t6 + _t7)**2, _t0 + (_t1*q_5 - _t3 - _t8)**2 + (design_0 - _t6 - _t7 - _t9)**2), 2, 1)
    eq11 = ca.reshape(ca.vertcat(-4*_t24 + _t29), 1, 1)
    eq11_printed = ca.reshape(ca.vertcat(-_t24 + _t29), 1, 1)
    eq9 = ca.reshape(ca.vertcat(_t27 + _t30*(4*_t18 - 4*_t19 + _t35) + _t31*(_t27 + _t32 + _t33 + _t34) - _t33 - _t34 + _t36, _t28 + _t30*(4*_t15 + 4*_t16 - _t35) + _t31*(_t28 + _t32 - _t37 + _t38) + _t36 + _t37 - _t38), 2, 1)
    eq9_printed = ca.reshape(ca.vertcat(_t13 + _t27 + _t30*(2*_t18 - 2*_t19 + _t40) + _t31*(-_t11 - _t12 + _t27 + _t39), _t23 + _t28 + _t30*(2*_t15 + 2*_t16 - _t40) + _t31*(-_t21 + _t22 + _t28 + _t39)), 2, 1)
    return ca.Function("paper_forward", [q, design], [eq8, eq11, eq11_printed, eq9, eq9_printed], ["q", "design"], ["eq8", "eq11", "eq11_printed", "eq9", "eq9_printed"])


def paper_first_order():
    """The paper's J_q and J_x (eqs. 16-20) and the type-2 condition of eqs. 24-25.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        J_q (2x2, column-major): eq. 19 [m^2]
        J_x (2x2, column-major): eq. 20 [m]
        det_J_x (1x1, column-major): -2 l_c det J_x [m^3]
        eq24 (1x1, column-major): eq. 24 as printed [m^3]
        eq25 (3x1, column-major): X1 Y2 - X2 Y1 [m^2], X_i sin theta - Y_i cos theta [m] (eq. 25)
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 50 common subexpressions, 230 operations
    _t0 = ca.cos(q_0)
    _t1 = ca.sin(q_2)
    _t2 = _t1*design_1
    _t3 = ca.sin(q_0)
    _t4 = _t3*design_2
    _t5 = _t2 - _t4 + x_1
    _t6 = -x_0
    _t7 = _t0*design_2
    _t8 = ca.cos(q_2)
    _t9 = _t8*design_1
    _t10 = design_0 - _t9
    _t11 = _t10 + _t6 + _t7
    _t12 = ca.cos(q_1)
    _t13 = ca.sin(q_1)
    _t14 = _t13*design_2
    _t15 = _t14 + _t2 - x_1
    _t16 = -_t15
    _t17 = _t12*design_2
    _t18 = _t10 - _t17 + x_0
    _t19 = -_t18
    _t20 = _t5*_t8
    _t21 = _t1*_t11 + _t20
    _t22 = _t1*x_0
    _t23 = _t8*x_1
    _t24 = 1/(_t22 - _t23)
    _t25 = _t24*_t9
    _t26 = -design_0 + _t9
    _t27 = _t16*_t8
    _t28 = _t1*_t19 + _t27
    _t29 = _t2*_t24
    _t30 = 2*_t22
    _t31 = -2*_t23 + _t30
    _t32 = x_1**2
    _t33 = design_0*_t23
    _t34 = x_0**2
    _t35 = _t1**2
    _t36 = 2*design_1
    _t37 = _t35*_t36
    _t38 = _t35*design_1*x_0
    _t39 = _t8**2
    _t40 = _t39*design_1*x_1
    _t41 = design_2**2
    _t42 = _t12*_t3
    _t43 = _t0*_t13
    _t44 = _t2*_t8
    _t45 = 2*_t41*_t44
    _t46 = -_t11
    _t47 = _t16*_t46 - _t18*_t5
    _t48 = _t1*_t18 - _t27
    _t49 = _t1*_t46 - _t20
    J_q = ca.reshape(ca.vertcat(design_2*(_t0*_t5 + _t11*_t3), 0, 0, design_2*(_t12*_t16 + _t13*_t19)), 2, 2)
    J_x = ca.reshape(ca.vertcat(_t21*_t25 + _t26 - _t7 + x_0, -_t17 - _t25*_t28 - _t26 - _t6, _t21*_t29 + _t5, -_t15 - _t28*_t29), 2, 2)
    det_J_x = ca.reshape(ca.vertcat(_t24*_t31*(-design_0**2*_t37 + design_0*_t1*_t13*design_2*x_0 + 2*design_0*_t1*_t3*_t8*design_2*design_1 + design_0*_t1*_t3*design_2*x_0 + 2*design_0*_t12*_t35*design_2*design_1 - 2*design_0*_t14*_t44 - design_0*_t30*x_1 + 2*design_0*_t32*_t8 - design_0*_t37*_t7 + _t0*_t1*_t13*_t41*x_0 + _t0*_t1*_t8*design_2*design_1*x_1 + 2*_t0*_t12*_t35*_t41*design_1 + _t0*_t32*_t8*design_2 + _t1*_t12*_t8*design_2*design_1*x_1 + _t1*_t12*design_2*x_0*x_1 + _t1*_t13*_t8*design_2*design_1*x_0 - _t1*_t14*_t34 + _t1*_t3*_t34*design_2 + _t1*_t3*_t8*design_2*design_1*x_0 + _t12*_t3*_t41*_t8*x_1 + 2*_t13*_t3*_t39*_t41*design_1 + _t13*_t8*design_2*x_0*x_1 - _t14*_t33 - _t14*_t40 - _t17*_t32*_t8 - _t17*_t38 - _t22*_t41*_t42 - _t22*_t7*x_1 - _t23*_t4*x_0 - _t23*_t41*_t43 - _t33*_t4 - _t38*_t7 - _t4*_t40 - _t42*_t45 - _t43*_t45)), 1, 1)
    eq24 = ca.reshape(ca.vertcat(_t31*_t47 + _t36*_t48*_t49), 1, 1)
    eq25 = ca.reshape(ca.vertcat(_t47, _t49, _t48), 3, 1)
    return ca.Function("paper_first_order", [q, x, design], [J_q, J_x, det_J_x, eq24, eq25], ["q", "x", "design"], ["J_q", "J_x", "det_J_x", "eq24", "eq25"])


def joint_angles():
    """The section-4 joint angles (>= 0 inside their ranges) and the working mode of a configuration.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        margins (4x1, column-major): sin of angle d1, d2, b1, b2 (section 4) [-]
        signs (2x1, column-major): the signs s1, s2 of eq. 6 of the configuration [-]
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 19 common subexpressions, 58 operations
    _t0 = ca.sin(q_0)
    _t1 = _t0*design_2
    _t2 = ca.sin(q_2)
    _t3 = _t2*design_1
    _t4 = _t3 + x_1
    _t5 = -_t1 + _t4
    _t6 = design_2*ca.cos(q_0)
    _t7 = design_1*ca.cos(q_2)
    _t8 = design_0 - _t7
    _t9 = _t6 + _t8 - x_0
    _t10 = 1/design_3
    _t11 = _t10/design_2
    _t12 = ca.sin(q_1)
    _t13 = _t3 - x_1
    _t14 = _t12*design_2 + _t13
    _t15 = design_2*ca.cos(q_1)
    _t16 = _t8 + x_0
    _t17 = -_t15 + _t16
    _t18 = _t10/design_1
    margins = ca.reshape(ca.vertcat(_t11*(_t1*_t9 + _t5*_t6), _t11*(_t12*_t17*design_2 + _t14*_t15), _t18*(_t2*_t9*design_1 + _t5*_t7), _t18*(-_t14*_t7 - _t17*_t2*design_1)), 4, 1)
    signs = ca.reshape(ca.vertcat(-ca.sign(_t0*design_2*(-design_0 + _t7 + x_0) - _t4*_t6), -ca.sign(_t12*_t16*design_2 + _t13*_t15)), 2, 1)
    return ca.Function("joint_angles", [q, x, design], [margins, signs], ["q", "x", "design"], ["margins", "signs"])


def joint_positions():
    """Positions of the joints B1, d1, b1, C, b2, d2, B2.

    Inputs:
        q (6): [phi1, phi2, theta, psi1, psi2, l_c] phi1, phi2 (actuated), theta, psi1, psi2 [rad], l_c [m]
        x (2): [x_c, y_c] x_c, y_c: centre C of the platform [m]
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        B1 (2x1, column-major): B1 [m]
        d1 (2x1, column-major): d1 [m]
        b1 (2x1, column-major): b1 [m]
        C (2x1, column-major): C [m]
        b2 (2x1, column-major): b2 [m]
        d2 (2x1, column-major): d2 [m]
        B2 (2x1, column-major): B2 [m]
    """
    q = ca.SX.sym("q", 6)
    q_0 = q[0]
    q_1 = q[1]
    q_2 = q[2]
    q_3 = q[3]
    q_4 = q[4]
    q_5 = q[5]
    x = ca.SX.sym("x", 2)
    x_0 = x[0]
    x_1 = x[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 2 common subexpressions, 19 operations
    _t0 = design_1*ca.cos(q_2)
    _t1 = design_1*ca.sin(q_2)
    B1 = ca.reshape(ca.vertcat(design_0, 0), 2, 1)
    d1 = ca.reshape(ca.vertcat(design_0 + design_2*ca.cos(q_0), design_2*ca.sin(q_0)), 2, 1)
    b1 = ca.reshape(ca.vertcat(_t0 + x_0, _t1 + x_1), 2, 1)
    C = ca.reshape(ca.vertcat(x_0, x_1), 2, 1)
    b2 = ca.reshape(ca.vertcat(-_t0 + x_0, -_t1 + x_1), 2, 1)
    d2 = ca.reshape(ca.vertcat(-design_0 + design_2*ca.cos(q_1), design_2*ca.sin(q_1)), 2, 1)
    B2 = ca.reshape(ca.vertcat(-design_0, 0), 2, 1)
    return ca.Function("joint_positions", [q, x, design], [B1, d1, b1, C, b2, d2, B2], ["q", "x", "design"], ["B1", "d1", "b1", "C", "b2", "d2", "B2"])


def workspace_boundary():
    """l_CM, l_cm of eqs. 12-13 as derived and as printed, and the radicands of eqs. 14-15.

    Inputs:
        a (1): [w_theta] theta [rad]: the abscissa of the workspace region
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        l_CM (1x1, column-major): l_CM [m]
        l_cm (1x1, column-major): l_cm [m]
        l_CM_printed (1x1, column-major): l_CM_printed [m]
        l_cm_printed (1x1, column-major): l_cm_printed [m]
        eq14 (1x1, column-major): eq14 [m^2]
        eq15 (1x1, column-major): eq15 [m^2]
    """
    a = ca.SX.sym("a", 1)
    a_0 = a[0]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 13 common subexpressions, 40 operations
    _t0 = ca.sin(a_0)
    _t1 = design_0*ca.fabs(_t0)
    _t2 = (design_2 + design_3)**2
    _t3 = 1e-30*_t2
    _t4 = 2*design_1
    _t5 = design_0*ca.cos(a_0)
    _t6 = design_0**2
    _t7 = _t0**2*_t6 - _t6
    _t8 = _t2 + _t4*_t5 + _t7 - design_1**2
    _t9 = ca.sqrt(ca.fmax(_t3, _t8))
    _t10 = _t5*(_t4 + 2*design_3) + _t7 + design_2**2 - (design_3 + design_1)**2
    _t11 = ca.sqrt(ca.fmax(_t10, _t3))
    _t12 = (1/2)*_t1
    l_CM = ca.reshape(ca.vertcat(-_t1 + _t9), 1, 1)
    l_cm = ca.reshape(ca.vertcat(_t1 + _t11), 1, 1)
    l_CM_printed = ca.reshape(ca.vertcat(-_t12 + (1/2)*_t9), 1, 1)
    l_cm_printed = ca.reshape(ca.vertcat((1/2)*_t11 + _t12), 1, 1)
    eq14 = ca.reshape(ca.vertcat(_t8), 1, 1)
    eq15 = ca.reshape(ca.vertcat(_t10), 1, 1)
    return ca.Function("workspace_boundary", [a, design], [l_CM, l_cm, l_CM_printed, l_cm_printed, eq14, eq15], ["a", "design"], ["l_CM", "l_cm", "l_CM_printed", "l_cm_printed", "eq14", "eq15"])


def workspace_range_negative():
    """The workspace's theta range below 0 (the boundaries have a kink at theta = 0).

    Inputs:
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        lo (1x1, column-major): -theta_hi [rad]
        hi (1x1, column-major): 0 [rad]
    """
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 0 common subexpressions, 13 operations
    lo = ca.reshape(ca.vertcat(-ca.acos(ca.fmax(ca.cos(design_4), (1/2)*(design_0**2 + design_1**2 - (design_2 + design_3)**2)/(design_0*design_1)))), 1, 1)
    hi = ca.reshape(ca.vertcat(0), 1, 1)
    return ca.Function("workspace_range_negative", [design], [lo, hi], ["design"], ["lo", "hi"])


def workspace_range_positive():
    """The workspace's theta range above 0.

    Inputs:
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        lo (1x1, column-major): 0 [rad]
        hi (1x1, column-major): theta_hi [rad]: theta_max, or less where l_CM <= 0
    """
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 0 common subexpressions, 12 operations
    lo = ca.reshape(ca.vertcat(0), 1, 1)
    hi = ca.reshape(ca.vertcat(ca.acos(ca.fmax(ca.cos(design_4), (1/2)*(design_0**2 + design_1**2 - (design_2 + design_3)**2)/(design_0*design_1)))), 1, 1)
    return ca.Function("workspace_range_positive", [design], [lo, hi], ["design"], ["lo", "hi"])


def workspace_curves():
    """The workspace at one theta: l_c from the inner to the outer boundary.

    Inputs:
        a (1): [w_theta] theta [rad]: the abscissa of the workspace region
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        lower (1x1, column-major): inner boundary l_c [m]
        upper (1x1, column-major): outer boundary l_CM [m]
    """
    a = ca.SX.sym("a", 1)
    a_0 = a[0]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 10 common subexpressions, 40 operations
    _t0 = 0.001*design_2 + 0.001*design_3
    _t1 = ca.sin(a_0)
    _t2 = design_0*ca.fabs(_t1)
    _t3 = (design_2 + design_3)**2
    _t4 = 1e-30*_t3
    _t5 = 2*design_1
    _t6 = design_0*ca.cos(a_0)
    _t7 = design_0**2
    _t8 = _t1**2*_t7 - _t7
    _t9 = _t6*(_t5 + 2*design_3) + _t8 + design_2**2 - (design_3 + design_1)**2
    lower = ca.reshape(ca.vertcat(ca.if_else((_t9 > 0), ca.fmax(_t0, _t2 + ca.sqrt(ca.fmax(_t4, _t9))), _t0)), 1, 1)
    upper = ca.reshape(ca.vertcat(-_t2 + ca.sqrt(ca.fmax(_t4, _t3 + _t5*_t6 + _t8 - design_1**2))), 1, 1)
    return ca.Function("workspace_curves", [a, design], [lower, upper], ["a", "design"], ["lower", "upper"])


def polar_to_pose():
    """The pose of a platform angle and passive-leg length (eq. 7).

    Inputs:
        y (2): [w_theta, w_lc] theta [rad], l_c [m]: the platform's angle and the passive leg's length
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        x (2x1, column-major): x_c, y_c [m] (eq. 7)
    """
    y = ca.SX.sym("y", 2)
    y_0 = y[0]
    y_1 = y[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 0 common subexpressions, 5 operations
    x = ca.reshape(ca.vertcat(-y_1*ca.sin(y_0), y_1*ca.cos(y_0)), 2, 1)
    return ca.Function("polar_to_pose", [y, design], [x], ["y", "design"], ["x"])


def polar_area():
    """The area element of eq. 7's map.

    Inputs:
        y (2): [w_theta, w_lc] theta [rad], l_c [m]: the platform's angle and the passive leg's length
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        element (1x1, column-major): dx_c dy_c / (dtheta dl_c) = l_c [m]
    """
    y = ca.SX.sym("y", 2)
    y_0 = y[0]
    y_1 = y[1]
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 0 common subexpressions, 0 operations
    element = ca.reshape(ca.vertcat(y_1), 1, 1)
    return ca.Function("polar_area", [y, design], [element], ["y", "design"], ["element"])


def footprint():
    """The mechanism's size with both legs stretched (eq. 30).

    Inputs:
        design (5): [R, r, l_a, l_b, theta_max] R, r, l_a, l_b [m]; theta_max [rad]
    Outputs:
        S (1x1, column-major): S of eq. 30 [m^2]
    """
    design = ca.SX.sym("design", 5)
    design_0 = design[0]
    design_1 = design[1]
    design_2 = design[2]
    design_3 = design[3]
    design_4 = design[4]
    # 0 common subexpressions, 9 operations
    S = ca.reshape(ca.vertcat((design_0 + design_1)*ca.sqrt(-(design_0 - design_1)**2 + (design_2 + design_3)**2)), 1, 1)
    return ca.Function("footprint", [design], [S], ["design"], ["S"])


def build():
    """All functions of this module by name."""
    return {name: globals()[name]() for name in FUNCTIONS}
