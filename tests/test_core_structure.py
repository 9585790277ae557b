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


def _module_name(path: Path, root: Path = ROOT) -> str:
    parts = path.relative_to(root).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules(root: Path, packages: tuple[str, ...]) -> dict[str, Path]:
    """The modules of ``packages`` (folders below ``root``) by their dotted names."""
    return {_module_name(p, root): p for package in packages for p in sorted((root / package).rglob("*.py"))}


MODULES = modules(ROOT, ("pkm",))
LATE = ("import_module", "_Delegate")  # calls whose first argument, a module's name, is an import done later


def _resolve(module: str, node: ast.ImportFrom, known: dict[str, Path]) -> str:
    if node.level == 0:
        return node.module or ""
    base = module.split(".")
    base = base if known[module].name == "__init__.py" else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join([*base, *([node.module] if node.module else [])])


def _named(node: ast.Call, known: dict[str, Path]) -> set[str]:
    """The modules a late import names: a constant's, or every module below an f-string's constant prefix
    (``import_module(f"pkm.regions.{name}")``)."""
    called = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
    if called not in LATE or not node.args:
        return set()
    first = node.args[0]
    if isinstance(first, ast.Constant) and isinstance(first.value, str):
        return {first.value}
    if isinstance(first, ast.JoinedStr) and first.values and isinstance(first.values[0], ast.Constant):
        prefix = first.values[0].value
        return {m for m in known if m.startswith(prefix)} if prefix.endswith(".") else set()
    return set()


def _packages_entered(module: str, target: str) -> set[str]:
    """The packages an import of ``target`` runs the __init__ of, beside the target: those above it that do
    not hold ``module`` too (a module's own packages are already being imported)."""
    parts = target.split(".")
    above = {".".join(parts[:n]) for n in range(2, len(parts))}
    return {p for p in above if not (module == p or module.startswith(p + "."))}


def imports(module: str, known: dict[str, Path] = MODULES) -> set[str]:
    """The modules of ``known`` that ``module`` imports anywhere in its source (at the top, in a function, by an
    import statement or by name: ``importlib.import_module("pkm.export")``, ``_Delegate("pkm.dynamics")``), and
    the packages whose __init__ such an import runs (pkm.spec for pkm.spec.vocabulary, from outside pkm.spec)."""
    tree = ast.parse(known[module].read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            out |= _named(node, known)
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, node, known)
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                out.add(sub if sub in known else target)
    out |= {p for target in list(out) for p in _packages_entered(module, target)}
    return {m for m in out if m in known and m != module}


def import_graph(known: dict[str, Path]) -> dict[str, set[str]]:
    return {m: imports(m, known) for m in known}


def cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """An import cycle of ``graph``, or None."""
    state: dict[str, int] = {}

    def visit(node: str, path: list[str]) -> list[str] | None:
        state[node] = 1
        for nxt in sorted(graph[node]):
            if state.get(nxt) == 1:
                return [*path[path.index(nxt) :], nxt]
            if nxt not in state:
                found = visit(nxt, [*path, nxt])
                if found:
                    return found
        state[node] = 2
        return None

    for module in sorted(graph):
        if module not in state:
            found = visit(module, [module])
            if found:
                return found
    return None


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    """Each pkm module's pkm imports (parsed where a test reads them, not when the suite collects)."""
    return import_graph(MODULES)


def test_import_graph_of_pkm_and_bench_is_acyclic():
    found = cycle(import_graph(modules(ROOT, ("pkm", "bench"))))
    assert found is None, "import cycle: " + " -> ".join(found or [])


def test_a_cycle_through_a_late_import_or_a_package_is_found(tmp_path):
    """A cycle that passes through importlib.import_module by name, an f-string's module or a package's
    __init__ is a cycle of the graph; the same modules without the closing edge are none."""
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "__init__.py").write_text("from pkg import a\n")
    (package / "sub" / "leaf.py").write_text("X = 1\n")
    (package / "b.py").write_text("def f():\n    from pkg.sub.leaf import X\n    return X\n")
    cases = {
        "import_module": "import importlib\n\ndef f():\n    return importlib.import_module('pkg.b')\n",
        "f-string": "from importlib import import_module\n\ndef f(n):\n    return import_module(f'pkg.{n}')\n",
        "none": "X = 1\n",
    }
    for name, text in cases.items():
        (package / "a.py").write_text(text)
        found = cycle(import_graph(modules(tmp_path, ("pkg",))))
        if name == "none":
            assert found is None
        else:
            assert found is not None, name
            assert {"pkg.a", "pkg.b", "pkg.sub"} <= set(found), (name, found)


def test_no_module_imports_the_package_facade(graph):
    offenders = sorted(m for m, deps in graph.items() if "pkm" in deps and m != "pkm")
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


MODULE_LINES = 800  # the longest module of pkm
FUNCTION_LINES = 100  # the longest function of pkm, a paper's run() aside (its steps read in the paper's order)


def test_no_module_or_function_of_pkm_is_too_long_to_read():
    found = []
    for module, path in MODULES.items():
        text = path.read_text()
        if text.count("\n") > MODULE_LINES:
            found.append(f"{module}: {text.count(chr(10))} lines")
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                lines = node.end_lineno - node.lineno + 1
                paper_run = module.startswith("pkm.reproduce.") and node.name == "run"
                if lines > FUNCTION_LINES and not paper_run:
                    found.append(f"{module}.{node.name}: {lines} lines")
    assert found == []
