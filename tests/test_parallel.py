"""The executor seam (pkm.parallel): serial, a local process pool and a Dask cluster give the same
atlases and optima; an interrupted atlas resumes from its stored chunks; a bad scheduler address and a
missing dask extra give pkm's errors."""

from __future__ import annotations

import sys
import time
from concurrent.futures import ProcessPoolExecutor
from multiprocessing import get_context

import numpy as np
import pytest

import pkm
from pkm import parallel, registry
from pkm.atlas import compute_atlas
from pkm.cli import main
from pkm.errors import ComputationError, PkmError

PROBLEM = "five_bar.max_gci_miw"


def _atlas(executor, **options):
    m = pkm.load("five_bar")
    options = {"chunk": 7, **options}
    return compute_atlas(m, registry.global_index("gci"), space=m.design_spaces["gao1998"], region="miw",
                         resolution=9, pose_resolution=3, executor=executor, **options)


def _synthesis(executor):
    return pkm.synthesize(PROBLEM, resolution=3, baseline_resolution=9, starts=2, executor=executor)


@pytest.fixture(scope="module")
def serial():
    return _atlas("serial"), _synthesis("serial")


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                                  processes=True) as local:
        yield local.scheduler_address


def _same(atlas_a, atlas_b) -> None:
    assert atlas_a.modes == atlas_b.modes
    for mode in atlas_a.modes:
        np.testing.assert_array_equal(atlas_a.values[mode], atlas_b.values[mode])
        np.testing.assert_array_equal(atlas_a.points[mode], atlas_b.points[mode])


def test_a_process_pool_gives_the_serial_atlas_and_optimum_bit_for_bit(serial):
    atlas, result = serial
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        _same(atlas, _atlas(pool))
        pooled = _synthesis(pool)
    assert pooled.variables == result.variables
    assert pooled.objective == result.objective
    assert [r.variables for r in pooled.runs] == [r.variables for r in result.runs]


def test_a_dask_cluster_by_address_gives_the_serial_atlas_and_optimum(serial, cluster):
    atlas, result = serial
    pkm.use_scheduler(cluster)
    try:
        _same(atlas, _atlas(None))
        dask = _synthesis(None)
    finally:
        pkm.use_scheduler(None)
    assert dask.variables == result.variables
    assert dask.objective == result.objective
    assert dask.baselines["grid"].best.variables == result.baselines["grid"].best.variables


def test_a_chunking_does_not_change_the_values(serial):
    atlas, _ = serial
    _same(atlas, _atlas("serial", chunk=1000))


def test_an_interrupted_atlas_resumes_from_its_chunks_and_matches(serial, tmp_path):
    atlas, _ = serial
    store = tmp_path / "chunks"
    finished = []

    def interrupt(done: int, total: int) -> None:
        finished.append(done)
        if len(finished) == 3:  # the resumed count (0), then two chunks
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _atlas("serial", store=store, progress=interrupt)
    kept = sorted(store.glob("*.npz"))
    assert len(kept) == 2
    assert not list(store.glob(".*"))  # nothing half-written
    computed = []
    resumed = _atlas("serial", store=store, progress=lambda done, total: computed.append((done, total)))
    _same(atlas, resumed)
    per_mode = int(atlas.inside.sum())
    total = per_mode * len(atlas.modes)
    sizes = [min(7, per_mode - k) for _ in atlas.modes for k in range(0, per_mode, 7)]
    assert computed[0] == (sizes[0] + sizes[1], total)  # the two stored chunks, counted at once
    assert computed[-1] == (total, total)


def test_a_failing_task_is_retried_once_then_reported_with_its_inputs():
    attempts = []

    def flaky(task):
        attempts.append(task)
        if task == "bad" or attempts.count(task) == 1:
            raise RuntimeError(f"boom {task}")
        return task * 2

    with parallel.executor("serial") as pool:
        assert parallel.run_tasks(pool, flaky, ["a", "b"], describe=str) == ["aa", "bb"]
        with pytest.raises(ComputationError, match="task bad failed twice: boom bad"):
            parallel.run_tasks(pool, flaky, ["bad"], describe=str)


def test_a_bad_scheduler_address_is_pkms_error_within_seconds(capfd, monkeypatch):
    monkeypatch.setattr(parallel, "CONNECT_TIMEOUT", "0.5s")
    start = time.perf_counter()
    status = main(["atlas", "five_bar", "gci", "--resolution", "5", "--scheduler", "tcp://127.0.0.1:9"])
    assert time.perf_counter() - start < 10
    assert status == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "cannot reach the Dask scheduler at tcp://127.0.0.1:9" in err[0]
    with pytest.raises(PkmError, match="protocol://host:port"):
        pkm.use_scheduler("  ")


def test_without_the_dask_extra_only_a_scheduler_needs_it(monkeypatch, tmp_path, serial):
    atlas, _ = serial
    monkeypatch.setitem(sys.modules, "distributed", None)
    _same(atlas, _atlas("serial"))
    monkeypatch.setenv(parallel.SCHEDULER_VARIABLE, "tcp://127.0.0.1:8786")
    with pytest.raises(PkmError, match=r"pip install 'pkm\[dask\]'"):
        _atlas(None)
    assert main(["atlas", "five_bar", "gci", "--resolution", "5", "--out", str(tmp_path),
                 "--scheduler", "tcp://127.0.0.1:8786"]) == 2


def _exit(_task):
    import os

    os._exit(1)


def test_a_lost_worker_is_pkms_computation_error_naming_the_task():
    with ProcessPoolExecutor(1, mp_context=get_context("fork")) as pool, pytest.raises(
            ComputationError, match=r"task chunk 7 .*worker"):
        parallel.run_tasks(pool, _exit, [7], describe=lambda t: f"chunk {t}")


def test_bad_input_in_a_task_is_not_retried():
    calls = []

    def bad(task):
        calls.append(task)
        raise PkmError("resolution = 0 violates resolution >= 1")

    with parallel.executor("serial") as pool, pytest.raises(PkmError, match="resolution = 0"):
        parallel.run_tasks(pool, bad, [1], describe=str)
    assert calls == [1]


def test_a_serial_atlas_leaves_the_callers_threads_alone(serial):
    from pkm import batch

    before = batch.THREADS
    _atlas("serial")
    assert before == batch.THREADS


def test_an_address_that_is_not_a_dask_scheduler_is_refused_within_seconds(monkeypatch):
    import socket

    monkeypatch.setattr(parallel, "CONNECT_TIMEOUT", "0.5s")
    with socket.socket() as server:
        server.bind(("127.0.0.1", 0))
        server.listen()
        start = time.perf_counter()
        with pytest.raises(PkmError, match="cannot reach the Dask scheduler"):
            parallel.connect(f"tcp://127.0.0.1:{server.getsockname()[1]}")
        assert time.perf_counter() - start < 5


@pytest.mark.parametrize("address", ["tcp://127.0.0.1", "tcp://127.0.0.1:http", "nonsense", "tcp://127.0.0.1:99999"])
def test_a_scheduler_address_that_cannot_be_one_exits_2_at_once(address, capsys):
    import time

    from pkm.cli import main

    start = time.perf_counter()
    assert main(["sweep", "five_bar", "--indices", "gci", "--scheduler", address]) == 2
    assert time.perf_counter() - start < 2.0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "protocol://host:port" in err[0]
    with pytest.raises(PkmError, match="protocol://host:port"):
        parallel.use_scheduler(address)


def _command(psutil, process) -> list[str]:
    try:
        return process.cmdline()
    except psutil.Error:  # gone, or a zombie
        return []


def test_sigterm_to_a_parallel_atlas_ends_its_worker_processes(tmp_path):
    import os
    import signal
    import subprocess

    psutil = pytest.importorskip("psutil")
    command = [sys.executable, "-m", "pkm.cli", "atlas", "five_bar", "gci", "--resolution", "101",
               "--executor", "processes", "--out", str(tmp_path)]
    parent = subprocess.Popen(command, env={**os.environ, "MPLBACKEND": "Agg"}, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    workers = []
    while time.monotonic() < deadline and len(workers) < 2 and parent.poll() is None:
        # the pool's forked workers carry the parent's command line (multiprocessing's resource tracker, which
        # ends on its own, and a finished compiler, a zombie until it is reaped, do not)
        workers = [p for p in psutil.Process(parent.pid).children(recursive=True) if _command(psutil, p) == command]
        time.sleep(0.1)
    assert len(workers) >= 2, "the atlas ended before its workers could be seen"
    parent.send_signal(signal.SIGTERM)
    assert parent.wait(timeout=60) == 130
    assert "interrupted" in parent.stderr.read()
    _, alive = psutil.wait_procs(workers, timeout=30)
    assert alive == []


def test_a_process_pool_carries_a_machine_described_by_the_user_and_gives_the_serial_atlas():
    """A described machine outside the registry goes to the workers as its description (registry.reference),
    and each worker derives it into the shared cache."""
    import tomllib

    from pkm.design_space import parameter_plane
    from pkm.models.described import DESCRIPTIONS

    mech = pkm.load(tomllib.loads(DESCRIPTIONS["delta"].read_text()))
    assert mech is not registry.mechanism("delta")
    assert registry.reference(mech).startswith(registry.DESCRIBED)
    space = parameter_plane(mech.parameters, [("L_a", 0.2, 0.3), ("L_b", 0.5, 0.7)])

    def atlas(executor):
        return compute_atlas(mech, registry.global_index("gci"), space=space, region="task", resolution=4,
                             pose_resolution=3, executor=executor, chunk=5)

    from pkm.catalogue import warm

    warm([mech])  # compiled before either run: a first evaluation would run on the interpreter while it compiles
    serial = atlas("serial")
    with ProcessPoolExecutor(2, mp_context=get_context("spawn")) as pool:
        _same(serial, atlas(pool))
