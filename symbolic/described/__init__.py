"""A machine described as data, derived: ``python -m symbolic.described DESCRIPTION.json MODULE.py``.

The description is the normalised form that :mod:`pkm.spec` writes (legs with their attachment points as
expressions of the design parameters, patterns already expanded). Each leg is one of the kinds below; its
closure rows, its joints, its inverse kinematics in closed form (the leg's known subproblem) and its
reach margins are derived in sympy, and the module gets the port convention's ``inverse_kinematics(x,
mode, design) -> (q, reach)`` and ``constraint(q, x, design) -> (h, H_q, H_x)`` (through
:func:`symbolic.kinematics.add_kinematics`, ``composed``: the runtime composes the first order from the
constraint in CasADi, so that a 6 x 6 solve is never expanded in sympy), ``home(design) -> x``, and where
given ``characteristic_length(design) -> L``.

Pose (``pose.frame``): ``planar_point`` (x, y), ``planar`` (x, y, phi), ``spatial_point`` (x, y, z) or
``spatial`` (x, y, z, roll, pitch, yaw) with R = Rz(yaw) Ry(pitch) Rx(roll). A platform attachment c
(in the platform frame) is at P + R c in the base frame.

Legs (A the base attachment, C the platform attachment in the base frame, sigma the leg's branch sign):

* ``RR``, planar: an actuated revolute at A (absolute angle theta of the first link, length ``proximal``)
  and a passive revolute (absolute angle phi of the second link, length ``distal``) ending at C:
  h = A + l1 e(theta) + l2 e(phi) - C. With d = C - A, theta = atan2(d) + sigma acos((l1^2 + |d|^2 -
  l2^2) / (2 l1 |d|)) and phi = atan2(C - B), B the elbow (two circles); reach: |d| within [|l1 - l2|,
  l1 + l2].
* ``RPR``, planar: a passive revolute at A, an actuated prismatic joint of length rho along it and a passive
  revolute at C: h = A + rho e(phi) - C, rho = |C - A|, phi = atan2(C - A), one branch.
* ``PRR``, planar: an actuated prismatic joint s along ``axis`` from A, then a link of length ``distal`` at
  the angle phi to C: h = A + s u + l e(phi) - C; the line meets the circle of radius l about C at s = (C -
  A).u + sigma sqrt(l^2 - ((C - A) x u)^2); reach: l^2 - ((C - A) x u)^2.
* ``R_parallelogram``, spatial: an actuated revolute at A about ``axis`` turning an arm of length ``arm``
  from the direction ``zero`` (theta = 0) towards ``axis`` x ``zero``, and a parallelogram of length
  ``rod`` from its tip E to C: h = |C - E|^2 - rod^2. With D = C - A, P = D.u, Q = D.w (u = zero, w =
  axis x zero) and K = (|D|^2 + arm^2 - rod^2) / (2 arm), theta = atan2(Q, P) + sigma acos(K / sqrt(P^2 +
  Q^2)); reach: P^2 + Q^2 - K^2.
* ``UPS``, spatial: an actuated prismatic joint of length l between A and C (universal and spherical joints
  at its ends): h = |C - A|^2 - l^2, l = |C - A|, one branch; with ``cone``, the leg's angle from the base's
  normal and from the platform's at most cone: (C - A).n - cos(cone) |C - A| >= 0 for both normals (two
  stated limits beside its reach).

* ``chain``, planar or spatial: R, P, U and parallelogram joints from A, each with its axes and its link in
  the frame of the body before it (the leg's frame the base's turned about z by ``turn``), ending at C in
  the platform's point joint: h = A + (the chain's end) - C, as many joint variables as h has rows. Its
  inverse kinematics is a closed form where its two joints are a known subproblem (:func:`_closed_chain`),
  else only the start of the runtime's Newton continuation (``continuation_start``, the branch's seed):
  :func:`pkm.spec.composed_inverse_kinematics` solves it from ``chain<k>(q_leg, c, design) -> (h, H)`` and
  ``chain<k>_ends(x, design) -> (a, c)``. Its side is the sign of det H.

A leg's ``range`` (lower, upper) bounds its actuated joint (a stroke, an arm's sweep): two more margins of
``workspace_margins``, not of the reach (the runtime states them as limits: :func:`pkm.kinematics.within_limits`).
With bodies, ``mass_matrix(q, x, design) -> M`` (T = z_dot^T M z_dot / 2 in z = (q, x)) and, with
``gravity``, ``gravity(q, x, design) -> (G, V)`` (dV/dz and V). ``skeleton(q, x, design)`` gives the joints'
points leg by leg (base, the leg's joints between, platform). ``branch_sides(q, x, design)`` has a sign per leg
with passive joints and two branches (RR: the elbow's side, sin(phi - theta); PRR: -e(phi).u) that names them
in the assembly modes. ``workspace_margins(q, x, design)`` gives every leg's margins at a configuration (the
ranges' in the actuated joints), ``region_<name>(design) -> (centre, size)`` places each region, and
``region_<name>_pose(y, design) -> x`` maps a region's coordinates into the pose where it spans fewer or
others.
"""

