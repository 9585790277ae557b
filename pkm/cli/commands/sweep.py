"""``pkm sweep``: several global indices over a design space and working modes in one pass."""

from __future__ import annotations

import argparse
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.cli import grid
from pkm.cli.arguments import listed, scheduled
from pkm.cli.common import emit, given_region, load_mechanism
from pkm.regions import region_name

HELP = ("several global indices over a design space and working modes in one pass (npz chunks with an index.json, "
        "and figures)")
PARALLEL = True


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism and indices, the design grid, the scheduler, the output folder."""
    listed(p, "mechanism", key="mechanism")
    listed(p, "--indices", key="indices", required=True)
    grid.options(p)
    scheduled(p)
    p.add_argument("--out", default="out", help="folder for the sweep's folder (default out; an interrupted run "
                                                "resumes); e.g. sweeps")


def run(args: argparse.Namespace) -> None:
    """The sweep's chunks, each atlas's npz and figure and an index.json listing them, in a folder of ``--out``
    named by the run's key."""
    m = load_mechanism(args.mechanism)
    names = [n.strip() for n in args.indices.split(",") if n.strip()]
    region = region_name(given_region(m, args.region))
    folder = Path(args.out) / f"{m.name}_sweep_{region}_{grid.run_key(m, args, names)[:8]}"
    (folder / "index.json").unlink(missing_ok=True)
    atlases = grid.atlases(m, args, names, folder / "chunks")
    first = next(iter(atlases.values()))
    chunks = []
    for path in (folder / "chunks").glob("[!.]*.npz"):
        with np.load(path) as data:
            chunks.append({"file": f"chunks/{path.name}", "mode": str(data["mode"]), "start": int(data["start"]),
                           "count": int(data["count"])})
    chunks.sort(key=lambda c: (list(first.modes).index(c["mode"]), c["start"]))

    def write(out: Path) -> tuple[Path, dict[str, Any]]:
        target = out / folder.name
        if target != folder:
            for chunk in chunks:
                io.copy_file(folder / chunk["file"], target / chunk["file"])
        figures = {name: str(a.plot(target / f"{name}.png")) for name, a in atlases.items()}
        listing = {
            "mechanism": m.name, "region": region, "space": first.space.name, "modes": list(first.modes),
            "indices": names, "resolution": first.resolution, "pose_resolution": first.pose_resolution,
            "chart_axes": list(first.space.chart_axes), "u": first.u.tolist(), "v": first.v.tolist(),
            "inside": first.inside.tolist(), "chunks": chunks, "figures": figures, "wall_time_s": first.wall_time,
            "checks": asdict(first.checks),
            "best": {name: {mode: a.checked[mode].to_dict() for mode in a.modes} for name, a in atlases.items()},
            "format": "each chunk holds values_<index> and points_<index> of `count` inside nodes of one mode from "
                      "`start` on (the chart grid's inside nodes in row-major order); <index>.npz holds each atlas "
                      "whole",
        }
        for name, a in atlases.items():
            a.save_npz(target / f"{name}.npz")
        io.write_text(target / "index.json", io.to_json(listing))
        return target, listing

    target, listing = io.write_result(Path(args.out), write)
    emit(args, {"folder": str(target), **listing}, f"wrote {len(names)} atlases and their chunks into {target}")
