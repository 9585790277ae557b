"""The one place where a name becomes a mechanism, a synthesis problem, an index or a paper.

Mechanisms and their problems are discovered in the packages of :mod:`pkm.models`: each exports
``MECHANISMS`` (its Mechanism classes), and its module ``problems`` defines ``problems()`` (its
synthesis problems, built on first use).
Papers are the modules of :mod:`pkm.reproduce` that define ``TITLE`` and ``run``. Indices come from the catalogues
of :mod:`pkm.indices`. Everything below this module takes objects, never names.
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import pkgutil
from functools import cache
from types import ModuleType
from typing import TYPE_CHECKING, Any

from pkm.errors import UnknownNameError, check_name

if TYPE_CHECKING:
    from pkm.indices import GlobalIndex, LocalIndex

MODELS = "pkm.models"
PAPERS = "pkm.reproduce"


def _submodule_names(package: str) -> list[str]:
    root = importlib.import_module(package)
    return [f"{package}.{m.name}" for m in pkgutil.iter_modules(root.__path__)]


def _submodules(package: str) -> list[ModuleType]:
    return [importlib.import_module(name) for name in _submodule_names(package)]


@cache
def _model_packages() -> tuple[ModuleType, ...]:
    return tuple(m for m in _submodules(MODELS) if hasattr(m, "MECHANISMS"))


@cache
def _mechanism_classes() -> dict[str, type]:
    return {cls.name: cls for package in _model_packages() for cls in package.MECHANISMS}


def mechanisms() -> list[str]:
    """Names of the registered mechanisms."""
    return sorted(_mechanism_classes())


def mechanism(name: str) -> Any:
    """The mechanism registered under ``name`` (one instance per name), its generated names checked."""
    if not isinstance(name, str) or _mechanism_class(name) is None:
        raise UnknownNameError("mechanism", name, mechanisms())
    return _instance(name)


DESCRIBED = "description:"  # a reference to a described machine begins with it, its description follows as JSON


def reference(mech: Any) -> str | None:
    """A text that names ``mech`` in another process (a task for a worker carries it, never the object):
    its registered name, or for a machine described as data its normalised description as JSON; None for
    any other object."""
    if mech.name in mechanisms() and mechanism(mech.name) is mech:
        return mech.name
    description = getattr(mech, "description", None)
    if description is not None:
        return DESCRIBED + json.dumps(description.data)
    return None


def label(text: str) -> str:
    """A reference's mechanism name, for messages."""
    return json.loads(text[len(DESCRIBED) :])["name"] if text.startswith(DESCRIBED) else text


@cache
def _mechanism_class(name: str) -> type | None:
    """The class registered under ``name``, found without importing every model package: the packages
    are searched one at a time, first those whose name ``name`` begins with (its own)."""
    packages = sorted(_submodule_names(MODELS), key=lambda package: not name.startswith(package.rsplit(".", 1)[1]))
    for package in packages:
        for cls in getattr(importlib.import_module(package), "MECHANISMS", ()):
            if cls.name == name:
                return cls
    return None


@cache
def _instance(name: str) -> Any:
    mech = _mechanism_class(name)()
    mech.functions.check()
    return mech


@cache
def problems() -> dict[str, Any]:
    """Every registered synthesis problem by name."""
    out = {}
    for package in _model_packages():
        if importlib.util.find_spec(f"{package.__name__}.problems") is not None:
            out.update({p.name: p for p in importlib.import_module(f"{package.__name__}.problems").problems()})
    return out


def problem(name: str) -> Any:
    """The synthesis problem registered under ``name``."""
    known = problems()
    if check_name("synthesis problem", name, sorted(known)) not in known:
        raise UnknownNameError("synthesis problem", name, sorted(known))
    return known[name]


def local_indices() -> tuple[LocalIndex, ...]:
    from pkm.indices import LOCAL_INDICES

    return LOCAL_INDICES


def global_indices() -> tuple[GlobalIndex, ...]:
    from pkm.indices import GLOBAL_INDICES

    return GLOBAL_INDICES


def local_index(name: str) -> LocalIndex:
    """The local index called ``name``."""
    known = local_indices()
    check_name("local index", name, [s.name for s in known])
    for spec in known:
        if spec.name == name:
            return spec
    raise UnknownNameError("local index", name, [s.name for s in known])


def global_index(name: str) -> GlobalIndex:
    """The global index called ``name``."""
    known = global_indices()
    check_name("index", name, [s.name for s in known])
    for spec in known:
        if spec.name == name:
            return spec
    raise UnknownNameError("index", name, [s.name for s in known])


@cache
def papers() -> dict[str, ModuleType]:
    """The reproducible papers by key: the modules of :mod:`pkm.reproduce` with ``TITLE`` and ``run``."""
    return {m.__name__.rsplit(".", 1)[1]: m for m in _submodules(PAPERS) if hasattr(m, "run") and hasattr(m, "TITLE")}


def paper(key: str) -> ModuleType:
    """The reproduction module of the paper ``key``."""
    known = papers()
    if check_name("paper", key, [*sorted(known), "all"]) not in known:
        raise UnknownNameError("paper", key, [*sorted(known), "all"])
    return known[key]
