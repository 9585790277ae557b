"""The compiled path (pkm.compiled): any SX graph compiled at first use into the kernel cache, the cache's
guarantees (atomic entries, concurrent builders, corrupted entries rebuilt, bounded size), the interpreter
wherever the compiled path is off, and status() counting which path ran and why. tests/test_contract.py
and tests/test_integrand.py compare every kernel of the catalogue with the interpreter."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import pkm
from pkm import batch, compiled
from pkm.catalogue import integrands, kernels
from pkm.compiled import cache
from pkm.regions.quadrature import global_value

HAS_COMPILER = bool(shutil.which("cc") or shutil.which("gcc") or shutil.which("clang"))
needs_compiler = pytest.mark.skipif(not HAS_COMPILER or os.environ.get("PKM_COMPILED") == "0",
                                    reason="no C compiler, or the interpreter is asked for")


@pytest.fixture
def fresh(monkeypatch, tmp_path):
    """A process state with nothing met yet, the cache in its own folder; restored afterwards."""
    monkeypatch.setenv("PKM_CACHE_DIR", str(tmp_path / "cache"))
    compiled.reset()
    yield tmp_path / "cache"
    monkeypatch.undo()
    compiled.reset()


def _graph(tag: float) -> ca.Function:
    """A function no one has met before: its constants carry ``tag``."""
    x = ca.SX.sym("x", 3)
    design = ca.SX.sym("design", 2)
    y = ca.vertcat(ca.sin(x[0]) * design[0] + tag, ca.sqrt(x[1] ** 2 + x[2] ** 2) / design[1], ca.atan2(x[2], x[0]))
    return ca.Function(f"lambda_index_{abs(hash(tag)) % 10**6}", [x, design], [y], ["x", "design"], ["y"])


def _evaluations() -> dict:
    return compiled.status()["evaluations"]


@pytest.fixture
def compile_at_once(monkeypatch):
    """Every graph compiled at its first evaluation: the evaluations of these tests are small."""
    monkeypatch.setattr(compiled, "price", lambda _: 1)


@needs_compiler
def test_a_graph_runs_on_the_interpreter_until_its_work_pays_for_its_compile(fresh):
    fn = _graph(0.125)
    share = compiled.price(fn.n_instructions()) // 4
    for _ in range(3):
        assert compiled.kernel(fn, work=share) is None
    assert compiled.kernel(fn, work=share - 1) is None
    assert compiled.kernel(fn, work=1) is not None
    other = _graph(0.375)
    assert compiled.kernel(other, work=compiled.price(other.n_instructions())) is not None
    assert _evaluations() == {"compiled": 2, "interpreter": {compiled.LITTLE_WORK: 4}}


@needs_compiler
def test_the_work_of_earlier_processes_counts_towards_a_compile(fresh):
    """A process that ends before a graph's work pays for its compile records the work in the cache (at
    exit); the next process compiles the graph once their work together reaches the price."""
    fn = _graph(0.625)
    price = compiled.price(fn.n_instructions())
    assert compiled.kernel(fn, work=price // 2) is None
    compiled._pay_rent()  # what the process does at exit
    assert compiled.Cache(fresh).rent(compiled.key(fn)) == price // 2
    compiled.reset()  # the next process
    assert compiled.kernel(fn, work=price // 4) is None
    assert compiled.kernel(fn, work=price // 4 + 1) is not None
    assert not (fresh / "rent" / compiled.key(fn)).exists()  # built: its record is gone
    compiled.reset()
    compiled._pay_rent()
    assert compiled.Cache(fresh).rent(compiled.key(fn)) == 0


@needs_compiler
def test_a_batch_of_designs_runs_a_kernel_of_its_own_that_reads_them_row_by_row(fresh):
    """A kernel reads the design once, shared by the batch; one row per design is a second kernel, compiled
    where such a batch asks for it and checked against the interpreter with designs row by row; the first
    refuses a design given per row."""
    fn = _graph(0.5)
    rng = np.random.default_rng(4)
    x, designs = rng.uniform(-1, 1, (300, 3)), rng.uniform(0.5, 2.0, (300, 2))
    price = compiled.price(fn.n_instructions())
    shared_run = compiled.kernel(fn, work=price)
    assert shared_run is not None
    rows_run = compiled.kernel(fn, work=price, rows=True)
    assert rows_run is not None
    assert rows_run is not shared_run
    before = _evaluations()["compiled"]
    (shared,) = batch.evaluate(fn, x, designs[0])
    (per_row,) = batch.evaluate(fn, x, designs)
    assert _evaluations()["compiled"] == before + 2
    np.testing.assert_allclose(shared, batch.interpreted(fn, x, designs[0])[0], rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(per_row, batch.interpreted(fn, x, designs)[0], rtol=1e-13, atol=1e-14)
    out = [np.empty((300, 3)), np.zeros((1, 1))]
    with pytest.raises(ValueError, match="reads the design once"):
        shared_run([3, 2], [([x, designs], out, 300, 300)], 1)


def test_rent_records_are_added_under_a_lock_and_kept_to_their_limit(fresh, monkeypatch):
    from pkm.compiled import cache as cache_module

    store = compiled.Cache(fresh)
    store.pay_rent({"a": 5, "b": 1})
    store.pay_rent({"a": 7})
    assert (store.rent("a"), store.rent("b"), store.rent("c")) == (12, 1, 0)
    monkeypatch.setattr(cache_module, "RENTS", 1)
    store.pay_rent({"c": 3})
    assert sorted(p.name for p in (fresh / "rent").iterdir()) == ["c"]  # the newest kept
    (fresh / "rent" / "c").write_text("junk")
    assert store.rent("c") == 0


@needs_compiler
def test_a_graph_never_seen_runs_compiled_once_its_work_reaches_a_compiles(fresh, monkeypatch):
    fn = _graph(0.25)
    x = np.random.default_rng(1).uniform(-1, 1, (1000, 3))
    design = np.array([1.5, 0.7])
    first = batch.evaluate(fn, x, design)
    assert _evaluations() == {"compiled": 0, "interpreter": {compiled.LITTLE_WORK: 1}}
    done = compiled._entries[(fn, False, False)].interpreted
    monkeypatch.setattr(compiled, "price", lambda _: done + 1)
    second = batch.evaluate(fn, x, design)
    assert _evaluations() == {"compiled": 1, "interpreter": {compiled.LITTLE_WORK: 1}}
    want = batch.interpreted(fn, x, design)
    for a, b, c in zip(first, second, want, strict=True):
        np.testing.assert_array_equal(a, c)
        np.testing.assert_allclose(b, c, rtol=1e-12, atol=1e-12)
    assert compiled.status()["kernels"] == 1


def test_a_graph_too_large_to_compile_quickly_stays_on_the_interpreter(fresh):
    x = ca.SX.sym("x")
    y = x
    for k in range(compiled.MAX_INSTRUCTIONS // 2 + 1):
        y = ca.sin(y) + k
    fn = ca.Function("long_chain", [x], [y], ["x"], ["y"])
    assert fn.n_instructions() > compiled.MAX_INSTRUCTIONS
    assert compiled.kernel(fn, work=compiled.price(fn.n_instructions())) is None
    got = batch.evaluate(fn, np.array([[0.1], [0.2]]))[0]
    np.testing.assert_array_equal(got, batch.interpreted(fn, np.array([[0.1], [0.2]]))[0])
    if compiled.status()["path"] == "compiled":
        assert _evaluations()["interpreter"] == {"too large to compile": 2}


@needs_compiler
def test_a_region_placed_by_numbers_runs_compiled(fresh, monkeypatch):
    """The five-bar's MIW disc fixed by numbers instead of its generated placement: its point integrands
    are graphs of their own, compiled at first use; value and gradient equal the interpreter's."""
    mech = pkm.load("five_bar")
    region = mech.region("miw").at([0.05, 1.45], [0.3])
    spec, branch, design = mech.global_spec("gci"), mech.working_mode(None), mech.design_vector(mech.design())

    def value():
        got, grad = global_value(mech, spec, region, design, branch=branch, resolution=8, gradient=True)
        return np.append(float(got), grad)

    first = value()
    assert _evaluations()["compiled"] == 0
    monkeypatch.setattr(compiled, "price", lambda _: 1)
    second = value()
    counts = _evaluations()
    assert counts["compiled"] > 0
    assert set(counts["interpreter"]) == {compiled.LITTLE_WORK}
    third_counts_before = counts["compiled"]
    third = value()
    assert _evaluations()["compiled"] > third_counts_before
    assert _evaluations()["interpreter"] == counts["interpreter"]  # nothing more on the interpreter
    np.testing.assert_allclose(second, first, rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(third, second)


@needs_compiler
def test_a_lambda_defined_index_runs_compiled(fresh, monkeypatch):
    """A local index defined by a user's lambda, evaluated through the fused pipeline like pkm's own."""
    from pkm.indices import LocalIndex
    from pkm.regions import evaluate_at

    spec = LocalIndex("trace_squared", "tr(J J^T), a user's index", "({actuator}/{pose})^2", 0.0, np.inf, np.inf,
                      lambda J: ca.trace(ca.mtimes(J, J.T)), arguments=("J",))
    mech = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9], [5.0, 5.0]])
    signs, design = np.array(mech.working_mode(None).signs), mech.design_vector(mech.design())
    first = evaluate_at(mech, (spec,), x, signs, design).values[0]
    monkeypatch.setattr(compiled, "price", lambda _: 1)
    second = evaluate_at(mech, (spec,), x, signs, design).values[0]
    assert _evaluations() == {"compiled": 1, "interpreter": {compiled.LITTLE_WORK: 1}}
    np.testing.assert_array_equal(np.isnan(second), np.isnan(first))
    np.testing.assert_allclose(second, first, rtol=1e-12)
    jacobians = mech.jacobian(x[:2])
    np.testing.assert_allclose(second[:2], np.einsum("nij,nij->n", jacobians, jacobians), rtol=1e-12)


@needs_compiler
def test_a_test_only_mechanism_runs_compiled(fresh, monkeypatch):
    """A mechanism outside the registry (tests/test_spatial_core.py's tripod) is compiled like any other."""
    from test_spatial_core import Tripod

    mech = Tripod()
    x = mech.workspace_box(mech.design().vector()).mean(axis=1)
    poses = x + np.random.default_rng(3).normal(scale=0.01, size=(50, mech.n_out))
    interpreted_jacobian = mech.jacobian(poses)
    monkeypatch.setattr(compiled, "price", lambda _: 1)
    second = mech.jacobian(poses)
    assert _evaluations()["compiled"] >= 1
    np.testing.assert_allclose(second, interpreted_jacobian, rtol=1e-12, atol=1e-12)


@needs_compiler
def test_two_processes_compiling_one_kernel_both_get_it_and_the_cache_holds_one_copy(fresh):
    script = """
import numpy as np
from pkm import batch, compiled
from test_compiled import _graph
fn = _graph(0.5)
x = np.random.default_rng(1).uniform(-1, 1, (8, 3))
batch.evaluate(fn, x, np.array([1.5, 0.7]))  # compiled where the other process's kernel is in the cache already
before = compiled.status()["evaluations"]["compiled"]
compiled.price = lambda _: 1
batch.evaluate(fn, x, np.array([1.5, 0.7]))
print(compiled.status()["evaluations"]["compiled"] - before, compiled.key(fn))
"""
    env = {**os.environ, "PKM_CACHE_DIR": str(fresh), "PYTHONPATH": str(Path(__file__).parent)}
    runs = [subprocess.Popen([sys.executable, "-c", script], env=env, stdout=subprocess.PIPE, text=True)
            for _ in range(2)]
    outputs = [run.communicate(timeout=300)[0].split() for run in runs]
    assert all(run.returncode == 0 for run in runs)
    assert [out[0] for out in outputs] == ["1", "1"]
    key = outputs[0][1]
    assert outputs[1][1] == key
    entries = [e for e in fresh.glob("??/*") if json.loads((e / cache.META).read_text())["function"] != "runner"]
    assert [e.name for e in entries] == [key]
    assert sorted(p.name for p in entries[0].iterdir()) == sorted(["kernel.c", cache.LIBRARY, cache.META,
                                                                    cache.CHECKED])
    assert (entries[0] / cache.CHECKED).read_text() == json.loads((entries[0] / cache.META).read_text())["sha256"]
    assert cache.Cache(fresh).checked(key)
    assert list((fresh / "tmp").iterdir()) == []


@needs_compiler
def test_a_truncated_or_corrupted_kernel_is_detected_and_rebuilt(fresh):
    fn = _graph(0.75)
    x = np.random.default_rng(2).uniform(-1, 1, (4, 3))
    design = np.array([1.5, 0.7])
    want = batch.interpreted(fn, x, design)
    compiled.build([(fn, False)])
    library = cache.Cache(fresh).entry(compiled.key(fn)) / cache.LIBRARY
    for damage in (lambda b: b[: len(b) // 2], lambda b: b[:100] + bytes(64) + b[164:]):
        # as a later process finds it: a new file (this process keeps the library it mapped)
        damaged = library.with_name("damaged")
        damaged.write_bytes(damage(library.read_bytes()))
        damaged.replace(library)
        compiled.reset()
        assert compiled.build([(fn, False)]) == {"cached": 0, "compiled": 1, "interpreted": 0}
        for a, b in zip(batch.evaluate(fn, x, design), want, strict=True):
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
        assert _evaluations() == {"compiled": 1, "interpreter": {}}


@needs_compiler
def test_a_library_is_checked_against_the_interpreter_once_and_again_where_it_changed(fresh, monkeypatch):
    fn = _graph(0.875)
    checks = []
    check = compiled._check
    monkeypatch.setattr(compiled, "_check", lambda *a, **k: checks.append(1) or check(*a, **k))
    compiled.build([(fn, False)])
    entry = cache.Cache(fresh).entry(compiled.key(fn))
    marks = []
    for mark in (None, "", "0" * 64, None):  # as found: checked; no mark; a mark of another library; checked again
        if mark is not None:
            (entry / cache.CHECKED).write_text(mark)
        compiled.reset()
        compiled.build([(fn, False)])
        marks.append(len(checks))
    assert marks == [1, 2, 3, 3]
    assert cache.Cache(fresh).checked(compiled.key(fn))


def test_a_cache_that_cannot_be_written_falls_back_to_the_interpreter_with_one_warning(monkeypatch, tmp_path):
    """A location under a regular file cannot be a folder, for any user (root included)."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("PKM_CACHE_DIR", str(blocker / "kernels"))
    compiled.reset()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            outputs = [batch.evaluate(_graph(tag), np.ones((3, 3)), np.array([1.0, 2.0])) for tag in (1.0, 2.0)]
            outputs += [batch.evaluate(_graph(tag), np.ones((3, 3)), np.array([1.0, 2.0])) for tag in (1.0, 2.0)]
        notices = [w for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]
        status = compiled.status()
    finally:
        monkeypatch.undo()
        compiled.reset()
    assert len(notices) == 1, [str(w.message) for w in notices]
    assert status["evaluations"]["compiled"] == 0
    assert sum(status["evaluations"]["interpreter"].values()) == 4
    if HAS_COMPILER and os.environ.get("PKM_COMPILED") != "0":
        assert "cannot be written" in str(notices[0].message)
        assert status["path"] == "interpreter"
    np.testing.assert_allclose(outputs[0][0], batch.interpreted(_graph(1.0), np.ones((3, 3)), [1.0, 2.0])[0])


def test_without_a_c_compiler_everything_runs_on_the_interpreter_and_status_says_why(monkeypatch, tmp_path):
    monkeypatch.setenv("PATH", str(tmp_path))
    monkeypatch.delenv("CC", raising=False)
    monkeypatch.delenv("PKM_COMPILED", raising=False)
    compiled.reset()
    try:
        m = pkm.load("five_bar")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            values = m.local_index("inverse_condition_f", np.array([[0.1, 1.5], [-0.3, 1.9]]))
            m.jacobian(np.array([0.1, 1.5]))
        status = compiled.status()
    finally:
        monkeypatch.undo()
        compiled.reset()
    assert status["path"] == "interpreter"
    assert status["reason"].startswith("no C compiler on PATH")
    assert status["evaluations"]["compiled"] == 0
    assert status["evaluations"]["interpreter"] == {"no C compiler": 2}
    assert len([w for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]) == 1
    assert np.all((values > 0) & (values <= 1))


@needs_compiler
def test_a_compile_error_falls_back_with_one_warning_naming_the_function(fresh, monkeypatch, tmp_path,
                                                                         compile_at_once):
    """A compiler that rejects every kernel (but builds the runner): each kernel says so once, by name."""
    wrapper = tmp_path / "bin" / "cc"
    wrapper.parent.mkdir()
    real = shutil.which("cc") or shutil.which("gcc")
    wrapper.write_text(f'#!/bin/sh\ncase "$*" in *kernel.c*) echo "kernel.c:1:1: error: injected" >&2; exit 1;; '
                       f'esac\nexec {real} "$@"\n')
    wrapper.chmod(0o755)
    monkeypatch.setenv("CC", str(wrapper))
    compiled.reset()
    fn = _graph(3.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(3):
            got = batch.evaluate(fn, np.ones((2, 3)), np.array([1.0, 2.0]))
    notices = [str(w.message) for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]
    assert len(notices) == 1
    assert fn.name() in notices[0]
    assert "injected" in notices[0]
    assert _evaluations() == {"compiled": 0, "interpreter": {"compile error": 3}}
    np.testing.assert_array_equal(got[0], batch.interpreted(fn, np.ones((2, 3)), np.array([1.0, 2.0]))[0])


def test_status_counts_evaluations_and_reports_a_casadi_version_mismatch(monkeypatch):
    compiled.reset()
    m = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9]])
    for _ in range(3):
        m.local_index("inverse_condition_f", x)
    counts = compiled.status()["evaluations"]
    assert counts["compiled"] + sum(counts["interpreter"].values()) == 3
    assert compiled.status()["casadi"] == {"running": ca.__version__, "generated_with": ca.__version__}
    monkeypatch.setattr(ca, "__version__", "3.6.5")
    note = compiled.status()["casadi"]["note"]
    assert "3.6.5" in note
    assert "evaluation works" in note
    compiled.reset()


def test_the_interpreter_fallback_says_so_once_and_gives_the_same_values(monkeypatch):
    m = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9], [5.0, 5.0]])
    monkeypatch.setenv("PKM_COMPILED", "0")
    compiled.reset()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            slow = m.local_index("inverse_condition_f", x)
            m.jacobian(x[:2])
        status = compiled.status()
    finally:
        monkeypatch.undo()
        compiled.reset()
    notices = [w for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]
    assert len(notices) == 1
    assert "PKM_COMPILED=0" in str(notices[0].message)
    assert status["path"] == "interpreter"
    assert status["evaluations"]["interpreter"] == {"disabled": 2}
    fast = m.local_index("inverse_condition_f", x)
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
    np.testing.assert_allclose(fast[:2], slow[:2], rtol=1e-13)


@needs_compiler
def test_the_cache_removes_the_entries_used_longest_ago_beyond_its_size(fresh, monkeypatch):
    functions = [_graph(10.0 + k) for k in range(3)]
    compiled.build([(fn, False) for fn in functions])
    store = cache.Cache(fresh)
    sizes = {e.name: size for _, size, e in store.entries()}
    keys = [compiled.key(fn) for fn in functions]
    for age, key in enumerate(keys):
        os.utime(store.entry(key), (1e9 + age, 1e9 + age))
    runner = [name for name in sizes if name not in keys]
    monkeypatch.setenv("PKM_CACHE_MB", str((sum(sizes.values()) - sizes[keys[0]]) / 2**20))
    store.evict()
    assert sorted(e.name for _, _, e in store.entries()) == sorted([*keys[1:], *runner])


def test_one_catalogue_lists_each_kernel_once_and_the_tests_cover_it_all():
    """tests/test_contract.py compares the catalogue's kernels that are not point integrands,
    tests/test_integrand.py the point integrands: together the whole catalogue."""
    for name in pkm.mechanisms():
        mech = pkm.load(name)
        listed = kernels(mech)
        identities = [(k.function.serialize(), k.summed) for k in listed]
        assert len(identities) == len(set(identities)), name
        compared = {(k.function.serialize(), k.summed) for k in listed if k.piece is None}
        compared |= {(k.function.serialize(), k.summed) for k in integrands(mech)}
        assert compared == set(identities), name


def test_calls_from_several_threads_at_once_give_each_its_own_sums(monkeypatch):
    """Kernels called from several Python threads at once, each call split into chunks (the runner's kept
    threads take one call at a time, the others run on their own thread): every result as alone."""
    from concurrent.futures import ThreadPoolExecutor

    from pkm.regions.integrand import sum_function

    mech = pkm.load("five_bar")
    spec, region, branch = mech.global_spec("gci"), mech.region("miw"), mech.working_mode(None)
    piece = region.pieces()[0]
    fn, _ = sum_function(mech, spec.local, piece, spec.reduce, 1)
    if compiled.kernel(fn, True, work=compiled.price(fn.n_instructions())) is None:
        pytest.skip(f"the compiled path is off: {compiled.status()['reason']}")
    nodes, weights = piece.reference(60, spec.reduce)
    base = mech.design_vector(mech.design())
    designs = [base * (1 + 0.01 * k) for k in range(8)]
    monkeypatch.setattr(batch, "THREADS", 2)

    def sums(design):
        return batch.total(fn, nodes, weights[:, None], np.array(branch.signs, dtype=float), design)

    alone = [sums(d) for d in designs]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(sums, designs * 25))
    for k, got in enumerate(together):
        for a, b in zip(got, alone[k % len(designs)], strict=True):
            np.testing.assert_array_equal(a, b)


@needs_compiler
def test_the_compiled_path_is_on_wherever_there_is_a_c_compiler():
    """A runner that fails to build would pass every evaluation unseen onto the interpreter."""
    assert compiled.status()["path"] == "compiled", compiled.status()["reason"]


def test_the_kernels_reject_arrays_they_cannot_read():
    m = pkm.load("five_bar")
    fn = m.functions["inverse_kinematics"]
    run = compiled.kernel(fn, work=compiled.price(fn.n_instructions()))
    if run is None:
        pytest.skip(f"the compiled path is off: {compiled.status()['reason']}")
    strides = [fn.numel_in(0), 0, 0]
    given = [np.array([[0.1, 1.5], [-0.3, 1.9]]), np.ones(fn.numel_in(1)), m.design_vector(m.design())]
    q, reach, flag = np.zeros((2, fn.numel_out(0))), np.zeros((2, fn.numel_out(1))), np.zeros((1, 1))
    run(strides, [(given, [q, reach, flag], 2, 1)], 1)
    np.testing.assert_allclose(q, m.functions["inverse_kinematics"].map(2)(given[0].T, *given[1:])[0].T.full(),
                               rtol=1e-13)
    assert flag[0, 0] == 0
    with pytest.raises(TypeError, match="float64"):
        run(strides, [(given, [q.astype(np.float32), reach, flag], 2, 1)], 1)
    with pytest.raises(ValueError, match="takes 3 inputs and 2 outputs and a flag"):
        run(strides, [(given, [q, reach], 2, 1)], 1)
    with pytest.raises(ValueError, match="not C-contiguous"):
        run(strides, [(given, [np.zeros((fn.numel_out(0), 2)).T, reach, flag], 2, 1)], 1)
    frozen = reach.copy()
    frozen.setflags(write=False)
    with pytest.raises(ValueError, match="read-only"):
        run(strides, [(given, [q, frozen, flag], 2, 1)], 1)
    given[0][1, 0] = np.inf
    run(strides, [(given, [q, reach, flag], 2, 1)], 1)
    assert flag[0, 0] == 1


def test_non_finite_poses_are_refused_after_the_kernel_has_read_them(monkeypatch):
    """The public batch methods leave the finiteness check of the poses to the kernel that reads them
    (its flag) and name the input only then; the interpreter's path checks with numpy."""
    from pkm import PoseError

    m = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9]] * 50)
    x[71, 1] = np.nan
    for call in (lambda: m.local_index("inverse_condition_f", x), lambda: m.jacobian(x),
                 lambda: m.inverse_kinematics(x), lambda: m.inertia_matrix(x),
                 lambda: m.inverse_dynamics(x, np.zeros(2), np.zeros(2))):
        for wait in (1 << 62, 1):  # on the interpreter, then compiled
            monkeypatch.setattr(compiled, "price", lambda _, wait=wait: wait)
            with pytest.raises(PoseError, match="pose contains non-finite values"):
                call()
    with pytest.raises(PoseError, match="velocity contains non-finite values"):
        m.inverse_dynamics(x[:3], [0.0, np.inf], np.zeros(2))
    with pytest.raises(PoseError, match="acceleration contains non-finite values"):
        m.inverse_dynamics(x[:3], np.zeros(2), np.full((3, 2), np.nan))
