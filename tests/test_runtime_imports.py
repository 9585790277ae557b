"""pkm never imports sympy, and importing it and loading a mechanism is quick (STYLE practice 5)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

SCRIPT = """
import json, sys, time
start = time.perf_counter()
import pkm
pkm.load("five_bar").functions
seconds = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "modules": sorted(sys.modules)}))
"""


def test_loading_a_mechanism_imports_no_sympy_and_is_quick():
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], cwd=ROOT, env=env, capture_output=True, text=True, timeout=60, check=True
    )
    report = json.loads(done.stdout.splitlines()[-1])
    roots = {name.split(".")[0] for name in report["modules"]}
    assert "sympy" not in roots
    assert "symbolic" not in roots
    assert report["seconds"] < 5.0, f"import pkm + load took {report['seconds']:.2f} s (target < 2 s)"
