"""The contract every registered mechanism passes (STYLE practice 8): a new mechanism gets it for free.

Only generic means are used: designs drawn near the defaults, poses drawn in ``workspace_box`` and kept
where ``reachable``, and the generated ``constraint`` function. As in sympy.physics.mechanics' four-bar
test, the loop-closure residual is checked before anything computed from the joints is compared.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from functools import cache
from types import SimpleNamespace

import casadi as ca
import numpy as np
import pytest
from helpers import port_inputs, random_design, reachable_poses

import pkm
from pkm import registry
from pkm.batch import evaluate, reached
from pkm.compiled.emit import GROUP_SHARED
from pkm.kinematics import from_pose

MECHANISMS = pkm.mechanisms()
SEEDS = (0, 1, 2)
SPREAD = 0.2  # designs within +-20 % of the defaults
N_POSES = 24
STEP = 1e-6  # central-difference step [pose units]
MIN_INVERSE_CONDITION = 0.05
MIN_DET_FRACTION = 0.05  # of the median |det|, so that the threshold carries the mechanism's units


@dataclass(frozen=True)
class Case:
    mech: pkm.Mechanism
    design: pkm.Design
    poses: dict[str, np.ndarray]

    @property
    def vector(self) -> np.ndarray:
        return self.design.vector()


@cache
def _case(name: str, seed: int) -> Case:
    m = pkm.load(name)
    rng = np.random.default_rng(seed)
    design = random_design(m, rng, spread=SPREAD)
    return Case(m, design, {mode: reachable_poses(m, design, mode, rng, count=N_POSES) for mode in m.modes})


@pytest.fixture(scope="module", params=[(n, s) for n in MECHANISMS for s in SEEDS], ids=lambda p: f"{p[0]}-{p[1]}")
def case(request) -> Case:
    return _case(*request.param)


@pytest.fixture(scope="module", params=MECHANISMS, ids=lambda name: f"{name}-{SEEDS[0]}")
def first_case(request) -> Case:
    """The case of the first seed alone, for a property of the evaluation path that the design and the poses
    (all that the seed changes) cannot reach: the same functions, chunks and threads run at every seed."""
    return _case(request.param, SEEDS[0])


def closed_joints(case: Case, mode: str, x: np.ndarray | None = None) -> np.ndarray:
    """All joints at the poses by inverse kinematics, after asserting that the loops close there."""
    x = case.poses[mode] if x is None else x
    q = case.mech.inverse_kinematics(x, case.design, mode=mode, passive=True)
    assert np.all(np.isfinite(q))
    (h, *_) = evaluate(case.mech.functions["constraint"], q, x, case.vector)
    scale = max(1.0, float(np.abs(case.vector).max()))
    np.testing.assert_allclose(h, 0.0, atol=1e-12 * scale, err_msg=f"loop residual, mode {mode}")
    return q


def regular(case: Case, mode: str) -> np.ndarray:
    """The sampled poses away from type I and type II singularities."""
    m, x = case.mech, case.poses[mode]
    keep = m.local_index("inverse_condition_f", x, case.design, mode=mode) > MIN_INVERSE_CONDITION
    for det in m.singularity(x, case.design, mode=mode).values():
        keep &= np.abs(det) > MIN_DET_FRACTION * np.median(np.abs(det))
    assert keep.sum() >= N_POSES // 3, f"mode {mode}: too few regular poses"
    return x[keep]


def test_loop_closes_at_inverse_kinematics(case):
    for mode in case.mech.modes:
        closed_joints(case, mode)


def _angle_difference(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.mod(a - b + np.pi, 2 * np.pi) - np.pi


def test_forward_kinematics_returns_the_pose_in_some_assembly(case):
    """FK(IK(x)) = x in some assembly mode, whose passive joints are IK's. The poses of every working mode go in
    one batch (FK solves each row alone): a call per assembly mode (32 for the 3-RRR), not per working mode
    and assembly mode (8 x 32)."""
    m = case.mech
    x = np.concatenate(list(case.poses.values()))
    q = np.concatenate([closed_joints(case, mode) for mode in case.poses])
    mode_of = np.repeat(list(case.poses), [len(v) for v in case.poses.values()])
    q_a = q[:, : m.n_act]
    errors = np.stack([np.linalg.norm(m.forward_kinematics(q_a, case.design, assembly=a) - x, axis=1)
                       for a in m.assemblies])
    errors = np.where(np.isnan(errors), np.inf, errors)
    best = errors.min(axis=0)
    worst = int(best.argmax())
    assert best[worst] < 1e-9, f"mode {mode_of[worst]}: FK(IK(x)) misses x by {best[worst]:.3g}"
    # and all joints: in the assembly mode that gives back x, FK's passive joints are IK's
    closest = errors.argmin(axis=0)
    q_fk = np.full_like(q, np.nan)
    for k in np.unique(closest):
        joints = m.forward_kinematics(q_a, case.design, assembly=m.assemblies[k], passive=True)
        assert joints.shape == q.shape
        q_fk[closest == k] = joints[closest == k]
    for mode in case.poses:
        rows = mode_of == mode
        np.testing.assert_array_equal(q_fk[rows, : m.n_act], q[rows, : m.n_act], err_msg=f"mode {mode}")
        np.testing.assert_allclose(_angle_difference(q_fk[rows], q[rows]), 0.0, atol=1e-9, err_msg=f"mode {mode}")


def test_jacobian_matches_central_differences_of_inverse_kinematics(case):
    m = case.mech
    for mode in m.modes:
        x = regular(case, mode)
        closed_joints(case, mode, x)
        J = m.jacobian(x, case.design, mode=mode)
        columns = []
        for e in np.eye(m.n_out):
            plus = m.inverse_kinematics(x + STEP * e, case.design, mode=mode)
            minus = m.inverse_kinematics(x - STEP * e, case.design, mode=mode)
            columns.append((np.mod(plus - minus + np.pi, 2 * np.pi) - np.pi) / (2 * STEP))
        fd = np.stack(columns, axis=2)
        scale = np.abs(J).max(axis=(1, 2), keepdims=True)
        assert np.all(np.abs(fd - J) <= 1e-6 * scale), f"mode {mode}: J differs from finite differences"


def test_jacobian_inverts_forward_jacobian(case):
    m = case.mech
    for mode in m.modes:
        x = regular(case, mode)
        closed_joints(case, mode, x)
        J = m.jacobian(x, case.design, mode=mode)
        J_f = m.forward_jacobian(x, case.design, mode=mode)
        np.testing.assert_allclose(J @ J_f, np.broadcast_to(np.eye(m.n_act), (len(x), m.n_act, m.n_act)), atol=1e-9)
        np.testing.assert_allclose(J_f @ J, np.broadcast_to(np.eye(m.n_out), (len(x), m.n_out, m.n_out)), atol=1e-9)


def test_first_order_from_the_pose_equals_inverse_kinematics_then_first_order(case):
    """Where a mechanism derives its first order from the pose (no trigonometric call), every output
    equals the inverse kinematics composed with ``first_order`` (the derivation through the joint
    angles) to 1e-12 of its largest entry at regular poses of every working mode, 1/kappa_f included, with
    the same reach margins; out of reach, local indices are NaN exactly where the composition's joints
    are."""
    m, d = case.mech, case.vector
    if "first_order_from_pose" not in m.functions:
        pytest.skip(f"{m.name} has no first_order_from_pose")
    anywhere = _anywhere(case)
    for mode in m.modes:
        signs = np.array(m.working_mode(mode).signs)
        for x, regular_only in ((regular(case, mode), True), (anywhere, False)):
            q, reach = evaluate(m.functions["inverse_kinematics"], x, signs, d)
            want = dict(zip(m.functions["first_order"].name_out(),
                            evaluate(m.functions["first_order"], q[:, :, 0], x, d), strict=True))
            want.update(q=q, reach=reach)
            got = dict(zip(m.functions["first_order_from_pose"].name_out(),
                           evaluate(m.functions["first_order_from_pose"], x, signs, d), strict=True))
            assert got.keys() == want.keys()
            ok = reached(q, reach)
            np.testing.assert_array_equal(reached(got["q"], got["reach"]), ok, err_msg=f"mode {mode}")
            value = m.local_index("inverse_condition_f", x, case.design, mode=mode)
            np.testing.assert_array_equal(np.isnan(value), ~ok, err_msg=f"mode {mode}: NaN of 1/kappa_f")
            if not regular_only:
                assert 0 < ok.sum() < len(x), f"mode {mode}: the poses anywhere are all in or all out of reach"
                continue
            n = m.n_act
            want["1/kappa_f"] = n / np.sqrt(np.sum(want["J"] ** 2, axis=(1, 2)) * np.sum(want["J_f"] ** 2, axis=(1, 2)))
            got["1/kappa_f"] = value
            for key, expected in want.items():
                error = _relative_errors(got[key], expected)
                assert np.all(error <= 1e-12), f"mode {mode}: {key}: {error.max():.1e}"


def _anywhere(case: Case) -> np.ndarray:
    """400 poses (400, n_out) in the workspace box widened by a quarter of its span on every side: some in
    reach of each working mode, some out."""
    box = case.mech.workspace_box(case.vector)
    span = box[:, 1] - box[:, 0]
    return np.random.default_rng(5).uniform(box[:, 0] - span / 4, box[:, 1] + span / 4, size=(400, case.mech.n_out))


def _relative_errors(got: np.ndarray, want: np.ndarray) -> np.ndarray:
    """Per row (N,): the largest difference of the entries relative to the largest |entry| of ``want``."""
    a, b = want.reshape(len(want), -1), got.reshape(len(got), -1)
    return np.max(np.abs(b - a), axis=1) / np.abs(a).max(axis=1)


def test_every_function_from_the_pose_equals_inverse_kinematics_then_the_function(case):
    """Every twin ``f_from_pose(x, mode, ...)`` of a function ``f(q, x, ...)`` (the cosines and sines of
    the joint angles from the links' position vectors, symbolic.kinematics.add_from_pose) returns the
    inverse kinematics' q and reach and every output of ``f`` at q = IK(x), within 1e-12 of its largest
    entry at regular poses of every working mode; the other inputs (velocities, accelerations) random."""
    m, d = case.mech, case.vector
    twins = [name for name in m.functions if from_pose(name) in m.functions]
    if not twins:
        pytest.skip(f"{m.name} derives no function from the pose")
    rng = np.random.default_rng(6)
    for mode in m.modes:
        signs = np.array(m.working_mode(mode).signs)
        x = regular(case, mode)
        q, reach = evaluate(m.functions["inverse_kinematics"], x, signs, d)
        inputs = {"x": x, "q": q[:, :, 0], "mode": signs, "design": d}
        for name in twins:
            fn, twin = m.functions[name], m.functions[from_pose(name)]
            for i, port in enumerate(fn.name_in()):
                inputs.setdefault(port, rng.normal(size=(len(x), fn.numel_in(i))))
            want = dict(zip(fn.name_out(), evaluate(fn, *(inputs[p] for p in fn.name_in())), strict=True))
            want.update(q=q, reach=reach)
            got = dict(zip(twin.name_out(), evaluate(twin, *(inputs[p] for p in twin.name_in())), strict=True))
            assert got.keys() == want.keys(), name
            for key, expected in want.items():
                error = _relative_errors(got[key], expected)
                assert np.all(error <= 1e-12), f"mode {mode}: {from_pose(name)}: {key}: {error.max():.1e}"


def test_inverse_dynamics_of_a_virtual_work_model_is_inverse_kinematics_then_the_model(case):
    """``Mechanism.inverse_dynamics`` of a model that generates ``inverse_dynamics(q, x, x_dot, x_ddot,
    design)`` (one fused pass, from the pose where the model has the twin) equals the inverse kinematics
    composed with it: NaN in exactly the rows whose pose is out of reach, and within 1e-12 of each row's
    largest force at regular poses."""
    m, d = case.mech, case.vector
    if "inverse_dynamics" not in m.functions:
        pytest.skip(f"{m.name} has no virtual-work inverse dynamics")
    rng = np.random.default_rng(8)
    for mode in m.modes:
        signs = np.array(m.working_mode(mode).signs)
        for x, regular_only in ((regular(case, mode), True), (_anywhere(case), False)):
            x_dot, x_ddot = rng.normal(size=(2, len(x), m.n_out))
            q, reach = evaluate(m.functions["inverse_kinematics"], x, signs, d)
            (want,) = evaluate(m.functions["inverse_dynamics"], q[:, :, 0], x, x_dot, x_ddot, d)
            got = m.inverse_dynamics(x, x_dot, x_ddot, case.design, mode=mode)
            assert got.shape == (len(x), m.n_act)
            ok = reached(q, reach)
            np.testing.assert_array_equal(np.isnan(got), np.broadcast_to(~ok[:, None], got.shape),
                                          err_msg=f"mode {mode}")
            if regular_only:
                error = _relative_errors(got, want[:, :, 0])
                assert np.all(error <= 1e-12), f"mode {mode}: {error.max():.1e}"
            else:
                assert 0 < ok.sum() < len(x), f"mode {mode}: the poses anywhere are all in or all out of reach"


def test_pipelines_through_the_joint_angles_equal_those_from_the_pose(case):
    """Without its functions from the pose, a mechanism's fused pipelines compose the inverse kinematics'
    joint angles with the functions of the joints: every local index and the inverse dynamics of a
    virtual-work model agree with the pipelines from the pose within 1e-12 of the largest value at regular
    poses, NaN at the same poses anywhere."""
    from pkm.dynamics.rigid import inverse_dynamics_pipeline
    from pkm.kinematics import FunctionTable
    from pkm.regions.pipeline import index_pipeline

    m, d = case.mech, case.vector
    if not any(name.endswith(from_pose("")) for name in m.functions):
        pytest.skip(f"{m.name} derives no function from the pose")
    angles = copy.copy(m)
    angles.functions = FunctionTable({k: f for k, f in m.functions.items() if not k.endswith(from_pose(""))},
                                     f"the {m.name} without its functions from the pose")
    locals_ = tuple(m.local_spec(name) for name in m.local_indices())
    pairs = [(index_pipeline(m, locals_), index_pipeline(angles, locals_), ())]
    rng = np.random.default_rng(9)
    if "inverse_dynamics" in m.functions:
        pairs.append((inverse_dynamics_pipeline(m), inverse_dynamics_pipeline(angles), ("x_dot", "x_ddot")))
    for mode in m.modes:
        signs = np.array(m.working_mode(mode).signs)
        for x, regular_only in ((regular(case, mode), True), (_anywhere(case), False)):
            for fused, through_angles, motion in pairs:
                inputs = {"x": x, "mode": signs, "design": d, **{k: rng.normal(size=x.shape) for k in motion}}
                args = [inputs[p] for p in fused.name_in()]
                for key, got, want in zip(fused.name_out(), evaluate(fused, *args), evaluate(through_angles, *args),
                                          strict=True):
                    np.testing.assert_array_equal(np.isnan(got), np.isnan(want), err_msg=f"mode {mode}: {key}")
                    if regular_only:
                        error = _relative_errors(got, want)
                        assert np.all(error <= 1e-12), f"mode {mode}: {key}: {error.max():.1e}"


def test_psi_lies_in_the_null_space_of_the_constraint_jacobian(case):
    m = case.mech
    for mode in m.modes:
        x = regular(case, mode)
        q = closed_joints(case, mode, x)
        _, H_q, H_x = evaluate(m.functions["constraint"], q, x, case.vector)
        psi = m.psi(x, case.design, mode=mode)
        J_f = m.forward_jacobian(x, case.design, mode=mode)
        identity = np.broadcast_to(np.eye(m.n_act), (len(x), m.n_act, m.n_act))
        np.testing.assert_array_equal(psi[:, : m.n_act, :], identity)
        residual = H_q @ psi + H_x @ J_f
        scale = np.abs(H_q).max() * np.abs(psi).max() + np.abs(H_x).max() * np.abs(J_f).max()
        np.testing.assert_allclose(residual, 0.0, atol=1e-12 * scale, err_msg=f"mode {mode}")


def test_every_local_index_lies_in_its_documented_range(case):
    m = case.mech
    for mode, x in case.poses.items():
        for name in m.local_indices():
            spec = m.local_spec(name)
            assert spec is registry.local_index(name)
            value = m.local_index(name, x, case.design, mode=mode)
            assert not np.any(np.isnan(value)), f"{name} is NaN at a reachable pose ({mode})"
            assert np.all((spec.lower <= value) & (value <= spec.upper)), f"{name} outside its range ({mode})"


def _outputs(m: pkm.Mechanism, x: np.ndarray, design: pkm.Design, mode: str) -> dict[str, np.ndarray]:
    out = {
        "q": m.inverse_kinematics(x, design, mode=mode, passive=True),
        "J": m.jacobian(x, design, mode=mode),
        "J_f": m.forward_jacobian(x, design, mode=mode),
        "psi": m.psi(x, design, mode=mode),
        "reachable": m.reachable(x, design, mode=mode),
        **m.singularity(x, design, mode=mode),
        **{name: m.local_index(name, x, design, mode=mode) for name in m.local_indices()},
    }
    q_a = out["q"][..., : m.n_act]
    out.update({f"fk_{a}": m.forward_kinematics(q_a, design, assembly=a) for a in m.assemblies})
    out.update({f"fk_joints_{a}": m.forward_kinematics(q_a, design, assembly=a, passive=True) for a in m.assemblies})
    return out


SINGLES = 4  # poses per mode evaluated one at a time


def test_batch_equals_stacked_single_poses(first_case, monkeypatch):
    """Equal to round-off: a function's first evaluation runs on the interpreter and its later ones
    compiled, and results kept from either (the forward polynomial's roots) may be reused. On two threads
    (a worker of the suite evaluates on one, tests/conftest.py), so that the tiled batch is split."""
    monkeypatch.setattr("pkm.batch.THREADS", 2)
    m, design = first_case.mech, first_case.design
    repeats = 100  # 2400 poses: beyond the size where batches are evaluated by threads
    for mode, x in first_case.poses.items():
        batch = _outputs(m, x, design, mode)
        singles = [_outputs(m, xi, design, mode) for xi in x[:SINGLES]]
        big = _outputs(m, np.tile(x, (repeats, 1)), design, mode)
        for key, value in batch.items():
            assert value.shape[0] == len(x), key
            stacked = np.stack([s[key] for s in singles])
            for got, want in ((stacked, value[:SINGLES]), (big[key], np.concatenate([value] * repeats))):
                np.testing.assert_array_equal(np.isnan(got), np.isnan(want), err_msg=key)
                np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12, err_msg=key)


def _named_inputs(case: Case) -> dict[str, np.ndarray]:
    """Inputs of the generated functions by port name at the poses of the first working mode, the
    assembly modes in turn."""
    m, mode = case.mech, case.mech.modes[0]
    x = case.poses[mode]
    assembly = np.resize(np.array([b.signs for b in m.assembly_modes]), (len(x), len(m.assembly_modes[0].signs)))
    return port_inputs(m, case.design, x, mode, assembly)


@cache
def _with_jacobians(key: str, fn: ca.Function) -> tuple[ca.Function, ca.Function]:
    """``fn`` with the Jacobian of each output in each input appended to its outputs, and the same outputs dense
    and stacked column by column into one (read back with one conversion per call); built once per function,
    shared by the seeds."""
    ins = [ca.SX.sym(fn.name_in(i), fn.sparsity_in(i)) for i in range(fn.n_in())]
    outs = fn.call(ins)
    outs += [ca.jacobian(o, i) for o in outs for i in ins]
    return ca.Function(key, ins, outs), ca.Function(key, ins, [ca.vertcat(*(ca.vec(ca.densify(o)) for o in outs))])


def test_batch_evaluation_equals_casadi_calls_with_jacobians(case):
    """pkm.batch.evaluate (mapped, compiled where there is a compiler) against one CasADi call per point
    (serial), sparse outputs included: equal to round-off, each point's output within 1e-12 of its largest
    finite entry (at least 1)."""
    inputs = _named_inputs(case)
    for key, fn in case.mech.functions.items():
        F, stacked = _with_jacobians(key, fn)
        rng = np.random.default_rng(11)
        args = [
            rng.normal(size=(len(inputs["x"]), fn.numel_in(i))) if n.endswith(("_dot", "_ddot"))
            else inputs[n][:, : fn.numel_in(i)] if n == "y" else inputs[n]
            for i, n in enumerate(fn.name_in())
        ]
        mapped = evaluate(F, *args)
        serial = np.stack([stacked.call([a[k] if a.ndim == 2 else a for a in args])[0].full()[:, 0]
                           for k in range(len(mapped[0]))])
        first = 0
        for j, got in enumerate(mapped):
            rows, cols = F.size_out(j)
            want = serial[:, first : first + rows * cols].reshape(len(serial), cols, rows).transpose(0, 2, 1)
            first += rows * cols
            assert got.shape == want.shape, f"{key}[{j}]"
            finite = np.nan_to_num(want, nan=0, posinf=0, neginf=0).reshape(len(want), -1)
            scale = np.maximum(1.0, np.max(np.abs(finite), axis=1, initial=0))[:, None, None]
            close = np.isclose(got, want, rtol=1e-12, atol=1e-12 * scale, equal_nan=True)
            bad = np.flatnonzero(~close.reshape(len(close), -1).all(axis=1))
            assert not len(bad), f"{key}[{j}]: point {bad[0]}: {got[bad[0]]} != {want[bad[0]]}"
        assert first == serial.shape[1]


@pytest.mark.parametrize("name", MECHANISMS)
def test_every_parameter_is_documented_with_a_valid_default(name):
    m = pkm.load(name)
    names = [p.name for p in m.parameters]
    assert names
    assert len(set(names)) == len(names)
    for p in m.parameters:
        assert p.doc.strip(), p.name
        assert p.unit.strip(), p.name
        assert p.lower <= p.default <= p.upper, p.name
        p.check(p.default)
    assert list(m.design()) == names
    for branch in (*m.working_modes, *m.assembly_modes):
        assert branch.doc.strip(), branch.name
    assert len(m.pose_names) == len(m.pose_units) == m.n_out
    assert len(m.actuator_names) == len(m.actuator_units) == m.n_act


@pytest.mark.parametrize("name", MECHANISMS)
def test_generated_functions_have_named_inputs_and_outputs(name):
    for fn in pkm.load(name).functions.values():
        ports = fn.name_in() + fn.name_out()
        assert len(set(ports)) == len(ports)
        assert not any(p.startswith(("i", "o")) and p[1:].isdigit() for p in ports), fn.name()


POSITIONAL = {
    "inverse_kinematics": lambda c: (c.x, c.design),
    "forward_kinematics": lambda c: (c.q, c.design),
    "jacobian": lambda c: (c.x, c.design),
    "forward_jacobian": lambda c: (c.x, c.design),
    "psi": lambda c: (c.x, c.design),
    "singularity": lambda c: (c.x, c.design),
    "reachable": lambda c: (c.x, c.design),
    "local_index": lambda c: ("inverse_condition_f", c.x, c.design),
    "design": lambda c: (c.design,),
    "global_index": lambda c: ("gci", c.design),
}


def _keyword_cases():
    for name in MECHANISMS:
        for method in POSITIONAL:
            yield pytest.param(name, method, {}, id=f"{name}-{method}")
        for region in pkm.load(name).regions:
            yield pytest.param(name, "global_index", {"region": region}, id=f"{name}-global_index-{region}")


@pytest.mark.parametrize(("name", "method", "options"), list(_keyword_cases()))
def test_unknown_keyword_argument_is_a_type_error(name, method, options):
    m = pkm.load(name)
    design = m.design()
    x = reachable_poses(m, design, m.modes[0], np.random.default_rng(0))[0]
    context = SimpleNamespace(x=x, q=m.inverse_kinematics(x, design), design=design)
    with pytest.raises(TypeError, match="bogus"):
        getattr(m, method)(*POSITIONAL[method](context), **options, bogus=1)


def test_registry_still_lists_mechanisms_after_loading_one():
    for name in MECHANISMS:
        pkm.load(name)
    assert pkm.mechanisms() == MECHANISMS


@cache
def _compared_kernels(name: str) -> list:
    """The catalogue's kernels of a mechanism but its point integrands, compiled (once per mechanism: the
    catalogue does not depend on the design, and building it is most of a case's time)."""
    from pkm import compiled
    from pkm.catalogue import kernels

    compared = [k for k in kernels(pkm.load(name)) if k.piece is None]
    assert compiled.build([(k.function, k.summed) for k in compared])["interpreted"] == 0
    return compared


def test_compiled_kernels_agree_with_the_interpreter_to_1e_12(case):
    """Every kernel of the catalogue but the point integrands (tests/test_integrand.py) against CasADi's
    interpreter on the same batch, a kernel for every function, NaN (out of reach) exactly where the
    interpreter has NaN, and every output within 1e-12 of its largest entry at the pose where the pose is
    well conditioned (1/kappa_f >= 0.05), within 1e-9 nearer a singularity: the vector functions of the C
    library differ from the scalar ones by an ulp, which the conditioning of J amplifies (1e-11 for the
    2-UPS-PU's statics, whose 6 x 6 solve amplifies them by the wrench matrix's condition number, and for the
    coefficients of the passive leg's sextic, sums of products that cancel). The
    kernels are compiled first, in parallel, as ``pkm build`` does (the point integrands by their own
    test, which runs beside this one)."""
    from pkm import compiled
    from pkm.batch import interpreted

    if compiled.status()["path"] != "compiled":
        pytest.skip(f"the compiled path is off: {compiled.status()['reason']}")
    compared = _compared_kernels(case.mech.name)
    inputs = _named_inputs(case)
    rng = np.random.default_rng(12)
    far = np.full((3, case.mech.n_out), 1e3)  # out of reach: NaN through both paths
    conditioning = case.mech.local_index("inverse_condition_f", inputs["x"], case.design, mode=case.mech.modes[0])
    well = np.concatenate([conditioning >= 0.05, np.zeros(len(far), dtype=bool)])
    for entry in compared:
        name, fn = entry.label, entry.function
        assert compiled.kernel(fn, work=compiled.price(fn.n_instructions())) is not None, name
        args = []
        for i, port in enumerate(fn.name_in()):
            value = rng.normal(size=(len(inputs["x"]), fn.numel_in(i))) if port.endswith(("_dot", "_ddot")) \
                else inputs[port][:, : fn.numel_in(i)] if port == "y" else inputs[port]
            if port == "x" and name.startswith("pipeline"):
                value = np.concatenate([value, far])
            args.append(value)
        n = max((len(a) for a in args if a.ndim == 2), default=1)
        args = [np.resize(a, (n, a.shape[1])) if a.ndim == 2 else a for a in args]
        slow = interpreted(fn, *args)
        # a pipeline's unreached rows: its indices are NaN there, its other outputs are not used; the far
        # poses are compared for NaN alone (where the legs assemble anywhere, as UPS legs beyond their strokes,
        # the first order there is a 6 x 6 determinant of kilometre lengths)
        used = slow[fn.name_out().index("valid")].reshape(n) > 0 if "valid" in fn.name_out() else np.ones(n, bool)
        used &= np.arange(n) < len(inputs["x"])
        # the design shared by the batch (computed once per call) and given row by row
        per_row = [np.broadcast_to(a, (n, a.size)) if a.ndim == 1 and port in GROUP_SHARED else a
                   for a, port in zip(args, fn.name_in(), strict=True)]
        for j, (got, want) in [(j, pair) for fast in (evaluate(fn, *args), evaluate(fn, *per_row))
                               for j, pair in enumerate(zip(fast, slow, strict=True))]:
            np.testing.assert_array_equal(np.isnan(got), np.isnan(want), err_msg=f"{name}: {fn.name_out(j)}")
            a, b = got.reshape(len(got), -1), want.reshape(len(want), -1)
            scale = np.maximum(1.0, np.max(np.abs(np.nan_to_num(b, posinf=0, neginf=0)), axis=1))
            with np.errstate(invalid="ignore"):
                error = np.max(np.abs(np.where(np.isfinite(b), a - b, 0.0)), axis=1)
            # the statics' 6 x 6 solve amplifies the vector maths' ulps by the wrench matrix's condition, the
            # passive leg's sextic (its eq. 11) by the cancellation in its coefficients' sums of products
            near = 1e-11 if fn.name().startswith(("statics", "paper_forward")) else 1e-12
            tolerance = np.where(np.resize(well, len(error)) if len(error) > 1 else True, near, 1e-9) * scale
            assert np.all((error <= tolerance) | ~used), f"{name}: {fn.name_out(j)}: {np.max(error / scale):.1e}"
