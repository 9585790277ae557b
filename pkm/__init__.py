"""pkm: design of parallel kinematic machines.

>>> import pkm
>>> m = pkm.load(pkm.mechanisms()[0])
>>> m.inverse_kinematics(m.workspace_box(m.design().vector()).mean(axis=1)).shape == (m.n_act,)
True
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from pkm import registry
from pkm.design import Design, Parameter
from pkm.errors import ComputationError, DesignError, PkmError, PoseError, SingularityError, UnknownNameError
from pkm.mechanism import Mechanism

if TYPE_CHECKING:
    from pkm.parallel import use_scheduler
    from pkm.synthesis import Objective, Problem, SynthesisResult
    from pkm.synthesis.designer import design_problem
    from pkm.synthesis.front import ParetoFront

__all__ = [
    "ComputationError",
    "Design",
    "DesignError",
    "Mechanism",
    "Parameter",
    "PkmError",
    "PoseError",
    "Problem",
    "SingularityError",
    "UnknownNameError",
    "design_problem",
    "load",
    "mechanisms",
    "pareto",
    "synthesize",
    "use_scheduler",
]

__version__ = "0.1.0"

# Imported at their first use, so that loading a mechanism does not import the synthesis and the executors.
_LAZY = {"Problem": "pkm.synthesis", "SynthesisResult": "pkm.synthesis", "use_scheduler": "pkm.parallel",
         "design_problem": "pkm.synthesis.designer"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'pkm' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})


def mechanisms() -> list[str]:
    """Names of the registered mechanisms."""
    return registry.mechanisms()


def load(name: Any) -> Mechanism:
    """The mechanism registered under ``name``, or a described machine: a description file (``.toml``), a
    mapping or a :class:`pkm.spec.schema.Description`, derived on first use (:mod:`pkm.spec`)."""
    from pkm.spec import machine, schema

    if (isinstance(name, str) and name.endswith(schema.SUFFIX)) or isinstance(name, Mapping | schema.Description):
        return machine.load(name)
    return registry.mechanism(name)


def synthesize(problem: str | Problem, **options: Any) -> SynthesisResult:
    """Solve a synthesis problem (a registered name or a :class:`pkm.synthesis.Problem`) with IPOPT and
    verify it; see :func:`pkm.synthesis.synthesize` for the options."""
    from pkm import synthesis

    if not isinstance(problem, synthesis.Problem):
        problem = registry.problem(problem)
    return synthesis.synthesize(problem, **options)


def pareto(problem: str | Problem, secondary: str | Objective, **options: Any) -> ParetoFront:
    """The verified Pareto front of a synthesis problem (a registered name or a :class:`pkm.synthesis.Problem`)
    against a secondary objective by the epsilon-constraint method; see :func:`pkm.synthesis.pareto.pareto` for
    the options."""
    from pkm import synthesis
    from pkm.synthesis.pareto import pareto as front

    if not isinstance(problem, synthesis.Problem):
        problem = registry.problem(problem)
    return front(problem, secondary, **options)
