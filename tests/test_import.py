"""Loading a mechanism imports what evaluating it needs and nothing more: plotting, SciPy, Dask, the
synthesis, the executors, the dynamics and the other mechanisms' packages load at their first use (issue 12:
``import pkm; pkm.load(...)`` in under 0.3 s, measured by ``python -m bench.import_time``, never here)."""

from __future__ import annotations

import inspect
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import pkm
from pkm import dynamics, parallel, synthesis

ROOT = Path(__file__).resolve().parent.parent

LOAD_AND_EVALUATE = """
import json, sys
import pkm
m = pkm.load("five_bar")
pose = m.workspace_box(m.design().vector()).mean(axis=1)
q = m.inverse_kinematics(pose)
print(json.dumps({"q": q.tolist(), "modules": sorted(sys.modules)}))
"""

LIST_PAPERS = """
import json, sys
from pkm import registry
print(json.dumps({"papers": sorted(registry.papers()), "modules": sorted(sys.modules)}))
"""

NOT_FOR_A_MECHANISM = ("matplotlib", "scipy", "dask", "distributed", "pkm.synthesis", "pkm.parallel", "pkm.dynamics")


def _fresh(script: str) -> dict:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    done = subprocess.run(
        [sys.executable, "-c", script], cwd=ROOT, env=env, capture_output=True, text=True, timeout=120, check=True
    )
    return json.loads(done.stdout.splitlines()[-1])


def _imported(modules: list[str], package: str) -> list[str]:
    return [name for name in modules if name == package or name.startswith(package + ".")]


@pytest.fixture(scope="module")
def loaded() -> dict:
    return _fresh(LOAD_AND_EVALUATE)


def test_loading_and_evaluating_a_mechanism_evaluates(loaded):
    m = pkm.load("five_bar")
    pose = m.workspace_box(m.design().vector()).mean(axis=1)
    assert loaded["q"] == pytest.approx(m.inverse_kinematics(pose).tolist(), rel=1e-12)


@pytest.mark.parametrize("package", NOT_FOR_A_MECHANISM)
def test_loading_and_evaluating_a_mechanism_does_not_import(loaded, package):
    assert _imported(loaded["modules"], package) == []


def test_loading_a_mechanism_imports_its_own_model_package_only(loaded):
    packages = {name.split(".")[2] for name in _imported(loaded["modules"], "pkm.models") if name.count(".") >= 2}
    assert packages == {"five_bar"}


def test_finding_the_papers_draws_nothing():
    report = _fresh(LIST_PAPERS)
    assert report["papers"]
    assert _imported(report["modules"], "matplotlib") == []


def test_the_lazy_names_of_pkm_are_the_modules_own():
    assert pkm.Problem is synthesis.Problem
    assert pkm.SynthesisResult is synthesis.SynthesisResult
    assert pkm.use_scheduler is parallel.use_scheduler
    assert {"Problem", "SynthesisResult", "use_scheduler"} <= set(dir(pkm))
    with pytest.raises(AttributeError, match="no_such_name"):
        pkm.no_such_name  # noqa: B018


@pytest.mark.parametrize("method", ["inertia_matrix", "inverse_dynamics", "natural_frequencies", "simulate"])
def test_the_dynamics_methods_keep_their_functions_signature_and_docstring(method):
    function = getattr(dynamics, method)
    bound = getattr(pkm.load("five_bar"), method)
    assert inspect.getdoc(bound) == inspect.getdoc(function) == inspect.getdoc(getattr(pkm.Mechanism, method))
    assert list(inspect.signature(bound).parameters) == list(inspect.signature(function).parameters)[1:]
