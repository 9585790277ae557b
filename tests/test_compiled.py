"""The compiled path's switch: PKM_COMPILED=0 (or no library) evaluates with CasADi's interpreter, says so
once, and gives the compiled path's values (tests/test_contract.py compares every kernel)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import pkm
from pkm import compiled


@pytest.fixture
def interpreter(monkeypatch):
    monkeypatch.setenv("PKM_COMPILED", "0")
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()
    monkeypatch.setattr(compiled, "_noticed", [])
    yield
    monkeypatch.delenv("PKM_COMPILED")
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()


def test_the_interpreter_fallback_says_so_once_and_gives_the_same_values(interpreter):
    m = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9], [5.0, 5.0]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        slow = m.local_index("inverse_condition_f", x)
        m.jacobian(x[:2])
    notices = [w for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]
    assert len(notices) == 1
    assert "PKM_COMPILED=0" in str(notices[0].message)
    assert compiled.status()["path"] == "interpreter"
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()
    with pytest.MonkeyPatch.context() as patch:
        patch.delenv("PKM_COMPILED")
        fast = m.local_index("inverse_condition_f", x)
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
    np.testing.assert_allclose(fast[:2], slow[:2], rtol=1e-13)


def test_calls_from_several_threads_at_once_give_each_its_own_sums(monkeypatch):
    """Kernels called from several Python threads at once, each call split into chunks (the library's kept
    threads take one call at a time, the others run on their own thread): every result as alone."""
    from concurrent.futures import ThreadPoolExecutor

    from pkm import batch
    from pkm.regions.integrand import sum_function

    if compiled.status()["path"] != "compiled":
        pytest.skip("the kernels are not built")
    mech = pkm.load("five_bar")
    spec, region, branch = mech.global_spec("gci"), mech.region("miw"), mech.working_mode(None)
    piece = region.pieces()[0]
    fn, _ = sum_function(mech, spec.local, piece, spec.reduce, 1)
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


def test_the_kernels_are_built_wherever_there_is_a_c_compiler():
    """The build is optional (pkm installs without a compiler), so a kernel that fails to compile would
    pass unseen onto the interpreter: where a compiler is present the library must be there."""
    import os
    import shutil

    if os.environ.get("PKM_COMPILED", "1") == "0" or not (shutil.which("cc") or shutil.which("gcc")):
        pytest.skip("the interpreter is asked for, or there is no C compiler")
    assert compiled.status()["path"] == "compiled", compiled.status()["reason"]


def test_the_kernels_reject_arrays_they_cannot_read():
    if compiled.status()["path"] != "compiled":
        pytest.skip("the kernels are not built")
    m = pkm.load("five_bar")
    fn = m.functions["inverse_kinematics"]
    run = compiled.kernel(fn)
    strides = [fn.numel_in(0), 0, 0]
    given = [np.array([[0.1, 1.5], [-0.3, 1.9]]), np.ones(fn.numel_in(1)), m.design_vector(m.design())]
    q, reach = np.zeros((2, fn.numel_out(0))), np.zeros((2, fn.numel_out(1)))
    run(strides, [(given, [q, reach], 2, 1)], 1)
    np.testing.assert_allclose(q, m.functions["inverse_kinematics"].map(2)(given[0].T, *given[1:])[0].T.full(),
                               rtol=1e-13)
    with pytest.raises(TypeError, match="float64"):
        run(strides, [(given, [q.astype(np.float32), reach], 2, 1)], 1)
    with pytest.raises(ValueError, match="takes 3 inputs and 2 outputs"):
        run(strides, [(given, [q], 2, 1)], 1)
    with pytest.raises(ValueError, match="not C-contiguous"):
        run(strides, [(given, [np.zeros((fn.numel_out(0), 2)).T, reach], 2, 1)], 1)
    frozen = reach.copy()
    frozen.setflags(write=False)
    with pytest.raises(ValueError, match="read-only"):
        run(strides, [(given, [q, frozen], 2, 1)], 1)
