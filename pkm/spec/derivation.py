"""Derivations of descriptions in a process of their own (pkm never imports sympy): ``python -m symbolic.described
--serve``, started at this process's first derivation and kept, takes one derivation at a time (the description's
JSON file and the module to write, a line on its standard input) and answers with its exit status and its last
words (a line on its standard output), so that the second and later derivations do not pay for an interpreter and
sympy's import again. A derivation that takes longer than its limit, or is interrupted, stops the server (the next
derivation starts another); a process forked from this one starts its own."""

from __future__ import annotations

import atexit
import json
import os
import selectors
import subprocess
import sys
import threading
import time
from pathlib import Path

from pkm.spec.schema import ROOT


class _Server:
    """This process's derivation server and the lock that gives it one derivation at a time."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.process: subprocess.Popen | None = None

    def _started(self) -> subprocess.Popen:
        if self.process is None or self.process.poll() is not None:
            self.process = subprocess.Popen([sys.executable, "-m", "symbolic.described", "--serve"], cwd=ROOT,
                                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                            text=True, bufsize=1)
        return self.process

    def stop(self) -> None:
        if self.process is not None and self.process.poll() is None:
            self.process.kill()
            self.process.wait()
        self.process = None

    def derive(self, source: Path, out: Path, seconds: float) -> tuple[int, str] | None:
        with self.lock:
            process = self._started()
            try:
                process.stdin.write(f"{json.dumps([str(source), str(out)])}\n")
                process.stdin.flush()
                line = _line_within(process, seconds)
            except BaseException:
                self.stop()
                raise
            if line is None:
                self.stop()
                return None
            if not line:  # the server ended (it could not start, or the derivation crashed it): its last words
                process.wait()
                words = (process.stderr.read().strip().splitlines() or ["no output"])[-1]
                self.stop()
                return 1, f"the derivation's process ended without an answer: {words}"
            code, last = json.loads(line)
            return int(code), str(last)


def _line_within(process: subprocess.Popen, seconds: float) -> str | None:
    """The server's next line of output, "" where it ended, None where none came within ``seconds``."""
    with selectors.DefaultSelector() as selector:
        selector.register(process.stdout, selectors.EVENT_READ)
        deadline = time.monotonic() + seconds
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return None
            if selector.select(timeout=min(left, 1.0)):
                return process.stdout.readline()


_SERVERS: dict[int, _Server] = {}
_LOCK = threading.Lock()


def derive(source: Path, out: Path, seconds: float) -> tuple[int, str] | None:
    """The exit status and last words of the derivation of ``source`` (a description's JSON) into ``out`` (its
    module), None where it took longer than ``seconds``."""
    with _LOCK:
        server = _SERVERS.setdefault(os.getpid(), _Server())
    return server.derive(source, out, seconds)


@atexit.register
def _stop_servers() -> None:
    server = _SERVERS.get(os.getpid())
    if server is not None:
        server.stop()
