"""``pkm export``: a design as an Extended URDF (:mod:`pkm.export`, docs/export.md)."""

from __future__ import annotations

import argparse
from pathlib import Path

from pkm.cli.arguments import design_option, example, listed, units_option
from pkm.cli.common import design_in, emit, given_design, given_poses, given_units, load_mechanism, with_units

HELP = ("a design as an Extended URDF: the mechanism cut open into a tree (robot.urdf), its loop closures and "
        "motors (robot.yaml, read by Pinocchio's closed-loop loaders) and a README of what was cut (docs/export.md)")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism and design, the reference configuration's mode and pose."""
    listed(p, "mechanism", key="mechanism")
    design_option(p)
    example(p, "--mode", help="working mode of the reference configuration, where every joint of the URDF is "
                              "zero (default: the first); e.g. {mode}")
    p.add_argument("--pose", help="the reference pose, comma-separated (default: the mechanism's reference pose); "
                                  "e.g. 0,1.4")
    p.add_argument("--out", required=True, help="folder for robot.urdf, robot.yaml and README.md (no default); "
                                                "e.g. urdf")
    units_option(p)


def run(args: argparse.Namespace) -> None:
    """An Extended URDF of a design (:mod:`pkm.export`) into ``--out``."""
    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    pose = units.to_si(given_poses([args.pose], m.n_out), m.pose_units)[0] if args.pose else None
    mode = m.working_mode(args.mode).name
    folder = m.export_urdf(d, args.out, pose=pose, mode=mode)
    files = sorted(str(p) for p in folder.iterdir())
    data = {"mechanism": m.name, "design": design_in(m, d, units), "mode": mode, "folder": str(folder),
            "files": files}
    emit(args, data, f"{m.name} at {with_units(data['design'], m, units)}, reference in working mode {mode}\n"
                     f"wrote {len(files)} files (SI, as URDF states) to {folder}: "
                     f"{', '.join(Path(f).name for f in files)}")
