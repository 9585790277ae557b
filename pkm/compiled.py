"""The compiled path: the kernels ``make generate`` emits as C (generated/*_kernels.c) and ``pip install``
builds into ``pkm._kernels``, found by the function they were emitted from.

:func:`kernel` returns a batch evaluator for a CasADi function whose key (its name and the sha256 of its
serialised graph, :func:`key`) is in the library, else None, and :func:`pkm.batch.evaluate`
uses it in place of CasADi's interpreter: same inputs, same (N, k) buffers, values equal to round-off.
Where the library was not built (no C compiler at install) or ``PKM_COMPILED=0``, every function runs on
the interpreter and a :class:`CompiledPathWarning` says so once; :func:`status` tells which path is active.
"""

from __future__ import annotations

import hashlib
import importlib
import os
import warnings
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import casadi as ca
import numpy as np


class CompiledPathWarning(UserWarning):
    """pkm evaluates with CasADi's interpreter because its compiled kernels are off or not built."""


@lru_cache(maxsize=1)
def _library() -> tuple[Any, dict[str, int], str]:
    """The kernels' extension module, its kernels by key, and why it is not used (empty when it is)."""
    if os.environ.get("PKM_COMPILED", "1") == "0":
        return None, {}, "PKM_COMPILED=0"
    try:
        lib = importlib.import_module("pkm._kernels")
    except ImportError:
        return None, {}, "pkm._kernels was not built at install (no C compiler?)"
    return lib, {key: i for i, key in enumerate(lib.keys())}, ""


def status() -> dict[str, Any]:
    """Which path evaluates pkm's functions: ``{"path": "compiled" | "interpreter", "kernels": count,
    "instruction_set": the kernels' on this processor, "reason": why not compiled}``."""
    lib, keys, reason = _library()
    if lib is None:
        return {"path": "interpreter", "kernels": 0, "instruction_set": None, "reason": reason}
    return {"path": "compiled", "kernels": len(keys), "instruction_set": lib.isa(), "reason": ""}


def key(fn: ca.Function, summed: bool = False) -> str:
    """A function's key: its name and the sha256 of its serialised graph, with ``:sum`` for the kernel
    that sums its outputs over the batch (symbolic.kernels lists the kernels by it)."""
    return f"{fn.name()}:{hashlib.sha256(fn.serialize().encode()).hexdigest()[:16]}" + (":sum" if summed else "")


_noticed = []


Chunk = tuple[list[np.ndarray], list[np.ndarray], int, int]


@lru_cache(maxsize=1024)
def kernel(fn: ca.Function, summed: bool = False) -> Callable[[list[int], list[Chunk], int], None] | None:
    """``run(strides, chunks, threads)`` evaluating ``fn`` compiled over the chunks of a batch, each chunk
    ``(inputs, outputs, n, group)``: n rows, inputs (n or 1, k_i) with the row strides ``strides``, outputs
    (n, k_j), C order; the chunks on up to ``threads`` threads (the caller's and threads the library keeps),
    without the GIL. None where ``fn`` has no kernel. With ``summed`` the kernel adds the sums of each
    output over consecutive groups of ``group`` rows to the rows of (n / group, k_j) outputs instead."""
    lib, keys, reason = _library()
    if lib is None:
        if not _noticed:
            _noticed.append(reason)
            warnings.warn(f"pkm evaluates with CasADi's interpreter: {reason}", CompiledPathWarning, stacklevel=3)
        return None
    if not fn.is_a("SXFunction"):
        return None
    index = keys.get(key(fn, summed))
    if index is None:
        return None

    n_in, n_out = fn.n_in(), fn.n_out()

    def run(strides: list[int], chunks: list[Chunk], threads: int) -> None:
        if len(strides) != n_in or any(len(c[0]) != n_in or len(c[1]) != n_out for c in chunks):
            raise ValueError(f"{fn.name()}'s kernel takes {n_in} inputs and {n_out} outputs per chunk")
        lib.run(index, threads, strides, chunks)

    return run
