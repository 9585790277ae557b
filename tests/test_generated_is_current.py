"""generated/ is what symbolic/ derives today: bytes (STYLE practices 2-3) and numbers (practice 4)."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import pkm
from pkm.batch import evaluate
from symbolic import codegen, generate

ROOT = Path(__file__).resolve().parent.parent
N_POINTS = 40


def test_committed_generated_folder_is_current():
    diffs = codegen.compare_or_update(generate.GENERATED, generate.write, update=False)
    assert diffs == [], f"generated/ is stale; run `{codegen.REFRESH_COMMAND}`:\n" + "\n".join(diffs)


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("fresh") / "generated"
    generate.write(out)
    return out


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


def sample_inputs(m: pkm.Mechanism, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """Valid points for the generated functions' inputs, by the names of mechanism.py's convention."""
    for _ in range(1000):
        try:
            design = m.design({p.name: p.default * (1 + 0.2 * rng.uniform(-1, 1)) for p in m.parameters})
            break
        except pkm.DesignError:
            continue
    box = m.workspace_box(design.vector())
    mode = m.working_modes[rng.integers(len(m.working_modes))]
    x = rng.uniform(box[:, 0], box[:, 1], size=(40 * N_POINTS, len(box)))
    x = x[m.reachable(x, design, mode=mode.name)][:N_POINTS]
    q = m.inverse_kinematics(x, design, mode=mode.name, passive=True)
    assemblies = np.array([m.assembly_modes[k].signs for k in rng.integers(len(m.assembly_modes), size=len(x))])
    return {
        "x": x,
        "q": q,
        "q_a": q[:, : m.n_act],
        "mode": np.array(mode.signs),
        "assembly": assemblies,
        "design": design.vector(),
    }


def arguments(fn: ca.Function, inputs: dict[str, np.ndarray], rng: np.random.Generator) -> list[np.ndarray]:
    """The function's inputs by name; rates and accelerations (names ending in _dot, _ddot) drawn at random."""
    n = len(inputs["x"])
    return [
        rng.normal(size=(n, fn.numel_in(i))) if name.endswith(("_dot", "_ddot")) else inputs[name]
        for i, name in enumerate(fn.name_in())
    ]


@pytest.mark.parametrize("name", pkm.mechanisms())
def test_committed_and_fresh_functions_agree_with_their_jacobians(fresh, name):
    committed = pkm.load(name).functions
    derived = load_fresh(fresh, name)
    assert list(committed) == list(derived)
    rng = np.random.default_rng(4)
    for key, fn in committed.items():
        other = derived[key]
        assert (fn.name_in(), fn.name_out()) == (other.name_in(), other.name_out()), key
        for _ in range(3):
            inputs = sample_inputs(pkm.load(name), rng)
            args = arguments(fn, inputs, rng)
            a = evaluate(with_jacobians(fn), *args)
            b = evaluate(with_jacobians(other), *args)
            assert all(np.isfinite(v).all() for v in a[: fn.n_out()]), key
            for j, (va, vb) in enumerate(zip(a, b, strict=True)):
                np.testing.assert_allclose(va, vb, rtol=1e-12, atol=1e-12, equal_nan=True, err_msg=f"{key}[{j}]")


def test_generation_is_independent_of_the_hash_seed(tmp_path):
    script = "import sys; from pathlib import Path; from symbolic.generate import write; write(Path(sys.argv[1]))"
    runs = {}
    for seed in ("0", "1"):
        env = {**os.environ, "PYTHONHASHSEED": seed, "PYTHONPATH": str(ROOT)}
        out = tmp_path / f"seed{seed}"
        runs[out] = subprocess.Popen([sys.executable, "-c", script, str(out)], cwd=ROOT, env=env)
    for out, proc in runs.items():
        assert proc.wait(timeout=120) == 0, out
    first, second = runs
    names = sorted(p.name for p in first.iterdir())
    assert names == sorted(p.name for p in second.iterdir())
    assert "manifest.json" in names
    for n in names:
        assert (first / n).read_bytes() == (second / n).read_bytes(), n
