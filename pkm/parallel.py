"""The executor seam: embarrassingly parallel work as tasks of names and numbers (DESIGN.md section 6a).

Atlas chunks, synthesis starts and baseline chunks are submitted to a ``concurrent.futures.Executor``:
in this process (small jobs), a local process pool (large ones), or a Dask cluster when a scheduler
address is set (:func:`use_scheduler`, the ``PKM_SCHEDULER`` environment variable or the CLI's
``--scheduler``). A task carries a mechanism's or problem's name, arrays and options, never a CasADi
object; each worker loads a mechanism once (the registry caches it), and the results are those of a
serial run, bit for bit, whatever the chunking: every design is evaluated on its own.

A task that fails is submitted once more; a second failure raises :class:`ComputationError` naming the
task's inputs.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, BrokenExecutor, Executor, Future, wait
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from pkm import batch, io
from pkm.errors import ComputationError, PkmError
from pkm.interrupts import check_interrupted, interruptible

SCHEDULER_VARIABLE = "PKM_SCHEDULER"
CONNECT_TIMEOUT = "3s"
LOCAL_POOL_WORK = 20_000_000  # design-pose evaluations from which a local process pool pays for its start
RETRIES = 1
EXECUTORS = ("auto", "serial", "processes")

_SETTINGS: dict[str, str | None] = {"scheduler": None}


ADDRESS = re.compile(r"(tcp|tls|ws|wss|ucx)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):([0-9]{1,5})")


def check_address(address: Any) -> str:
    """``address`` where it is a scheduler address ``protocol://host:port`` with a port in 1-65535, else
    PkmError naming what it violates (before any connection is tried)."""
    match = ADDRESS.fullmatch(address.strip()) if isinstance(address, str) else None
    if match is None or not 0 < int(match[3]) < 65536:
        raise PkmError(f"scheduler address {address!r} violates: protocol://host:port with a port number in "
                       "1-65535, like tcp://127.0.0.1:8786")
    return address.strip()


def use_scheduler(address: str | None) -> None:
    """Send parallel work to the Dask scheduler at ``address`` (``tcp://host:port``); None restores the
    local default (serial for small jobs, a process pool for large ones, unless ``PKM_SCHEDULER`` is set)."""
    _SETTINGS["scheduler"] = None if address is None else check_address(address)


@contextmanager
def scheduled(address: str | None) -> Iterator[None]:
    """:func:`use_scheduler` for the duration of a block, the previous setting restored after it."""
    previous = _SETTINGS["scheduler"]
    use_scheduler(address)
    try:
        yield
    finally:
        _SETTINGS["scheduler"] = previous


def scheduler() -> str | None:
    """The scheduler address in force: :func:`use_scheduler`'s, else ``PKM_SCHEDULER``, else None."""
    return _SETTINGS["scheduler"] or os.environ.get(SCHEDULER_VARIABLE) or None


class SerialExecutor(Executor):
    """Runs each task when it is submitted, in this process."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except Exception as error:
            future.set_exception(error)
        return future


def connect(address: str) -> Any:
    """A Dask client of the scheduler at ``address``: PkmError where dask is missing, or where the
    scheduler does not answer as one within CONNECT_TIMEOUT (whatever listens there)."""
    address = check_address(address)
    try:
        from distributed import Client
    except ImportError:
        raise PkmError(
            f"a Dask scheduler ({address}) needs the dask extra: pip install 'pkm[dask]' (dask and distributed)"
        ) from None
    seconds = float(CONNECT_TIMEOUT.rstrip("s"))
    outcome: dict[str, Any] = {}

    def start() -> None:
        try:
            outcome["client"] = Client(address, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except BaseException as error:
            outcome["error"] = error

    thread = threading.Thread(target=start, daemon=True)
    thread.start()
    thread.join(2 * seconds)
    if "client" in outcome:
        return outcome["client"]
    reason = outcome.get("error", f"no answer as a Dask scheduler within {2 * seconds:g} s")
    raise PkmError(f"cannot reach the Dask scheduler at {address}: {reason}")


@contextmanager
def executor(kind: str | Executor | None = None, *, work: int = 0, tasks: int = 1) -> Iterator[Executor]:
    """The executor for a job: ``kind`` an Executor (used as it is), ``"serial"``, ``"processes"``, or
    ``"auto"``/None: the Dask cluster of :func:`scheduler` if one is set, else serial below
    LOCAL_POOL_WORK evaluations (``work``) and a local process pool above (forked on Linux, so that a
    script without a ``__main__`` guard is not run again in the workers; spawned elsewhere)."""
    if isinstance(kind, Executor):
        yield kind
        return
    kind = "auto" if kind is None else kind
    if kind not in EXECUTORS:
        raise PkmError(f"executor {kind!r} violates: one of {', '.join(EXECUTORS)} or a concurrent.futures.Executor")
    address = scheduler() if kind == "auto" else None
    if address:
        client = connect(address)
        try:
            yield client.get_executor()
        finally:
            client.close()
        return
    workers = min(os.cpu_count() or 1, max(tasks, 1))
    if kind == "serial" or (kind == "auto" and (work < LOCAL_POOL_WORK or workers < 2)):
        yield SerialExecutor()
        return
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    method = "fork" if sys.platform == "linux" else "spawn"
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context(method))
    try:
        yield pool
    except BaseException:
        # an interrupt or a termination of this process ends its workers too, not only their queued tasks, and
        # the tasks still buffered for them are dropped, not flushed into the pipe of workers that are gone (the
        # pool's manager thread, which exit joins, would wait on that flush forever); concurrent.futures has no
        # public call for either before Python 3.14
        queue = getattr(pool, "_call_queue", None)
        if queue is not None:
            queue.cancel_join_thread()
        for process in list((getattr(pool, "_processes", None) or {}).values()):
            process.terminate()
        pool.shutdown(wait=False, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def run_tasks(
    pool: Executor,
    fn: Callable[..., Any],
    tasks: Sequence[Any],
    *,
    describe: Callable[[Any], str],
    done: Callable[[int, Any], None] | None = None,
) -> list[Any]:
    """``fn(task)`` for every task on the executor, results in the tasks' order; ``done(k, result)`` as
    each finishes (in order on the serial executor, which runs one task at a time). A task that fails
    is submitted once more; a second failure, or a lost worker, raises ComputationError naming the
    task; pkm's own errors (bad input) pass at once. On any error the tasks still queued are cancelled."""
    with interruptible():
        return _run_tasks(pool, fn, tasks, describe=describe, done=done)


def _run_tasks(
    pool: Executor,
    fn: Callable[..., Any],
    tasks: Sequence[Any],
    *,
    describe: Callable[[Any], str],
    done: Callable[[int, Any], None] | None,
) -> list[Any]:
    results: list[Any] = [None] * len(tasks)
    if isinstance(pool, SerialExecutor):
        for k, task in enumerate(tasks):
            results[k] = _twice(fn, task, describe)
            if done is not None:
                done(k, results[k])
        return results
    pending: dict[Future, tuple[int, int]] = {}
    try:
        for k, task in enumerate(tasks):
            pending[_submit(pool, fn, task, describe)] = (k, 0)
        while pending:
            finished, _ = wait(list(pending), return_when=FIRST_COMPLETED)
            check_interrupted()
            for future in finished:
                k, attempt = pending.pop(future)
                try:
                    results[k] = future.result()
                except PkmError:
                    raise
                except BrokenExecutor as error:
                    raise ComputationError(f"task {describe(tasks[k])} lost its worker: {error}") from error
                except Exception as error:
                    if attempt >= RETRIES:
                        raise ComputationError(f"task {describe(tasks[k])} failed twice: {error}") from error
                    pending[_submit(pool, fn, tasks[k], describe)] = (k, attempt + 1)
                    continue
                if done is not None:
                    done(k, results[k])
    except BaseException:
        for future in pending:
            future.cancel()
        raise
    return results


def _submit(pool: Executor, fn: Callable[[Any], Any], task: Any, describe: Callable[[Any], str]) -> Future:
    try:
        return pool.submit(fn, task)
    except BrokenExecutor as error:
        raise ComputationError(f"task {describe(task)} could not start: a worker was lost ({error})") from error


def _twice(fn: Callable[[Any], Any], task: Any, describe: Callable[[Any], str]) -> Any:
    """``fn(task)`` in this process, tried once more if it fails (pkm's own errors pass at once)."""
    failure: Exception | None = None
    for _ in range(RETRIES + 1):
        try:
            result = fn(task)
        except PkmError:
            raise
        except Exception as error:
            failure = error
        else:
            check_interrupted()
            return result
        check_interrupted()
    raise ComputationError(f"task {describe(task)} failed twice: {failure}") from failure


def as_worker() -> None:
    """Evaluate on one thread in this process: a worker is one core of its executor, whose number of
    workers is the parallelism (CasADi's thread maps in every worker would oversubscribe the cores)."""
    batch.THREADS = 1


def task_key(*parts: Any) -> str:
    """A key for a task's inputs (names, numbers, arrays): the first 20 hex digits of their SHA-256."""
    digest = hashlib.sha256()
    for part in parts:
        if isinstance(part, np.ndarray):
            digest.update(str(part.shape).encode())
            digest.update(np.ascontiguousarray(part, dtype=float).tobytes())
        else:
            digest.update(repr(part).encode())
        digest.update(b"\0")
    return digest.hexdigest()[:20]


class ChunkStore:
    """Results of finished tasks as ``<folder>/<key>.npz``, each written atomically, so that an
    interrupted job run again with the same folder computes only what is missing."""

    def __init__(self, folder: Path) -> None:
        self.folder = Path(folder)

    def load(self, key: str) -> dict[str, np.ndarray] | None:
        path = self.folder / f"{key}.npz"
        if not path.exists():
            return None
        with np.load(path) as data:
            return {name: data[name] for name in data.files}

    def save(self, key: str, arrays: dict[str, np.ndarray]) -> None:
        io.atomic_write(self.folder / f"{key}.npz", lambda tmp: _savez(tmp, arrays))


def _savez(path: Path, arrays: dict[str, np.ndarray]) -> None:
    with open(path, "wb") as handle:
        np.savez(handle, **arrays)
