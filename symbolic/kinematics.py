"""The kinematic port convention of every mechanism, written by one helper.

pkm's runtime reads the same four functions from every generated module, with the same ports in the
same order:

* ``inverse_kinematics(x, mode, design) -> (q, reach)``: all joints, actuated first, on the working
  mode's branch; reach >= 0 where the pose is reachable;
* ``forward_kinematics(q_a, assembly, design) -> (x, q, reach)``: only where a closed form exists;
  reach >= 0 where the chains close;
* ``constraint(q, x, design) -> (h, H_q, H_x)``: the loop closure h(q, x) = 0 and its Jacobians;
* ``first_order(q, x, design) -> (J, J_f, psi, det_type1, det_type2)``: q_a_dot = J x_dot,
  x_dot = J_f q_a_dot, q_dot = Psi q_a_dot and the singularity measures (:mod:`symbolic.loops`);
* ``first_order_from_pose(x, mode, design) -> (q, reach, J, J_f, psi, det_type1, det_type2)``: only where
  the inverse kinematics gives the cosine and sine of every joint angle without trigonometric calls
  (``InverseKinematics.directions``); the outputs of ``inverse_kinematics`` and ``first_order`` at
  q = IK(x), with the first order free of trigonometric calls, so that a caller that does not read q
  evaluates none;

and the names of the design parameters, pose coordinates and actuated joints, which the runtime
checks against its own so that a design vector means the same on both sides. A mechanism supplies the
maths (:class:`LoopClosure`, :class:`InverseKinematics`, optionally :class:`ForwardKinematics`) and
its ports; :func:`add_kinematics` emits the rest.

Any other function of the joints, such as a mechanism's ``inertia(q, x, design)`` or
``inverse_dynamics(q, x, x_dot, x_ddot, design)``, gets the same twin from the pose with
:func:`add_from_pose`: ``<name>_from_pose`` takes (x, mode, ...) in place of (q, x, ...) and returns
(q, reach, outputs...) with the joints replaced as in ``first_order_from_pose``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.loops import LoopClosure


@dataclass(frozen=True)
class InverseKinematics:
    """A closed-form inverse kinematics on the branch chosen by the signs of the ``mode`` port.

    Attributes
    ----------
    q : sympy.Matrix, shape (n_a + n_p, 1)
        All joints, actuated first, in the pose, mode and design symbols.
    reach : sympy.Matrix, shape (k, 1)
        Margins, all >= 0 where the pose is reachable on the branch.
    doc : str
        Docstring of the emitted function.
    q_doc, reach_doc : str
        Meaning and units of the outputs ``q`` and ``reach``.
    directions : dict, optional
        ``cos(q_k)`` and ``sin(q_k)`` of the joint angles, equal to the cosine and sine of ``q``, as
        rational functions of the design symbols and the symbols of ``vectors`` (the components of the
        links' position vectors); with them :func:`add_kinematics` emits ``first_order_from_pose``.
    vectors : dict, optional
        The symbols of ``directions`` as algebraic expressions of the pose, mode and design symbols
        (square roots where the geometry gives them: no trigonometric call).
    """

    q: sp.Matrix
    reach: sp.Matrix
    doc: str
    q_doc: str
    reach_doc: str
    directions: dict[sp.Expr, sp.Expr] | None = None
    vectors: dict[sp.Symbol, sp.Expr] | None = None


@dataclass(frozen=True)
class ForwardKinematics:
    """A closed-form forward kinematics on the branch chosen by the signs of the ``assembly`` port.

    Attributes
    ----------
    x : sympy.Matrix, shape (n_x, 1)
        The pose, in the actuated joint, assembly and design symbols.
    q : sympy.Matrix, shape (n_a + n_p, 1)
        All joints, actuated first.
    reach : sympy.Matrix, shape (k, 1)
        Margins, all >= 0 where the chains close.
    doc : str
        Docstring of the emitted function.
    x_doc, q_doc, reach_doc : str
        Meaning and units of the outputs ``x``, ``q`` and ``reach``.
    """

    x: sp.Matrix
    q: sp.Matrix
    reach: sp.Matrix
    doc: str
    x_doc: str
    q_doc: str
    reach_doc: str


FIRST_ORDER_UNITS = ("h", "H_q", "H_x", "J", "J_f", "psi", "det")


def add_kinematics(
    spec: ModuleSpec,
    loop: LoopClosure,
    *,
    pose: Port,
    joints: Port,
    actuated: Port,
    design: Port,
    mode: Port,
    inverse: InverseKinematics,
    forward: ForwardKinematics | None = None,
    assembly: Port | None = None,
    units: dict[str, str],
    composed: bool = False,
    inverse_name: str = "inverse_kinematics",
) -> None:
    """Emit the kinematic functions of the port convention (module docstring) and record the names.

    Parameters
    ----------
    spec : ModuleSpec
        The module to add to; its ``parameters``, ``pose`` and ``actuators`` are set to the names of
        the symbols of ``design``, ``pose`` and ``actuated``.
    loop : LoopClosure
        The loop closure h(q_a, q_p, x) = 0 in the symbols of ``actuated``, ``joints`` and ``pose``.
    pose, joints, actuated, design : Port
        The ports ``x`` (n_x), ``q`` (n_a + n_p, actuated first), ``q_a`` (n_a) and ``design``.
    mode : Port
        The working-mode signs read by ``inverse``.
    inverse : InverseKinematics
        The closed-form inverse kinematics.
    forward : ForwardKinematics, optional
        The closed-form forward kinematics, with the ``assembly`` port of its branch signs; without it
        no ``forward_kinematics`` is emitted.
    units : dict
        Bracketed units of the outputs of ``constraint`` and ``first_order`` by name: ``h``, ``H_q``,
        ``H_x``, ``J``, ``J_f``, ``psi`` and ``det`` (both determinants).
    composed : bool
        Emit no ``first_order``: the runtime composes it from ``constraint`` in CasADi
        (:func:`pkm.spec.composed_first_order`), for machines whose solves sympy should not expand.
    inverse_name : str
        The name ``inverse`` is emitted under: another than ``inverse_kinematics`` where it is not the whole
        inverse kinematics (the runtime composes that from it, as :mod:`pkm.spec` does for legs solved by
        continuation).

    Raises
    ------
    ValueError
        If the ports do not match the loop's coordinates, the joint counts differ, ``forward`` and
        ``assembly`` are not given together, a unit is missing, or the directions of ``inverse`` are
        given for something other than the cosine or sine of a joint, or leave a joint angle in the first
        order.
    """
    _check_ports(loop, pose=pose, joints=joints, actuated=actuated)
    if (forward is None) != (assembly is None):
        raise ValueError(f"{spec.name}: forward kinematics and the assembly port go together")
    missing = [k for k in FIRST_ORDER_UNITS if k not in units]
    if missing:
        raise ValueError(f"{spec.name}: no units for {missing}")
    n_q = len(joints.symbols)
    solutions = [("inverse", inverse.q)] + ([("forward", forward.q)] if forward is not None else [])
    for kind, q in solutions:
        if q.shape != (n_q, 1):
            raise ValueError(f"{spec.name}: {kind} kinematics gives q of shape {q.shape}, not ({n_q}, 1)")

    spec.parameters = tuple(s.name for s in design.symbols)
    spec.pose = tuple(s.name for s in pose.symbols)
    spec.actuators = tuple(s.name for s in actuated.symbols)
    spec.add(
        inverse_name,
        (pose, mode, design),
        (Output("q", inverse.q, inverse.q_doc), Output("reach", inverse.reach, inverse.reach_doc)),
        inverse.doc,
    )
    if forward is not None:
        spec.add(
            "forward_kinematics",
            (actuated, assembly, design),
            (
                Output("x", forward.x, forward.x_doc),
                Output("q", forward.q, forward.q_doc),
                Output("reach", forward.reach, forward.reach_doc),
            ),
            forward.doc,
        )
    spec.add(
        "constraint",
        (joints, pose, design),
        (
            Output("h", loop.h, f"loop-closure residuals [{units['h']}]"),
            Output("H_q", loop.H_a.row_join(loop.H_p), f"dh/dq, actuated then passive [{units['H_q']}]"),
            Output("H_x", loop.H_x, f"dh/dx [{units['H_x']}]"),
        ),
        "Loop-closure residuals and their Jacobians.",
    )
    if composed:
        return
    first_order = (
        Output("J", loop.jacobian(), f"q_a_dot = J x_dot [{units['J']}]"),
        Output("J_f", loop.forward_jacobian(), f"x_dot = J_f q_a_dot [{units['J_f']}]"),
        Output("psi", loop.psi(), f"q_dot = Psi q_a_dot, all joints from actuated [{units['psi']}]"),
        Output("det_type1", sp.Matrix([loop.det_type1()]), f"serial singularity measure [{units['det']}]"),
        Output("det_type2", sp.Matrix([loop.det_type2()]), f"parallel singularity measure [{units['det']}]"),
    )
    spec.add("first_order", (joints, pose, design), first_order,
             "First-order kinematics by implicit differentiation of the loop closure.")
    if inverse.directions is not None:
        add_from_pose(spec, "first_order", inverse=inverse, joints=joints, pose=pose, mode=mode)


def add_from_pose(
    spec: ModuleSpec, name: str, *, inverse: InverseKinematics, joints: Port, pose: Port, mode: Port
) -> None:
    """Emit ``<name>_from_pose``: the function ``name`` of ``spec`` at q = IK(x), from the pose.

    ``name`` takes the joints q among its inputs; its twin takes the pose and the working mode in their
    place, ``(x, mode, *others)`` with ``others`` the remaining inputs in their order, and returns
    ``(q, reach, *outputs)``: the inverse kinematics' outputs, then each output of ``name`` with

        cos(q_k), sin(q_k) -> directions[cos(q_k)], directions[sin(q_k)]   (the joint angles),
        q_j -> IK(x)_j                                                      (the other joints),

    after the trigonometric functions of sums of joint angles are expanded (cos(a - b) = cos a cos b +
    sin a sin b), each entry brought over one denominator in the links' vector components (CasADi
    evaluates every product with a reciprocal as a division: a sum of fractions would cost a division
    per term), and then the components replaced by ``inverse.vectors``: the same values as ``name`` at
    q = IK(x), to round-off, with no trigonometric call.

    Parameters
    ----------
    spec : ModuleSpec
        The module that already holds ``name``.
    name : str
        The function of the joints to derive from the pose.
    inverse : InverseKinematics
        The closed-form inverse kinematics, with ``directions`` and ``vectors``.
    joints, pose, mode : Port
        The ports ``q`` (n_a + n_p), ``x`` (n_x) and ``mode`` of :func:`add_kinematics`.

    Raises
    ------
    ValueError
        If ``spec`` has no function ``name``, it does not take ``joints`` and ``pose``, ``inverse`` has no
        directions or has them for something other than the cosine or sine of a joint, or a joint angle is
        left in an output (:meth:`ModuleSpec.add` names it).
    """
    found = [f for f in spec.functions if f.name == name]
    if not found:
        raise ValueError(f"{spec.name}: no function {name} to derive from the pose")
    fn = found[0]
    if joints not in fn.inputs or pose not in fn.inputs:
        raise ValueError(f"{spec.name}.{name}: takes no {joints.name} and {pose.name} to replace by the pose")
    if inverse.directions is None:
        raise ValueError(f"{spec.name}.{name}: the inverse kinematics gives no directions of the joint angles")
    angles = {f(s) for s in joints.symbols for f in (sp.cos, sp.sin)}
    stray = sorted(set(inverse.directions) - angles, key=sp.default_sort_key)
    if stray:
        raise ValueError(f"{spec.name}: directions are given for {stray}, not the cosine or sine of a joint")
    others = [p for p in fn.inputs if p not in (joints, pose)]
    spec.add(
        f"{name}_from_pose",
        (pose, mode, *others),
        (
            Output("q", inverse.q, inverse.q_doc),
            Output("reach", inverse.reach, inverse.reach_doc),
            *(Output(o.name, _from_vectors(o.expr, inverse, joints), o.doc) for o in fn.outputs),
        ),
        f"inverse_kinematics and {name} at its q, {name} with the cosine and sine of each joint angle from the "
        f"position vectors of the links (no trigonometric call). {name}: {fn.doc}",
    )


def _from_vectors(expr: sp.Matrix, inverse: InverseKinematics, joints: Port) -> sp.Matrix:
    """``expr`` from the pose (:func:`add_from_pose`): trigonometric functions of the joints expanded, the
    angles' cosines and sines replaced by ``inverse.directions`` and the other joints by their inverse
    kinematics, each entry over one denominator, the vector components replaced by ``inverse.vectors``;
    a component that is a product is kept whole, for sympy would distribute a power over its factors
    ((sigma sqrt(m))^3 = sigma^3 m^(3/2), a call of pow)."""
    angles = {s for s in joints.symbols if sp.cos(s) in inverse.directions}
    others = {s: inverse.q[k] for k, s in enumerate(joints.symbols) if s not in angles}
    vectors = {s: sp.UnevaluatedExpr(v) if v.is_Mul else v for s, v in (inverse.vectors or {}).items()}
    return expr.applyfunc(lambda e: sp.together(sp.expand_trig(e).xreplace(inverse.directions))
                          .xreplace(others).xreplace(vectors))


def _check_ports(loop: LoopClosure, *, pose: Port, joints: Port, actuated: Port) -> None:
    """The ports must carry the loop's coordinates in its order: q = (q_a, q_p), q_a, x."""
    expected = (
        ("joints", joints, (*loop.q_a, *loop.q_p)),
        ("actuated", actuated, loop.q_a),
        ("pose", pose, loop.x),
    )
    for role, port, wanted in expected:
        if tuple(port.symbols) != tuple(wanted):
            raise ValueError(f"the {role} port {port.name} carries {list(port.symbols)}, the loop {list(wanted)}")
