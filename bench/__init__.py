"""Benchmarks of pkm against baselines measured in the same run (DESIGN.md section 9).

Run them with ``make bench`` (``python -m bench.run``); docs/benchmarks.md records the latest figures.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any


def json_main(prog: str, doc: str | None, run: Callable[..., dict[str, Any]], markdown: Callable[[dict[str, Any]], str],
              argv: list[str] | None) -> int:
    """A benchmark's command line: run it (``run(log=...)``, its progress on standard error), write the run to
    ``--json PATH`` where given, print its markdown on standard output."""
    parser = argparse.ArgumentParser(prog=prog, description=doc)
    parser.add_argument("--json", help="write the run here (default: print only)")
    args = parser.parse_args(argv)
    data = run(log=lambda text: print(text, file=sys.stderr))
    if args.json:
        Path(args.json).write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    print(markdown(data))
    return 0
