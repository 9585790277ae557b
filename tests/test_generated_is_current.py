"""generated/ is what symbolic/ derives today: bytes (STYLE practices 2-3) and numbers (practice 4).

Both comparisons read the one derivation of the session fixture ``fresh_generated`` (tests/conftest.py), under
the worker's own hash seed. That the derivation does not depend on the hash seed (practice 3) is checked by `make
check-generated`, which regenerates under PYTHONHASHSEED=0 and 1, and in CI by `make check-generated-after-test`
after this suite: one more derivation, under PYTHONHASHSEED=1.
"""

from __future__ import annotations

import importlib
import importlib.util
from pathlib import Path

import casadi as ca
import numpy as np
import pytest
from helpers import derived_by_hand, inputs_by_port

import pkm
from pkm.batch import evaluate
from symbolic import codegen, generate

N_POINTS = 40


def test_committed_generated_folder_is_current(fresh_generated):
    diffs = codegen.compare_folders(generate.GENERATED, fresh_generated)
    assert diffs == [], f"generated/ is stale; run `{codegen.REFRESH_COMMAND}`:\n" + "\n".join(diffs)


def load_fresh(folder: Path, name: str) -> dict[str, ca.Function]:
    spec = importlib.util.spec_from_file_location(f"fresh_generated_{name}", folder / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build()


def with_jacobians(fn: ca.Function) -> ca.Function:
    """The function's outputs followed by the Jacobian of every output with respect to every input.

    Dense outputs: pkm.batch.evaluate reads numel (not nnz) entries per output; test_contract checks it.
    """
    ins = [ca.SX.sym(fn.name_in(i), fn.sparsity_in(i)) for i in range(fn.n_in())]
    outs = fn(*ins)
    outs = list(outs) if isinstance(outs, (list, tuple)) else [outs]
    jacobians = [ca.jacobian(o, i) for o in outs for i in ins]
    return ca.Function(f"{fn.name()}_with_jacobians", ins, [ca.densify(o) for o in outs + jacobians])


def arguments(fn: ca.Function, inputs: dict[str, np.ndarray], rng: np.random.Generator) -> list[np.ndarray]:
    """The function's inputs by name; rates and accelerations (names ending in _dot, _ddot) drawn at random."""
    n = len(inputs["x"])
    return [
        rng.normal(size=(n, fn.numel_in(i))) if name.endswith(("_dot", "_ddot")) else inputs[name]
        for i, name in enumerate(fn.name_in())
    ]


@pytest.mark.parametrize("name", derived_by_hand())
def test_committed_and_fresh_functions_agree_with_their_jacobians(fresh_generated, name):
    committed = importlib.import_module(f"generated.{name}").build()
    derived = load_fresh(fresh_generated, name)
    assert list(committed) == list(derived)
    rng = np.random.default_rng(4)
    for key, fn in committed.items():
        other = derived[key]
        assert (fn.name_in(), fn.name_out()) == (other.name_in(), other.name_out()), key
        for _ in range(3):
            inputs = inputs_by_port(pkm.load(name), rng, N_POINTS)
            args = arguments(fn, inputs, rng)
            a = evaluate(with_jacobians(fn), *args)
            b = evaluate(with_jacobians(other), *args)
            assert all(np.isfinite(v).all() for v in a[: fn.n_out()]), key
            for j, (va, vb) in enumerate(zip(a, b, strict=True)):
                np.testing.assert_allclose(va, vb, rtol=1e-12, atol=1e-12, equal_nan=True, err_msg=f"{key}[{j}]")
