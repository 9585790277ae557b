"""``pkm fk``: every real assembly at given actuated joints (:mod:`pkm.assemblies`)."""

from __future__ import annotations

import argparse
import reprlib
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.cli.arguments import design_option, listed, units_option
from pkm.cli.common import emit, given_design, given_units, load_mechanism, unit_text
from pkm.errors import PkmError
from pkm.mechanism import Mechanism
from pkm.units import Units

HELP = "every real assembly at given actuated joints, each with its closure residual and singularity margin"
PARALLEL = False
SAME_JOINTS = 1e-8  # a working mode whose inverse kinematics gives the joints back to this is the assembly's


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


def _mode(m: Mechanism, pose: np.ndarray, q_a: np.ndarray, design: Any) -> str | None:
    """The working mode whose inverse kinematics gives ``q_a`` back at ``pose``, if one does."""
    angles = np.array([u == "rad" for u in m.actuator_units])
    for mode in m.modes:
        gap = m.inverse_kinematics(pose, design, mode=mode, limits=False) - q_a
        gap[angles] = np.angle(np.exp(1j * gap[angles]))
        if np.all(np.abs(gap) <= SAME_JOINTS * max(1.0, float(np.abs(q_a).max()))):
            return mode
    return None


def run(args: argparse.Namespace) -> None:
    """Every assembly's pose, closure residual, working mode and singularity margins."""
    m = load_mechanism(args.mechanism)
    units = given_units(args)
    d = given_design(m, args.design, units)
    q_a = _joints(m, args.joints, units)
    found = m.every_assembly(q_a, d, certify=args.certify)
    rows = []
    for pose, residual in zip(found.poses[0, : found.counts[0]], found.residuals[0, : found.counts[0]],
                              strict=True):
        mode = _mode(m, pose, q_a, d)
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
        poses = found.poses[0, : found.counts[0]]
        drawn = [(pose, row) for pose, row in zip(poses, rows, strict=True)]

        def write(folder: Path) -> list[Path]:
            from pkm.figures import save

            out = [io.write_text(folder / "fk.json", io.to_json(data))]
            fig = _figure(m, d, drawn)
            return out + [save(fig, folder / f"fk.{suffix}", dpi=150) for suffix in ("png", "svg")]

        text += "\nwrote " + ", ".join(str(path) for path in io.write_result(Path(args.out), write))
    emit(args, data, text)


def _figure(m: Mechanism, design: Any, drawn: list[tuple[np.ndarray, dict[str, Any]]]) -> Any:
    """One panel per assembly: each leg's joints joined from the base, the platform's joints joined; in the
    plane of the linkage, or seen from the side (across the first and the third coordinate) in space."""
    from matplotlib.ticker import MaxNLocator

    from pkm.figures import figure

    fig = figure(3.2 * max(len(drawn), 1), 3.4)
    for k, (pose, row) in enumerate(drawn, 1):
        ax = fig.add_subplot(1, max(len(drawn), 1), k)
        legs = m.linkage(pose, design, mode=row["mode"]) if row["mode"] is not None else []
        across = (0, 2) if legs and legs[0].shape[1] == 3 else (0, 1)
        for points in legs:
            ax.plot(points[:, across[0]], points[:, across[1]], "o-", color="C0", lw=1.5, ms=3)
        ends = np.array([points[-1, list(across)] for points in legs]) if legs else np.zeros((0, 2))
        if len(ends) > 2:
            ax.fill(ends[:, 0], ends[:, 1], color="C1", alpha=0.4)
        ax.set_aspect("equal")
        ax.set_title(f"assembly {k}: {row['mode'] or 'no working mode'}", fontsize=8)
        names = ("x", "z") if across == (0, 2) else m.pose_names[:2]
        ax.set_xlabel(f"{names[0]} [m]", fontsize=8)
        ax.set_ylabel(f"{names[1]} [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.xaxis.set_major_locator(MaxNLocator(4))
    return fig
