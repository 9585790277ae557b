"""``pkm certify``: a region's properties proved, refuted with a witness or left undecided (:mod:`pkm.certify`);
with ``--around``, the largest certified disc or ball about a pose; with ``--extreme``, a local index's largest or
least value over the region certified from both sides (:mod:`pkm.certify_extreme`)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from pkm import certify_pieces, io, parallel
from pkm.certify import DEPTH, MAX_BOXES, PROPERTIES, SECONDS, plot_certificate
from pkm.cli.arguments import design_option, listed, scheduled
from pkm.cli.common import emit, given_design, given_poses, given_region, load_mechanism, named
from pkm.errors import PkmError

HELP = "prove a region free of singularities and within the limits, by branch and prune on rigorous enclosures"
PARALLEL = True


def options(p: argparse.ArgumentParser) -> None:
    """The mechanism, the region or the pose, the properties, the search's budget."""
    listed(p, "mechanism", key="mechanism")
    listed(p, "--region", key="region", default="task")
    listed(p, "--mode", key="mode")
    p.add_argument("--properties", help=f"comma-separated, of {', '.join(PROPERTIES)} (default: singularity and "
                                        "limits, and collisions where the legs state their capsules)")
    p.add_argument("--threshold", type=float, help="the least singularity margin, in [0, 1) (default: 1e-6, a "
                                                   "singular pose's)")
    p.add_argument("--around", help="a pose: the largest disc or ball of its position where the properties hold, "
                                    "instead of the region (default: none); e.g. 0,0,-0.5")
    p.add_argument("--radius", type=float, default=1.0, help="with --around, the largest radius tried [m] "
                                                            "(default: 1)")
    p.add_argument("--extreme", help="a local index: its largest value over the region certified from both sides "
                                     "instead of the properties (a pose where it is found, a bound proved "
                                     "everywhere; default: none); e.g. inverse_condition_f")
    p.add_argument("--sense", choices=("max", "min"), default="max", help="with --extreme, its largest or its least "
                                                                          "value (default: max)")
    p.add_argument("--gap", type=float, default=0.05, help="with --extreme, the bound proved at most this far "
                                                          "beyond the value found, relative (default: 0.05)")
    p.add_argument("--tolerances", type=float, help="with --extreme pose_error, the tolerance on every part's "
                                                    "geometry [m] (docs/accuracy.md; default: none); e.g. 1e-5")
    p.add_argument("--depth", type=int, default=DEPTH, help=f"halvings of a box at most (default: {DEPTH})")
    p.add_argument("--boxes", type=int, default=MAX_BOXES, help=f"boxes at most (default: {MAX_BOXES})")
    p.add_argument("--seconds", type=float, default=SECONDS, help=f"time at most (default: {SECONDS:g} s)")
    p.add_argument("--designs", help="design parameters spanning intervals, every design within them certified: "
                                     "comma-separated name=lower:upper (default: none); e.g. r2=0.98:1.02")
    p.add_argument("--executor", choices=parallel.EXECUTORS, default="serial",
                   help="where the search runs: serial (one search, the default), processes (its box cut into "
                        "pieces, a local process for each in turn) or auto (a Dask scheduler if set); e.g. processes")
    p.add_argument("--out", help="folder for certify.json, and for a region's certification certify.png and .svg: its "
                                 "boxes over the workspace (default: none); e.g. certified")
    design_option(p)
    scheduled(p)


def _designs(text: str | None) -> dict[str, list[str]] | None:
    """--designs as {name: [lower, upper]} (the numbers checked by pkm.certify)."""
    if text is None:
        return None
    out = {}
    for item in (part.strip() for part in text.split(",") if part.strip()):
        name, _, span = item.partition("=")
        if not span or span.count(":") != 1:
            raise PkmError(f"--designs violates: comma-separated name=lower:upper; got {item!r}")
        out[name.strip()] = span.split(":")
    return out


def _extreme(m: Any, d: Any, args: argparse.Namespace, budget: dict[str, Any]) -> tuple[dict[str, Any], str]:
    """--extreme: the index's extreme over the region, found at a pose and proved within the gap."""
    index = args.extreme
    if index == "pose_error":
        if args.tolerances is None:
            raise PkmError("--tolerances violates: given with --extreme pose_error (the tolerance on every part's "
                           "geometry, m)")
        index = m.error_model().index(args.tolerances)
    found = m.certified_extreme(index, given_region(m, args.region), d, sense=args.sense, mode=args.mode,
                                gap=args.gap, **budget)
    word = "largest" if found.sense == "max" else "least"
    proved = ("NOT PROVED: " + found.steps[-1]["verdict"] if found.proved is None else
              f"proved {'<=' if found.sense == 'max' else '>='} {found.proved:.6g} {found.unit}")
    text = (f"{m.name}: the {word} {found.index} over {found.region} in mode {found.mode}: {found.found:.6g} "
            f"{found.unit} at {named(found.pose)}; {proved} ({len(found.steps)} certifications, "
            f"{sum(s['boxes'] for s in found.steps)} boxes, {found.seconds:.2f} s)")
    return found.as_dict(), text


def run(args: argparse.Namespace) -> None:
    """The verdict, the witnesses, the undecided volume and the time; or the largest certified radius; or the
    index's certified extreme."""
    m = load_mechanism(args.mechanism)
    d = given_design(m, args.design)
    properties = ([p.strip() for p in args.properties.split(",") if p.strip()] if args.properties is not None else
                  ["singularity", "limits", *(["collisions"] if "collision" in m.functions
                                              and getattr(m, "description", None) is not None else [])])
    if not 0 < args.depth <= 40 or not 0 < args.boxes <= 10**7 or not 0 < args.seconds <= 3600:
        raise PkmError("--depth, --boxes and --seconds violate: within 1-40, 1-10^7 and 0-3600 s")
    budget = {"depth": args.depth, "max_boxes": args.boxes, "seconds": args.seconds}
    drawn = None  # a certification of the region, whose boxes --out draws
    if args.extreme is not None:
        data, text = _extreme(m, d, args, budget)
    elif args.around:
        (pose,) = given_poses([args.around], m.n_out)
        found = m.largest_region(pose, d, radius=args.radius, properties=properties, mode=args.mode,
                                 designs=_designs(args.designs),
                                 threshold=args.threshold, **budget)
        data = found.as_dict()
        spanning = _designs(args.designs) or {}
        beyond = "no witness found" if found.witness is None else (
            f"witness at {found.witness['distance']:.6g} m: {named(found.witness['pose'])}"
            + "".join(f", {n} = {found.witness['design'][n]:.6g}" for n in spanning))
        text = (f"{m.name}: {', '.join(found.properties)} certified within {found.proved:.6g} m of "
                f"{named(found.centre)}; not proved at {found.beyond:.6g} m; {beyond} ({len(found.steps)} "
                f"certifications, {found.seconds:.2f} s)")
    else:
        options = {"properties": properties, "mode": args.mode, "threshold": args.threshold,
                   "designs": _designs(args.designs), **budget}
        region = given_region(m, args.region)
        where = "auto" if parallel.scheduler() else args.executor  # a Dask scheduler set takes the work
        found = m.certify(region, d, **options) if where == "serial" else \
            certify_pieces.certify(m, region, d, executor=where, **options)
        data, drawn = found.as_dict(), found
        spanned = "".join(f", {n} in [{lo:g}, {hi:g}]" for n, (lo, hi) in found.designs.items())
        text = (f"{m.name}: {', '.join(f'{p} >= {v:g}' for p, v in found.properties.items())} over "
                f"{found.region}{spanned} in mode {found.mode}: {found.verdict.upper()} ({found.boxes} boxes, depth "
                f"{found.depth}, {found.seconds:.2f} s"
                + (f"; {found.undecided:.3g} of the region's box undecided" if found.undecided else "")
                + (f"; stopped at {found.stopped}" if found.stopped else "") + ")")
        for w in found.witnesses:
            values = {k: v for k, v in w.items() if k not in ("pose", "u", "design")}
            at = "".join(f", {n} = {w['design'][n]:.6g}" for n in found.designs)
            text += f"\n  witness {named(w['pose'])}{at}: {named(values)}"
    if args.out:
        def write(folder: Path) -> list[Path]:
            written = [io.write_text(folder / "certify.json", io.to_json(data))]
            if drawn is not None:
                written += [plot_certificate(m, given_region(m, args.region), drawn, folder / f"certify.{suffix}", d)
                            for suffix in ("png", "svg")]
            return written

        text += "\nwrote " + ", ".join(str(p) for p in io.write_result(Path(args.out), write))
    emit(args, data, text)
