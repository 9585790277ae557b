"""Writing results so that nothing half-written is ever left in an output folder."""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from pkm.interrupts import check_interrupted


def _default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    raise TypeError(f"{type(obj).__name__} is not JSON serialisable")


def to_json(data: Any) -> str:
    """JSON text (NaN and inf as null) with numpy scalars and arrays converted."""
    return json.dumps(_finite(data), indent=2, default=_default) + "\n"


def _finite(data: Any) -> Any:
    if isinstance(data, np.ndarray):
        return _finite(data.tolist())
    if isinstance(data, float | np.floating):
        return float(data) if np.isfinite(data) else None
    if isinstance(data, dict):
        return {k: _finite(v) for k, v in data.items()}
    if isinstance(data, list | tuple):
        return [_finite(v) for v in data]
    return data


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write(path: Path, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it into place."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    try:
        write(Path(tmp))
        os.chmod(tmp, 0o666 & ~_umask())  # as an ordinary new file: mkstemp makes it private
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def write_text(path: Path, text: str) -> Path:
    return atomic_write(path, lambda tmp: tmp.write_text(text))


def _remove_abandoned(target: Path) -> None:
    """Remove the staging folders of ``target`` whose process is gone (a run that was killed)."""
    for stage in target.parent.glob(f".{target.name}.*.*"):
        pid = stage.name[len(target.name) + 2 :].split(".")[0]
        if stage.is_dir() and pid.isdigit() and not _alive(int(pid)):
            shutil.rmtree(stage, ignore_errors=True)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


@contextmanager
def staged_folder(target: Path) -> Iterator[Path]:
    """Yield a temporary folder beside ``target`` whose files move into ``target`` only if the block
    succeeds (and no Ctrl-C was caught below it, :mod:`pkm.interrupts`), each by an atomic rename; files
    of ``target`` that the block did not write are kept."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(target)
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.{os.getpid()}.", dir=target.parent))
    try:
        yield stage
        check_interrupted()
        target.mkdir(exist_ok=True)
        for path in sorted(stage.rglob("*")):
            destination = target / path.relative_to(stage)
            if path.is_dir():
                destination.mkdir(exist_ok=True)
            else:
                os.replace(path, destination)
    finally:
        if stage.exists():
            shutil.rmtree(stage)
