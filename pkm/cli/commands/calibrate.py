"""``pkm calibrate``: a machine's geometric errors identified from measured poses at read actuated joints
(:func:`pkm.accuracy.calibrate`)."""

from __future__ import annotations

import argparse
import csv
from pathlib import Path

import numpy as np

from pkm import io
from pkm.accuracy import ATTACHMENTS, calibrate
from pkm.cli.arguments import design_option, listed
from pkm.cli.common import emit, given_design, load_mechanism
from pkm.errors import PkmError

HELP = "identify a machine's geometric errors from measured poses at read joints (a CSV file)"
PARALLEL = False
MAX_ROWS = 100_000


def options(p: argparse.ArgumentParser) -> None:
    listed(p, "mechanism", key="mechanism")
    p.add_argument("data", help="a CSV file: a header of the actuators' and the pose coordinates' names, a row per "
                                "measurement in SI; a coordinate left empty is not measured (a probe's one)")
    listed(p, "--mode", key="mode")
    p.add_argument("--attachments", choices=ATTACHMENTS, default="cartesian",
                   help="the attachments' errors along x, y, z, or (polar) of their circle's radius and angle where "
                        "placed on one (default: cartesian)")
    p.add_argument("--axes", action="store_true",
                   help="the joints' axes' tilts too (an R_parallelogram's drive axis, a PRR's slide, each axis of a "
                        "chain's joints: two angles per axis in space, one in the plane; default: off)")
    p.add_argument("--parameters", help="the error parameters identified, comma-separated (default: all); the others "
                                        "held at 0")
    p.add_argument("--out", help="folder for calibration.json (default: none); e.g. calibrated")
    design_option(p)


def _read(path: str, joints: tuple[str, ...], pose: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
    try:
        with open(path, newline="") as handle:
            rows = list(csv.DictReader(handle))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise PkmError(f"data {path!r} violates: a readable CSV file ({exc})") from None
    missing = [n for n in (*joints, *pose) if not rows or n not in rows[0]]
    if missing or not 1 <= len(rows) <= MAX_ROWS:
        raise PkmError(f"data violates: 1 to {MAX_ROWS} rows under a header naming {', '.join((*joints, *pose))}; "
                       f"{'missing ' + ', '.join(missing) if missing else f'{len(rows)} rows'}")

    def number(text: str | None, where: str, empty: bool) -> float:
        if text is None:
            raise PkmError(f"data violates: as many fields in each row as in the header; {where} is missing")
        if empty and not text.strip():
            return float("nan")
        try:
            value = float(text)
        except ValueError:
            raise PkmError(f"data violates: a number at {where}; got {text!r}") from None
        if not np.isfinite(value):
            raise PkmError(f"data violates: a finite number at {where}; got {text!r}")
        return value

    q = np.array([[number(r[n], f"row {k + 1}, {n}", False) for n in joints] for k, r in enumerate(rows)])
    x = np.array([[number(r[n], f"row {k + 1}, {n}", True) for n in pose] for k, r in enumerate(rows)])
    return q, x


def run(args: argparse.Namespace) -> None:
    """The errors with their deviations, the residuals before and after, and the identifiability."""
    m = load_mechanism(args.mechanism)
    d = given_design(m, args.design)
    q, x = _read(args.data, m.actuator_names, m.pose_names)
    chosen = None if args.parameters is None else [n.strip() for n in args.parameters.split(",")]
    found = calibrate(m.error_model(args.attachments, args.axes), q, x, d, mode=args.mode, parameters=chosen)
    data = {"mechanism": m.name, "measurements": len(q), **found.__dict__}
    lines = [f"{m.name}: {len(q)} measurements, residual RMS {found.rms_before:.3g} -> {found.rms_after:.3g} "
             f"({found.iterations} steps); {found.rank} of {len(found.errors)} parameters identified"]
    lines += [f"  {n} = {v:.4g} +- {found.deviations[n]:.2g}" for n, v in found.errors.items()]
    lines += [f"  not identified apart: {', '.join(f'{v:+.2f} {n}' for n, v in direction.items())}"
              for direction in found.unidentifiable]
    lines += [f"  poorly identified (singular value {direction.pop('ratio'):.1e} of the largest): "
              f"{', '.join(f'{v:+.2f} {n}' for n, v in direction.items())}"
              for direction in (dict(w) for w in found.weakly_identified)]
    text = "\n".join(lines)
    if args.out:
        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(
            Path(args.out), lambda folder: [io.write_text(folder / "calibration.json", io.to_json(data))]))
    emit(args, data, text)
