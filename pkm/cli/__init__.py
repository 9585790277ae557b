"""The ``pkm`` command line (DESIGN.md section 7): one module per command in :mod:`pkm.cli.commands`, which
lists them; what they share in :mod:`pkm.cli.arguments` (options), :mod:`pkm.cli.common` (what a user gives,
the output) and :mod:`pkm.cli.grid` (the design grid of atlas and sweep); here the parser and :func:`main`.

Exit status 0 on success, 2 on bad input (one line on standard error, no traceback), 1 when a valid
computation fails (for instance IPOPT does not converge) or when --out cannot take a computed result,
which is then kept in a new folder of the system's temporary directory that the line names
(:func:`pkm.io.keeping`), 3 when a synthesis finds no design that meets its constraints (the line names
the constraints and their best attainable values).
"""

from __future__ import annotations

import argparse
import functools
import os
import re
import signal
import sys
import threading
import warnings
from importlib.metadata import version
from typing import Any

from pkm import interrupts, io, parallel
from pkm.cli.arguments import HelpParser
from pkm.cli.commands import COMMANDS
from pkm.cli.common import check_out
from pkm.compiled import CompiledPathWarning
from pkm.errors import ComputationError, PkmError
from pkm.interrupts import interruptible
from pkm.synthesis import InfeasibleError

__all__ = ["build_parser", "main"]

INFEASIBLE = 3  # the exit status of a synthesis without a design that meets its constraints
PARALLEL_COMMANDS = tuple(command.run for command in COMMANDS if command.PARALLEL)
NEGATIVE = re.compile(r"^-[0-9.]")


@functools.cache
def build_parser() -> argparse.ArgumentParser:
    """The command line's parser, built once per process (its commands take milliseconds to build; a parse
    leaves it as it was): each command's parser holds ``--json``, its own options and its function."""
    parser = HelpParser(prog="pkm", description="Design of parallel kinematic machines.")
    parser.add_argument("--version", action="version", version=version("pkm"))
    sub = parser.add_subparsers(dest="command", required=True, parser_class=HelpParser)
    for command in COMMANDS:
        name = command.__name__.rpartition(".")[2]
        p = sub.add_parser(name, help=command.HELP, description=command.HELP)
        p.add_argument("--json", action="store_true", help="machine-readable output on standard output (default: text)")
        p.set_defaults(func=command.run)
        command.options(p)
    return parser


def _negative_values(argv: list[str]) -> list[str]:
    """``--pose -0.3,1.9`` as ``--pose=-0.3,1.9``: argparse reads a value that starts with a minus sign
    and is not a lone number as an option, and half of every workspace has negative coordinates."""
    out: list[str] = []
    for token in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and NEGATIVE.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def _terminated(signum: int, _frame: Any) -> None:
    interrupts.remember(signum)
    raise KeyboardInterrupt


def _line(message: object) -> str:
    """A message as one line: its line breaks and other unprintable characters escaped (a file's key may hold
    them)."""
    return "".join(c if c.isprintable() else c.encode("unicode_escape").decode() for c in str(message))


def _one_line_warning(message: Warning | str, *_args: Any, **_kwargs: Any) -> None:
    print(f"pkm: warning: {_line(message)}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """The command line. Warnings are one line each on standard error (the interpreter answering where a
    kernel did not compile, for instance), but none where ``PKM_COMPILED=0`` asks for the interpreter."""
    main_thread = threading.current_thread() is threading.main_thread()
    # SIGTERM ends the command as Ctrl-C does: its worker processes end with it, nothing half-written stays
    previous = signal.signal(signal.SIGTERM, _terminated) if main_thread else None
    try:
        return _main(argv)
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    if os.environ.get("PKM_COMPILED") == "0":
        warnings.filterwarnings("ignore", category=CompiledPathWarning)
    else:
        warnings.showwarning = _one_line_warning
    keeper = None
    try:
        args = build_parser().parse_args(_negative_values(sys.argv[1:] if argv is None else list(argv)))
        out = getattr(args, "out", None)
        check_out(out)
        address = getattr(args, "scheduler", None) or parallel.scheduler()
        if address and args.func in PARALLEL_COMMANDS:
            parallel.connect(address).close()
        with parallel.scheduled(address), interruptible(), io.keeping(out, args.command) as keeper:
            args.func(args)
    except PkmError as exc:
        print(f"pkm: error: {_line(exc)}", file=sys.stderr)
        return 2
    except InfeasibleError as exc:
        print(f"pkm: infeasible: {_line(exc)}", file=sys.stderr)
        return INFEASIBLE
    except ComputationError as exc:
        print(f"pkm: computation failed: {_line(exc)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("pkm: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader of stdout has gone (e.g. `pkm list | head -1`): nothing more can be written there
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1
    finally:
        # a result that --out failed to take after the computation is kept, and said so, whatever came after
        if keeper is not None and keeper.kept is not None:
            print(f"pkm: {_line(keeper.message)}", file=sys.stderr)
    return 0 if keeper is None or keeper.kept is None else 1
