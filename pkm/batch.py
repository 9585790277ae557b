"""Vectorised evaluation of CasADi functions over batches (leading axis), without copies.

A numpy array of shape (N, k) in C order has the memory layout of a k x N CasADi matrix (column
major), so a ``Function.map(N)`` can read and write numpy buffers directly.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from functools import lru_cache
from itertools import pairwise
from typing import NamedTuple

import casadi as ca
import numpy as np

from pkm.compiled import kernel
from pkm.compiled.emit import GROUP_SHARED

REACH_TOLERANCE = 1e-12
THREADS = max(1, min(os.cpu_count() or 1, 8))
CHUNK = 1 << 16
COMPILED_WORK = 1 << 20  # instructions times rows per thread at least: smaller batches run on the calling thread


@lru_cache(maxsize=256)
def _mapped(f: ca.Function, n: int) -> ca.Function:
    if n < 2048 or THREADS == 1:
        return f.map(n, "serial")
    return f.map(n, "thread", THREADS)


@lru_cache(maxsize=256)
def _dense(f: ca.Function) -> ca.Function:
    """``f`` with dense inputs and outputs: buffers hold every entry, structural zeros included. An SX
    function stays one (so that it compiles)."""
    dense_in = all(f.sparsity_in(i).is_dense() for i in range(f.n_in()))
    if dense_in and all(f.sparsity_out(j).is_dense() for j in range(f.n_out())):
        return f
    symbol = ca.SX.sym if f.is_a("SXFunction") else ca.MX.sym
    args = [symbol(f.name_in(i), *f.size_in(i)) for i in range(f.n_in())]
    outs = [ca.densify(o) for o in f.call(args)]
    return ca.Function(f.name(), args, outs, f.name_in(), f.name_out())


def evaluate(f: ca.Function, *args: np.ndarray) -> tuple[np.ndarray, ...]:
    """Evaluate ``f`` over a batch: compiled where ``f`` has a kernel (:mod:`pkm.compiled`), else by
    CasADi's interpreter.

    Each argument is (N, f.numel_in(i)) or 1-D of length f.numel_in(i) (then shared by the batch).
    Returns one (N, rows, cols) array per output (matrices in natural, row-major indexing).
    """
    return _evaluate(f, args, check=False)[0]


def evaluate_finite(f: ca.Function, *args: np.ndarray) -> tuple[tuple[np.ndarray, ...], bool]:
    """:func:`evaluate`, and whether every entry of the arguments that ``f`` reads row by row (all but the
    mode and the design, which a kernel reads once) is finite: the kernel says so as it reads them, the
    interpreter's path checks every argument with numpy."""
    return _evaluate(f, args, check=True)


def _evaluate(f: ca.Function, args: tuple[np.ndarray, ...], *, check: bool) -> tuple[tuple[np.ndarray, ...], bool]:
    f = _dense(f)
    arrays = [np.asarray(a, dtype=float) for a in args]
    layout = _layout(f)
    rows = any(a.ndim == 2 and f.name_in(i) in GROUP_SHARED for i, a in enumerate(arrays))
    run = kernel(f, work=layout.instructions * _rows(arrays), rows=rows)
    if run is not None:
        return _compiled(f, layout, run, arrays)
    return interpreted(f, *arrays), not check or all(map(all_finite, arrays))


def all_finite(arr: np.ndarray) -> bool:
    """Whether every entry is finite: the sum of finite values is finite unless it overflows, so one
    vectorised pass answers the usual case (an overflow, which only sends it to the entry-wise check, is not
    warned about)."""
    with np.errstate(over="ignore", invalid="ignore"):
        total = np.add.reduce(arr, axis=None)
    return bool(np.isfinite(total) or np.all(np.isfinite(arr)))


def interpreted(f: ca.Function, *args: np.ndarray) -> tuple[np.ndarray, ...]:
    """:func:`evaluate` by CasADi's interpreter (``map`` over the batch), whatever kernels there are."""
    f = _dense(f)
    layout = _layout(f)
    arrays = [np.asarray(a, dtype=float) for a in args]
    n = _batch_size(f, layout, arrays)
    inputs = [np.ascontiguousarray(np.broadcast_to(a, (n, width)))
              for a, width in zip(arrays, layout.widths_in, strict=True)]
    outputs = [np.empty((n, width)) for width in layout.widths_out]
    for start in range(0, n, CHUNK):
        stop = min(n, start + CHUNK)
        mapped = _mapped(f, stop - start)
        buf, run_mapped = mapped.buffer()
        for i, a in enumerate(inputs):
            buf.set_arg(i, memoryview(a[start:stop]))
        for j, o in enumerate(outputs):
            buf.set_res(j, memoryview(o[start:stop]))
        run_mapped()
    return _shaped(layout, outputs, n)


class _Layout(NamedTuple):
    """What a batch evaluation reads of a function, read from CasADi once per function (and passed
    down, as looking a CasADi function up costs more than a small batch's arithmetic)."""

    widths_in: tuple[int, ...]
    widths_out: tuple[int, ...]
    sizes_out: tuple[tuple[int, int], ...]
    instructions: int  # of an SX function (what a kernel runs), else 0


@lru_cache(maxsize=1024)
def _layout(f: ca.Function) -> _Layout:
    return _Layout(tuple(f.numel_in(i) for i in range(f.n_in())), tuple(f.numel_out(j) for j in range(f.n_out())),
                   tuple(f.size_out(j) for j in range(f.n_out())), f.n_instructions() if f.is_a("SXFunction") else 0)


def _rows(arrays: list[np.ndarray]) -> int:
    """The rows of a batch (one where every argument is shared), without checking them."""
    return max((len(a) for a in arrays if a.ndim == 2), default=1)


def _batch_size(f: ca.Function, layout: _Layout, arrays: list[np.ndarray]) -> int:
    sizes = {a.shape[0] for a in arrays if a.ndim == 2}
    if len(sizes) > 1:
        raise ValueError(f"{f.name()}: batch sizes differ: {sorted(sizes)}")
    for i, (a, width) in enumerate(zip(arrays, layout.widths_in, strict=True)):
        if a.shape[-1] != width:
            raise ValueError(f"{f.name()}: input {f.name_in(i)} has width {a.shape[-1]}, expected {width}")
    return sizes.pop() if sizes else 1


def _shaped(layout: _Layout, outputs: list[np.ndarray], n: int) -> tuple[np.ndarray, ...]:
    return tuple(o.reshape(n, cols, rows).transpose(0, 2, 1)
                 for o, (rows, cols) in zip(outputs, layout.sizes_out, strict=True))


def total(f: ca.Function, *args: np.ndarray, group: int | None = None) -> tuple[np.ndarray, ...]:
    """The sums of each output of ``f`` over the batch (arguments as for :func:`evaluate`): one (rows, cols)
    array per output; or with ``group`` over each run of ``group`` consecutive rows: one (N / group, rows,
    cols) array per output. By ``f``'s summing kernel where it has one (rows added in order), else by
    CasADi's interpreter and numpy. A summing kernel reads its inputs named in
    ``pkm.compiled.emit.GROUP_SHARED`` (``mode``, ``design``, ``t``) from the first row of each group: they must
    be the same on every row of a group."""
    f = _dense(f)
    arrays = [np.asarray(a, dtype=float) for a in args]
    layout = _layout(f)
    n = _batch_size(f, layout, arrays)
    size = n if group is None else group
    if size < 1 or n % size:
        raise ValueError(f"{f.name()}: a batch of {n} rows does not split into groups of {size}")
    run = kernel(f, summed=True, work=layout.instructions * n)
    if run is None:
        sums = tuple(o.reshape(n // size, size, *o.shape[1:]).sum(axis=1) for o in interpreted(f, *arrays))
    else:
        sums = _shaped(layout, _compiled_sums(layout, run, arrays, n, size)[0], n // size)
    return sums if group is not None else tuple(s[0] for s in sums)


def _compiled_sums(
    layout: _Layout, run: Callable[..., None], arrays: list[np.ndarray], n: int, size: int
) -> tuple[list[np.ndarray], bool]:
    """The sums (n / size, numel_j) of each output over each run of ``size`` rows by the summing kernel,
    and whether every input entry it read was finite; where there are fewer runs than threads, each is
    split into chunks whose partial sums are added in chunk order."""
    groups, widths = n // size, layout.widths_out
    outputs = [np.zeros((groups, width)) for width in widths]
    bounds = _chunks(layout, n, size)
    if len(bounds) <= groups:
        finite = _run_chunks(layout, run, arrays, bounds,
                             lambda _, start, stop: [o[start // size:stop // size] for o in outputs], group=size)
        return outputs, finite
    partial = [np.zeros((len(bounds), width)) for width in widths]
    finite = _run_chunks(layout, run, arrays, bounds, lambda k, *_: [o[k:k + 1] for o in partial], group=None)
    for k, (start, _) in enumerate(bounds):
        for o, p in zip(outputs, partial, strict=True):
            o[start // size] += p[k]
    return outputs, finite


def _chunks(layout: _Layout, n: int, unit: int = 1) -> list[tuple[int, int]]:
    """Chunks of a batch of n rows, one per thread and of at least COMPILED_WORK / (the instructions) rows;
    each a multiple of ``unit`` rows, or where there are fewer runs of ``unit`` rows than threads, pieces of
    one run each."""
    least = -(-COMPILED_WORK // max(1, layout.instructions))
    step = max(least, -(-n // THREADS))
    if unit == 1 or n // unit >= THREADS:
        step = -(-step // unit) * unit
        return [(start, min(n, start + step)) for start in range(0, n, step)]
    bounds = []
    for first in range(0, n, unit):
        last = min(n, first + unit)
        pieces = max(1, min(THREADS, (last - first) // least))
        edges = [first + (last - first) * k // pieces for k in range(pieces + 1)]
        bounds += list(pairwise(edges))
    return bounds


def _run_chunks(
    layout: _Layout,
    run: Callable[..., None],
    arrays: list[np.ndarray],
    bounds: list[tuple[int, int]],
    outputs_of: Callable[[int, int, int], list[np.ndarray]],
    *,
    group: int | None = 1,
) -> bool:
    """The kernel over the chunks of the batch on up to THREADS threads (:func:`pkm.compiled.kernel`),
    shared inputs read with stride 0; ``outputs_of(k, start, stop)`` are the buffers chunk k writes (a
    summing kernel adds runs of ``group`` rows, or with ``group`` None the whole chunk). Returns whether
    every input entry the kernel read row by row was finite (each chunk's flag)."""
    inputs = [np.ascontiguousarray(a) for a in arrays]
    strides = [width if a.ndim == 2 else 0 for a, width in zip(inputs, layout.widths_in, strict=True)]
    flags = np.zeros((len(bounds), 1))
    chunks = [([a[start:stop] if a.ndim == 2 else a for a in inputs], [*outputs_of(k, start, stop), flags[k:k + 1]],
               stop - start, stop - start if group is None else group) for k, (start, stop) in enumerate(bounds)]
    if chunks:
        run(strides, chunks, THREADS)
    return not flags.any()


def _compiled(
    f: ca.Function, layout: _Layout, run: Callable[..., None], arrays: list[np.ndarray]
) -> tuple[tuple[np.ndarray, ...], bool]:
    """``f`` over the batch by its compiled kernel, and whether every input entry it read was finite."""
    n = _batch_size(f, layout, arrays)
    outputs = [np.empty((n, width)) for width in layout.widths_out]
    finite = _run_chunks(layout, run, arrays, _chunks(layout, n),
                         lambda _, start, stop: [o[start:stop] for o in outputs])
    return _shaped(layout, outputs, n), finite


def reached(values: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Mask (N,) of the solutions that exist: reach margins >= 0 up to round-off and values finite."""
    margins = reach.reshape(len(reach), int(np.prod(reach.shape[1:])))
    finite = np.all(np.isfinite(values.reshape(len(values), int(np.prod(values.shape[1:])))), axis=1)
    return np.all(margins >= -REACH_TOLERANCE, axis=1) & finite
