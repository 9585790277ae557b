"""``pkm tolerance``: the widest tolerances of a machine's parts whose worst-case pose error over its task stays
within a budget (:func:`pkm.accuracy.widest_tolerances`)."""

from __future__ import annotations

import argparse
import math
import tomllib
from pathlib import Path

import numpy as np

from pkm import io
from pkm.accuracy import widest_tolerances
from pkm.cli.common import emit, load_mechanism, named
from pkm.errors import PkmError

HELP = "the widest tolerances whose worst-case pose error over the task stays within a budget (a TOML file)"
PARALLEL = False
FIELDS = ("mechanism", "region", "budget", "mode", "design", "weights", "fixed", "resolution")


def options(p: argparse.ArgumentParser) -> None:
    p.add_argument("task", help="a TOML file: mechanism, region (a region of it, its task by default), budget [m], "
                                "and optionally mode, design, weights and fixed (by error parameter) and resolution "
                                "(the region's sampling, 6 by default)")
    p.add_argument("--out", help="folder for tolerance.json (default: none); e.g. tolerances")


def run(args: argparse.Namespace) -> None:
    """The tolerances, each's share of the budget where it binds, and the binding poses."""
    path = Path(args.task)
    try:
        raw = tomllib.loads(path.read_text())
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise PkmError(f"task {args.task!r} violates: a readable TOML file ({exc})") from None
    extra = sorted(set(raw) - set(FIELDS))
    if extra or "mechanism" not in raw or "budget" not in raw:
        raise PkmError(f"task violates: a table of {', '.join(FIELDS)} with mechanism and budget; "
                       f"{'got ' + ', '.join(extra) if extra else 'one is missing'}")
    given = raw["mechanism"]
    m = load_mechanism(str(path.parent / given) if str(given).endswith(".toml") else given)
    resolution = raw.get("resolution", 6)
    if not isinstance(resolution, int) or not 2 <= resolution <= 64:
        raise PkmError(f"resolution violates: an integer from 2 to 64; got {resolution!r}")
    design = m.design_vector(raw.get("design"))
    region = m.region(raw.get("region", "task"))
    poses, _ = region.sample(m.functions, design, resolution)
    model = m.error_model()
    found = widest_tolerances(model, poses, raw["budget"], raw.get("design"), mode=raw.get("mode"),
                              weights=raw.get("weights"), fixed=raw.get("fixed"))
    data = {"mechanism": m.name, "poses": len(poses), "budget": found.budget, "status": found.status,
            "tolerances": found.tolerances, "units": found.units, "shares": found.shares, "binding": found.binding}
    lines = [f"{m.name}: the widest tolerances within {found.budget:g} m over {len(poses)} task poses "
             f"({found.status}); binding at {len(found.binding)} pose coordinates"]
    for name, width in found.tolerances.items():
        share = found.shares[name]
        lines.append(f"  {name} = +-{width:.3g} {found.units[name]}"
                     + (f" ({100 * share:.1f}% of the budget where it binds)" if math.isfinite(share) else ""))
    for row in found.binding[:5]:
        lines.append(f"  binds at {named(dict(zip(m.pose_names, np.round(row['pose'], 6).tolist(), strict=True)))} "
                     f"in {row['coordinate']}")
    text = "\n".join(lines)
    if args.out:
        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(
            Path(args.out), lambda folder: [io.write_text(folder / "tolerance.json", io.to_json(data))]))
    emit(args, data, text)
