"""Writing results so that nothing half-written is ever left in an output folder, and so that a result
that cannot be written there once computed is kept elsewhere rather than lost (:func:`keeping`)."""

from __future__ import annotations

import errno
import json
import math
import os
import reprlib
import shutil
import tempfile
import tomllib
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import Any, TypeVar

import numpy as np

from pkm.errors import ComputationError, PkmError, shown_path
from pkm.interrupts import check_interrupted

T = TypeVar("T")


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
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it into place. An OSError on the
    way names ``path`` where the system named the temporary file or no file (a full disk)."""
    path = Path(path)
    try:
        return _write_beside(path, write)
    except OSError as exc:
        named = exc.filename is not None and not Path(exc.filename).name.startswith(f".{path.name}.")
        if exc.errno is not None and not named:  # an OSError of a message alone keeps its message
            exc.filename = str(path)
        raise


def _write_beside(path: Path, write: Callable[[Path], None]) -> Path:
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


def csv_text(columns: list[str], rows: list[list[Any]]) -> str:
    """A CSV table: a header of ``columns`` (names with their units, ``x [m]``) and rows of numbers (repr,
    so that they read back to the same floats), text or booleans (0/1)."""
    def cell(value: Any) -> str:
        if isinstance(value, bool | np.bool_):
            return str(int(value))
        if isinstance(value, float | np.floating | int | np.integer):
            return repr(float(value)) if isinstance(value, float | np.floating) else str(int(value))
        text = str(value)
        return f'"{text}"' if "," in text else text

    return "\n".join([",".join(columns), *(",".join(cell(v) for v in row) for row in rows)]) + "\n"


def read_toml(path: str | os.PathLike, error: type[PkmError] = PkmError, kind: str = "TOML file") -> dict[str, Any]:
    """The table of a TOML file; ``error`` naming the ``kind`` of file, the file and what is wrong where it
    cannot be read, is not UTF-8 text or not TOML (nested deeper than the reader's recursion included)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except (OSError, ValueError) as exc:  # a ValueError: a NUL character in the name
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise error(f"{kind} {shown_path(path)} cannot be read ({reason})") from None
    try:
        return tomllib.loads(data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise error(f"{kind} {shown_path(path)} violates: UTF-8 text; byte {exc.start} is not") from None
    except (tomllib.TOMLDecodeError, RecursionError) as exc:
        reason = str(exc) if isinstance(exc, tomllib.TOMLDecodeError) else "nested too deep"
        raise error(f"{kind} {shown_path(path)} violates: TOML ({reason})") from None


RESULT_BYTES = 1 << 24  # the largest result file a design is read from


def read_design(path: str | os.PathLike, error: type[PkmError] = PkmError) -> dict[str, float]:
    """The design a result file records (a JSON object whose ``design`` is a table of parameter names and
    finite numbers, SI: what ``pkm design``, ``pkm synth`` and ``pkm index`` write), or ``error`` naming the
    file and what is wrong."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            data = handle.read(RESULT_BYTES + 1)
    except (OSError, ValueError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else str(exc)
        raise error(f"result file {shown_path(path)} cannot be read ({reason})") from None
    if len(data) > RESULT_BYTES:
        raise error(f"result file {shown_path(path)} violates: at most {RESULT_BYTES} bytes")
    try:
        record = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise error(f"result file {shown_path(path)} violates: JSON ({exc.__class__.__name__})") from None
    design = record.get("design") if isinstance(record, dict) else None
    if not isinstance(design, dict) or not design or not all(
            isinstance(k, str) and isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for k, v in design.items()):
        raise error(f"result file {shown_path(path)} violates: a JSON object whose design is a table of parameter "
                    "names and finite numbers (what pkm design, synth and index write)")
    return {k: float(v) for k, v in design.items()}


def read_poses(path: str | Path, names: tuple[str, ...]) -> np.ndarray:
    """Poses (N, len(names)) of finite numbers from a .npy array of real numbers (integers or floats: not
    booleans, complex numbers, text, dates or records) or a CSV file (a header of exactly the pose's names,
    optionally with units in brackets, or none); :class:`PkmError` naming the file and the violated
    condition."""
    path = Path(path)
    where = f"poses file {shown_path(path)} violates:"
    try:
        if path.suffix == ".npy":
            data = np.load(path, allow_pickle=False)
        else:
            lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, ValueError, EOFError) as exc:  # a decoding error and a .npy's bad header are ValueErrors
        raise PkmError(f"{where} a readable .npy or CSV file of numbers ({reprlib.repr(str(exc))})") from None
    poses = _npy_poses(data, where) if path.suffix == ".npy" else _csv_poses(lines, names, where)
    poses = np.atleast_2d(poses)
    if poses.ndim != 2 or poses.shape[1] != len(names) or not len(poses):
        raise PkmError(f"{where} rows of {len(names)} values ({', '.join(names)}); got shape {poses.shape}")
    if not np.isfinite(poses).all():
        row = int(np.flatnonzero(~np.isfinite(poses).all(axis=1))[0])
        raise PkmError(f"{where} finite numbers; row {row} is {reprlib.repr(poses[row].tolist())}")
    return poses


def _npy_poses(data: Any, where: str) -> np.ndarray:
    """The array of a .npy file as floats: integers and floats only (a boolean would pass as 0 or 1, a
    complex number lose its imaginary part, text, dates and records have no pose)."""
    if not isinstance(data, np.ndarray):  # a .npz archive under a .npy name
        data.close()
        raise PkmError(f"{where} a .npy array; got an archive of arrays")
    if data.dtype.kind not in "iuf":
        raise PkmError(f"{where} an array of real numbers (integers or floats); got dtype {data.dtype}")
    return data.astype(float)


def _csv_poses(lines: list[str], names: tuple[str, ...], where: str) -> np.ndarray:
    """The rows of a CSV file's lines (blank ones skipped) after its header, if it has one."""
    numbered = [(k, line.split(",")) for k, line in enumerate(lines, start=1) if line.strip()]
    header = [c.strip().split(" [")[0] for c in numbered[0][1]] if numbered else []
    if header and not _numeric(header[0]):
        if header != list(names):
            raise PkmError(f"{where} a header of the pose's coordinates {', '.join(names)}, exactly; got "
                           f"{reprlib.repr(', '.join(header))}")
        numbered = numbered[1:]
    for k, row in numbered:
        if len(row) != len(names):
            raise PkmError(f"{where} rows of {len(names)} values ({', '.join(names)}); line {k} has {len(row)}")
        if not all(_numeric(v) for v in row):
            raise PkmError(f"{where} a readable .npy or CSV file of numbers; line {k} is {reprlib.repr(','.join(row))}")
    return np.array([[float(v) for v in row] for _, row in numbered], dtype=float)


def _numeric(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def copy_file(source: Path, path: Path) -> Path:
    return atomic_write(path, lambda tmp: shutil.copyfile(source, tmp))


class Keeper:
    """The output folder of a command and, once a write into it has failed, the folder that keeps the
    result instead: ``failure`` is that write's OSError and ``kept`` the new folder (both None until then)."""

    def __init__(self, folder: Path | None, prefix: str) -> None:
        self.folder = None if folder is None else Path(folder)
        self.prefix = prefix
        self.failure: OSError | None = None
        self.kept: Path | None = None

    def holds(self, path: Path) -> bool:
        """Whether ``path`` is in the output folder (and not in the kept one, which may lie inside it)."""
        path = Path(path)
        return (self.folder is not None and path.is_relative_to(self.folder)
                and not (self.kept is not None and path.is_relative_to(self.kept)))

    def place(self, path: Path) -> Path:
        """Where a result meant for ``path``, inside the output folder, goes now."""
        return path if self.kept is None else self.kept / Path(path).relative_to(self.folder)

    def write(self, folder: Path, write: Callable[[Path], T]) -> T:
        """``write(folder)``; if it raises OSError, ``write`` again into the counterpart of ``folder`` in a
        new folder of the system's temporary directory, where every later write goes too."""
        if self.kept is None:
            try:
                return write(folder)
            except OSError as exc:
                self.failure = exc
        kept = self.kept
        try:
            kept = kept or Path(tempfile.mkdtemp(prefix=self.prefix))
            result = write(kept / folder.relative_to(self.folder))
        except OSError as exc:
            if self.kept is None and kept is not None:
                shutil.rmtree(kept, ignore_errors=True)
            raise ComputationError(
                f"{_failed(self.failure)}, nor in {self.kept or tempfile.gettempdir()} ({_reason(exc)})"
            ) from None
        self.kept = kept
        return result

    @property
    def message(self) -> str:
        return f"{_failed(self.failure)}; the result is kept in {self.kept}"


def _failed(exc: OSError | None) -> str:
    """``could not write <path> (<reason>)``, the path a rename's destination where ``exc`` names two."""
    path = exc and (exc.filename2 or exc.filename)
    return f"could not write {path or 'the result'} ({_reason(exc)})"


def _reason(exc: OSError | None) -> str:
    return (exc and exc.strerror) or str(exc)


_KEEPER: ContextVar[Keeper | None] = ContextVar("pkm.io keeper", default=None)


@contextmanager
def keeping(folder: Path | str | None, command: str) -> Iterator[Keeper]:
    """Within the block, :func:`write_result` into ``folder`` (a command's --out) keeps a result that cannot
    be written there (the folder removed or made read-only during the run, a full disk) in a new folder
    ``pkm-<command>-*`` of the system's temporary directory, with the same atomic writes. The yielded
    :class:`Keeper` says, after the block, whether that happened and where."""
    keeper = Keeper(None if folder is None else Path(folder), f"pkm-{command}-")
    token = _KEEPER.set(keeper)
    try:
        yield keeper
    finally:
        _KEEPER.reset(token)


def write_result(folder: Path, write: Callable[[Path], T]) -> T:
    """``write(folder)``: the files of a computed result written into ``folder`` (and nothing else, as it
    may be called again with another folder); returns what ``write`` returns. Inside :func:`keeping`, where
    ``folder`` lies in the output folder, an OSError sends the result to the folder that keeps it."""
    keeper = _KEEPER.get()
    if keeper is None or not keeper.holds(folder):
        return write(Path(folder))
    return keeper.write(Path(folder), write)


def kept_path(path: Path) -> Path:
    """Where :func:`write_result` writes a result meant for ``path`` now: ``path``, or its counterpart in the
    folder that keeps the results once the output folder has failed (:func:`keeping`)."""
    keeper = _KEEPER.get()
    return keeper.place(Path(path)) if keeper is not None and keeper.holds(path) else Path(path)


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
    of ``target`` that the block did not write are kept. Moving them is a :func:`write_result`: within
    :func:`keeping`, files that cannot move into ``target`` are kept elsewhere, where the next staged
    folders are made too."""
    target = kept_path(Path(target))
    target.parent.mkdir(parents=True, exist_ok=True)
    _remove_abandoned(target)
    stage = Path(tempfile.mkdtemp(prefix=f".{target.name}.{os.getpid()}.", dir=target.parent))
    try:
        yield stage
        check_interrupted()
        names = sorted(path.relative_to(stage) for path in stage.rglob("*"))
        write_result(target, lambda folder: _publish(stage, names, target, folder))
    finally:
        # beside a folder made read-only the stage stays; the next run removes it (_remove_abandoned)
        shutil.rmtree(stage, ignore_errors=True)


def _publish(stage: Path, names: list[Path], target: Path, folder: Path) -> None:
    """Move the files ``names`` of ``stage`` into ``folder`` (``target``, or the folder keeping the result
    meant for it): by atomic renames, or atomic copies onto another file system. A file that an attempt
    which failed already moved into ``target`` is copied from there."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in names:
        source, destination = stage / name, folder / name
        if source.is_dir():
            destination.mkdir(exist_ok=True)
        elif not source.exists():
            copy_file(target / name, destination)
        else:
            try:
                os.replace(source, destination)
            except OSError as exc:
                if exc.errno != errno.EXDEV:
                    raise
                copy_file(source, destination)
