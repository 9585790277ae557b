"""The ``pkm`` command line (DESIGN.md section 7).

Exit status 0 on success, 2 on bad input (one line on standard error, no traceback), 1 when a valid
computation fails (for instance IPOPT does not converge).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any, NoReturn

import numpy as np

import pkm
from pkm import indices, io
from pkm.design import parse_design
from pkm.errors import ComputationError, PkmError
from pkm.progress import Progress


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise PkmError(f"{self.prog}: {message}")


def _design(mech: pkm.Mechanism, text: str | None) -> pkm.Design:
    return mech.design(parse_design(text) if text else None, partial=True)


def _poses(text: list[str] | None, n: int) -> np.ndarray:
    if not text:
        raise PkmError(f"--pose is required (comma-separated, {n} values)")
    try:
        poses = [[float(v) for v in item.split(",")] for item in text]
    except ValueError:
        raise PkmError(f"--pose values must be numbers; got {text}") from None
    if any(len(p) != n for p in poses):
        raise PkmError(f"--pose needs {n} comma-separated values")
    return np.array(poses)


def _emit(args: argparse.Namespace, data: Any, text: str) -> None:
    sys.stdout.write(io.to_json(data) if args.json else text + "\n")


def cmd_list(args: argparse.Namespace) -> None:
    data = {}
    for name in pkm.mechanisms():
        m = pkm.load(name)
        data[name] = {
            "doc": m.doc,
            "parameters": [
                {"name": p.name, "default": p.default, "lower": p.lower, "upper": p.upper, "unit": p.unit, "doc": p.doc}
                for p in m.parameters
            ],
            "modes": {b.name: {"aliases": list(b.aliases), "doc": b.doc} for b in m.working_modes},
            "assemblies": {b.name: b.doc for b in m.assembly_modes},
            "regions": list(m.region_names()),
            "design_spaces": sorted(getattr(m, "design_spaces", {})),
        }
    from pkm.synthesis import PROBLEMS
    from pkm.task_synthesis import TASK_PROBLEMS

    out = {
        "mechanisms": data,
        "indices": {k: v.doc for k, v in indices.GLOBAL.items()},
        "problems": {k: v.doc for k, v in {**PROBLEMS, **TASK_PROBLEMS}.items()},
    }
    lines = []
    for name, info in data.items():
        lines.append(f"{name}: {info['doc']}")
        lines += [f"  {p['name']} = {p['default']:g} {p['unit']}: {p['doc']}" for p in info["parameters"]]
        lines.append("  modes: " + ", ".join(f"{k} ({'/'.join(v['aliases'])})" for k, v in info["modes"].items()))
        lines.append("  regions: " + ", ".join(info["regions"]))
    lines.append("indices: " + ", ".join(out["indices"]))
    lines.append("problems: " + ", ".join(out["problems"]))
    _emit(args, out, "\n".join(lines))


def cmd_eval(args: argparse.Namespace) -> None:
    m = pkm.load(args.mechanism)
    d = _design(m, args.design)
    x = _poses(args.pose, m.n_out)
    mode = m.working_mode(args.mode).name
    q = m.inverse_kinematics(x, d, mode=mode, passive=True, strict=True)
    J = m.jacobian(x, d, mode=mode)
    local = {name: m.local_index(name, x, d, mode=mode) for name in m.local_indices()}
    sing = m.singularity(x, d, mode=mode)
    rows = []
    for k in range(len(x)):
        rows.append(
            {
                "pose": x[k],
                "q": q[k],
                "J": J[k],
                **{name: float(v[k]) for name, v in local.items()},
                **{name: float(v[k]) for name, v in sing.items()},
            }
        )
    text = "\n".join(
        f"pose {r['pose'].tolist()}: q = {np.round(r['q'], 6).tolist()} rad, "
        f"1/kappa_f = {r['inverse_condition_f']:.6g}, |V|max = {r['velocity_max']:.6g}, "
        f"|V|min = {r['velocity_min']:.6g}"
        for r in rows
    )
    _emit(args, {"mechanism": m.name, "design": dict(d), "mode": mode, "poses": rows}, text)


def cmd_index(args: argparse.Namespace) -> None:
    m = pkm.load(args.mechanism)
    d = _design(m, args.design)
    mode = m.working_mode(args.mode).name
    out = m.global_index(
        args.index,
        d,
        region=args.region,
        mode=mode,
        resolution=args.resolution,
        gradient=args.gradient,
        singularity_margin=args.margin,
    )
    value, grad = out if args.gradient else (out, None)
    data = {
        "mechanism": m.name,
        "index": args.index,
        "region": args.region,
        "mode": mode,
        "design": dict(d),
        "value": float(value),
        "points": value.points,
        "resolution": value.resolution,
    }
    text = f"{args.index} over {args.region} ({mode}, {value.points} points) = {float(value):.8g}"
    if grad is not None:
        data["gradient"] = grad
        text += "\ngradient: " + ", ".join(f"d/d{k} = {v:.6g}" for k, v in grad.items())
    _emit(args, data, text)


def cmd_atlas(args: argparse.Namespace) -> None:
    from pkm.atlas import compute_atlas, default_modes

    m = pkm.load(args.mechanism)
    modes = tuple(args.modes.split(",")) if args.modes else default_modes(m, args.region)
    spaces = getattr(m, "design_spaces", {})
    inside = int(spaces[args.space].chart_grid(args.resolution)[2].sum()) if args.space in spaces else 1
    bar = Progress(len(modes) * inside, f"atlas {args.index}")
    atlas = compute_atlas(
        m,
        args.index,
        space=args.space,
        modes=modes,
        region=args.region,
        resolution=args.resolution,
        pose_resolution=args.pose_resolution,
        progress=bar.advance,
    )
    bar.close()
    out = Path(args.out)
    stem = f"{m.name}_{args.index}_{args.region}"
    npz = out / f"{stem}.npz"
    png = out / f"{stem}.png"
    atlas.save_npz(npz)
    atlas.plot(png)
    best = {mode: atlas.best(mode) for mode in atlas.modes}
    data = {"npz": str(npz), "figure": str(png), "wall_time_s": atlas.wall_time, "best": best}
    text = "\n".join(
        [f"wrote {npz} and {png} in {atlas.wall_time:.1f} s"]
        + [f"best {args.index} in {mode}: {b[2]:.6g} at (u, v) = ({b[0]:.4f}, {b[1]:.4f})" for mode, b in best.items()]
    )
    _emit(args, data, text)


def cmd_synth(args: argparse.Namespace) -> None:
    from pkm.synthesis import synthesize

    result = synthesize(
        args.problem,
        resolution=args.resolution,
        starts=args.starts,
        verbose=args.verbose,
        progress=(lambda msg: print(msg, file=sys.stderr)) if sys.stderr.isatty() else None,
    )
    data = result.to_dict()
    if args.out:
        io.write_text(Path(args.out) / f"{args.problem}.json", io.to_json(data))
    o, b = result.optimum, result.baseline
    text = (
        f"{args.problem}: {result.status} after {result.iterations} iterations "
        f"({result.optimizer['wall_time_s']:.2f} s, {result.optimizer['evaluations']} evaluations)\n"
        f"design: " + ", ".join(f"{k} = {v:.6g}" for k, v in o.design.items()) + "\n"
        f"objective {o.objective:.6g}, verified {o.verified_objective:.6g} (4x quadrature), "
        f"sampled {o.sampled_objective:.6g} ({o.sampled_points} points)\n"
        f"baseline (atlas grid, {result.baseline_cost['evaluations']} evaluations, "
        f"{result.baseline_cost['wall_time_s']:.2f} s): {b.objective:.6g}, verified {b.verified_objective:.6g}"
    )
    for label, cand in (
        ("Wu's two-step family", getattr(result, "two_step", None)),
        ("Wu's design", getattr(result, "paper", None)),
    ):
        if cand is not None:
            text += f"\n{label}: {cand.objective:.6g} at (l, d1) = ({cand.chart[0]:.6g}, {cand.chart[1]:.6g}) m"
    _emit(args, data, text)


def cmd_reproduce(args: argparse.Namespace) -> None:
    from pkm.reproduce import PAPERS, reproduce

    keys = sorted(PAPERS) if args.paper == "all" else [args.paper]
    summaries = [reproduce(key, Path(args.out), quick=args.quick) for key in keys]
    text = "\n".join(f"{s['paper']}: {s['counts']} -> {s['folder']}" for s in summaries)
    _emit(args, summaries, text)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="pkm", description="Design of parallel kinematic machines.")
    parser.add_argument("--version", action="version", version=pkm.__version__)
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)

    def command(name: str, func, help_text: str) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help_text, description=help_text)
        p.add_argument("--json", action="store_true", help="machine-readable output")
        p.set_defaults(func=func)
        return p

    command("list", cmd_list, "mechanisms, their parameters, modes and regions; indices; problems")
    p = command("eval", cmd_eval, "inverse kinematics, Jacobian and local indices at poses")
    p.add_argument("mechanism")
    p.add_argument("--pose", action="append", help="x,y (repeat for several poses)")
    p.add_argument("--design", help="name=value,... (missing parameters take their defaults)")
    p.add_argument("--mode", help="working mode (name or paper alias)")
    p = command("index", cmd_index, "a global index of a design")
    p.add_argument("mechanism")
    p.add_argument("index")
    p.add_argument("--design")
    p.add_argument("--mode")
    p.add_argument("--region", default="reachable")
    p.add_argument("--resolution", type=int)
    p.add_argument("--margin", type=float, help="singularity margin of the sampled region (1/kappa_f)")
    p.add_argument("--gradient", action="store_true", help="exact gradient (parametrised regions)")
    p = command("atlas", cmd_atlas, "a global index over a normalised design space (npz and figure)")
    p.add_argument("mechanism")
    p.add_argument("index")
    p.add_argument("--space", default="gao1998")
    p.add_argument("--region", default="reachable")
    p.add_argument("--modes", help="comma-separated working modes (default: the distinct ones)")
    p.add_argument("--resolution", type=int, default=41, help="design grid nodes per chart axis")
    p.add_argument("--pose-resolution", type=int, help="pose grid (reachable) or quadrature (miw)")
    p.add_argument("--out", default="out", help="folder for the npz and the figure")
    p = command("synth", cmd_synth, "solve a synthesis problem with IPOPT and verify it")
    p.add_argument("problem")
    p.add_argument("--resolution", type=int)
    p.add_argument("--starts", type=int)
    p.add_argument("--verbose", action="store_true", help="show IPOPT's iterations")
    p.add_argument("--out", help="folder for <problem>.json")
    p = command("reproduce", cmd_reproduce, "reproduce a paper's checkable claims into OUT/<key>/")
    p.add_argument("paper", help="gao1998, lara_molina2016 or all")
    p.add_argument("--out", default="out")
    p.add_argument("--quick", action="store_true", help="low resolutions (for tests)")
    return parser


def main(argv: list[str] | None = None) -> int:
    try:
        args = build_parser().parse_args(argv)
        args.func(args)
    except PkmError as exc:
        print(f"pkm: error: {exc}", file=sys.stderr)
        return 2
    except ComputationError as exc:
        print(f"pkm: computation failed: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
