"""pkm: design of parallel kinematic machines.

>>> import pkm
>>> m = pkm.load("five_bar")
>>> m.inverse_kinematics([0.0, 1.5], {"r1": 1.2, "r2": 1.0, "r3": 0.8}, mode="out_out").shape
(2,)
"""

from __future__ import annotations

from functools import cache

from pkm.design import Design, Parameter
from pkm.errors import ComputationError, DesignError, PkmError, PoseError, SingularityError, UnknownNameError
from pkm.mechanism import Mechanism

__all__ = [
    "ComputationError",
    "Design",
    "DesignError",
    "Mechanism",
    "Parameter",
    "PkmError",
    "PoseError",
    "SingularityError",
    "UnknownNameError",
    "load",
    "mechanisms",
    "synthesize",
]

__version__ = "0.1.0"


def _registry() -> dict[str, type[Mechanism]]:
    from pkm.models.five_bar import FiveBar
    from pkm.models.slider_gantry import SliderGantry, SliderGantrySymmetric

    return {cls.name: cls for cls in (FiveBar, SliderGantry, SliderGantrySymmetric)}


def mechanisms() -> list[str]:
    """Names of the registered mechanisms."""
    return sorted(_registry())


@cache
def load(name: str) -> Mechanism:
    """The mechanism registered under ``name``."""
    registry = _registry()
    if name not in registry:
        raise UnknownNameError("mechanism", name, sorted(registry))
    return registry[name]()


def synthesize(problem: str, **options):
    """Solve a registered synthesis problem with IPOPT; see :func:`pkm.synthesis.synthesize`."""
    from pkm.synthesis import synthesize as _synthesize

    return _synthesize(problem, **options)
