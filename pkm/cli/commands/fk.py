"""``pkm fk``: every real assembly at given actuated joints (:mod:`pkm.assemblies`)."""

from __future__ import annotations

import argparse
import reprlib
from pathlib import Path

import numpy as np

from pkm import io
from pkm.cli.arguments import design_option, listed, units_option
from pkm.cli.common import emit, given_design, given_units, load_mechanism, unit_text
from pkm.drawn_assemblies import assemblies_figure, working_modes
from pkm.errors import PkmError
from pkm.mechanism import Mechanism
from pkm.units import Units

HELP = "every real assembly at given actuated joints, each with its closure residual and singularity margin"
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism, the actuated joints, the design."""
    listed(p, "mechanism", key="mechanism")
    p.add_argument("--joints", required=True, help="the actuated joints, comma-separated, in the actuators' units "
                                                   "(no default); e.g. 0.7,0.8,0.9")
    p.add_argument("--certify", action="store_true", help="check the count against a certified count of the real "
                                                        "roots (python-flint's ball arithmetic; default: off)")
    p.add_argument("--out", help="folder for fk.json and fk.png, fk.svg: each assembly's linkage drawn (default: "
                                 "none); e.g. assemblies")
    design_option(p)
    units_option(p)


def _joints(m: Mechanism, text: str, units: Units) -> np.ndarray:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise PkmError(f"--joints {reprlib.repr(text)} violates: {m.n_act} numbers, comma-separated") from None
    if len(values) != m.n_act:
        raise PkmError(f"--joints violates: {m.n_act} numbers ({', '.join(m.actuator_names)}); got {len(values)}")
    infinite = [f"{n} = {v}" for n, v in zip(m.actuator_names, values, strict=True) if not np.isfinite(v)]
    if infinite:
        raise PkmError(f"--joints violates: finite numbers; {', '.join(infinite)}")
    return units.to_si(np.array(values), m.actuator_units)


def run(args: argparse.Namespace) -> None:
    """Every assembly's pose, closure residual, working mode and singularity margins."""
    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    q_a = _joints(m, args.joints, units)
    found = m.every_assembly(q_a, d, certify=args.certify)
    rows = []
    poses = found.poses[0, : found.counts[0]]
    modes = working_modes(m, poses, q_a, d)
    for pose, residual, mode in zip(poses, found.residuals[0, : found.counts[0]], modes, strict=True):
        margins = {name: None if mode is None else float(m.local_index(name, pose, d, mode=mode))
                   for name in ("singularity_margin_type1", "singularity_margin_type2")}
        rows.append({"pose": dict(zip(m.pose_names, units.from_si(pose, m.pose_units).tolist(), strict=True)),
                     "residual": float(residual), "mode": mode, **margins})
    pose_units = {n: units.convert(u)[1] for n, u in zip(m.pose_names, m.pose_units, strict=True)}
    data = {"mechanism": m.name, "joints": dict(zip(m.actuator_names, units.from_si(q_a, m.actuator_units).tolist(),
                                                    strict=True)),
            "units": pose_units, "count": int(found.counts[0]), "bound": found.bound,
            "failed": int(found.failed[0]), "method": found.method, "assemblies": rows,
            "certified": None if found.certified is None else bool(found.certified[0])}
    lines = [f"{m.name}: {data['count']} real assemblies (at most {found.bound}; {found.method})"
             + (f"; {data['failed']} {found.failures}" if data["failed"] else "")
             + ("" if data["certified"] is None else "; the count certified" if data["certified"] else
                "; the count NOT certified (a double root: assemblies meeting at a singularity)")]
    for k, row in enumerate(rows, 1):
        pose = ", ".join(f"{n} = {v:.8g}{unit_text(pose_units[n])}" for n, v in row["pose"].items())
        where = "in no working mode" if row["mode"] is None else (
            f"working mode {row['mode']}, singularity margins type I {row['singularity_margin_type1']:.3g}, type II "
            f"{row['singularity_margin_type2']:.3g}")
        lines.append(f"  {k}: {pose}; closure residual {row['residual']:.1e} m; {where}")
    text = "\n".join(lines)
    if args.out:
        def write(folder: Path) -> list[Path]:
            from pkm.figures import save

            out = [io.write_text(folder / "fk.json", io.to_json(data))]
            fig = assemblies_figure(m, d, poses, modes)
            return out + [save(fig, folder / f"fk.{suffix}", dpi=150) for suffix in ("png", "svg")]

        text += "\nwrote " + ", ".join(str(path) for path in io.write_result(Path(args.out), write))
    emit(args, data, text)

