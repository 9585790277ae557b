"""``pkm reproduce``: a paper's checkable claims reproduced (:mod:`pkm.reproduce`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pkm import io, registry
from pkm.cli.arguments import listed, scheduled
from pkm.cli.common import emit
from pkm.reproduce import reproduce

HELP = "reproduce a paper's checkable claims into OUT/<key>/"
PARALLEL = True


def options(p: argparse.ArgumentParser) -> None:
    """The paper (or all), the output folder, the quick mode, the scheduler."""
    listed(p, "paper", key="paper")
    p.add_argument("--out", default="out", help="folder holding <key>/ (default out); e.g. reports")
    p.add_argument("--quick", action="store_true", help="low resolutions, for tests (default off)")
    scheduled(p)


def run(args: argparse.Namespace) -> None:
    """Each paper's report into ``--out``/<key>/, and a line per paper counting its claims by status."""
    keys = sorted(registry.papers()) if args.paper == "all" else [args.paper]
    summaries = []
    for key in keys:
        summary = reproduce(key, Path(args.out), quick=args.quick)
        summaries.append({**summary, "folder": str(io.kept_path(Path(summary["folder"])))})
    text = "\n".join(f"{s['paper']}: {s['counts']} -> {s['folder']}" for s in summaries)
    emit(args, summaries, text)
