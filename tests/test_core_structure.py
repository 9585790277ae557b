"""The shape of the core (DESIGN.md section 1): one direction of imports, one registry, generic modules
that name no mechanism, paper or design parameter, and generated modules whose names are the runtime's."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from helpers import derived_by_hand

import pkm
from pkm import registry
from pkm.errors import PkmError, UnknownNameError
from pkm.kinematics import GeneratedFunctions

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "pkm"
SPECIFIC = ("models", "reproduce")


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _resolve(module: str, node: ast.ImportFrom) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    is_package = MODULES[module].name == "__init__.py"
    base = base if is_package else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, *([node.module] if node.module else [])])


LATE = ("import_module", "_Delegate")  # calls whose first argument, a module's name, is an import done later


def imports(module: str) -> set[str]:
    """The pkm modules that ``module`` imports anywhere in its source (not only at the top), by an import
    statement or by name (``importlib.import_module("pkm.export")``, ``_Delegate("pkm.dynamics")``)."""
    tree = ast.parse(MODULES[module].read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant) and \
                isinstance(node.args[0].value, str) and node.args[0].value.split(".")[0] == "pkm":
            called = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
            if called in LATE:
                out.add(node.args[0].value)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.split(".")[0] == "pkm"}
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node)
            if target.split(".")[0] != "pkm":
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                out.add(sub if sub in MODULES else target)
    return {m for m in out if m in MODULES and m != module}


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    """Each pkm module's pkm imports (parsed where a test reads them, not when the suite collects)."""
    return {m: imports(m) for m in MODULES}


def test_import_graph_of_pkm_is_acyclic(graph):
    state: dict[str, int] = {}

    def visit(node: str, path: list[str]) -> None:
        state[node] = 1
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                cycle = [*path[path.index(nxt) :], nxt] if nxt in path else [node, nxt]
                pytest.fail("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt, [*path, nxt])
        state[node] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])


def test_no_module_imports_the_package_facade(graph):
    offenders = sorted(m for m, deps in graph.items() if "pkm" in deps and m not in ("pkm", "pkm.cli"))
    assert offenders == [], f"modules below the facade that import it: {offenders}"


def _names_of_the_models() -> dict[str, set[str]]:
    names: dict[str, set[str]] = {
        "mechanism": set(),
        "paper": set(registry.papers()),
        "problem": set(registry.problems()),
    }
    parameters, spaces = set(), set()
    for name in registry.mechanisms():
        m = registry.mechanism(name)
        names["mechanism"].add(name)
        parameters |= set(m.parameter_names())
        spaces |= set(m.design_spaces)
    names["design parameter"] = parameters
    names["design space"] = spaces
    return names


def _string_constants(path: Path) -> list[tuple[int, str, bool]]:
    """String constants of a module that are neither docstrings nor format specifications, with
    whether each is a subscript key (``values["name"]``)."""
    tree = ast.parse(path.read_text())
    keys = {id(n.slice) for n in ast.walk(tree) if isinstance(n, ast.Subscript)}
    docstrings = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FormattedValue) and node.format_spec is not None:
            docstrings |= {id(c) for c in ast.walk(node.format_spec)}
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant):
                docstrings.add(id(first.value))
    return [
        (node.lineno, node.value, id(node) in keys)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docstrings
    ]


def test_generic_modules_name_no_mechanism_paper_or_design_parameter():
    names = _names_of_the_models()
    words = names["mechanism"] | names["paper"]
    found = []
    for module, path in MODULES.items():
        if module.split(".")[1:2] and module.split(".")[1] in SPECIFIC:
            continue
        for line, text, key in _string_constants(path):
            for kind, values in names.items():
                # a one-letter parameter ("l", "g") counts where it is used as a key, not as any letter
                if text in values and (len(text) > 1 or key):
                    found.append(f"{module}:{line} names the {kind} {text!r}")
            for word in words:
                if re.search(rf"\b{re.escape(word)}\b", text) and text not in words:
                    found.append(f"{module}:{line} mentions {word!r} in {text!r}")
    assert found == []


def test_generic_docs_and_comments_name_no_mechanism():
    """Docstrings and comments of generic modules speak of mechanisms in general (the facade's usage
    example aside)."""
    variants = {v for n in registry.mechanisms() for v in (n, n.replace("_", "-"), n.replace("_", " "))}
    found = []
    for module, path in MODULES.items():
        if module == "pkm" or (module.split(".")[1:2] and module.split(".")[1] in SPECIFIC):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            found += [f"{module}:{number}: {v!r}" for v in variants if re.search(rf"\b{re.escape(v)}\b", line, re.I)]
    assert found == []


@pytest.mark.parametrize("name", derived_by_hand())
def test_generated_names_equal_the_runtime_names(name):
    m = pkm.load(name)
    module = __import__(f"generated.{name}", fromlist=["PARAMETERS"])
    assert m.parameter_names() == module.PARAMETERS
    assert m.pose_names == module.POSE
    assert m.actuator_names == module.ACTUATORS
    assert "inverse_kinematics" in m.functions


def test_loading_checks_the_generated_names():
    m = pkm.load("five_bar")
    wrong = GeneratedFunctions("five_bar", parameters=("a", *m.parameter_names()[1:]), pose=m.pose_names,
                               actuators=m.actuator_names)
    with pytest.raises(PkmError, match=r"PARAMETERS .* differs from the runtime's"):
        wrong.check()
    with pytest.raises(PkmError, match=r"PARAMETERS .* differs from the runtime's"):
        wrong["inverse_kinematics"]


def test_registry_resolves_every_name_and_rejects_unknown_ones():
    for name in registry.mechanisms():
        assert registry.mechanism(name).name == name
    for name, problem in registry.problems().items():
        assert registry.problem(name) is problem
        assert problem.mechanism is registry.mechanism(problem.mechanism.name)
    for key in registry.papers():
        assert callable(registry.paper(key).run)
    for spec in registry.global_indices():
        assert registry.global_index(spec.name) is spec
        assert spec.sense in ("max", "min")
        assert spec.local in registry.local_indices()
    for lookup, kind in (
        (registry.mechanism, "mechanism"),
        (registry.problem, "synthesis problem"),
        (registry.paper, "paper"),
        (registry.global_index, "index"),
        (registry.local_index, "local index"),
    ):
        with pytest.raises(UnknownNameError, match=f"unknown {kind}"):
            lookup("nothing")
