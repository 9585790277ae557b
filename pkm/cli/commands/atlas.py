"""``pkm atlas``: a global index over a normalised design space, and its best design that passes the checks."""

from __future__ import annotations

import argparse
import contextlib
import shutil
from dataclasses import asdict
from pathlib import Path

from pkm import io
from pkm.cli import grid
from pkm.cli.arguments import listed, scheduled
from pkm.cli.common import emit, load_mechanism

HELP = ("a global index over a normalised design space (npz and figure) and its best design that passes the "
        "convergence and size checks")
PARALLEL = True
CHUNKS = ".pkm-chunks"


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism and index, the design grid, the scheduler, the output folder."""
    listed(p, "mechanism", key="mechanism")
    listed(p, "index", key="index")
    grid.options(p)
    scheduled(p)
    p.add_argument("--out", default="out", help="folder for the npz and the figure (default out; an interrupted run "
                                                "resumes from the chunks kept there); e.g. atlases")


def run(args: argparse.Namespace) -> None:
    """The atlas's npz and figure into ``--out``, its chunks removed once they are written."""
    m = load_mechanism(args.mechanism)
    out = Path(args.out)
    store = out / CHUNKS / grid.run_key(m, args, [args.index])
    atlas = grid.atlases(m, args, [args.index], store)[args.index]
    index, space = atlas.index, atlas.space
    space_name = "axes" if args.axes else atlas.space.name
    stem = "_".join([m.name, args.index, atlas.region_name, space_name, *atlas.modes])

    def write(folder: Path) -> tuple[Path, Path]:
        npz, png = folder / f"{stem}.npz", folder / f"{stem}.png"
        atlas.plot(png)
        atlas.save_npz(npz)
        return npz, png

    npz, png = io.write_result(out, write)
    shutil.rmtree(store, ignore_errors=True)
    _remove_if_empty(out / CHUNKS)
    data = {"npz": str(npz), "figure": str(png), "wall_time_s": atlas.wall_time, "sense": index.sense,
            "chart_axes": list(space.chart_axes), "checks": asdict(atlas.checks),
            "best": {mode: atlas.checked[mode].to_dict() for mode in atlas.modes}}
    text = "\n".join([f"wrote {npz} and {png} in {atlas.wall_time:.1f} s",
                      *(str(atlas.checked[mode]) for mode in atlas.modes)])
    emit(args, data, text)


def _remove_if_empty(folder: Path) -> None:
    """Remove ``folder`` if it is empty and can be removed: a cache folder, whose removal is a courtesy."""
    with contextlib.suppress(OSError):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
