"""``python -m symbolic.described DESCRIPTION.json MODULE.py``: derive a description into a module; with
``--serve``, derive one description per line of standard input (a JSON list of the two paths) and answer each with a
line of standard output (a JSON list of the exit status and the derivation's last line on standard error), until
standard input ends (:mod:`pkm.spec.derivation`)."""

import contextlib
import io
import json
import sys

from symbolic.described.module import main


def serve() -> int:
    for line in sys.stdin:
        source, target = json.loads(line)
        errors = io.StringIO()
        with contextlib.redirect_stderr(errors):
            try:
                code = main([source, target])
            except Exception as exc:  # the derivation failed: its last words answer, the server goes on
                print(f"{type(exc).__name__}: {exc}", file=errors)
                code = 1
        last = (errors.getvalue().strip().splitlines() or ["no output"])[-1]
        sys.stdout.write(json.dumps([code, last]) + "\n")
        sys.stdout.flush()
    return 0


sys.exit(serve() if sys.argv[1:] == ["--serve"] else main())
