"""What a new user waits for: ``python -m bench.first_use [--json PATH] [--no-demo] [--no-install]``.

* ``make demo`` on a fresh clone of HEAD (a new virtual environment, pkm installed, the Gao 1998
  reproduction from an empty kernel cache), wall time; pip's download cache is the machine's own, so the
  figure is the install and the compiles, not the network;
* ``pip install --no-deps .`` into a fresh virtual environment (pkm's own install: nothing is compiled);
* ``pkm build MECHANISM`` of every mechanism from an empty cache: wall time and the compilers' CPU time;
* the first and the second call of ``five_bar.global_index("gci", region="miw", gradient=True)`` and of
  ``pkm.synthesize`` of every registered problem, each in a fresh process with an empty kernel cache
  (the first call compiles what it needs, the second finds it compiled).

Every step runs in a process of its own with ``PKM_CACHE_DIR`` set to a new, empty folder. Nothing
asserts on time.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from bench.report import log, machine, write_json

ROOT = Path(__file__).resolve().parent.parent

CHILD = """
import json, sys, time
start = time.perf_counter()
import pkm
from pkm import compiled
kind, name = sys.argv[1], sys.argv[2]
out = {"import_s": time.perf_counter() - start}
for call in (1, 2):
    start = time.perf_counter()
    if kind == "gci":
        pkm.load("five_bar").global_index("gci", region="miw", gradient=True)
    else:
        result = pkm.synthesize(name)
        out["status"] = result.status
    out[f"call{call}_s"] = time.perf_counter() - start
out["evaluations"] = compiled.status()["evaluations"]
print(json.dumps(out))
"""


def _run(command: list[str], cwd: Path, cache: Path, **env: str) -> tuple[float, subprocess.CompletedProcess]:
    start = time.perf_counter()
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, check=False,
                          env={**os.environ, "PKM_CACHE_DIR": str(cache), "MPLBACKEND": "Agg", **env})
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return seconds, done


def demo(tmp: Path) -> dict[str, Any]:
    """``make demo`` on a fresh clone of HEAD."""
    clone = tmp / "clone"
    subprocess.run(["git", "clone", "--quiet", str(ROOT), str(clone)], check=True)
    seconds, _ = _run(["make", "demo"], clone, tmp / "demo-cache", PYTHON=sys.executable)
    log(f"make demo on a fresh clone: {seconds:.1f} s")
    return {"wall_s": seconds}


def install(tmp: Path) -> dict[str, Any]:
    """``pip install --no-deps .`` into a fresh virtual environment."""
    venv = tmp / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    seconds, _ = _run([str(venv / "bin" / "python"), "-m", "pip", "install", "--quiet", "--no-deps", str(ROOT)],
                      tmp, tmp / "install-cache")
    log(f"pip install --no-deps .: {seconds:.1f} s")
    return {"wall_s": seconds}


def builds(tmp: Path) -> dict[str, Any]:
    """``pkm build MECHANISM`` of every mechanism, each from an empty cache."""
    import pkm

    out = {}
    for name in pkm.mechanisms():
        seconds, done = _run([sys.executable, "-m", "pkm.cli", "build", name, "--json"], ROOT, tmp / f"build-{name}")
        counts = json.loads(done.stdout)["mechanisms"][name]
        out[name] = {"wall_s": seconds, "compiler_cpu_s": counts["compiler_cpu_s"], "kernels": counts["compiled"]}
        log(f"pkm build {name}: {counts['compiled']} kernels, {seconds:.1f} s wall, "
            f"{counts['compiler_cpu_s']:.1f} s of compiler CPU")
    return out


def first_calls(tmp: Path) -> dict[str, Any]:
    """First and second calls, each case in a fresh process with an empty cache."""
    import pkm

    cases = [("gci", "five_bar.global_index('gci', region='miw', gradient=True)")]
    cases += [("synthesize", name) for name in sorted(pkm.registry.problems())]
    out = {}
    for k, (kind, name) in enumerate(cases):
        _, done = _run([sys.executable, "-c", CHILD, kind, name], ROOT, tmp / f"calls-{k}")
        out[name] = json.loads(done.stdout.strip().splitlines()[-1])
        log(f"{name}: first call {out[name]['call1_s']:.2f} s, second {out[name]['call2_s']:.3f} s")
    return out


def markdown(report: dict[str, Any], before: dict[str, Any]) -> str:
    """The tables docs/benchmarks.md quotes: this run beside ``before`` (the same figures measured before
    compiling on demand, docs/benchmarks/first_use_before.json)."""
    lines = ["| step | before (s) | now (s) |", "|---|---:|---:|"]
    steps = (("demo", "`make demo` on a fresh clone (install, compiles, Gao 1998)"),
             ("install", "`pip install .` (before: with its kernels; now: `--no-deps`, nothing to compile)"))
    lines += [f"| {label} | {before[key]['wall_s']:.1f} | {report[key]['wall_s']:.1f} |" for key, label in steps
              if key in report]
    lines += ["", "| `pkm build`, empty cache | kernels | wall (s) | compiler CPU (s) |", "|---|---:|---:|---:|"]
    lines += [f"| {name} | {b['kernels']} | {b['wall_s']:.1f} | {b['compiler_cpu_s']:.1f} |"
              for name, b in report["build"].items()]
    lines += ["", "| call | before: first / second (s) | now, empty cache: first / second (s) |", "|---|---:|---:|"]
    for name, c in report["first_calls"].items():
        old = before["first_calls"].get(name)
        shown = f"{old['call1_s']:.2f} / {old['call2_s']:.3f}" if old else "-"
        lines.append(f"| `{name}` | {shown} | {c['call1_s']:.2f} / {c['call2_s']:.3f} |")
    return "\n".join(lines)


def ci_markdown(ci: dict[str, Any]) -> str:
    """CI's wall time before and after (docs/benchmarks/ci.json, each with where it was measured)."""
    rows = [f"| {when} | {ci[when]['wall_s']:.0f} | {ci[when]['source']} |" for when in ("before", "after")]
    return "\n".join(["| `.ci/run` on a fresh clone | wall (s) | measured |", "|---|---:|---|", *rows])


BEFORE = ROOT / "docs" / "benchmarks" / "first_use_before.json"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="write every figure here")
    parser.add_argument("--no-demo", action="store_true", help="skip make demo on a fresh clone")
    parser.add_argument("--no-install", action="store_true", help="skip pip install into a fresh environment")
    args = parser.parse_args(argv)
    report: dict[str, Any] = {"machine": machine(), "load_before": os.getloadavg()}
    with tempfile.TemporaryDirectory(prefix="pkm-first-use-") as folder:
        tmp = Path(folder)
        if not args.no_demo:
            report["demo"] = demo(tmp)
        if not args.no_install:
            report["install"] = install(tmp)
        report["build"] = builds(tmp)
        report["first_calls"] = first_calls(tmp)
    report["load_after"] = os.getloadavg()
    print(markdown(report, json.loads(BEFORE.read_text())))
    if args.json:
        write_json(args.json, report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
