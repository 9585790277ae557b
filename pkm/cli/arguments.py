"""The command line's options: argparse's parser as pkm wants it (one line, exit 2), the types of numeric
options, the options several commands share, and the help texts that list the registry's names, filled only
when help is shown."""

from __future__ import annotations

import argparse
import math
import reprlib
from typing import Any, NoReturn

import numpy as np

from pkm import parallel, registry
from pkm.errors import PkmError
from pkm.regions import QUADRATURE_RESOLUTION, SAMPLED_RESOLUTION

# the help of a resolution over a region, sampled or parametrised (pkm index, and an atlas's poses)
RESOLUTION = (f"pose grid per axis over the sampled region (default {SAMPLED_RESOLUTION}) or quadrature "
              f"resolution of a parametrised region (default {QUADRATURE_RESOLUTION}); e.g. 32")


class Parser(argparse.ArgumentParser):
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


class HelpParser(Parser):
    """Fills the help texts that list the registry's names only when help is shown: building them loads
    every mechanism and paper, which the other commands do not need."""

    def format_help(self) -> str:
        for action in self._actions:
            text = getattr(action, "lazy_help", None)
            if text is not None:
                action.help = text()
        return super().format_help()


def integer(text: str) -> int:
    """An option's integer (argparse's ``type``)."""
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{reprlib.repr(text)} violates: an integer") from None


def number(text: str) -> float:
    """An option's finite number (argparse's ``type``)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{reprlib.repr(text)} violates: a finite number")
    return value


def listed(p: argparse.ArgumentParser, *names: str, key: str, **kwargs: Any) -> None:
    """An option whose help lists the registry's names of ``key`` (:data:`HELP`), filled when shown."""
    action = p.add_argument(*names, help=f"see {key} in pkm {p.prog.split()[-1]} --help", **kwargs)
    action.lazy_help = HELP[key]  # type: ignore[attr-defined]


def example(p: argparse.ArgumentParser, *names: str, help: str, **kwargs: Any) -> None:
    """An option whose help names an example ({design}, {mode}, ...: :func:`examples`), filled when shown."""
    p.add_argument(*names, help=help, **kwargs).lazy_help = lambda: help.format(**examples())


def design_option(p: argparse.ArgumentParser) -> None:
    """``--design``: one design, the defaults where it names no value."""
    example(p, "--design", help="design as name=value in SI, comma-separated (default: the defaults); e.g. "
                                "{design}")


def units_option(p: argparse.ArgumentParser) -> None:
    """``--units``: the user's units of lengths and angles."""
    p.add_argument("--units", help="units of the lengths and angles given, printed and written instead of m and "
                                   "rad: mm or cm, deg; every number of the text, JSON (its units named), CSV "
                                   "and figures in them (default: SI); e.g. mm,deg")


def card_options(p: argparse.ArgumentParser, region_of: str) -> None:
    """The working modes and the region of a design card's maps and indices."""
    example(p, "--mode", help="working modes, comma-separated (default: all); e.g. {mode}")
    example(p, "--region", help=f"the region of {region_of} (default: the mechanism's first parametrised one, "
                                "else reachable), or a task file (.toml) whose task region it takes; e.g. "
                                "{region}")


def map_resolution(p: argparse.ArgumentParser, *, default: int, suggested: int) -> None:
    """``--resolution``: poses per axis of a design card's maps."""
    from pkm.workspace_map import MAX_RESOLUTION

    p.add_argument("--resolution", type=integer, default=default, help=f"poses per axis of the maps (default "
                                                                      f"{default}, 3 to {MAX_RESOLUTION}); e.g. "
                                                                      f"{suggested}")


def scheduled(p: argparse.ArgumentParser) -> None:
    """``--scheduler``: where the parallel work of a parallel command goes."""
    p.add_argument("--scheduler", help=f"address of a Dask scheduler for the parallel work (default "
                                       f"${parallel.SCHEDULER_VARIABLE}, else local); needs pip install "
                                       f"'pkm[dask]'; e.g. tcp://127.0.0.1:8786")




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


def examples() -> dict[str, str]:
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
