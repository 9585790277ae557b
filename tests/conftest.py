"""Shared fixtures of the test suite, in one block per concern."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# --- Cores: each of the suite's workers is one ----------------------------------------------------------


def pytest_configure(config: pytest.Config) -> None:
    """A worker of ``pytest -n N`` evaluates on one thread, as a Dask worker does (pkm.parallel.as_worker): the
    workers are the parallelism, and pkm's kept threads in each would contend for the same cores. The tests of
    the threads themselves set pkm.batch.THREADS where they run."""
    if os.environ.get("PYTEST_XDIST_WORKER"):
        from pkm import parallel

        parallel.as_worker()


# --- Generated code: one fresh derivation of generated/ per test session --------------------------------


@pytest.fixture(scope="session")
def fresh_generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """generated/ derived afresh from symbolic/ into a folder, once per state of the derivation.

    The derivation takes seconds; the byte comparison and the numeric comparison of
    tests/test_generated_is_current.py share it. It is kept in the user's cache under the sha256 of every
    Python file of symbolic/ and the versions of Python, sympy and CasADi: the same sources give the same bytes
    (``make check-generated`` derives twice, under two hash seeds, and compares), so a session whose
    derivation did not change compares with the derivation of an earlier one, and any edit of symbolic/
    derives again. sympy is imported here, not at the top of this module, so that tests that never ask
    for the fixture do not pay for it.
    """
    import hashlib
    import platform
    import shutil

    import casadi
    import sympy

    from symbolic import generate

    digest = hashlib.sha256(f"{platform.python_version()} {sympy.__version__} {casadi.__version__}".encode())
    for path in sorted((generate.ROOT / "symbolic").rglob("*.py")):
        digest.update(path.relative_to(generate.ROOT).as_posix().encode())
        digest.update(path.read_bytes())
    cache = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "pkm" / "fresh-generated"
    out = cache / digest.hexdigest()[:24] / "generated"
    if not out.is_dir():
        staging = tmp_path_factory.mktemp("fresh") / "generated"
        generate.write(staging)
        out.parent.mkdir(parents=True, exist_ok=True)
        held = out.parent / f".{os.getpid()}"
        shutil.move(staging, held)
        try:
            os.replace(held, out)
        except OSError:  # another session stored the same derivation first
            shutil.rmtree(held)
    return out
