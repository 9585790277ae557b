"""Run pkm's benchmarks and print a markdown table: ``python -m bench.run [--quick] [--json PATH]``.

* throughput: IK + J + 1/kappa_f of the five-bar on 10^6 random reachable poses, pkm against a
  hand-written numpy implementation in the same run (bench/throughput.py);
* dynamics: IK + M_t + M_w + 1/kappa_2(M_w) of the five-bar (Lara-Molina 2016) on the same poses, pkm
  against a hand-written numpy implementation in the same run (bench/dynamics.py);
* gantry: inverse dynamics (IK + slider forces by virtual work) of the slider gantry (Wu 2008) on 10^6
  random states, pkm against a hand-written numpy implementation in the same run (bench/gantry.py);
* synthesis: ``pkm.synthesize("five_bar.max_gci_miw")`` (IPOPT) against its baseline on the same model,
  when pkm.synthesis is available (skipped with a note otherwise);
* integrals: global indices with their gradients over 10^4 nodes by the point integrands against the
  CasADi graph of the nodes, and every registered synthesis against its baseline (bench/integrals.py).

Figures are ratios against baselines measured in the same run; nothing asserts on time.
"""

from __future__ import annotations

import argparse
import importlib.util
import sys
import time
from pathlib import Path
from typing import Any

from bench import dynamics, gantry, integrals, passive_leg, scale_out, throughput, ups_pu
from bench.report import log, machine, write_json

SYNTHESIS_PROBLEM = "five_bar.max_gci_miw"


def synthesis_bench() -> dict[str, Any]:
    """IPOPT synthesis against its baseline; skipped (with the reason) when pkm.synthesis does not exist."""
    if importlib.util.find_spec("pkm.synthesis") is None:
        log("synthesis: pkm.synthesis is not available; skipped")
        return {"problem": SYNTHESIS_PROBLEM, "skipped": "pkm.synthesis is not available"}
    import pkm
    import pkm.synthesis

    synthesize = getattr(pkm, "synthesize", None) or pkm.synthesis.synthesize
    log(f"synthesis: {SYNTHESIS_PROBLEM}")
    start = time.perf_counter()
    try:
        result = synthesize(SYNTHESIS_PROBLEM).to_dict()
    except Exception as exc:  # report the failure with the other figures, then exit 1
        return {"problem": SYNTHESIS_PROBLEM, "error": f"{type(exc).__name__}: {exc}"}
    total = time.perf_counter() - start
    opt, base = result["optimizer"], result["baseline"]
    base_verified = base.get("verified_objective")
    if base_verified is None:  # compare like with like: both verified, or both as optimised
        gain = result["objective"] - result["baseline_objective"]
    else:
        gain = result["verified_objective"] - base_verified
    return {
        "problem": SYNTHESIS_PROBLEM,
        "total_wall_time_s": total,
        "status": result.get("status"),
        "optimizer": {
            "wall_time_s": opt["wall_time_s"],
            "evaluations": opt["evaluations"],
            "objective": result["objective"],
            "verified_objective": result["verified_objective"],
        },
        "baseline": {
            "wall_time_s": base["wall_time_s"],
            "evaluations": base["evaluations"],
            "objective": result["baseline_objective"],
            "verified_objective": base.get("verified_objective"),
        },
        "time_ratio_baseline_over_optimizer": base["wall_time_s"] / opt["wall_time_s"],
        "objective_gain": gain,
    }


def _fmt(value: Any, spec: str) -> str:
    return "-" if value is None else format(value, spec)


def dynamics_markdown(dyn: dict[str, Any]) -> list[str]:
    if "skipped" in dyn:
        return ["", f"## Dynamics throughput (Lara-Molina 2016): skipped ({dyn['skipped']})"]
    lines = [
        "",
        f"## Dynamics throughput (Lara-Molina 2016): IK + M_t + M_w + 1/kappa_2(M_w), five-bar, "
        f"{dyn['poses']:,} reachable poses (best of {dyn['repeats']}, seed {dyn['seed']})",
        "",
        "| benchmark | threads | poses/s | vs numpy | time (s) |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in dyn["rows"]:
        lines.append(
            f"| {r['name']} | {r['threads']} | {r['poses_per_s'] / 1e6:.2f} M | {r['ratio_vs_numpy']:.2f}x "
            f"| {r['seconds']:.3f} |"
        )
    lines += ["", f"pkm.batch.THREADS default: {dyn['default_threads']}. Every row agrees with numpy to 1e-9."]
    return lines + [f"- {note}" for note in dyn["notes"]]


def gantry_markdown(gan: dict[str, Any]) -> list[str]:
    if "skipped" in gan:
        return ["", f"## Slider gantry inverse dynamics (Wu 2008): skipped ({gan['skipped']})"]
    lines = [
        "",
        f"## Slider gantry inverse dynamics (Wu 2008): IK + slider forces, {gan['states']:,} random states "
        f"(best of {gan['repeats']}, seed {gan['seed']})",
        "",
        "| benchmark | threads | states/s | vs numpy | time (s) |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in gan["rows"]:
        lines.append(
            f"| {r['name']} | {r['threads']} | {r['states_per_s'] / 1e6:.2f} M | {r['ratio_vs_numpy']:.2f}x "
            f"| {r['seconds']:.3f} |"
        )
    lines += ["", f"pkm.batch.THREADS default: {gan['default_threads']}. Every row agrees with numpy to 1e-9."]
    return lines + [f"- {note}" for note in gan["notes"]]


def markdown(report: dict[str, Any]) -> str:
    env, tp = report["machine"], report["throughput"]
    lines = [
        f"# pkm benchmarks ({env['date']})",
        "",
        f"{env['cpu']}, {env['cores']} cores; {env['os']}; Python {env['python']}, numpy {env['numpy']}, "
        f"CasADi {env['casadi']}.",
        "",
        f"## Throughput: IK + J + 1/kappa_f, five-bar, {tp['poses']:,} reachable poses "
        f"(best of {tp['repeats']}, seed {tp['seed']})",
        "",
        "| benchmark | threads | poses/s | vs numpy | time (s) |",
        "|---|---:|---:|---:|---:|",
    ]
    for r in tp["rows"]:
        lines.append(
            f"| {r['name']} | {r['threads']} | {r['poses_per_s'] / 1e6:.2f} M | {r['ratio_vs_numpy']:.2f}x "
            f"| {r['seconds']:.3f} |"
        )
    lines += ["", f"pkm.batch.THREADS default: {tp['default_threads']}. Every row agrees with numpy to 1e-9."]
    lines += [f"- {note}" for note in tp["notes"]]
    lines += dynamics_markdown(report["dynamics"])
    lines += gantry_markdown(report["gantry"])
    syn = report["synthesis"]
    lines += ["", f"## Synthesis: {SYNTHESIS_PROBLEM}", ""]
    if "skipped" in syn:
        lines.append(f"skipped: {syn['skipped']}.")
    elif "error" in syn:
        lines.append(f"failed: {syn['error']}")
    else:
        lines += [
            "| method | wall time (s) | evaluations | objective | verified objective |",
            "|---|---:|---:|---:|---:|",
        ]
        for label, key in (("IPOPT (pkm.synthesize)", "optimizer"), ("baseline (atlas grid)", "baseline")):
            s = syn[key]
            lines.append(
                f"| {label} | {s['wall_time_s']:.3f} | {s['evaluations']} | {_fmt(s['objective'], '.6f')} "
                f"| {_fmt(s['verified_objective'], '.6f')} |"
            )
        lines += [
            "",
            f"Baseline / IPOPT wall time: {syn['time_ratio_baseline_over_optimizer']:.2f}x; objective of IPOPT "
            f"minus baseline (verified): {syn['objective_gain']:+.3g}; status {syn['status']}; "
            f"total with verification {syn['total_wall_time_s']:.2f} s.",
        ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.run", description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="10^5 poses (and states) instead of 10^6")
    parser.add_argument("--json", metavar="PATH", help="also write the figures as JSON to PATH")
    parser.add_argument("--no-compiled", action="store_true", help="skip the C-compiled experiments")
    parser.add_argument("--no-dynamics", action="store_true", help="skip the dynamics throughput benchmark")
    parser.add_argument("--no-gantry", action="store_true", help="skip the slider gantry inverse dynamics benchmark")
    parser.add_argument("--no-synthesis", action="store_true", help="skip the synthesis benchmark")
    parser.add_argument("--no-ups-pu", action="store_true", help="skip the 2-UPS-PU benchmarks (bench.ups_pu)")
    parser.add_argument(
        "--no-passive-leg", action="store_true", help="skip the passive-leg manipulator benchmarks (bench.passive_leg)"
    )
    parser.add_argument("--no-scale-out", action="store_true", help="skip the executor benchmark (bench.scale_out)")
    parser.add_argument(
        "--no-integrals", action="store_true", help="skip the global indices and syntheses benchmark (bench.integrals)"
    )
    args = parser.parse_args(argv)
    report: dict[str, Any] = {"command": "python -m bench.run " + " ".join(sys.argv[1:] if argv is None else argv)}
    report["machine"] = machine()
    n = 100_000 if args.quick else 1_000_000
    report["throughput"] = throughput.run(n, 3, compiled=not args.no_compiled, log=log)
    report["dynamics"] = {"skipped": "--no-dynamics"} if args.no_dynamics else dynamics.run(n, 3, log=log)
    report["gantry"] = {"skipped": "--no-gantry"} if args.no_gantry else gantry.run(n, 3, log=log)
    report["synthesis"] = {"skipped": "--no-synthesis"} if args.no_synthesis else synthesis_bench()
    if not args.no_ups_pu:
        report["ups_pu"] = ups_pu.run(n, 3, log)
    if not args.no_passive_leg:
        report["passive_leg"] = passive_leg.run(n, n // 10, 3, log)
    if not args.no_scale_out:
        report["scale_out"] = scale_out.run(21 if args.quick else 61, 32, 64, 3, log)
    if not args.no_integrals:
        report["integrals"] = integrals.run(quick=args.quick, log=log)
    print(markdown(report))
    if "ups_pu" in report:
        print("\n## 2-UPS-PU (Zhao 2008)\n\n" + ups_pu.markdown(report["ups_pu"]))
    if "passive_leg" in report:
        print("\n## passive_leg (Nam 2006)\n\n" + passive_leg.markdown(report["passive_leg"]))
    if "scale_out" in report:
        print("\n## Scale-out (executor seam)\n\n" + scale_out.markdown(report["scale_out"]))
    if "integrals" in report:
        print("\n## Compiled global indices and syntheses (issue 12)\n\n" + integrals.markdown(report["integrals"]))
    if args.json:
        write_json(Path(args.json), report)
    syntheses = report.get("integrals", {}).get("syntheses", ())
    failed = "error" in report["synthesis"] or any("error" in s for s in syntheses)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
