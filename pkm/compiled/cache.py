"""The kernel cache: compiled libraries by content, per user, shared by every process of that user.

The cache is a folder, ``$PKM_CACHE_DIR`` or else ``$XDG_CACHE_HOME/pkm/kernels`` (``~/.cache/pkm/kernels``).
An entry is a folder named by its key (the sha256 of everything its binary depends on: the graph, the emitter,
the compiler and its flags, the instruction set, CasADi's version) holding the translation unit, the library
and ``entry.json`` with the library's sha256, and ``checked`` once a process has found the library to give the
interpreter's values (that sha256 again: a later process loads it without checking). An entry is built in a
folder of its own under ``tmp/`` and renamed into place, which is atomic: a reader sees a whole entry or none.
Builders of one key take its lock (``locks/<key>``) in turn, so that processes or Dask workers that meet the
same kernel at once compile it once and all get it. An entry whose library does not match its sha256 (truncated,
corrupted) is removed and built again. The cache holds at most ``$PKM_CACHE_MB`` MiB (default
:data:`LIMIT_MB`): after each build the entries used longest ago are removed until it fits.

Beside the entries, ``rent/<key>`` holds the interpreter's work that processes have done for a kernel not
yet built (:meth:`Cache.rent`, :meth:`Cache.pay_rent`), so that a graph a little of which each run evaluates
is compiled once the runs together have paid for it; at most :data:`RENTS` are kept, the oldest removed.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: builders of one key may compile it twice
    fcntl = None

LIMIT_MB = 1024
RENTS = 10_000  # rent records kept at most
LIBRARY = "kernel.so"
META = "entry.json"
CHECKED = "checked"


def location() -> Path:
    """The cache folder (module docstring)."""
    named = os.environ.get("PKM_CACHE_DIR")
    if named:
        return Path(named).expanduser()
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base).expanduser() / "pkm" / "kernels"


def limit_bytes() -> int:
    try:
        return max(1, int(float(os.environ.get("PKM_CACHE_MB", LIMIT_MB)) * 2**20))
    except ValueError:
        return LIMIT_MB * 2**20


def _modified(path: Path) -> float:
    try:
        return path.stat().st_mtime
    except OSError:
        return 0.0


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


class Cache:
    """The cache at ``root`` (module docstring)."""

    def __init__(self, root: Path):
        self.root = root

    def writable(self) -> str:
        """Empty where entries can be added, else why not."""
        try:
            self._folders()
            with tempfile.NamedTemporaryFile(dir=self.root / "tmp"):
                pass
        except OSError as exc:
            return f"the kernel cache {self.root} cannot be written ({exc.strerror or exc})"
        return ""

    def entry(self, key: str) -> Path:
        return self.root / key[:2] / key

    def find(self, key: str) -> Path | None:
        """The library of ``key`` if its entry is whole (its sha256 matches), marked as just used; an entry
        that is not whole is removed."""
        entry = self.entry(key)
        try:
            meta = json.loads((entry / META).read_text())
            whole = meta.get("sha256") == _digest(entry / LIBRARY)
        except (OSError, ValueError):
            whole = False
        if whole:
            with contextlib.suppress(OSError):
                os.utime(entry)
            return entry / LIBRARY
        if entry.exists():
            self._remove(entry)
        return None

    def checked(self, key: str) -> bool:
        """Whether the library of ``key`` as it is now has passed the check against the interpreter."""
        entry = self.entry(key)
        try:
            meta = json.loads((entry / META).read_text())
            return (entry / CHECKED).read_text() == meta.get("sha256")
        except (OSError, ValueError):
            return False

    def mark_checked(self, key: str) -> None:
        """Record that the library of ``key`` passed the check (atomically; nothing where it cannot be
        written)."""
        entry = self.entry(key)
        try:
            digest = json.loads((entry / META).read_text())["sha256"]
            staging = entry / f".{CHECKED}.{os.getpid()}.{threading.get_ident()}"
            staging.write_text(digest)
            os.replace(staging, entry / CHECKED)
        except (OSError, ValueError, KeyError):
            return

    def add(self, key: str, build: Callable[[Path], dict]) -> Path:
        """The library of ``key``, built by ``build(folder)`` unless another process has built it meanwhile.
        ``build`` writes :data:`LIBRARY` (and whatever else) into the folder and returns what ``entry.json``
        records besides the library's sha256. Raises OSError where the cache cannot be written."""
        self._folders()
        with self._locked(key):
            found = self.find(key)
            if found is not None:
                return found
            staging = Path(tempfile.mkdtemp(prefix=f"{key[:16]}.", dir=self.root / "tmp"))
            try:
                meta = build(staging)
                meta = {**meta, "key": key, "sha256": _digest(staging / LIBRARY), "created": time.time()}
                (staging / META).write_text(json.dumps(meta, indent=1, sort_keys=True) + "\n")
                self.entry(key).parent.mkdir(exist_ok=True)
                try:
                    os.rename(staging, self.entry(key))
                except OSError:
                    if self.find(key) is None:
                        raise
                (self.root / "rent" / key).unlink(missing_ok=True)
            finally:
                shutil.rmtree(staging, ignore_errors=True)
        self.evict()
        return self.entry(key) / LIBRARY

    def rent(self, key: str) -> int:
        """The interpreter's work for ``key`` that processes have recorded (0 where none)."""
        try:
            return max(0, int((self.root / "rent" / key).read_text()))
        except (OSError, ValueError):
            return 0

    def pay_rent(self, paid: dict[str, int]) -> None:
        """Add each key's work to its record, under the key's lock (no addition is lost), and keep at most
        :data:`RENTS` records. Raises OSError where the cache cannot be written."""
        folder = self.root / "rent"
        self._folders()
        folder.mkdir(exist_ok=True)
        for key, work in paid.items():
            with self._locked(key):
                staging = folder / f".{key}.{os.getpid()}"
                staging.write_text(str(self.rent(key) + work))
                os.replace(staging, folder / key)
        records = sorted(folder.iterdir(), key=_modified)
        for record in records[: max(0, len(records) - RENTS)]:
            record.unlink(missing_ok=True)

    def _folders(self) -> None:
        for sub in ("tmp", "locks"):
            (self.root / sub).mkdir(parents=True, exist_ok=True)

    @contextlib.contextmanager
    def _locked(self, key: str) -> Iterator[None]:
        if fcntl is None:
            yield
            return
        with open(self.root / "locks" / key, "a") as handle:
            fcntl.flock(handle, fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)

    def entries(self) -> list[tuple[float, int, Path]]:
        """(last use, bytes, folder) of every entry."""
        out = []
        for entry in self.root.glob("??/*"):
            try:
                size = sum(f.stat().st_size for f in entry.iterdir())
                out.append((entry.stat().st_mtime, size, entry))
            except OSError:
                continue
        return out

    def evict(self) -> None:
        """Remove the entries used longest ago until the cache holds at most its limit."""
        entries = sorted(self.entries())
        excess = sum(size for _, size, _ in entries) - limit_bytes()
        for _, size, entry in entries:
            if excess <= 0:
                break
            self._remove(entry)
            excess -= size

    def _remove(self, entry: Path) -> None:
        """Remove an entry by renaming it away first, so that no reader sees it half removed."""
        doomed = self.root / "tmp" / f"removed.{entry.name[:16]}.{os.getpid()}.{time.monotonic_ns()}"
        try:
            os.rename(entry, doomed)
        except OSError:
            return
        shutil.rmtree(doomed, ignore_errors=True)
