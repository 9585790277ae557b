"""Ctrl-C that CasADi catches: it stops an IPOPT solve or a graph operation, reports
KeyboardInterruptException (or loses the interrupt in a callback) and carries on. Inside
:func:`interruptible` the interrupt is remembered; :func:`check_interrupted` raises it at the next safe
point (between tasks, before a staged output is committed), and the block's end at the latest, also where
the block ends in an error the interrupt caused (a solve that failed because it was stopped).
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

_INTERRUPTS: list[int] = []


@contextmanager
def interruptible() -> Iterator[None]:
    """Ctrl-C in the block ends it with KeyboardInterrupt even where CasADi catches the interrupt. Only the
    main thread with Python's own handler in place installs it; a nested block uses the outer one."""
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous is not signal.default_int_handler:
        yield
        return

    def handler(signum: int, frame: Any) -> None:
        _INTERRUPTS.append(signum)
        signal.default_int_handler(signum, frame)

    signal.signal(signal.SIGINT, handler)
    try:
        yield
    except Exception:
        # an error after a caught interrupt is the interrupt's (IPOPT stopped by it, a graph operation that
        # reported it as its own error): the block ends as interrupted
        if not _INTERRUPTS:
            raise
    finally:
        signal.signal(signal.SIGINT, previous)
        interrupted = bool(_INTERRUPTS)
        _INTERRUPTS.clear()
    if interrupted:
        raise KeyboardInterrupt


def remember(signum: int) -> None:
    """Note an interrupt raised by another handler (SIGTERM on the command line), so that it is raised again
    at the next safe point where CasADi caught it."""
    _INTERRUPTS.append(signum)


def check_interrupted() -> None:
    """KeyboardInterrupt where Ctrl-C came during an :func:`interruptible` block and was caught below."""
    if _INTERRUPTS:
        raise KeyboardInterrupt
