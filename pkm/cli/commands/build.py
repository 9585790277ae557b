"""``pkm build``: the kernels of mechanisms compiled ahead of time into the kernel cache."""

from __future__ import annotations

import argparse
import os
import time

from pkm import registry
from pkm.cli.arguments import listed
from pkm.cli.common import emit, evaluation_lines, load_mechanism
from pkm.compiled import status as compiled_status
from pkm.errors import ComputationError

HELP = ("compile the kernels of mechanisms ahead of time into the kernel cache, in parallel (everything else "
        "compiles at first use)")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The mechanisms, all by default."""
    listed(p, "mechanisms", key="mechanism", nargs="*")


def run(args: argparse.Namespace) -> None:
    """Compile each mechanism's kernels with a progress bar, and fail where one stays on the interpreter."""
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
    emit(args, {"mechanisms": data, "evaluation": compiled_status()},
         "\n".join([*lines, *evaluation_lines(compiled_status())[:1]]))
    if any(d["interpreted"] for d in data.values()):
        raise ComputationError("some kernels did not compile (the warnings above name them)")


def _children_cpu() -> float:
    """CPU seconds of the finished child processes (the compilers)."""
    times = os.times()
    return times.children_user + times.children_system
