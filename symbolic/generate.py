"""``python -m symbolic.generate [--check] [--out DIR]``: write or check ``generated/``."""

from __future__ import annotations

import argparse
import multiprocessing
import os
import platform
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import casadi
import sympy as sp

from symbolic import codegen
from symbolic.mechanisms import MECHANISMS

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def sources(spec: codegen.ModuleSpec) -> list[Path]:
    """The files whose bytes determine a mechanism's generated module, relative to the repository root
    and sorted: every module of symbolic/ outside symbolic/mechanisms/ and symbolic/described/, and the
    mechanism's own source.

    The shared modules are found, not listed, so that a new helper cannot be forgotten; the other
    mechanisms' sources are left out, so that editing one mechanism does not restamp the others, and so is
    the derivation of machines described as data, which no hand-derived module runs.
    """
    here = ROOT / "symbolic"
    shared = [p.relative_to(ROOT) for p in here.rglob("*.py")
              if p.relative_to(here).parts[0] not in ("mechanisms", "described")]
    return sorted({*shared, Path(spec.source)}, key=Path.as_posix)


def derive(name: str) -> codegen.RenderedModule:
    """One registered mechanism's module, rendered, with the hash of its sources."""
    spec = MECHANISMS[name]()
    return codegen.RenderedModule.of(spec, codegen.source_hash(ROOT, sources(spec)))


def write(out: Path) -> None:
    """Derive every registered mechanism and write the generated tree into ``out``. On Linux the
    derivations run in forked processes, one per core (each is independent and deterministic); elsewhere
    one after the other. The manifest records the tools, CasADi's version among them (the builders are
    written for its API; pkm.compiled.status() reports a runtime with another)."""
    names = sorted(MECHANISMS)
    workers = min(len(names), os.cpu_count() or 1)
    if workers > 1 and sys.platform == "linux":
        with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("fork")) as pool:
            modules = list(pool.map(derive, names))
    else:
        modules = [derive(name) for name in names]
    tools = {"casadi": casadi.__version__, "python": platform.python_version(), "sympy": sp.__version__}
    codegen.write_tree(out, modules, tools)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--check", action="store_true", help="fail if generated/ is not current")
    parser.add_argument("--out", type=Path, default=GENERATED, help="target folder")
    args = parser.parse_args(argv)
    diffs = codegen.compare_or_update(args.out, write, update=not args.check)
    if diffs and args.check:
        print("\n".join(diffs), file=sys.stderr)
        print(f"{args.out} is stale: run `{codegen.REFRESH_COMMAND}`.", file=sys.stderr)
        return 1
    print(f"{args.out}: {'updated' if diffs else 'current'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
