"""sympy -> CasADi emitter.

A mechanism's symbolic module describes named functions (named vector inputs of sympy symbols, named
matrix outputs of sympy expressions). :func:`render_module` turns them into a readable, deterministic
Python module that builds ``casadi.Function`` objects from ``casadi.SX`` graphs after ``sympy.cse``.
:func:`compare_or_update` regenerates a whole folder into a temporary directory and either updates the
committed folder or fails with a unified diff; it is behind ``make generate`` and ``make check-generated``,
and its comparison :func:`compare_folders` behind a test.
"""

from __future__ import annotations

import difflib
import filecmp
import hashlib
import json
import shutil
import tempfile
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

REFRESH_COMMAND = "make generate"


@dataclass(frozen=True)
class Port:
    """A named vector input: an ordered tuple of sympy symbols and a one-line meaning."""

    name: str
    symbols: tuple[sp.Symbol, ...]
    doc: str


@dataclass(frozen=True)
class Output:
    """A named matrix output (column-major in CasADi) and a one-line meaning."""

    name: str
    expr: sp.Matrix
    doc: str


@dataclass(frozen=True)
class FunctionSpec:
    """One emitted ``casadi.Function``: its name, inputs, outputs and docstring."""

    name: str
    inputs: tuple[Port, ...]
    outputs: tuple[Output, ...]
    doc: str


@dataclass
class ModuleSpec:
    """Everything emitted for one mechanism into ``generated/<name>.py``.

    ``parameters``, ``pose`` and ``actuators`` are the names of the symbols of the design port, the
    pose port and the actuated joints (set by :func:`symbolic.kinematics.add_kinematics`); they are
    emitted as the module's ``PARAMETERS``, ``POSE`` and ``ACTUATORS`` for the runtime to check; ``limits``
    names the margins of a ``workspace_margins`` function, emitted as ``LIMITS`` where there are any.
    """

    name: str
    source: str
    doc: str
    functions: list[FunctionSpec] = field(default_factory=list)
    parameters: tuple[str, ...] = ()
    pose: tuple[str, ...] = ()
    actuators: tuple[str, ...] = ()
    limits: tuple[str, ...] = ()

    def add(
        self,
        name: str,
        inputs: Sequence[Port],
        outputs: Sequence[Output],
        doc: str,
    ) -> None:
        """Register a function; output expressions may only use the symbols of the inputs."""
        known = {s for port in inputs for s in port.symbols}
        for out in outputs:
            stray = sorted(free_symbols(out.expr) - known, key=sp.default_sort_key)
            if stray:
                raise ValueError(f"{self.name}.{name}: output {out.name} uses undeclared symbols {stray}")
        self.functions.append(FunctionSpec(name, tuple(inputs), tuple(outputs), doc))


def free_symbols(expr: sp.Basic) -> set[sp.Symbol]:
    """The symbols of an expression (or matrix), each shared subexpression walked once: sympy's free_symbols walks
    a subexpression at each of its occurrences, seconds for a closed form that repeats a large one. Every symbol
    counts, a bound one (a Sum's, a Lambda's) too: the derivations bind none."""
    seen: set[sp.Basic] = set()
    found: set[sp.Symbol] = set()
    stack = list(expr) if isinstance(expr, sp.MatrixBase) else [expr]
    while stack:
        e = stack.pop()
        if e in seen:
            continue
        seen.add(e)
        if isinstance(e, sp.Symbol):
            found.add(e)
        stack.extend(e.args)
    return found


class UndefinedError(ValueError):
    """An expression to be emitted holds a value that is not a finite number (sympy's nan, oo or zoo)."""


def docstring(text: str) -> str:
    """A docstring's literal: triple-quoted where the text is plain (no backslash, no quote at its end or
    three in a row, printable lines), else the text's ``repr``: no text becomes code."""
    plain = ("\\" not in text and '"""' not in text and not text.endswith('"')
             and all(line.isprintable() for line in text.split("\n")))
    return f'"""{text}"""' if plain else repr(text)


class CasadiPrinter(PythonCodePrinter):
    """Prints sympy expressions as Python operating on ``casadi.SX`` (module imported as ``ca``)."""

    _kf: ClassVar[dict[str, str]] = {k: "ca." + v.split(".")[-1] for k, v in PythonCodePrinter._kf.items()}

    def __init__(self, names: dict[sp.Symbol, str]) -> None:
        super().__init__({"fully_qualified_modules": True})
        self._names = names

    def _print_Symbol(self, expr: sp.Symbol) -> str:
        return self._names[expr]

    def _print_Pow(self, expr: sp.Pow, rational: bool = False) -> str:
        return self._hprint_Pow(expr, rational=rational, sqrt="ca.sqrt")

    def _print_Abs(self, expr: sp.Abs) -> str:
        return f"ca.fabs({self._print(expr.args[0])})"

    def _print_sign(self, expr: sp.sign) -> str:
        return f"ca.sign({self._print(expr.args[0])})"

    def _print_Min(self, expr: sp.Min) -> str:
        return self._fold("ca.fmin", expr.args)

    def _print_Max(self, expr: sp.Max) -> str:
        return self._fold("ca.fmax", expr.args)

    def _fold(self, func: str, args: tuple[sp.Expr, ...]) -> str:
        text = self._print(args[0])
        for arg in args[1:]:
            text = f"{func}({text}, {self._print(arg)})"
        return text

    def _print_Pi(self, _expr: sp.Expr) -> str:
        return "ca.pi"

    def _undefined(self, expr: sp.Expr) -> str:
        raise UndefinedError(f"the value {expr} is not a finite number")

    _print_NaN = _print_Infinity = _print_NegativeInfinity = _print_ComplexInfinity = _undefined

    def _print_Float(self, expr: sp.Float) -> str:
        return repr(float(expr))

    def _print_Piecewise(self, expr: sp.Piecewise) -> str:
        *pieces, (last, cond) = expr.args
        if cond is not sp.true:
            raise ValueError("a Piecewise needs a final (expr, True) piece to be emitted")
        text = self._print(last)
        for value, test in reversed(pieces):
            text = f"ca.if_else({self._print(test)}, {self._print(value)}, {text})"
        return text

    def _print_Relational(self, expr: sp.core.relational.Relational) -> str:
        return f"({self._print(expr.lhs)} {expr.rel_op} {self._print(expr.rhs)})"


def _one_quotient(
    replacements: list[tuple[sp.Symbol, sp.Expr]], reduced: list[sp.Expr]
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], list[sp.Expr]]:
    """Products with several reciprocals that cse named (``_t8 = 1/_t1``, ``_t9 = 1/_t4``, ``_t7*_t8*_t9``)
    written over one denominator (``_t7/(_t1*_t4)``): CasADi evaluates each product with a reciprocal as a
    division, so that the kernels would divide once per reciprocal instead of once."""
    reciprocal = {lhs: 1 / rhs.base for lhs, rhs in replacements if rhs.is_Pow and rhs.exp == -1}

    def quotients(expr: sp.Expr) -> sp.Expr:
        return expr.replace(lambda e: e.is_Mul and sum(f in reciprocal for f in e.args) >= 2,
                            lambda e: e.xreplace(reciprocal))

    return [(lhs, quotients(rhs)) for lhs, rhs in replacements], [quotients(e) for e in reduced]


def _render_function(spec: FunctionSpec, *, canonical: bool) -> list[str]:
    names: dict[sp.Symbol, str] = {}
    doc = [spec.doc, "", "    Inputs:"]
    for port in spec.inputs:
        members = ", ".join(str(s) for s in port.symbols)
        doc.append(f"        {port.name} ({len(port.symbols)}): [{members}] {port.doc}")
    doc.append("    Outputs:")
    for out in spec.outputs:
        doc.append(f"        {out.name} ({out.expr.rows}x{out.expr.cols}, column-major): {out.doc}")
    lines = [f"def {spec.name}():", "    " + docstring("\n".join([*doc, "    "]))]
    for port in spec.inputs:
        lines.append(f'    {port.name} = ca.SX.sym("{port.name}", {len(port.symbols)})')
        for k, s in enumerate(port.symbols):
            names[s] = f"{port.name}_{k}"
            lines.append(f"    {port.name}_{k} = {port.name}[{k}]")

    flat = [e for out in spec.outputs for e in out.expr.T]
    symbols = (sp.Symbol(f"_t{k}") for k in range(10**9))
    replacements, reduced = sp.cse(flat, symbols=symbols, order="canonical" if canonical else "none")
    replacements, reduced = _one_quotient(replacements, reduced)
    ops = sum(sp.count_ops(rhs) for _, rhs in replacements) + sum(sp.count_ops(e) for e in reduced)
    lines.append(f"    # {len(replacements)} common subexpressions, {ops} operations")
    for lhs, _ in replacements:
        names[lhs] = str(lhs)
    printer = CasadiPrinter(names)
    for lhs, rhs in replacements:
        lines.append(f"    {lhs} = {printer.doprint(rhs)}")
    pos = 0
    for out in spec.outputs:
        n = out.expr.rows * out.expr.cols
        items = ", ".join(printer.doprint(e) for e in reduced[pos : pos + n])
        pos += n
        lines.append(f"    {out.name} = ca.reshape(ca.vertcat({items}), {out.expr.rows}, {out.expr.cols})")
    in_names = ", ".join(f'"{p.name}"' for p in spec.inputs)
    out_names = ", ".join(f'"{o.name}"' for o in spec.outputs)
    ins = ", ".join(p.name for p in spec.inputs)
    outs = ", ".join(o.name for o in spec.outputs)
    lines.append(f'    return ca.Function("{spec.name}", [{ins}], [{outs}], [{in_names}], [{out_names}])')
    return lines


def _tuple(names: Iterable[str]) -> str:
    """A tuple of strings as Python text, one trailing comma each so that one name is still a tuple."""
    return "(" + "".join(f'"{n}", ' for n in names) + ")"


def render_module(spec: ModuleSpec, source_hash: str, *, canonical: bool = True) -> str:
    """Render a mechanism's functions as the text of a generated Python module; ``canonical``: the common
    subexpressions in sympy's canonical order, the same text from every run (generated/'s), else in the order
    found, in seconds where the canonical order's sorting of large repeated subexpressions takes minutes (a
    described machine's module, kept in the cache by its description's key)."""
    lines = [
        f"# Generated from {spec.source} (source sha256 {source_hash}).",
        f"# Do not edit: regenerate with `{REFRESH_COMMAND}`.",
        "# ruff: noqa",
        docstring(spec.doc),
        "",
        "import casadi as ca",
        "",
        f'SOURCE_HASH = "{source_hash}"',
        "FUNCTIONS = " + _tuple(f.name for f in spec.functions),
        "PARAMETERS = " + _tuple(spec.parameters),
        "POSE = " + _tuple(spec.pose),
        "ACTUATORS = " + _tuple(spec.actuators),
        *(["LIMITS = " + _tuple(spec.limits)] if spec.limits else []),
        "",
    ]
    for fn in spec.functions:
        lines.append("")
        lines.extend(_render_function(fn, canonical=canonical))
        lines.append("")
    lines += [
        "",
        "def build():",
        '    """All functions of this module by name."""',
        "    return {name: globals()[name]() for name in FUNCTIONS}",
        "",
    ]
    return "\n".join(lines)


def source_hash(root: Path, paths: Sequence[Path]) -> str:
    """sha256 over the given source files (paths relative to ``root``), in the given order.

    Each file contributes its relative path, so that moving or renaming a file changes the hash.
    """
    digest = hashlib.sha256()
    for path in paths:
        digest.update(path.as_posix().encode())
        digest.update((root / path).read_bytes())
    return digest.hexdigest()[:16]


@dataclass(frozen=True)
class RenderedModule:
    """A module's text and what the manifest records of it (small, so that it travels between processes)."""

    name: str
    source: str
    source_hash: str
    functions: tuple[str, ...]
    text: str

    @classmethod
    def of(cls, spec: ModuleSpec, source_hash: str, *, canonical: bool = True) -> RenderedModule:
        return cls(spec.name, spec.source, source_hash, tuple(f.name for f in spec.functions),
                   render_module(spec, source_hash, canonical=canonical))


def write_tree(out: Path, modules: Sequence[RenderedModule], tools: dict[str, str]) -> None:
    """Write ``<name>.py`` for each module, ``__init__.py`` and ``manifest.json`` into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    names = sorted(m.name for m in modules)
    init = [
        "# Generated by `make generate`. Do not edit.",
        "# ruff: noqa",
        '"""CasADi functions generated from symbolic/ (one module per mechanism)."""',
        "",
        "MECHANISMS = " + _tuple(names),
        "",
    ]
    (out / "__init__.py").write_text("\n".join(init))
    files = {}
    for module in modules:
        (out / f"{module.name}.py").write_text(module.text)
        files[f"{module.name}.py"] = {
            "source": module.source,
            "source_sha256": module.source_hash,
            "functions": list(module.functions),
        }
    manifest = {"files": files, "tools": tools}
    (out / "manifest.json").write_text(json.dumps(manifest, indent=2, sort_keys=True) + "\n")


MANIFEST_VOLATILE = ("tools",)


def _comparable(path: Path) -> str:
    text = path.read_text()
    if path.name == "manifest.json":
        data = json.loads(text)
        for key in MANIFEST_VOLATILE:
            data.pop(key, None)
        return json.dumps(data, indent=2, sort_keys=True)
    return text


def compare_folders(target: Path, fresh: Path) -> list[str]:
    """The differences of the committed folder ``target`` from a freshly written one: file set and
    unified diffs; empty when ``target`` is current.

    Tool versions in the manifest are not compared, so that the check does not depend on the installed
    sympy.
    """
    diffs: list[str] = []
    old = {p.name for p in target.glob("*") if p.is_file()} if target.exists() else set()
    new = {p.name for p in fresh.glob("*") if p.is_file()}
    diffs += [f"missing from {target}: {n}" for n in sorted(new - old)]
    diffs += [f"stale in {target}: {n}" for n in sorted(old - new)]
    for name in sorted(old & new):
        a, b = target / name, fresh / name
        if filecmp.cmp(a, b, shallow=False):
            continue
        sa, sb = _comparable(a), _comparable(b)
        if sa == sb:
            continue
        diff = difflib.unified_diff(
            sa.splitlines(), sb.splitlines(), f"committed/{name}", f"regenerated/{name}", lineterm="", n=2
        )
        diffs.append("\n".join(list(diff)[:200]))
    return diffs


def compare_or_update(target: Path, write: Callable[[Path], None], *, update: bool) -> list[str]:
    """Regenerate into a temporary folder and compare with ``target`` (:func:`compare_folders`).

    Returns the list of differences; empty when ``target`` is current. With ``update`` the files that
    differ are replaced and the stale ones removed; the others are left untouched, so that a build that
    depends on them is not redone.
    """
    with tempfile.TemporaryDirectory() as tmp:
        fresh = Path(tmp) / "generated"
        write(fresh)
        diffs = compare_folders(target, fresh)
        if diffs and update:
            target.mkdir(parents=True, exist_ok=True)
            made = {p.name for p in fresh.glob("*") if p.is_file()}
            for stale in (p for p in target.glob("*") if p.is_file() and p.name not in made):
                stale.unlink()
            for name in sorted(made):
                if not (target / name).is_file() or not filecmp.cmp(fresh / name, target / name, shallow=False):
                    shutil.copyfile(fresh / name, target / name)
        return diffs
