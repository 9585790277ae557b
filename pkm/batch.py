"""Vectorised evaluation of CasADi functions over batches (leading axis), without copies.

A numpy array of shape (N, k) in C order has the memory layout of a k x N CasADi matrix (column
major), so a ``Function.map(N)`` can read and write numpy buffers directly.
"""

from __future__ import annotations

import os
from functools import lru_cache

import casadi as ca
import numpy as np

REACH_TOLERANCE = 1e-12
THREADS = max(1, min(os.cpu_count() or 1, 8))
CHUNK = 1 << 16


@lru_cache(maxsize=256)
def _mapped(f: ca.Function, n: int) -> ca.Function:
    if n < 2048 or THREADS == 1:
        return f.map(n, "serial")
    return f.map(n, "thread", THREADS)


@lru_cache(maxsize=256)
def _dense(f: ca.Function) -> ca.Function:
    """``f`` with dense inputs and outputs: buffers hold every entry, structural zeros included."""
    dense_in = all(f.sparsity_in(i).is_dense() for i in range(f.n_in()))
    if dense_in and all(f.sparsity_out(j).is_dense() for j in range(f.n_out())):
        return f
    args = [ca.MX.sym(f.name_in(i), *f.size_in(i)) for i in range(f.n_in())]
    outs = [ca.densify(o) for o in f.call(args)]
    return ca.Function(f.name(), args, outs, f.name_in(), f.name_out())


def evaluate(f: ca.Function, *args: np.ndarray) -> tuple[np.ndarray, ...]:
    """Evaluate ``f`` over a batch.

    Each argument is (N, f.numel_in(i)) or 1-D of length f.numel_in(i) (then shared by the batch).
    Returns one (N, rows, cols) array per output (matrices in natural, row-major indexing).
    """
    f = _dense(f)
    arrays = [np.asarray(a, dtype=float) for a in args]
    sizes = {a.shape[0] for a in arrays if a.ndim == 2}
    if len(sizes) > 1:
        raise ValueError(f"{f.name()}: batch sizes differ: {sorted(sizes)}")
    n = sizes.pop() if sizes else 1
    inputs = []
    for i, a in enumerate(arrays):
        width = f.numel_in(i)
        if a.shape[-1] != width:
            raise ValueError(f"{f.name()}: input {f.name_in(i)} has width {a.shape[-1]}, expected {width}")
        inputs.append(np.ascontiguousarray(np.broadcast_to(a, (n, width))))
    outputs = [np.empty((n, f.numel_out(j))) for j in range(f.n_out())]
    for start in range(0, n, CHUNK):
        stop = min(n, start + CHUNK)
        mapped = _mapped(f, stop - start)
        buf, run = mapped.buffer()
        for i, a in enumerate(inputs):
            buf.set_arg(i, memoryview(a[start:stop]))
        for j, o in enumerate(outputs):
            buf.set_res(j, memoryview(o[start:stop]))
        run()
    shaped = []
    for j, o in enumerate(outputs):
        rows, cols = f.size_out(j)
        shaped.append(o.reshape(n, cols, rows).transpose(0, 2, 1))
    return tuple(shaped)


def reached(values: np.ndarray, reach: np.ndarray) -> np.ndarray:
    """Mask (N,) of the solutions that exist: reach margins >= 0 up to round-off and values finite."""
    margins = reach.reshape(len(reach), int(np.prod(reach.shape[1:])))
    finite = np.all(np.isfinite(values.reshape(len(values), int(np.prod(values.shape[1:])))), axis=1)
    return np.all(margins >= -REACH_TOLERANCE, axis=1) & finite
