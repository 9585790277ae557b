"""What the commands share: the mechanism, design, region, problem, modes, poses and units a user gives, the
output (text or ``--json``) and its formatting, and the checks of an output path before any work."""

from __future__ import annotations

import argparse
import contextlib
import reprlib
import sys
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stdout
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io, registry
from pkm.design import Design, parse_design
from pkm.errors import PkmError
from pkm.mechanism import Mechanism
from pkm.units import Units

RESULT = ".json"  # a design given as a result file
TASK = ".toml"  # a region or a problem given as a task file


def load_mechanism(name: str) -> Mechanism:
    """A command's mechanism: a registered one by name, or a description file (``.toml``) derived on first use
    (:func:`pkm.spec.machine.resolve_name`, as :func:`pkm.load` takes a name)."""
    from pkm.spec.machine import resolve_name

    return resolve_name(name)


def given_design(mech: Mechanism, text: str | None, units: Units | None = None) -> Design:
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


def given_region(m: Mechanism, text: str) -> Any:
    """A region by name, or a task file's (``.toml``: the region its objective is taken over)."""
    if text.endswith(TASK):
        from pkm.synthesis.designer import task_of

        return task_of(text, m)
    return text


def given_problem(text: str) -> Any:
    """A synthesis problem: a registered one by name, or a task file's (``.toml``)."""
    if text.endswith(TASK):
        from pkm.synthesis.designer import read_problem

        return read_problem(text)
    return registry.problem(text)


def given_modes(m: Mechanism, text: str | None) -> list[str] | None:
    """Working modes from ``a,b`` (names or aliases), or None for all."""
    return [m.working_mode(mode).name for mode in text.split(",")] if text else None


def given_units(args: argparse.Namespace) -> Units:
    """The user's units (``--units``), SI where the command has none."""
    return Units.parse(getattr(args, "units", None))


def given_poses(text: list[str] | None, n: int) -> np.ndarray:
    """Poses of ``n`` coordinates from ``--pose`` values, each comma-separated."""
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


def emit(args: argparse.Namespace, data: Any, text: str) -> None:
    """A command's answer on standard output: ``data`` as JSON with ``--json``, else ``text``."""
    sys.stdout.write(io.to_json(data) if args.json else text + "\n")


def evaluation_lines(path: dict[str, Any]) -> list[str]:
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


def unit_text(unit: str) -> str:
    """`` m/rad`` after a value, nothing for a dimensionless one."""
    return "" if unit == "-" else f" {unit}"


def valued(values: np.ndarray, units: dict[str, str]) -> str:
    """``x = 0.1 m, y = 1.5 m``: values by name with their units."""
    return ", ".join(f"{name} = {v:.6g} {unit}" for (name, unit), v in zip(units.items(), values, strict=True))


def design_in(m: Mechanism, design: Design, units: Units) -> dict[str, float]:
    """A design's values in the user's units."""
    return {p.name: units.value(float(design[p.name]), p.unit) for p in m.parameters}


def with_units(values: dict[str, float], m: Mechanism, units: Units) -> str:
    """A design's values by name, each with its unit in the user's units."""
    names = {p.name: units.convert(p.unit)[1] for p in m.parameters}
    return ", ".join(f"{k} = {v:.6g}{unit_text(names[k])}" for k, v in values.items())


def named(values: dict[str, float]) -> str:
    """``a = 1, b = 2``: values by name."""
    return ", ".join(f"{k} = {v:.6g}" for k, v in values.items())


def numbers(values: list[float]) -> str:
    """``(1, 2)``: values in parentheses."""
    return "(" + ", ".join(f"{v:.6g}" for v in values) + ")"


@contextmanager
def logs_to_stderr(active: bool) -> Iterator[None]:
    """Send what the solver prints to standard output to standard error while ``active`` (with ``--json``
    standard output holds the JSON alone): CasADi passes IPOPT's log to Python's ``sys.stdout``."""
    if not active:
        yield
        return
    with redirect_stdout(sys.stderr):
        yield


def check_out(folder: str | None) -> None:
    """Refuse a given ``--out`` that cannot be an output folder (:func:`check_path`) before any work."""
    if folder is not None:
        check_path("--out", folder, Path(folder), "a folder")


def check_path(option: str, given: str, folder: Path, what: str) -> None:
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


def check_file(option: str, given: str | None) -> None:
    """Refuse a given file option (``--html``) that cannot be a file this process writes, before any work: an
    existing folder, or a path whose folder cannot be one (:func:`check_path`)."""
    if given is None:
        return
    check_path(option, given, Path(given).parent, "a file in a folder")
    shown = f"{option} {reprlib.repr(given)} violates: a file"
    try:
        folder = Path(given).is_dir()
    except OSError as exc:
        raise PkmError(f"{shown} this user can write ({exc.strerror or exc})") from None
    if folder:
        raise PkmError(f"{shown}; it is a folder")
