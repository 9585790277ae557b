"""``pkm eval``: inverse kinematics, Jacobian and local indices at poses."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.cli.arguments import listed, units_option
from pkm.cli.common import design_in, emit, given_design, given_poses, given_units, load_mechanism, unit_text, valued
from pkm.errors import PkmError
from pkm.units import Units

HELP = "inverse kinematics, Jacobian and local indices at poses"
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism, the poses (given or from a file), the design and the mode."""
    listed(p, "mechanism", key="mechanism")
    listed(p, "--pose", key="pose", action="append")
    p.add_argument("--poses", help="poses from a file instead of --pose: .npy (N x n) or CSV (a header of the pose's "
                                   "coordinates, optional; default: none); e.g. path.csv")
    listed(p, "--design", key="design")
    listed(p, "--mode", key="mode")
    p.add_argument("--strict", action="store_true",
                   help="fail on a pose out of reach (default: report it with reachable false and null values)")
    p.add_argument("--out", help="folder for eval.json and eval.csv (SI, units in the header; default: none); "
                                 "e.g. results")
    units_option(p)


def run(args: argparse.Namespace) -> None:
    """Each pose's actuators, Jacobian, local indices and singularity, or why it is out of reach."""
    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    if args.poses and args.pose:
        raise PkmError("--pose and --poses violate: one or the other")
    given = io.read_poses(args.poses, m.pose_names) if args.poses else given_poses(args.pose, m.n_out)
    x = units.to_si(given, m.pose_units)
    mode = m.working_mode(args.mode).name
    q = m.inverse_kinematics(x, d, mode=mode, passive=True, strict=args.strict)
    reached = np.all(np.isfinite(q), axis=1)
    margins = m.limit_margins(x, d, mode=mode)
    J = m.jacobian(x, d, mode=mode)
    local = {name: m.local_index(name, x, d, mode=mode) for name in m.local_indices()}
    sing = m.singularity(x, d, mode=mode)
    singular = m.singular_types(x, d, mode=mode)
    si = {"pose": dict(zip(m.pose_names, m.pose_units, strict=True)),
          "actuators": dict(zip(m.actuator_names, m.actuator_units, strict=True)),
          "indices": {name: m.index_unit(name) for name in local}}
    mine = {key: {n: units.convert(u)[1] for n, u in table.items()} for key, table in si.items()}
    jacobian = np.outer(1 / np.array([units.scale(u) for u in m.actuator_units]),
                        [units.scale(u) for u in m.pose_units])
    rows = []
    for k in range(len(x)):
        rows.append(
            {
                "pose": units.from_si(x[k], m.pose_units),
                "reachable": bool(reached[k]),
                "singular": singular[k],
                "violated_limits": [name for name, v in margins.items() if v[k] < 0],
                **({"q": q[k]} if units == Units() else {}),
                "actuators": dict(zip(m.actuator_names, units.from_si(q[k][: m.n_act], m.actuator_units).tolist(),
                                      strict=True)),
                "J": J[k] * jacobian,
                **{name: units.value(float(v[k]), si["indices"][name]) for name, v in local.items()},
                **{name: float(v[k]) for name, v in sing.items()},
            }
        )
    shown = [name for name in ("inverse_condition_f", "singularity_margin_type1", "singularity_margin_type2",
                               "velocity_max", "velocity_min", "stiffness_min", "elastic_frequency") if name in local]
    text = "\n".join(
        f"pose {valued(r['pose'], mine['pose'])}: {valued(list(r['actuators'].values()), mine['actuators'])}, "
        + ", ".join(f"{name} = {r[name]:.6g}{unit_text(mine['indices'][name])}" for name in shown)
        + (f"; SINGULAR ({' and '.join(r['singular'])}): the values at a singular pose are its limits, not a "
           "machine's" if r["singular"] else "")
        if r["reachable"] else f"pose {r['pose'].tolist()}: out of reach in mode {mode}{_why(m, r, d, units)}"
        for r in rows
    )
    data = {"mechanism": m.name, "design": design_in(m, d, units), "mode": mode, "units": mine, "poses": rows}
    if args.out:
        columns = [*(f"{n} [{u}]" for n, u in mine["pose"].items()), "reachable",
                   *(f"{n} [{u}]" for n, u in mine["actuators"].items()),
                   *(f"{n} [{u}]" for n, u in mine["indices"].items()), *sing]
        table = [[*r["pose"], r["reachable"], *r["actuators"].values(), *(r[n] for n in local),
                  *(r[n] for n in sing)] for r in rows]

        def write(folder: Path) -> list[Path]:
            return [io.write_text(folder / "eval.json", io.to_json(data)),
                    io.write_text(folder / "eval.csv", io.csv_text(columns, table))]

        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(Path(args.out), write))
    emit(args, data, text)


def _why(m: Any, row: dict[str, Any], design: Any, units: Units) -> str:
    """Why a pose is out of reach, where pkm can say: the stated limits it violates, an angle beyond a turn
    (typed in degrees where radians go?) and a length beyond the workspace box that would lie in it read in
    mm (each where the pose is given in SI; the pose looked at in SI)."""
    pose = units.to_si(row["pose"], m.pose_units)
    reasons = [f"violates {', '.join(row['violated_limits'])}"] if row["violated_limits"] else []
    turns = [f"{name} = {v:g} rad: in degrees?" for name, unit, v in zip(m.pose_names, m.pose_units, pose,
                                                                         strict=True)
             if unit == "rad" and units.angle == "rad" and abs(v) > 2 * math.pi]
    box = m.workspace_box(m.design_vector(design))
    lengths = [f"{name} = {v:g} m: in mm? (--units mm)" for name, unit, v, (lo, hi)
               in zip(m.pose_names, m.pose_units, pose, box, strict=True)
               if unit == "m" and units.length == "m" and not lo <= v <= hi and lo <= v / 1000 <= hi]
    notes = reasons + turns + lengths
    return f" ({'; '.join(notes)})" if notes else ""
