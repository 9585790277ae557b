"""The compiled path: any CasADi SX function pkm evaluates over a batch is emitted as C
(:mod:`pkm.compiled.emit`), compiled at first use by the system C compiler (:mod:`pkm.compiled.toolchain`)
into the per-user kernel cache (:mod:`pkm.compiled.cache`), loaded, checked against CasADi's interpreter
once per library (the cache records it), and run by the runner extension (``_runner.c``, itself compiled into
the cache) in place of the interpreter: same inputs, same (N, k) buffers, values equal to round-off.

:func:`kernel` is the one door: ``pkm.batch`` asks it for a function's kernel at every evaluation. A
function whose kernel is in the cache runs compiled from its first evaluation. Otherwise its evaluations are
answered by the interpreter until the work they have asked for (instructions times rows, summed) reaches
what its compile costs (:func:`price`, measured by ``bench/compile_price.py``: a fixed part and a part
that grows with the graph's instructions; the work of earlier processes counts, recorded in the cache at
exit), and then the evaluation that reaches it compiles it and waits:
a graph evaluated at scale is compiled at once, one evaluated a few times on a few rows (a test's, a single
pose's) never, and no graph costs more than twice what the better of the two paths would have (the rule of
renting until the rent reaches the price), with a progress bar on a terminal where the compile takes more
than half a second.
:func:`build` compiles many kernels ahead of time, in parallel (``pkm build``).

Nothing is silent: :func:`status` counts, per process, the evaluations that ran compiled and those that ran
on the interpreter with the reason (disabled by ``PKM_COMPILED=0``, no C compiler, little work so far, a
compile error, a cache that cannot be written, not an SX graph, a graph of more than
:data:`MAX_INSTRUCTIONS` instructions). A compile that fails, a cache that cannot be
written and a missing compiler each give one :class:`CompiledPathWarning`.
"""

from __future__ import annotations

import atexit
import contextlib
import hashlib
import json
import os
import sys
import threading
import time
import warnings
from collections import Counter, OrderedDict
from collections.abc import Callable, Iterable
from concurrent.futures import CancelledError, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm.compiled import emit
from pkm.compiled.cache import Cache, location
from pkm.compiled.toolchain import SMALL, CompileError, Toolchain, find
from pkm.progress import Progress

COMPILE_WORK = 1 << 27  # a compile's cost whatever the graph (the compiler's start, the link, the load), in
# the interpreter's work: about 0.24 s at its 1-4 ns per instruction and row
COMPILE_ROWS = 1 << 16  # and its cost per instruction of the graph, in rows of that instruction: the compiler's
# 0.12 ms per instruction (docs/benchmarks.md, "What a compile costs")
LITTLE_WORK = "little work so far"  # the reason of an evaluation on the interpreter below its compile's price


def price(instructions: int) -> int:
    """The work (instructions times rows, summed over evaluations) from which a graph of ``instructions``
    instructions is compiled: what its compile costs, in the interpreter's time."""
    return COMPILE_WORK + COMPILE_ROWS * instructions
MAX_INSTRUCTIONS = 50_000  # a larger graph stays on the interpreter: its compile takes minutes
CHECK_ROWS = 5  # rows of the check against the interpreter after loading
CHECK_TOLERANCE = 1e-9  # of the largest entry of an output, at the check's random inputs
CHECK_NUDGE = 1e-15  # relative: the check's inputs rounded again, to see how far the function itself moves
CHECK_NUDGES = 3  # times, the median move counting (one nudge across a branch's switch does not)
CHECK_SENSITIVITY = 100  # times that move: a kernel within it of the interpreter is as right as the interpreter


class CompiledPathWarning(UserWarning):
    """pkm evaluates with CasADi's interpreter where it would rather run a compiled kernel."""


_evaluations: Counter[str] = Counter()
_warned: set[str] = set()
_lock = threading.Lock()


def _warn(topic: str, message: str) -> None:
    """One warning per topic and process."""
    with _lock:
        if topic in _warned:
            return
        _warned.add(topic)
    warnings.warn(f"pkm evaluates with CasADi's interpreter: {message}", CompiledPathWarning, stacklevel=4)


@dataclass(frozen=True)
class _Path:
    """What the compiled path has in this process: the runner and toolchain, or why not."""

    runner: Any
    toolchain: Toolchain | None
    cache: Cache
    reason: str  # why the compiled path is off (empty when on)
    unwritable: str  # why no kernel can be added to the cache (empty when they can)
    label: str = ""  # the reason in a few words, as status() counts the evaluations


RUNNER_SOURCE = Path(__file__).with_name("_runner.c")


@lru_cache(maxsize=1)
def _path() -> _Path:
    cache = Cache(location())
    if os.environ.get("PKM_COMPILED", "1") == "0":
        return _Path(None, None, cache, "disabled by PKM_COMPILED=0", "", "disabled")
    toolchain = find()
    if isinstance(toolchain, str):
        return _Path(None, None, cache, toolchain, "", "no C compiler")
    unwritable = cache.writable()
    try:
        runner = _load_runner(toolchain, cache, unwritable)
    except (CompileError, OSError, ImportError) as exc:
        return _Path(None, toolchain, cache, f"the kernel runner could not be built: {exc}", unwritable,
                     "no kernel runner")
    return _Path(runner, toolchain, cache, "", unwritable)


def _load_runner(toolchain: Toolchain, cache: Cache, unwritable: str) -> Any:
    import importlib.machinery
    import importlib.util
    import sysconfig

    source = RUNNER_SOURCE.read_bytes()
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    key = hashlib.sha256(b"\0".join([b"runner", source, toolchain.identity.encode(), suffix.encode(),
                                     sys.version.encode()])).hexdigest()
    library = cache.find(key)
    if library is None:
        if unwritable:
            raise OSError(unwritable)

        def build(folder: Path) -> dict:
            (folder / "_runner.c").write_bytes(source)
            toolchain.compile_runner(folder / "_runner.c", folder / "kernel.so")
            return {"function": "runner", "compiler": toolchain.identity}

        library = cache.add(key, build)
    loader = importlib.machinery.ExtensionFileLoader("_runner", str(library))
    spec = importlib.util.spec_from_file_location("_runner", str(library), loader=loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


_compilers: list[ThreadPoolExecutor] = []  # the threads that wait for compilers, made at the first compile
_compiles = {"submitted": 0, "finished": 0}


def _submit(job: Callable[[], Path]) -> Future:
    with _lock:
        if not _compilers:
            _compilers.append(ThreadPoolExecutor(os.cpu_count() or 1, thread_name_prefix="pkm-compile"))
        _compiles["submitted"] += 1
    future = _compilers[0].submit(job)

    def finished(_: Future) -> None:
        with _lock:
            _compiles["finished"] += 1

    future.add_done_callback(finished)
    return future


def _pay_rent() -> None:
    """Record in the cache the interpreter's work this process did for the kernels it met and did not
    compile (at exit: a later process counts it towards their compiles' price)."""
    paid = {e.key: e.interpreted - e.recorded for e in list(_entries.values())
            if e.state == "met" and e.interpreted > e.recorded}
    if paid:
        with contextlib.suppress(OSError):
            _path().cache.pay_rent(paid)


atexit.register(_pay_rent)


def _forget_in_child() -> None:
    """A forked child has none of its parent's compile threads: it starts their bookkeeping afresh."""
    _compilers.clear()
    _compiles.update(submitted=0, finished=0)
    _entries.clear()


os.register_at_fork(after_in_child=_forget_in_child)


def _wait(futures: Iterable[Future]) -> None:
    """Wait for compiles, with a progress bar on a terminal where it takes more than half a second; an
    interrupt (Ctrl-C, or SIGTERM on the command line) drops the compiles not yet started, so that the process
    ends after the compilers already running rather than after every queued one."""
    try:
        _wait_for(futures)
    except KeyboardInterrupt:
        with _lock:
            if _compilers:
                _compilers.pop().shutdown(wait=False, cancel_futures=True)
        raise


def _wait_for(futures: Iterable[Future]) -> None:
    pending = {f for f in futures if not f.done()}
    if pending:
        pending = wait(pending, timeout=0.5).not_done
    if not pending:
        return
    with Progress(1, "compiling kernels") as bar:
        while pending:
            bar.total, bar.done = max(1, _compiles["submitted"]), 0
            bar.advance(_compiles["finished"])
            pending = wait(pending, timeout=0.2).not_done


@lru_cache(maxsize=1)
def _emitter() -> str:
    return hashlib.sha256(Path(emit.__file__).read_bytes()).hexdigest()


def key(fn: ca.Function, summed: bool = False, rows: bool = False) -> str:
    """The cache key of ``fn``'s kernel: the sha256 of its serialised graph, whether it sums over the batch or
    reads the design row by row, the emitter's source, the toolchain's fingerprint, the optimisation level for its
    size and kind and CasADi's version."""
    toolchain = _path().toolchain
    level = toolchain.optimisation(fn.n_instructions(), summed) if toolchain else ""
    parts = [fn.serialize(), str(summed), str(rows), _emitter(), toolchain.fingerprint if toolchain else "", level,
             ca.__version__]
    return hashlib.sha256("\0".join(parts).encode()).hexdigest()


Chunk = tuple[list[np.ndarray], list[np.ndarray], int, int]
Run = Callable[[list[int], list[Chunk], int], None]


class _Kernel:
    """One function's kernel in this process (summing, or reading the design row by row: :func:`kernel`): new,
    met once (not in the cache), compiling, ready, or off with the reason."""

    def __init__(self, fn: ca.Function, summed: bool, rows: bool = False):
        self.fn, self.summed, self.rows = fn, summed, rows
        self.run: Run | None = None
        self.future: Future | None = None
        self.reason, self.key = "", ""
        self.lock = threading.Lock()
        self.state = "new"
        self.interpreted = 0  # the work the interpreter has done for the kernel while it was met, earlier
        self.recorded = 0  # processes' included: those recorded in the cache when this one met it

    def get(self, work: int) -> Run | None:
        if self.state == "ready":
            return self.run
        with self.lock:
            if self.state == "new":
                self._look()
            if self.state == "met" and self.interpreted + work < price(self.fn.n_instructions()):
                self.interpreted += work
                return None
            if self.state == "met":
                self._compile()
            if self.state == "compiling":
                _wait([self.future])
                self._finish()
        return self.run

    def _look(self) -> None:
        """Ready where the cache has the kernel; else met, or off with the reason."""
        path = _path()
        if path.runner is None:
            self._off(path.label, path.reason, topic="path")
            return
        if not self.fn.is_a("SXFunction"):
            self._off("not an SX graph", "")
            return
        if self.fn.n_instructions() > MAX_INSTRUCTIONS:
            self._off("too large to compile", "")
            return
        self.key = key(self.fn, self.summed, self.rows)
        library = path.cache.find(self.key)
        if library is not None:
            self._load(library)
            return
        if path.unwritable:
            self._off("cache not writable", path.unwritable, topic="cache")
            return
        self.state, self.reason = "met", LITTLE_WORK
        self.interpreted = self.recorded = path.cache.rent(self.key)

    def _compile(self) -> None:
        """Emit the kernel here (CasADi's objects stay on this thread) and compile it in the background."""
        try:
            source = emit.source(self.fn, self.summed, self.rows)
        except ValueError:  # not emittable: ports not dense, or an operation the emitter does not know
            self._off("not an SX graph", "")
            return
        path = _path()
        toolchain, name, summed, instructions = path.toolchain, self.fn.name(), self.summed, self.fn.n_instructions()

        def build(folder: Path) -> dict:
            (folder / "kernel.c").write_text(source)
            started = time.perf_counter()
            toolchain.compile_kernel(folder / "kernel.c", folder / "kernel.so", instructions, summed)
            return {"function": name, "summed": summed, "instructions": instructions, "compiler": toolchain.identity,
                    "instruction_set": toolchain.instruction_set, "seconds": round(time.perf_counter() - started, 3)}

        self.future = _submit(lambda: path.cache.add(self.key, build))
        self.state = "compiling"

    def _finish(self) -> None:
        try:
            library = self.future.result()
        except CancelledError:  # dropped by an interrupt: met again, compiled when next asked
            self.state, self.future = "met", None
            return
        except CompileError as exc:
            self._off("compile error", f"{self.fn.name()}'s kernel did not compile: {exc}", topic=self.key)
            return
        except OSError as exc:
            self._off("cache not writable", f"the kernel cache cannot be written ({exc})", topic="cache")
            return
        self._load(library)

    def _load(self, library: Path) -> None:
        runner = _path().runner
        try:
            address = runner.load(str(library))
        except OSError as exc:
            self._off("load error", f"{self.fn.name()}'s kernel did not load: {exc}", topic=self.key)
            return
        n_in, n_out, name = self.fn.n_in(), self.fn.n_out(), self.fn.name()
        once = [] if self.summed or self.rows else sorted(emit.shared_inputs(self.fn))

        def run(strides: list[int], chunks: list[Chunk], threads: int) -> None:
            if len(strides) != n_in or any(len(c[0]) != n_in or len(c[1]) != n_out + 1 for c in chunks):
                raise ValueError(f"{name}'s kernel takes {n_in} inputs and {n_out} outputs and a flag per chunk")
            if any(strides[i] for i in once):
                raise ValueError(f"{name}'s kernel reads the design once: one shared by the batch (stride 0)")
            runner.run(address, threads, strides, chunks)

        cache = _path().cache
        if not cache.checked(self.key):
            error = _check(self.fn, self.summed, run, self.rows)
            if error:
                self._off("check failed", f"{name}'s kernel differs from the interpreter ({error})", topic=self.key)
                return
            cache.mark_checked(self.key)
        self.run, self.state, self.reason = run, "ready", ""

    def _off(self, reason: str, message: str, topic: str = "") -> None:
        self.state, self.reason, self.run = "off", reason, None
        if message:
            _warn(topic or reason, message)


def _interpreted(fn: ca.Function, inputs: list[np.ndarray], shared: list[bool], n: int) -> list[np.ndarray]:
    """The interpreter's outputs (n, numel_j) at the check's rows."""
    rows = []
    for p in range(n):
        args = [ca.DM(a.reshape(fn.size_in(i), order="F") if shared[i] else a[p].reshape(fn.size_in(i), order="F"))
                for i, a in enumerate(inputs)]
        rows.append([np.asarray(o).reshape(-1, order="F") for o in fn.call(args)])
    return [np.array([r[j] for r in rows]) for j in range(fn.n_out())]


def _check(fn: ca.Function, summed: bool, run: Run, rows: bool = False) -> str:
    """Empty where ``run`` gives the interpreter's values at CHECK_ROWS random rows (the inputs named in
    ``emit.GROUP_SHARED`` shared by the rows, unless ``rows``), else what differs: to CHECK_TOLERANCE of each
    output's largest entry, or CHECK_SENSITIVITY times as far as the interpreter's value moves when the inputs
    are rounded once more (CHECK_NUDGE, the median of CHECK_NUDGES moves), where the function itself amplifies
    rounding (the least eigenvalue of a stiffness whose largest is 1e9 times larger is known to 1e-7 of it)."""
    rng = np.random.default_rng(0)
    n = CHECK_ROWS
    shared = [fn.name_in(i) in emit.GROUP_SHARED and not rows for i in range(fn.n_in())]
    inputs = [rng.uniform(0.5, 1.5, size=fn.numel_in(i) if shared[i] else (n, fn.numel_in(i)))
              for i in range(fn.n_in())]
    want = _interpreted(fn, inputs, shared, n)
    nudged = [_interpreted(fn, [a * (1 + CHECK_NUDGE * rng.standard_normal(a.shape)) for a in inputs], shared, n)
              for _ in range(CHECK_NUDGES)]
    if summed:
        got = [np.zeros((1, fn.numel_out(j))) for j in range(fn.n_out())]
        scales = [np.abs(w).sum(axis=0) for w in want]
        moves = [np.median([np.abs((m[j] - w).sum(axis=0, keepdims=True)) for m in nudged], axis=0)
                 for j, w in enumerate(want)]
        want = [w.sum(axis=0, keepdims=True) for w in want]
    else:
        got = [np.zeros((n, fn.numel_out(j))) for j in range(fn.n_out())]
        scales = [np.abs(np.nan_to_num(w, posinf=0, neginf=0)).max(initial=0.0) for w in want]
        moves = [np.median([np.abs(m[j] - w) for m in nudged], axis=0) for j, w in enumerate(want)]
    strides = [0 if shared[i] else fn.numel_in(i) for i in range(fn.n_in())]
    run(strides, [(inputs, [*got, np.zeros((1, 1))], n, n)], 1)
    for j, (g, w, scale, move) in enumerate(zip(got, want, scales, moves, strict=True)):
        with np.errstate(invalid="ignore"):
            close = np.abs(g - w) <= np.maximum(CHECK_TOLERANCE * np.maximum(1.0, np.nan_to_num(
                scale, posinf=0, neginf=0)), CHECK_SENSITIVITY * np.nan_to_num(move, nan=0, posinf=0))
        same = close | (np.isnan(g) & np.isnan(w)) | (np.isinf(w) & (g == w))
        if not np.all(same):
            return f"output {fn.name_out(j)}: {np.count_nonzero(~same)} of {same.size} entries"
    return ""


ENTRIES = 4096  # kernels a process keeps track of, the first met forgotten first
_entries: OrderedDict[tuple[ca.Function, bool], _Kernel] = OrderedDict()


def _entry(fn: ca.Function, summed: bool, rows: bool = False) -> _Kernel:
    rows = rows and not summed and bool(emit.shared_inputs(fn))  # one kernel where the design is read once
    entry = _entries.get((fn, summed, rows))
    if entry is None:
        with _lock:
            entry = _entries.setdefault((fn, summed, rows), _Kernel(fn, summed, rows))
            while len(_entries) > ENTRIES:
                _entries.popitem(last=False)
    return entry


def kernel(fn: ca.Function, summed: bool = False, *, work: int = 0, rows: bool = False) -> Run | None:
    """``run(strides, chunks, threads)`` evaluating ``fn`` compiled over the chunks of a batch, each chunk
    ``(inputs, outputs, n, group)``: n rows, inputs (n or 1, k_i) with the row strides ``strides``, outputs
    (n, k_j) and a flag (1, 1) that the kernel sets to 1 where an input entry it reads row by row is not
    finite, C order; the chunks on up to ``threads`` threads (the caller's and threads the runner keeps),
    without the GIL. With ``summed`` the kernel adds the sums of each output over consecutive groups of
    ``group`` rows to the rows of (n / group, k_j) outputs instead. A kernel that is not summed reads the
    inputs named in ``emit.GROUP_SHARED`` (the mode, the design) once, shared by the batch (stride 0); with
    ``rows``, where a batch gives one per row, it is a kernel of its own, compiled where such batches ask for
    it. None where this evaluation runs on the interpreter (module docstring; ``work``, its instructions times
    rows, counts towards the compile). Each call counts as one evaluation in :func:`status`."""
    entry = _entry(fn, summed, rows)
    run = entry.get(work)
    _evaluations["compiled" if run is not None else entry.reason] += 1
    return run


def build(functions: Iterable[tuple[ca.Function, bool]], *, progress: Callable[[int, int], None] | None = None
          ) -> dict[str, int]:
    """Compile the kernels of ``(function, summed)`` pairs ahead of time, in parallel (one compile per
    core), and load them; ``progress(done, total)`` after each (by default a progress bar on a terminal
    where it takes more than half a second). Returns how many were found in the cache,
    compiled, and left on the interpreter."""
    entries = list(dict.fromkeys(_entry(fn, summed) for fn, summed in functions))
    for entry in entries:
        with entry.lock:
            if entry.state == "new":
                entry._look()
            if entry.state == "met":
                entry._compile()
    counts = Counter({"cached": sum(e.state == "ready" for e in entries)})
    done = counts["cached"]
    if progress:
        progress(done, len(entries))
    else:
        _wait([e.future for e in entries if e.state == "compiling"])
    for entry in entries:
        if entry.state == "compiling":
            entry.future.exception()
            with entry.lock:
                if entry.state == "compiling":
                    entry._finish()
            counts["compiled" if entry.state == "ready" else "interpreted"] += 1
            done += 1
            if progress:
                progress(done, len(entries))
    counts["interpreted"] += sum(e.state == "off" and e.future is None for e in entries)
    return {k: counts[k] for k in ("cached", "compiled", "interpreted")}


_written: dict[Path, tuple[Run | None, str]] = {}


def written_kernel(source: Path) -> tuple[Run | None, str]:
    """``(run, "")`` for a kernel pkm writes in C itself (``source``, one of its own files: a routine with a loop
    of its own, which no CasADi graph expresses, such as a path tracker), with the emitted kernels' interface
    (``pkm_kernel``; :func:`kernel`'s ``run``); compiled into the cache at its first use in any process and kept,
    its key the source's sha256 and the toolchain's fingerprint. ``(None, why)`` where the compiled path is off
    or the kernel does not compile or load."""
    with _lock:
        if source not in _written:
            _written[source] = _written_kernel(source)
        return _written[source]


def _written_kernel(source: Path) -> tuple[Run | None, str]:
    path = _path()
    if path.runner is None:
        return None, path.reason
    text = source.read_bytes()
    toolchain = path.toolchain
    key = hashlib.sha256(b"\0".join([b"written", text, toolchain.fingerprint.encode()])).hexdigest()
    library = path.cache.find(key)
    try:
        if library is None:
            if path.unwritable:
                return None, path.unwritable

            def build(folder: Path) -> dict:
                (folder / "kernel.c").write_bytes(text)
                toolchain.compile_kernel(folder / "kernel.c", folder / "kernel.so", SMALL)  # at -O2
                return {"function": source.stem, "compiler": toolchain.identity}

            library = path.cache.add(key, build)
        address = path.runner.load(str(library))
    except (CompileError, OSError) as exc:
        return None, f"{source.name} did not compile or load: {exc}"
    runner = path.runner

    def run(strides: list[int], chunks: list[Chunk], threads: int) -> None:
        runner.run(address, threads, strides, chunks)

    return run, ""


def casadi_versions() -> dict[str, str]:
    """CasADi's version here and the one generated/'s builders were written with (their manifest)."""
    try:
        import generated

        manifest = json.loads((Path(generated.__file__).with_name("manifest.json")).read_text())
        written = manifest.get("tools", {}).get("casadi", "")
    except (ImportError, OSError, ValueError):
        written = ""
    return {"running": ca.__version__, "generated_with": written}


def status() -> dict[str, Any]:
    """The compiled path in this process: ``path`` ("compiled" or "interpreter") and ``reason`` (why the
    compiled path is off, empty when on), the ``compiler`` and its ``instruction_set``, the ``cache`` folder
    (and why it cannot be written, ``cache_unwritable``), ``kernels`` loaded, ``compiling`` now, the
    ``evaluations`` that ran ``compiled`` and on the ``interpreter`` by reason, and ``casadi``: the version
    running and the one generated/ was written with, with a ``note`` where they differ."""
    path = _path()
    loaded = sum(e.state == "ready" for e in list(_entries.values()))
    versions = casadi_versions()
    if versions["generated_with"] and versions["generated_with"] != versions["running"]:
        versions["note"] = (f"generated/ was written with CasADi {versions['generated_with']}, this is "
                            f"{versions['running']}: evaluation works, kernels are compiled for this version")
    interpreted = {reason: n for reason, n in sorted(_evaluations.items()) if reason != "compiled"}
    return {
        "path": "compiled" if path.runner is not None else "interpreter",
        "reason": path.reason,
        "compiler": path.toolchain.identity if path.toolchain else None,
        "instruction_set": path.toolchain.instruction_set if path.toolchain else None,
        "cache": str(path.cache.root),
        "cache_unwritable": path.unwritable,
        "kernels": loaded,
        "compiling": _compiles["submitted"] - _compiles["finished"],
        "evaluations": {"compiled": _evaluations["compiled"], "interpreter": interpreted},
        "casadi": versions,
    }


def reset() -> None:
    """Forget this process's kernels, counts and warnings, and look for the toolchain and the cache again
    (after a change of ``PKM_COMPILED``, ``PKM_CACHE_DIR``, ``CC`` or PATH)."""
    _path.cache_clear()
    find.cache_clear()
    _entries.clear()
    _evaluations.clear()
    _warned.clear()
