"""The ``pkm`` command line (DESIGN.md section 7).

Exit status 0 on success, 2 on bad input (one line on standard error, no traceback), 1 when a valid
computation fails (for instance IPOPT does not converge) or when --out cannot take a computed result,
which is then kept in a new folder of the system's temporary directory that the line names
(:func:`pkm.io.keeping`), 3 when a synthesis finds no design that meets its constraints (the line names
the constraints and their best attainable values).
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import math
import os
import re
import reprlib
import shutil
import signal
import sys
import tempfile
import threading
import time
import warnings
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stdout
from dataclasses import asdict
from importlib.metadata import version
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

from pkm import interrupts, io, parallel, registry
from pkm import load as load_mechanism
from pkm.compiled import CompiledPathWarning
from pkm.compiled import status as compiled_status
from pkm.design import Design, parse_design
from pkm.design_space import parameter_plane, parse_axes
from pkm.errors import ComputationError, PkmError, UnknownNameError, check_integer
from pkm.interrupts import interruptible
from pkm.mechanism import Mechanism
from pkm.parallel import task_key
from pkm.regions import region_name
from pkm.reproduce import reproduce
from pkm.synthesis import InfeasibleError, SynthesisError, SynthesisResult, synthesize
from pkm.synthesis.driver import constraint_lines
from pkm.synthesis.pareto import FRONT_TOLERANCE
from pkm.units import Units, placement_in, placement_text


class _Parser(argparse.ArgumentParser):
    """argparse that raises :class:`PkmError` (one line, exit 2) and shows the arguments it refuses capped
    (reprlib), where argparse's own messages would echo them whole."""

    def error(self, message: str) -> NoReturn:
        raise PkmError(f"{self.prog}: {message}")

    def parse_args(self, args: Any = None, namespace: Any = None) -> argparse.Namespace:
        parsed, extra = self.parse_known_args(args, namespace)
        if extra:
            self.error(f"unrecognized arguments: {reprlib.repr(' '.join(extra))}")
        return parsed

    def _check_value(self, action: argparse.Action, value: Any) -> None:
        if action.choices is not None and value not in action.choices:
            raise argparse.ArgumentError(action, f"invalid choice: {reprlib.repr(value)} (choose from "
                                                 f"{', '.join(map(str, action.choices))})")


def _integer(text: str) -> int:
    """An option's integer (argparse's ``type``)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{reprlib.repr(text)} violates: an integer") from None


def _number(text: str) -> float:
    """An option's finite number (argparse's ``type``)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{reprlib.repr(text)} violates: a finite number")
    return value


RESULT = ".json"  # a design given as a result file
TASK = ".toml"  # a region or a problem given as a task file


def _design(mech: Mechanism, text: str | None, units: Units | None = None) -> Design:
    """A design from ``name=value,...`` in the user's units (SI by default), or the design a result file
    records (``.json``: what ``design``, ``synth`` and ``index`` write, SI)."""
    if not text:
        return mech.design(None, partial=True)
    if text.endswith(RESULT):
        return mech.design(io.read_design(text), partial=True)
    values = parse_design(text)
    if units is not None:
        scale = {p.name: units.scale(p.unit) for p in mech.parameters}
        values = {k: v * scale.get(k, 1.0) for k, v in values.items()}
    return mech.design(values, partial=True)


def _region(m: Mechanism, text: str) -> Any:
    """A region by name, or a task file's (``.toml``: the region its objective is taken over)."""
    if text.endswith(TASK):
        from pkm.synthesis.designer import task_of

        return task_of(text, m)
    return text


def _problem(text: str) -> Any:
    """A synthesis problem: a registered one by name, or a task file's (``.toml``)."""
    if text.endswith(TASK):
        from pkm.synthesis.designer import read_problem

        return read_problem(text)
    return registry.problem(text)


def _modes(m: Mechanism, text: str | None) -> list[str] | None:
    """Working modes from ``a,b`` (names or aliases), or None for all."""
    return [m.working_mode(mode).name for mode in text.split(",")] if text else None


def _units(args: argparse.Namespace) -> Units:
    return Units.parse(getattr(args, "units", None))


def _poses(text: list[str] | None, n: int) -> np.ndarray:
    if not text:
        raise PkmError(f"--pose is required (comma-separated, {n} values)")
    poses = []
    for item in text:
        try:
            poses.append([float(v) for v in str(item).split(",")])
        except ValueError:
            raise PkmError(f"--pose {reprlib.repr(item)} violates: {n} numbers, comma-separated") from None
    if any(len(p) != n for p in poses):
        raise PkmError(f"--pose needs {n} comma-separated values")
    return np.array(poses)


def _emit(args: argparse.Namespace, data: Any, text: str) -> None:
    sys.stdout.write(io.to_json(data) if args.json else text + "\n")


def cmd_list(args: argparse.Namespace) -> None:
    data = {}
    for name in registry.mechanisms():
        m = registry.mechanism(name)
        data[name] = {
            "doc": m.doc,
            "parameters": [
                {"name": p.name, "default": p.default, "lower": p.lower, "upper": p.upper, "unit": p.unit, "doc": p.doc}
                for p in m.parameters
            ],
            "modes": {b.name: {"aliases": list(b.aliases), "doc": b.doc} for b in m.working_modes},
            "assemblies": {b.name: b.doc for b in m.assembly_modes},
            "pose": dict(zip(m.pose_names, m.pose_units, strict=True)),
            "actuators": dict(zip(m.actuator_names, m.actuator_units, strict=True)),
            "regions": list(m.region_names()),
            "design_spaces": sorted(m.design_spaces),
            "indices": list(m.global_indices()),
            "trajectory_quantities": list(m.trajectory_quantities),
        }
    out = {
        "mechanisms": data,
        "indices": {i.name: {"doc": i.doc, "reduce": i.reduce, "sense": i.sense} for i in registry.global_indices()},
        "problems": {
            p.name: {"doc": p.doc, "variables": [v.name for v in p.variables],
                     "settings": {x.name: {"value": p.values[x.name], "lower": x.lower, "upper": x.upper,
                                           "unit": x.unit, "doc": x.doc} for x in p.settings}}
            for p in registry.problems().values()
        },
        "papers": {key: module.TITLE for key, module in registry.papers().items()},
        "evaluation": compiled_status(),
    }
    lines = []
    for name, info in data.items():
        lines.append(f"{name}: {info['doc']}")
        lines += [f"  {p['name']} = {p['default']:g} {p['unit']}: {p['doc']}" for p in info["parameters"]]
        lines.append("  modes: " + ", ".join(f"{k} ({'/'.join(v['aliases'])})" for k, v in info["modes"].items()))
        lines.append("  regions: " + ", ".join(info["regions"]))
        lines.append("  design spaces: " + (", ".join(info["design_spaces"]) or "none (atlases take --axes)"))
        lines.append("  along a trajectory region: " + ", ".join(info["trajectory_quantities"]))
        lines.append("  pose: " + ", ".join(f"{k} [{u}]" for k, u in info["pose"].items())
                     + "; actuators: " + ", ".join(f"{k} [{u}]" for k, u in info["actuators"].items()))
    lines.append("indices: " + ", ".join(out["indices"]))
    lines.append("problems: " + ", ".join(out["problems"]))
    lines += [f"  {name} settings (--set): " + ", ".join(f"{k} = {v['value']:.6g}{_unit(v['unit'])}"
                                                      for k, v in problem["settings"].items())
              for name, problem in out["problems"].items() if problem["settings"]]
    lines.append("papers:")
    lines += [f"  {key}: {title}" for key, title in out["papers"].items()]
    lines += _evaluation_lines(out["evaluation"])
    _emit(args, out, "\n".join(lines))


def _evaluation_lines(path: dict[str, Any]) -> list[str]:
    """What ``pkm.compiled.status()`` says, in words."""
    if path["path"] == "compiled":
        lines = [f"evaluation: compiled at first use by {path['compiler']} for {path['instruction_set']} into "
                 f"{path['cache']}" + (f" (read only: {path['cache_unwritable']})" if path["cache_unwritable"] else "")]
    else:
        lines = [f"evaluation: CasADi's interpreter ({path['reason']})"]
    counts = path["evaluations"]
    interpreted = ", ".join(f"{n} {reason}" for reason, n in counts["interpreter"].items())
    lines.append(f"  this process: {counts['compiled']} evaluations compiled, {sum(counts['interpreter'].values())} "
                 "on the interpreter" + (f" ({interpreted})" if interpreted else ""))
    if "note" in path["casadi"]:
        lines.append(f"  {path['casadi']['note']}")
    return lines


def cmd_build(args: argparse.Namespace) -> None:
    from pkm.catalogue import warm
    from pkm.progress import Progress

    mechanisms = [load_mechanism(name) for name in args.mechanisms or registry.mechanisms()]
    status = compiled_status()
    if status["path"] != "compiled":
        raise ComputationError(f"nothing can be compiled: {status['reason']}")
    data = {}
    for mech in mechanisms:
        wall, cpu = time.perf_counter(), _children_cpu()
        with Progress(1, f"pkm build {mech.name}") as bar:
            def progress(done: int, total: int, bar: Progress = bar) -> None:
                bar.total = max(total, 1)
                bar.done = 0
                bar.advance(done)

            counts = warm([mech], progress=progress)
        data[mech.name] = {**counts, "wall_s": round(time.perf_counter() - wall, 2),
                           "compiler_cpu_s": round(_children_cpu() - cpu, 2)}
    lines = [f"{name}: {d['cached']} kernels in the cache, {d['compiled']} compiled, {d['interpreted']} left on the "
             f"interpreter; {d['wall_s']:.1f} s ({d['compiler_cpu_s']:.1f} s of compiler CPU)"
             for name, d in data.items()]
    _emit(args, {"mechanisms": data, "evaluation": compiled_status()},
          "\n".join([*lines, *_evaluation_lines(compiled_status())[:1]]))
    if any(d["interpreted"] for d in data.values()):
        raise ComputationError("some kernels did not compile (the warnings above name them)")


def _children_cpu() -> float:
    """CPU seconds of the finished child processes (the compilers)."""
    times = os.times()
    return times.children_user + times.children_system


def cmd_eval(args: argparse.Namespace) -> None:
    m = load_mechanism(args.mechanism)
    units = _units(args)
    d = _design(m, args.design, units)
    if args.poses and args.pose:
        raise PkmError("--pose and --poses violate: one or the other")
    given = io.read_poses(args.poses, m.pose_names) if args.poses else _poses(args.pose, m.n_out)
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
                               "velocity_max", "velocity_min") if name in local]
    text = "\n".join(
        f"pose {_valued(r['pose'], mine['pose'])}: {_valued(list(r['actuators'].values()), mine['actuators'])}, "
        + ", ".join(f"{name} = {r[name]:.6g}{_unit(mine['indices'][name])}" for name in shown)
        + (f"; SINGULAR ({' and '.join(r['singular'])}): the values at a singular pose are its limits, not a "
           "machine's" if r["singular"] else "")
        if r["reachable"] else f"pose {r['pose'].tolist()}: out of reach in mode {mode}{_why(m, r, d, units)}"
        for r in rows
    )
    data = {"mechanism": m.name, "design": _design_in(m, d, units), "mode": mode, "units": mine, "poses": rows}
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
    _emit(args, data, text)


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


def _per(unit: str, other: str) -> str:
    """The unit of a derivative of ``unit`` in a quantity of unit ``other`` (``-`` for a pure number)."""
    if other == "-":
        return unit
    other = f"({other})" if any(c in other for c in " /") else other
    return f"1/{other}" if unit == "-" else f"{unit}/{other}"


def _design_in(m: Mechanism, design: Design, units: Units) -> dict[str, float]:
    """A design's values in the user's units."""
    return {p.name: units.value(float(design[p.name]), p.unit) for p in m.parameters}


def _unit(unit: str) -> str:
    """`` m/rad`` after a value, nothing for a dimensionless one."""
    return "" if unit == "-" else f" {unit}"


def _valued(values: np.ndarray, units: dict[str, str]) -> str:
    """``x = 0.1 m, y = 1.5 m``: values by name with their units."""
    return ", ".join(f"{name} = {v:.6g} {unit}" for (name, unit), v in zip(units.items(), values, strict=True))


def cmd_index(args: argparse.Namespace) -> None:
    m = load_mechanism(args.mechanism)
    units = _units(args)
    d = _design(m, args.design, units)
    mode = m.working_mode(args.mode).name
    region = _region(m, args.region)
    args.region = region_name(region)
    out = m.global_index(
        args.index,
        d,
        region=region,
        mode=mode,
        resolution=args.resolution,
        gradient=args.gradient,
        singularity_margin=args.margin,
    )
    value, grad = out if args.gradient else (out, None)
    unit = m.index_unit(args.index)
    scale, shown = units.convert(unit)
    data = {
        "mechanism": m.name,
        "index": args.index,
        "region": args.region,
        "mode": mode,
        "design": _design_in(m, d, units),
        "value": float(value) / scale,
        "points": value.points,
        "resolution": value.resolution,
        "accuracy": value.accuracy / scale,
        "unit": shown,
    }
    if grad is not None:
        grad = {p.name: grad[p.name] * units.convert(p.unit)[0] / scale for p in m.parameters}
    text = f"{args.index} over {args.region} ({mode}, {value.points} points) = {data['value']:.8g}{_unit(shown)}"
    if np.isfinite(value.accuracy):
        text += f" (accuracy {data['accuracy']:.1e}, resolution {value.resolution})"
    data["converged"] = value.converged
    if not value.converged:
        text += f"\nNOT CONVERGED: {value.note.removeprefix('not converged: ')}"
    if np.isnan(float(value)):
        data["undefined"] = _undefined(m, region)
        text += f" (undefined: {data['undefined']})"
    if args.region not in {"reachable", "assembled"}:
        try:
            placed = m.region_placement(region, d)
        except PkmError:
            placed = None
        if placed is not None:
            data["placement"] = placed = placement_in(m, region, placed, units)
            text += f"\nregion {args.region}: {placement_text(placed)}"
    if args.out:
        columns = ["mechanism", "index", "region", "mode", f"value [{shown}]", "points", "resolution",
                   f"accuracy [{shown}]", *(f"{p.name} [{units.convert(p.unit)[1]}]" for p in m.parameters)]
        row = [m.name, args.index, args.region, mode, data["value"], value.points, value.resolution,
               data["accuracy"], *data["design"].values()]

        def write(folder: Path) -> list[Path]:
            return [io.write_text(folder / "index.json", io.to_json({**data, **({"gradient": grad} if grad else {})})),
                    io.write_text(folder / "index.csv", io.csv_text(columns, [row]))]

        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(Path(args.out), write))
    if grad is not None:
        data["gradient"] = grad
        text += "\ngradient: " + ", ".join(
            f"d/d{p.name} = {grad[p.name]:.6g}{_unit(_per(shown, units.convert(p.unit)[1]))}" for p in m.parameters)
        if value.note and value.converged:
            text += f"\nnote: {value.note}"
    if value.note:
        data["note"] = value.note
    _emit(args, data, text)


def cmd_show(args: argparse.Namespace) -> None:
    """A design card (:mod:`pkm.card`) into ``--out``."""
    from pkm.card import design_card

    m = load_mechanism(args.mechanism)
    units = _units(args)
    d = _design(m, args.design, units)
    modes = _modes(m, args.mode)
    axes = tuple(args.plane.split(",")) if args.plane else None
    held = parse_design(args.held, "held coordinates", "pose coordinate", PkmError) if args.held else None
    if held is not None:
        named = dict(zip(m.pose_names, m.pose_units, strict=True))
        held = {k: v * units.scale(named.get(k, "-")) for k, v in held.items()}
    card = design_card(m, d, modes=modes, region=_region(m, args.region) if args.region else None, index=args.index,
                       axes=axes, held=held, resolution=args.resolution, units=units)
    folder = Path(args.out)
    written = io.write_result(folder, card.write)
    data = {**card.to_dict(), "files": [str(p) for p in written]}
    lines = [f"{m.name} at {_with_units(_design_in(m, d, units), m, units)}"]
    if card.placement is not None:
        lines.append(f"region {card.region}: {placement_text(card.placement)}")
    lines += [f"SINGULAR: the linkage's pose {_numbers(data['pose'].values())} is a {' and '.join(types)} "
              f"singularity in mode {mode}" for mode, types in card.singular.items()]
    lines += [f"{r['index']} ({r['mode']}) = {r['value']:.6g}{_unit(r['unit'])} (resolution {r['resolution']}, "
              f"accuracy {r['accuracy']:.1e})" for r in card.indices]
    lines.append(f"wrote {len(written)} files to {io.kept_path(folder)}")
    _emit(args, data, "\n".join(lines))


def cmd_compare(args: argparse.Namespace) -> None:
    """Designs side by side (:func:`pkm.card.compare`) into ``--out``."""
    from pkm.card import compare

    m = load_mechanism(args.mechanism)
    units = _units(args)
    designs = [_design(m, text, units) for text in args.design]
    modes = _modes(m, args.mode)
    comparison = compare(m, designs, modes=modes, region=_region(m, args.region) if args.region else None,
                         resolution=args.resolution, units=units)
    folder = Path(args.out)
    written = io.write_result(folder, comparison.write)
    data = {**comparison.to_dict(), "files": [str(p) for p in written]}
    _emit(args, data, comparison.markdown() + f"\n\nwrote {len(written)} files to {io.kept_path(folder)}")


def cmd_export(args: argparse.Namespace) -> None:
    """An Extended URDF of a design (:mod:`pkm.export`) into ``--out``."""
    m = load_mechanism(args.mechanism)
    units = _units(args)
    d = _design(m, args.design, units)
    pose = units.to_si(_poses([args.pose], m.n_out), m.pose_units)[0] if args.pose else None
    mode = m.working_mode(args.mode).name
    folder = m.export_urdf(d, args.out, pose=pose, mode=mode)
    files = sorted(str(p) for p in folder.iterdir())
    data = {"mechanism": m.name, "design": _design_in(m, d, units), "mode": mode, "folder": str(folder),
            "files": files}
    _emit(args, data, f"{m.name} at {_with_units(data['design'], m, units)}, reference in working mode {mode}\n"
                      f"wrote {len(files)} files (SI, as URDF states) to {folder}: "
                      f"{', '.join(Path(f).name for f in files)}")


def cmd_explore(args: argparse.Namespace) -> None:
    """The explorer (:mod:`pkm.explore`): a local server and its page until Ctrl-C or the page's stop
    request, or with ``--html`` the page with its data as one file."""
    from pkm.explore import Explorer, Server, export_html, require_plotly

    require_plotly()
    _check_file("--html", args.html)
    m = load_mechanism(args.mechanism)
    problem = args.problem
    if problem and problem.endswith(".toml"):
        from pkm.synthesis.designer import read_problem

        problem = read_problem(problem)
    design = io.read_design(args.design) if args.design and args.design.endswith(RESULT) else args.design
    explorer = Explorer(m, index=args.index, region=args.region, space=args.space, axes=args.axes,
                        design=design, problem=problem, resolution=args.resolution,
                        map_resolution=args.map_resolution)
    if args.html is not None:
        path = export_html(explorer, args.html, grid=args.grid)
        _emit(args, {"mechanism": m.name, "html": str(path)}, f"wrote {path}")
        return
    server = Server(explorer, port=args.port)
    _emit(args, {"mechanism": m.name, "url": server.url},
          f"pkm explore: {m.name} at {server.url} (Ctrl-C or the page's stop button ends it)")
    sys.stdout.flush()
    if not args.no_browser:
        import webbrowser

        webbrowser.open(server.url)
    server.serve_forever()
    print("pkm explore: stopped", file=sys.stderr)


def _numbers(values: list[float]) -> str:
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"


def _undefined(m: Any, region: str | Any) -> str:
    """Why an index over a region can be NaN."""
    guard = getattr(m.region(region), "guard", None)
    reasons = ["a node of the region is out of reach in this mode"]
    if guard is not None:
        reasons.append(f"or fails a margin of {guard} (a singularity or a joint limit inside the region)")
    return " ".join(reasons)


CHUNKS = ".pkm-chunks"
INFEASIBLE = 3  # the exit status of a synthesis without a design that meets its constraints


def _space(m: Mechanism, args: argparse.Namespace) -> Any:
    if args.axes:
        base = dict(_design(m, args.design)) if args.design else None
        return parameter_plane(m.parameters, parse_axes(args.axes, "--axes"), base=base)
    if args.design:
        raise PkmError("--design holds the parameters off the chart of an atlas over --axes; a design space "
                       "fixes its own")
    if not m.design_spaces:
        raise PkmError(f"the {m.name} has no design space to draw an atlas in: give --axes")
    name = args.space or next(iter(m.design_spaces))
    if name not in m.design_spaces:
        raise UnknownNameError(f"{m.name} design space", name, sorted(m.design_spaces))
    return m.design_spaces[name]


def _sweep(m: Mechanism, args: argparse.Namespace, names: list[str], store: Path) -> dict[str, Any]:
    """The atlases of ``names`` over the command's design space, chunks kept in ``store``."""
    from pkm.atlas import MAX_CHART, Checks, compute_sweep, default_modes

    space = _space(m, args)
    indices = tuple(m.global_spec(name) for name in names)
    region = _region(m, args.region)
    modes = tuple(args.modes.split(",")) if args.modes else default_modes(m, region)
    check_integer("resolution", args.resolution, 3, MAX_CHART)
    checks = Checks(tolerance=args.tolerance, min_points=args.min_points, min_fraction=args.min_fraction)
    return compute_sweep(
        m, indices, space=space, modes=modes, region=region, resolution=args.resolution,
        pose_resolution=args.pose_resolution, executor=args.executor, store=store, checks=checks,
    )


def _run_key(m: Mechanism, args: argparse.Namespace, names: list[str]) -> str:
    return task_key(m.name, names, args.space, args.axes, args.design, args.region, args.modes, args.resolution,
                    args.pose_resolution)


def cmd_atlas(args: argparse.Namespace) -> None:
    m = load_mechanism(args.mechanism)
    out = Path(args.out)
    store = out / CHUNKS / _run_key(m, args, [args.index])
    atlas = _sweep(m, args, [args.index], store)[args.index]
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
    _emit(args, data, text)


def cmd_sweep(args: argparse.Namespace) -> None:
    m = load_mechanism(args.mechanism)
    names = [n.strip() for n in args.indices.split(",") if n.strip()]
    region = region_name(_region(m, args.region))
    folder = Path(args.out) / f"{m.name}_sweep_{region}_{_run_key(m, args, names)[:8]}"
    (folder / "index.json").unlink(missing_ok=True)
    atlases = _sweep(m, args, names, folder / "chunks")
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
    _emit(args, {"folder": str(target), **listing}, f"wrote {len(names)} atlases and their chunks into {target}")


def _remove_if_empty(folder: Path) -> None:
    """Remove ``folder`` if it is empty and can be removed: a cache folder, whose removal is a courtesy."""
    with contextlib.suppress(OSError):
        if folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()


def _named(values: dict[str, float]) -> str:
    return ", ".join(f"{k} = {v:.6g}" for k, v in values.items())


def _with_units(values: dict[str, float], m: Mechanism, units: Units) -> str:
    """A design's values by name, each with its unit in the user's units."""
    names = {p.name: units.convert(p.unit)[1] for p in m.parameters}
    return ", ".join(f"{k} = {v:.6g}{_unit(names[k])}" for k, v in values.items())


@contextmanager
def _logs_to_stderr(active: bool) -> Iterator[None]:
    """Send what the solver prints to standard output to standard error while ``active`` (with ``--json``
    standard output holds the JSON alone): CasADi passes IPOPT's log to Python's ``sys.stdout``."""
    if not active:
        yield
        return
    with redirect_stdout(sys.stderr):
        yield


def cmd_synth(args: argparse.Namespace) -> None:
    """Solve and report; a failed synthesis still writes and prints its record (the last iterate) before
    it fails with the reason (exit 1; 3 where no design meets the constraints)."""
    try:
        _synth(args)
    except SynthesisError as exc:
        if exc.result is not None:
            _report_synthesis(args, exc.result)
        raise


def _synth(args: argparse.Namespace) -> None:
    with _logs_to_stderr(args.json):
        problem = _problem(args.problem)
        args.problem = problem.name
        settings = parse_design(args.set, "settings", "setting", PkmError) if args.set else {}
        result = synthesize(
            problem.configure(**settings),
            resolution=args.resolution,
            starts=args.starts,
            max_iter=args.max_iter,
            tol=args.tol,
            print_level=args.print_level,
            verbose=args.verbose,
        )
    _report_synthesis(args, result)


def cmd_design(args: argparse.Namespace) -> None:
    """A designer's synthesis from a TOML file (:func:`pkm.synthesis.designer.read_problem`), solved and
    reported as ``synth`` does."""
    from pkm.synthesis.designer import read_problem

    problem = read_problem(args.task)
    args.problem = problem.name
    try:
        with _logs_to_stderr(args.json):
            result = synthesize(problem, resolution=args.resolution, starts=args.starts, verbose=args.verbose)
    except SynthesisError as exc:
        if exc.result is not None:
            _report_synthesis(args, exc.result)
        raise
    _report_synthesis(args, result)


def cmd_pareto(args: argparse.Namespace) -> None:
    """A verified Pareto front of a problem's objective against a secondary one (:func:`pkm.pareto`), written
    with its figure and report where ``--out`` is given."""
    from pkm.synthesis.pareto import pareto

    with _logs_to_stderr(args.json):
        front = pareto(_problem(args.problem), args.secondary, n=args.points, tolerance=args.tolerance,
                       resolution=args.resolution, baselines=tuple(b for b in args.baselines.split(",") if b))
    if args.out:
        front.write(Path(args.out))
    _emit(args, front.to_dict(), str(front))


def _report_synthesis(args: argparse.Namespace, result: SynthesisResult) -> None:
    data = result.to_dict()
    if args.out:
        io.write_result(Path(args.out), lambda out: io.write_text(out / f"{args.problem}.json", io.to_json(data)))
    o = result.optimum
    lines = [
        f"{result.problem}: {result.status} after {result.iterations} iterations "
        f"({result.optimizer['wall_time_s']:.2f} s, {result.optimizer['evaluations']} evaluations)",
        f"variables: {_named(o.variables)}",
        f"design: {_named(o.design)}",
        f"mode {result.mode}; regions: " + ", ".join(f"{q} over {r}" for q, r in result.regions.items()),
        f"objective ({result.sense}; {result.objective_unit}) {o.objective:.6g} at resolution "
        f"{result.resolutions['quadrature']}, "
        f"verified {o.verified_objective:.6g} (4x quadrature; accuracy {result.accuracy:.1e}), "
        f"sampled {o.sampled_objective:.6g} ({o.sampled_points} points)",
    ]
    lines += constraint_lines(o.constraints)
    for base in result.baselines.values():
        lines.append(
            f"baseline {base.name} ({base.evaluations} evaluations, {base.wall_time_s:.2f} s): "
            f"{base.best.objective:.6g}, verified {base.best.verified_objective:.6g}"
            f"{'' if base.best.feasible else ' (infeasible)'} at {_named(base.best.variables)}"
        )
    _emit(args, data, "\n".join(lines))


def cmd_reproduce(args: argparse.Namespace) -> None:
    keys = sorted(registry.papers()) if args.paper == "all" else [args.paper]
    summaries = []
    for key in keys:
        summary = reproduce(key, Path(args.out), quick=args.quick)
        summaries.append({**summary, "folder": str(io.kept_path(Path(summary["folder"])))})
    text = "\n".join(f"{s['paper']}: {s['counts']} -> {s['folder']}" for s in summaries)
    _emit(args, summaries, text)


def _catalogue(kind: str) -> str:
    """Each mechanism's allowed values of ``kind`` (for help texts): ``mechanism: a, b, c``, one line each."""
    lines = []
    for name in registry.mechanisms():
        m = registry.mechanism(name)
        values = {
            "design": [f"{p.name} [{p.unit}]" for p in m.parameters],
            "mode": [f"{b.name} ({'/'.join(b.aliases)})" if b.aliases else b.name for b in m.working_modes],
            "region": list(m.region_names()),
            "space": list(m.design_spaces) or ["none (use --axes)"],
            "pose": [f"{n} [{u}]" for n, u in zip(m.pose_names, m.pose_units, strict=True)],
            "index": list(m.global_indices()),
        }[kind]
        lines.append(f"{name}: {', '.join(values)}")
    return "; ".join(lines)


def _example_design() -> str:
    m = registry.mechanism(registry.mechanisms()[0])
    return ",".join(f"{p.name}={p.default:g}" for p in m.parameters[:3])


def _examples() -> dict[str, str]:
    """The names the help texts' examples take, from the registry: the first mechanism's design, a mode, a
    parametrised region, axes and a local index; a problem's setting; a declared secondary objective."""
    m = registry.mechanism(registry.mechanisms()[0])
    first, second = m.parameters[:2]
    placed = [r for r in m.region_names() if r not in ("reachable", "assembled")] or ["reachable"]
    problems = registry.problems().values()
    setting = next((f"{x.name}={x.default:g}" for p in problems for x in p.settings), "none")
    secondary = next((name for p in problems for name in p.secondaries), "none")
    return {
        "design": _example_design(), "parameter": f"{first.name}={first.default:g}", "mode": m.modes[0],
        "region": placed[0],
        "axes": ",".join(f"{q.name}={0.5 * q.default:g}:{1.5 * q.default:g}" for q in (first, second)),
        "index": m.global_indices()[0], "local": m.local_indices()[-1], "setting": setting, "secondary": secondary,
    }


def _example_space() -> str:
    return next(space for name in registry.mechanisms() for space in registry.mechanism(name).design_spaces)


def _example_pose() -> str:
    """The best-conditioned pose of the first mechanism's default design on a coarse grid of its workspace box."""
    m = registry.mechanism(registry.mechanisms()[0])
    box = m.workspace_box(m.design().vector())
    axes = np.meshgrid(*(np.linspace(lo, hi, 7)[1:-1] for lo, hi in box), indexing="ij")
    poses = np.stack([a.ravel() for a in axes], axis=1)
    condition = np.nan_to_num(m.local_index("inverse_condition_f", poses), nan=-1.0)
    return ",".join(f"{c:.3g}" for c in poses[int(np.argmax(condition))]) + f" ({m.name})"


HELP = {
    "mechanism": lambda: f"mechanism: one of {', '.join(registry.mechanisms())}, or a description file (.toml); e.g. "
                         f"{registry.mechanisms()[0]}",
    "index": lambda: f"global index, per mechanism: {_catalogue('index')}; e.g. gci",
    "indices": lambda: f"comma-separated global indices (required, no default), per mechanism: "
                       f"{_catalogue('index')}; e.g. gci,gamma_max",
    "design": lambda: f"design parameters name=value,... in the units shown (missing ones take their defaults, "
                      f"see `pkm list`), or a result file (.json) whose design it takes; per mechanism: "
                      f"{_catalogue('design')}; e.g. --design {_example_design()}",
    "mode": lambda: f"working mode by name or paper alias (default: the first); per mechanism: {_catalogue('mode')}; "
                    f"e.g. --mode out_out",
    "modes": lambda: f"comma-separated working modes (default: the distinct ones over the region); per mechanism: "
                     f"{_catalogue('mode')}; e.g. --modes out_out,out_in",
    "region": lambda: f"region of the index (default reachable: the sampled workspace of the mode), or a task file "
                      f"(.toml) whose task region it takes; per mechanism: {_catalogue('region')}; e.g. --region miw",
    "space": lambda: f"normalised design space (default: the mechanism's first); per mechanism: {_catalogue('space')}; "
                     f"e.g. --space {_example_space()}",
    "pose": lambda: f"a pose (required, no default), comma-separated in the mechanism's pose coordinates (repeat "
                    f"for several poses); per "
                    f"mechanism: {_catalogue('pose')}; e.g. --pose {_example_pose()}",
    "problem": lambda: "synthesis problem, or a task file (.toml): " + "; ".join(f"{p.name} ({p.doc.split(':')[0]})"
                                                        for p in registry.problems().values())
                       + f"; e.g. {next(iter(registry.problems()))}",
    "paper": lambda: "paper key, or all: "
                     + "; ".join(f"{key}: {module.TITLE}" for key, module in registry.papers().items())
                     + f"; e.g. {next(iter(registry.papers()))}",
}


def _lazy(action: argparse.Action, key: str) -> None:
    action.lazy_help = HELP[key]  # type: ignore[attr-defined]


class _HelpParser(_Parser):
    """Fills the help texts that list the registry's names only when help is shown: building them loads
    every mechanism and paper, which the other commands do not need."""

    def format_help(self) -> str:
        for action in self._actions:
            text = getattr(action, "lazy_help", None)
            if text is not None:
                action.help = text()
        return super().format_help()


@functools.cache
def build_parser() -> argparse.ArgumentParser:
    """The command line's parser, built once per process (its 14 commands take milliseconds to build; a parse
    leaves it as it was)."""
    from pkm.atlas import Checks
    from pkm.regions import QUADRATURE_RESOLUTION, SAMPLED_RESOLUTION, SINGULARITY_MARGIN
    from pkm.workspace_map import MAX_RESOLUTION as MAX_MAP

    parser = _HelpParser(prog="pkm", description="Design of parallel kinematic machines.")
    parser.add_argument("--version", action="version", version=version("pkm"))
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_HelpParser)

    def command(name: str, func, help_text: str) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.add_argument("--json", action="store_true", help="machine-readable output on standard output (default: text)")
        p.set_defaults(func=func)
        return p

    def listed(p: argparse.ArgumentParser, *names: str, key: str, **kwargs: Any) -> None:
        _lazy(p.add_argument(*names, help=f"see {key} in pkm {p.prog.split()[-1]} --help", **kwargs), key)

    def example(p: argparse.ArgumentParser, *names: str, help: str, **kwargs: Any) -> None:
        """An option whose help names an example ({design}, {mode}, ...: :func:`_examples`), filled when shown."""
        p.add_argument(*names, help=help, **kwargs).lazy_help = lambda: help.format(**_examples())

    def card_options(p: argparse.ArgumentParser, region_of: str) -> None:
        """The working modes and the region of a design card's maps and indices."""
        example(p, "--mode", help="working modes, comma-separated (default: all); e.g. {mode}")
        example(p, "--region", help=f"the region of {region_of} (default: the mechanism's first parametrised one, "
                                    "else reachable), or a task file (.toml) whose task region it takes; e.g. "
                                    "{region}")

    resolution = (f"pose grid per axis over the sampled region (default {SAMPLED_RESOLUTION}) or quadrature "
                  f"resolution of a parametrised region (default {QUADRATURE_RESOLUTION}); e.g. 32")

    command("list", cmd_list, "mechanisms with their parameters, units, modes, regions and design spaces; indices; "
                              "problems; papers; the evaluation path")
    p = command("build", cmd_build, "compile the kernels of mechanisms ahead of time into the kernel cache, in "
                                    "parallel (everything else compiles at first use)")
    listed(p, "mechanisms", key="mechanism", nargs="*")
    def units_option(p: argparse.ArgumentParser) -> None:
        p.add_argument("--units", help="units of the lengths and angles given, printed and written instead of m and "
                                       "rad: mm or cm, deg; every number of the text, JSON (its units named), CSV "
                                       "and figures in them (default: SI); e.g. mm,deg")

    p = command("eval", cmd_eval, "inverse kinematics, Jacobian and local indices at poses")
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
    p = command("index", cmd_index, "a global index of a design")
    listed(p, "mechanism", key="mechanism")
    listed(p, "index", key="index")
    listed(p, "--design", key="design")
    listed(p, "--mode", key="mode")
    listed(p, "--region", key="region", default="reachable")
    p.add_argument("--resolution", type=_integer, help=resolution)
    p.add_argument("--margin", type=_number, help=f"singularity margin of the sampled region: poses with 1/kappa_f "
                                                  f"below it are left out (default {SINGULARITY_MARGIN}, in [0, 1)); "
                                                  f"e.g. 0.05")
    p.add_argument("--gradient", action="store_true",
                   help="also the exact gradient in every design parameter (parametrised regions; default off)")
    p.add_argument("--out", help="folder for index.json and index.csv (default: none); e.g. results")
    units_option(p)

    def grid_options(p: argparse.ArgumentParser) -> None:
        listed(p, "--space", key="space")
        example(p, "--axes", help="two design parameters with bounds instead of a design space (default: none): "
                                  "name=lower:upper,name=lower:upper; e.g. --axes {axes}")
        example(p, "--design", help="with --axes, the design whose other parameters the atlas holds (default: "
                                    "the defaults): name=value in SI; e.g. {parameter}")
        listed(p, "--region", key="region", default="reachable")
        listed(p, "--modes", key="modes")
        p.add_argument("--resolution", type=_integer, default=41, help="design grid nodes per chart axis (default 41, "
                                                                       "3 to 4001); e.g. 21")
        p.add_argument("--pose-resolution", type=_integer, help=resolution)
        p.add_argument("--tolerance", type=_number, default=Checks.tolerance,
                       help=f"the best design's value must change by less than this (relative) when the pose "
                            f"resolution doubles (default {Checks.tolerance}, in (0, 1)); e.g. 0.005")
        p.add_argument("--min-points", type=_integer, default=Checks.min_points,
                       help=f"the best design's region must hold at least this many poses or nodes "
                            f"(default {Checks.min_points}); e.g. 100")
        p.add_argument("--min-fraction", type=_number, default=Checks.min_fraction,
                       help=f"the best design's region must measure at least this fraction of its workspace box "
                            f"(default {Checks.min_fraction}, in [0, 1)); e.g. 0.05")
        p.add_argument("--executor", choices=parallel.EXECUTORS, default="auto",
                       help="where the chunks run: auto (a Dask scheduler if set, else serial for small jobs and "
                            "local processes for large ones), serial or processes; default auto; e.g. serial")

    def scheduled(p: argparse.ArgumentParser) -> None:
        p.add_argument("--scheduler", help=f"address of a Dask scheduler for the parallel work (default "
                                           f"${parallel.SCHEDULER_VARIABLE}, else local); needs pip install "
                                           f"'pkm[dask]'; e.g. tcp://127.0.0.1:8786")

    p = command("atlas", cmd_atlas, "a global index over a normalised design space (npz and figure) and its best "
                                    "design that passes the convergence and size checks")
    listed(p, "mechanism", key="mechanism")
    listed(p, "index", key="index")
    grid_options(p)
    scheduled(p)
    p.add_argument("--out", default="out", help="folder for the npz and the figure (default out; an interrupted run "
                                                 "resumes from the chunks kept there); e.g. atlases")
    p = command("sweep", cmd_sweep, "several global indices over a design space and working modes in one pass "
                                    "(npz chunks with an index.json, and figures)")
    listed(p, "mechanism", key="mechanism")
    listed(p, "--indices", key="indices", required=True)
    grid_options(p)
    scheduled(p)
    p.add_argument("--out", default="out", help="folder for the sweep's folder (default out; an interrupted run "
                                                 "resumes); e.g. sweeps")
    p = command("synth", cmd_synth, "solve a synthesis problem with IPOPT and verify it (exit 1 with the record of "
                                    "the last iterate when it fails)")
    listed(p, "problem", key="problem")
    p.add_argument("--resolution", type=_integer, help="quadrature resolution of the optimised indices (default: the "
                                                       "problem's, 8 for most); e.g. 6")
    p.add_argument("--starts", type=_integer, help="IPOPT starts from the best screening points (default: the "
                                                   "problem's, 3 or 4; 1 to 1000); e.g. 2")
    p.add_argument("--max-iter", type=_integer, help="IPOPT's max_iter per start (default: the problem's, 100 to 500); "
                                                     "e.g. 1000")
    p.add_argument("--tol", type=_number, help="IPOPT's tol, > 0 (default: the problem's, 1e-10); e.g. 1e-8")
    p.add_argument("--print-level", type=_integer, help="IPOPT's print_level, 0 to 12 (default 0, or 5 with "
                                                        "--verbose); e.g. 3")
    p.add_argument("--verbose", action="store_true", help="show IPOPT's iterations (default off)")
    example(p, "--set", help="the problem's settings as name=value in SI, comma-separated (default: the "
                             "problem's; `pkm list` names them); e.g. {setting}")
    p.add_argument("--out", help="folder for <problem>.json, written also when the synthesis fails (default: none); "
                                 "e.g. results")
    scheduled(p)
    p = command("pareto", cmd_pareto, "a verified Pareto front of a problem's objective against a secondary one by "
                                      "the epsilon-constraint method (front.json, front.csv, figures, report.md)")
    listed(p, "problem", key="problem")
    example(p, "--secondary", required=True, help="the secondary objective, one of the problem's quantities or "
                                                  "secondaries (required, no default); e.g. {secondary}")
    p.add_argument("--points", type=_integer, help="distinct designs on the front, at least 2 (default: as many as "
                                                 "it takes for --tolerance); e.g. 5")
    p.add_argument("--tolerance", type=_number, default=FRONT_TOLERANCE,
                   help="the hypervolume the front's points may leave open between them, as a share of the anchors' "
                        f"box (default {FRONT_TOLERANCE:g}); e.g. 0.01")
    p.add_argument("--resolution", type=_integer, help="quadrature resolution (default: the problem's); e.g. 4")
    p.add_argument("--baselines", default="grid", help="comma-separated among grid and nsga2 (pymoo) (default "
                                                       "grid); e.g. grid,nsga2")
    p.add_argument("--out", help="folder for the front's files (default: none); e.g. fronts")
    p = command("show", cmd_show, "a design card: workspace maps per working mode with singularity curves, the "
                                  "region and the linkage, and a table of parameters and global indices")
    listed(p, "mechanism", key="mechanism")
    example(p, "--design", help="design as name=value in SI, comma-separated (default: the defaults); e.g. "
                                "{design}")
    card_options(p, "the global indices and the map's nodes")
    example(p, "--index", default="inverse_condition_f", help="local index of the maps (default "
                                                              "inverse_condition_f); e.g. {local}")
    p.add_argument("--plane", help="two pose coordinates of the maps (default: the first two); e.g. x,z")
    p.add_argument("--held", help="values of the other pose coordinates (default: the region's centre); e.g. "
                                  "z=-0.5")
    p.add_argument("--resolution", type=_integer, default=81, help=f"poses per axis of the maps (default 81, 3 to "
                                                                    f"{MAX_MAP}); e.g. 121")
    p.add_argument("--out", required=True, help="folder for report.json, report.md and the maps (no default); "
                                                "e.g. card")
    units_option(p)
    p = command("compare", cmd_compare, "designs side by side: their cards and one table of every global index "
                                        "per design and mode (JSON, CSV, markdown)")
    listed(p, "mechanism", key="mechanism")
    example(p, "--design", action="append", required=True, help="a design as name=value in SI (repeat for each "
                                                                "design, at least two; no default); e.g. {parameter}")
    card_options(p, "the global indices")
    p.add_argument("--resolution", type=_integer, default=61, help=f"poses per axis of the maps (default 61, 3 to "
                                                                    f"{MAX_MAP}); e.g. 81")
    p.add_argument("--out", required=True, help="folder for comparison.json, .csv, .md and a card per design "
                                                "(no default); e.g. compared")
    units_option(p)
    p = command("explore", cmd_explore, "an atlas in the browser: click or hover a design to see its workspace "
                                        "map, singularities, region, linkage and card (a local server on "
                                        "127.0.0.1; needs pip install 'pkm[explore]')")
    listed(p, "mechanism", key="mechanism")
    example(p, "--index", help="global index of the atlas (default: the mechanism's first, see pkm list); e.g. "
                               "{index}")
    example(p, "--region", help="region of the atlas and the cards (default: the mechanism's first parametrised "
                                "one, else reachable); e.g. {region}")
    listed(p, "--space", key="space")
    example(p, "--axes", help="two design parameters with bounds instead of a design space (default: the first "
                              "design space, else the first two parameters at half to 1.5 times their defaults): "
                              "name=lower:upper,name=lower:upper; e.g. {axes}")
    example(p, "--design", help="the parameters off the atlas's chart, name=value in SI (default: the defaults); "
                                "e.g. {parameter}")
    p.add_argument("--problem", help="a synthesis problem whose optimum the atlas marks: a registered name or a "
                                     "task file (default: a registered problem of the mechanism that optimises "
                                     "the index over the region); e.g. my_task.toml")
    p.add_argument("--resolution", type=_integer, default=21, help="design grid nodes per chart axis (default 21, 3 to "
                                                                   "81); e.g. 41")
    p.add_argument("--map-resolution", type=_integer, default=128, help="poses per axis of the workspace maps "
                                                                        "(default 128, 3 to 256); e.g. 256")
    p.add_argument("--port", type=_integer, default=0, help="port on 127.0.0.1 (default 0: a free port); e.g. 8765")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser (default: open one)")
    p.add_argument("--html", help="write the page with a precomputed atlas and grid of cards as one "
                                  "self-contained file instead of serving it (default: serve); e.g. atlas.html")
    p.add_argument("--grid", type=_integer, default=5, help="with --html, precomputed designs per chart axis (default "
                                                            "5, 1 to 21); e.g. 7")
    p = command("design", cmd_design, "a synthesis for the designer's task, variables, objective and constraints, "
                                      "from a TOML file (docs/mechanisms.md), solved with IPOPT and verified")
    p.add_argument("task", help="the problem's TOML file: mechanism, task, variables, fixed, objective, "
                                "constraints, mode, baseline; e.g. my_task.toml")
    p.add_argument("--resolution", type=_integer, help="quadrature resolution (default: the file's, 8); e.g. 6")
    p.add_argument("--starts", type=_integer, help="IPOPT starts from the best screening points (default 4); e.g. 2")
    p.add_argument("--verbose", action="store_true", help="show IPOPT's iterations (default off)")
    p.add_argument("--out", help="folder for <problem>.json, written also when the synthesis fails (default: "
                                 "none); e.g. results")
    p = command("export", cmd_export, "a design as an Extended URDF: the mechanism cut open into a tree "
                                      "(robot.urdf), its loop closures and motors (robot.yaml, read by Pinocchio's "
                                      "closed-loop loaders) and a README of what was cut (docs/export.md)")
    listed(p, "mechanism", key="mechanism")
    example(p, "--design", help="design as name=value in SI, comma-separated (default: the defaults); e.g. "
                                "{design}")
    example(p, "--mode", help="working mode of the reference configuration, where every joint of the URDF is "
                              "zero (default: the first); e.g. {mode}")
    p.add_argument("--pose", help="the reference pose, comma-separated (default: the mechanism's reference pose); "
                                  "e.g. 0,1.4")
    p.add_argument("--out", required=True, help="folder for robot.urdf, robot.yaml and README.md (no default); "
                                                "e.g. urdf")
    units_option(p)
    p = command("reproduce", cmd_reproduce, "reproduce a paper's checkable claims into OUT/<key>/")
    listed(p, "paper", key="paper")
    p.add_argument("--out", default="out", help="folder holding <key>/ (default out); e.g. reports")
    p.add_argument("--quick", action="store_true", help="low resolutions, for tests (default off)")
    scheduled(p)
    return parser


NEGATIVE = re.compile(r"^-[0-9.]")


def _negative_values(argv: list[str]) -> list[str]:
    """``--pose -0.3,1.9`` as ``--pose=-0.3,1.9``: argparse reads a value that starts with a minus sign
    and is not a lone number as an option, and half of every workspace has negative coordinates."""
    out: list[str] = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and NEGATIVE.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def _check_out(folder: str | None) -> None:
    """Refuse a given ``--out`` that cannot be an output folder (:func:`_check_path`) before any work."""
    if folder is not None:
        _check_path("--out", folder, Path(folder), "a folder")


def _check_path(option: str, given: str, folder: Path, what: str) -> None:
    """Refuse the value ``given`` of ``option`` (``what`` it names: a folder, a file in a folder) before any
    work, so that no computed result is lost to it, unless it is a path and ``folder`` (the path itself or the
    folder of a file) can be a folder this process writes into: not empty (which would write into the current
    folder unasked), no existing file on the way, creatable and writable (tried, and whatever the trial created
    removed again)."""
    shown = f"{option} {reprlib.repr(given)} violates:"
    if not given:
        raise PkmError(f"{shown} a path to {what} (it is empty)")
    missing: list[Path] = []
    try:
        for part in (folder, *folder.parents):
            if part.exists() and not part.is_dir():
                raise PkmError(f"{shown} {what} (or a path to one); {reprlib.repr(str(part))} is a file")
        missing = [part for part in (folder, *folder.parents) if not part.exists()]
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".pkm-probe-"):
            pass
    except OSError as exc:
        raise PkmError(f"{shown} {what} this user can write ({exc.strerror or exc})") from None
    finally:
        for part in missing:
            with contextlib.suppress(OSError):
                part.rmdir()


def _check_file(option: str, given: str | None) -> None:
    """Refuse a given file option (``--html``) that cannot be a file this process writes, before any work: an
    existing folder, or a path whose folder cannot be one (:func:`_check_path`)."""
    if given is None:
        return
    _check_path(option, given, Path(given).parent, "a file in a folder")
    shown = f"{option} {reprlib.repr(given)} violates: a file"
    try:
        folder = Path(given).is_dir()
    except OSError as exc:
        raise PkmError(f"{shown} this user can write ({exc.strerror or exc})") from None
    if folder:
        raise PkmError(f"{shown}; it is a folder")


def _terminated(signum: int, _frame: Any) -> None:
    interrupts.remember(signum)
    raise KeyboardInterrupt


def _line(message: object) -> str:
    """A message as one line: its line breaks and other unprintable characters escaped (a file's key may hold
    them)."""
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode() for c in str(message))


def _one_line_warning(message: Warning | str, *_args: Any, **_kwargs: Any) -> None:
    print(f"pkm: warning: {_line(message)}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """The command line. Warnings are one line each on standard error (the interpreter answering where a
    kernel did not compile, for instance), but none where ``PKM_COMPILED=0`` asks for the interpreter."""
    main_thread = threading.current_thread() is threading.main_thread()
    # SIGTERM ends the command as Ctrl-C does: its worker processes end with it, nothing half-written stays
    previous = signal.signal(signal.SIGTERM, _terminated) if main_thread else None
    try:
        return _main(argv)
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    if os.environ.get("PKM_COMPILED") == "0":
        warnings.filterwarnings("ignore", category=CompiledPathWarning)
    else:
        warnings.showwarning = _one_line_warning
    keeper = None
    try:
        args = build_parser().parse_args(_negative_values(sys.argv[1:] if argv is None else list(argv)))
        out = getattr(args, "out", None)
        _check_out(out)
        address = getattr(args, "scheduler", None) or parallel.scheduler()
        if address and args.func in PARALLEL_COMMANDS:
            parallel.connect(address).close()
        with parallel.scheduled(address), interruptible(), io.keeping(out, args.command) as keeper:
            args.func(args)
    except PkmError as exc:
        print(f"pkm: error: {_line(exc)}", file=sys.stderr)
        return 2
    except InfeasibleError as exc:
        print(f"pkm: infeasible: {_line(exc)}", file=sys.stderr)
        return INFEASIBLE
    except ComputationError as exc:
        print(f"pkm: computation failed: {_line(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("pkm: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader of stdout has gone (e.g. `pkm list | head -1`): nothing more can be written there
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    finally:
        # a result that --out failed to take after the computation is kept, and said so, whatever came after
        if keeper is not None and keeper.kept is not None:
            print(f"pkm: {_line(keeper.message)}", file=sys.stderr)
    return 0 if keeper is None or keeper.kept is None else 1


PARALLEL_COMMANDS = (cmd_atlas, cmd_sweep, cmd_synth, cmd_reproduce)


if __name__ == "__main__":
    sys.exit(main())
