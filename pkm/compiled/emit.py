"""CasADi SX function -> C: the emitter of the compiled path (DESIGN.md section 6a).

:func:`source` writes a function's instruction list, one C statement per instruction, as the body of a
loop over the rows of pkm's batch arrays, in a translation unit of its own that exports one function,
``pkm_kernel``: input ``i`` of row ``p`` is read from ``in[i] + p * stride[i]`` (a stride of 0 shares one
row with the whole batch), output ``j`` written to ``out[j] + p * numel_j``, both in CasADi's
column-major order of the matrix entries, as :func:`pkm.batch.evaluate` lays them out; one more output,
``out[n_out]``, is set to 1 where an entry that the kernel reads row by row is not finite, so that a caller
checks its inputs without a pass of its own over them. Each operation is
the C library's or IEEE arithmetic (no fast-math, no contraction: :mod:`pkm.compiled.toolchain` compiles
with those flags; comparisons and logic as selects, so that the loop vectorises), so the compiled kernel
agrees with CasADi's interpreter to round-off; constants are written as hexadecimal floats, so they are
exact. The text depends only on the graph: the same function gives the same bytes.
"""

from __future__ import annotations

import math

import casadi as ca

UNARY = {
    ca.OP_ASSIGN: "{0}", ca.OP_NEG: "-{0}", ca.OP_SQ: "{0} * {0}", ca.OP_TWICE: "{0} + {0}",
    ca.OP_INV: "1. / {0}", ca.OP_NOT: "(double)({0} == 0)", ca.OP_SIGN: "PKM_SIGN({0})",
    ca.OP_EXP: "exp({0})", ca.OP_LOG: "log({0})", ca.OP_SQRT: "sqrt({0})", ca.OP_FABS: "fabs({0})",
    ca.OP_SIN: "sin({0})", ca.OP_COS: "PKM_COS({0})", ca.OP_TAN: "tan({0})", ca.OP_ASIN: "asin({0})",
    ca.OP_ACOS: "acos({0})", ca.OP_ATAN: "atan({0})", ca.OP_SINH: "sinh({0})", ca.OP_COSH: "cosh({0})",
    ca.OP_TANH: "tanh({0})", ca.OP_ASINH: "asinh({0})", ca.OP_ACOSH: "acosh({0})", ca.OP_ATANH: "atanh({0})",
    ca.OP_FLOOR: "floor({0})", ca.OP_CEIL: "ceil({0})", ca.OP_ERF: "erf({0})", ca.OP_LOG1P: "log1p({0})",
    ca.OP_EXPM1: "expm1({0})",
}
BINARY = {
    ca.OP_ADD: "{0} + {1}", ca.OP_SUB: "{0} - {1}", ca.OP_MUL: "{0} * {1}", ca.OP_DIV: "{0} / {1}",
    ca.OP_POW: "pow({0}, {1})", ca.OP_CONSTPOW: "pow({0}, {1})", ca.OP_ATAN2: "atan2({0}, {1})",
    ca.OP_FMIN: "PKM_FMIN({0}, {1})", ca.OP_FMAX: "PKM_FMAX({0}, {1})", ca.OP_FMOD: "fmod({0}, {1})",
    ca.OP_COPYSIGN: "copysign({0}, {1})", ca.OP_HYPOT: "hypot({0}, {1})",
    ca.OP_LT: "(double)({0} < {1})", ca.OP_LE: "(double)({0} <= {1})", ca.OP_EQ: "(double)({0} == {1})",
    ca.OP_NE: "(double)({0} != {1})", ca.OP_AND: "PKM_AND({0}, {1})", ca.OP_OR: "PKM_OR({0}, {1})",
    ca.OP_IF_ELSE_ZERO: "{0} == 0 ? 0. : {1}",
}
NAMES = {getattr(ca, n): n for n in dir(ca) if n.startswith("OP_")}

PRELUDE = """#include <math.h>

/* CasADi's sign (-1, 0 or 1, NaN for NaN) and the C library's fmin and fmax (the other operand where
   one is NaN), written as selects so that a loop of them vectorises */
#define PKM_SIGN(x) ((x) < 0 ? -1. : (x) > 0 ? 1. : (x))
#define PKM_FMIN(a, b) ((a) != (a) ? (b) : (b) != (b) ? (a) : (a) < (b) ? (a) : (b))
#define PKM_FMAX(a, b) ((a) != (a) ? (b) : (b) != (b) ? (a) : (a) > (b) ? (a) : (b))

/* logic on truth values (nonzero is true) in double arithmetic: GCC 12 does not vectorise a loop in which
   a comparison's result, converted to double, meets another in a bitwise & or | */
#define PKM_TRUE(a) ((double)((a) != 0))
#define PKM_AND(a, b) (PKM_TRUE(a) * PKM_TRUE(b))
#define PKM_OR(a, b) (PKM_TRUE(a) + PKM_TRUE(b) - PKM_TRUE(a) * PKM_TRUE(b))

/* the vector variants of the C library's functions (glibc's libmvec, within 4 ulp) where it has them */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \\
    defined(__GLIBC__) && __GLIBC_PREREQ(2, 35)
#define PKM_X86_VECTOR 1
#define PKM_SIMD __attribute__((simd("notinbranch")))
PKM_SIMD double sin(double);
PKM_SIMD double cos(double);
PKM_SIMD double tan(double);
PKM_SIMD double asin(double);
PKM_SIMD double acos(double);
PKM_SIMD double atan(double);
PKM_SIMD double atan2(double, double);
PKM_SIMD double exp(double);
PKM_SIMD double log(double);
PKM_SIMD double pow(double, double);
#else
#define PKM_SIMD
#endif

/* cos goes through a wrapper of its own, or the compiler would merge sin and cos of one argument into a
   complex exponential that does not vectorise */
#define PKM_COS pkm_cos

#define PKM_BLOCK 64 /* poses a kernel transposes into columns and evaluates at a time */

PKM_SIMD __attribute__((noinline)) static double pkm_cos(double x) { return cos(x); }

/* one entry of rows p0 .. p0 + m - 1 of an (N, k) input (stride k, or 0 for one row shared by the batch;
   in points at the entry in row 0) into a column of a block, the last row repeated to fill it */
static inline void pkm_gather(double *restrict a, const double *in, long stride, long p0, long m)
{
  for (long q = 0; q < PKM_BLOCK; ++q) a[q] = in[(p0 + (q < m ? q : m - 1)) * stride];
}

/* the first m rows of a block's k columns, rows p0 .. p0 + m - 1 of the batch, added in row order to
   the rows of a (N / group, k) output: batch row p to output row p / group. The rows of one output row
   are added in registers, up to PKM_SUMS columns at a time side by side (k independent chains instead of
   one through memory, and one division per output row instead of one per batch row) */
#define PKM_SUMS 16
static inline void pkm_accumulate(double *out, long k, const double *restrict b, long p0, long m, long group)
{
  double s[PKM_SUMS];
  for (long q = 0; q < m;) {
    const long row = (p0 + q) / group;
    const long end = (row + 1) * group - p0 < m ? (row + 1) * group - p0 : m;
    double *restrict o = out + row * k;
    for (long e0 = 0; e0 < k; e0 += PKM_SUMS) {
      const long e1 = k - e0 < PKM_SUMS ? k : e0 + PKM_SUMS;
      for (long e = e0; e < e1; ++e) s[e - e0] = o[e];
      for (long r = q; r < end; ++r)
        for (long e = e0; e < e1; ++e) s[e - e0] += b[e * PKM_BLOCK + r];
      for (long e = e0; e < e1; ++e) o[e] = s[e - e0];
    }
    q = end;
  }
}

/* the first m rows of a block's k columns into rows p0 .. p0 + m - 1 of an (N, k) output */
static inline void pkm_scatter(double *out, long k, const double *restrict b, long p0, long m)
{
  for (long q = 0; q < m; ++q)
    for (long e = 0; e < k; ++e) out[(p0 + q) * k + e] = b[e * PKM_BLOCK + q];
}
"""


def literal(value: float) -> str:
    """An exact C literal of a double."""
    if math.isnan(value):
        return "NAN"
    if math.isinf(value):
        return "INFINITY" if value > 0 else "-INFINITY"
    return value.hex()


def emittable(fn: ca.Function) -> bool:
    """Whether :func:`kernel` can write ``fn``: an SX function with dense ports and known operations."""
    if not fn.is_a("SXFunction"):
        return False
    ports = [fn.sparsity_in(i) for i in range(fn.n_in())] + [fn.sparsity_out(j) for j in range(fn.n_out())]
    if not all(s.is_dense() for s in ports):
        return False
    known = {ca.OP_INPUT, ca.OP_OUTPUT, ca.OP_CONST, *UNARY, *BINARY}
    return all(fn.instruction_id(k) in known for k in range(fn.n_instructions()))


GROUP_SHARED = ("mode", "design", "t")  # the inputs a summing kernel reads once per group


def _expression(fn: ca.Function, k: int, ref: list[str]) -> str:
    """The C expression of instruction k (not an input or output) with its operands named by ``ref``."""
    op, ins = fn.instruction_id(k), fn.instruction_input(k)
    if op == ca.OP_CONST:
        return literal(fn.instruction_constant(k))
    if op in UNARY:
        return UNARY[op].format(ref[ins[0]])
    return BINARY[op].format(ref[ins[0]], ref[ins[1]])


def _split(fn: ca.Function, shared: set[int]) -> tuple[list[str], list[str], set[tuple[int, int]]]:
    """The statements that depend on the ``shared`` inputs alone (once, ``const double h<k>``), the others
    (per row of a block, ``w<k>`` and the outputs ``b<j>``), and the entries of the other inputs they read."""
    ref = [f"w{k}" for k in range(fn.sz_w())]  # each work variable's current name: w (per row) or h (once)
    varies = [True] * fn.sz_w()
    once_lines, row_lines, gathered = [], [], set()
    for k in range(fn.n_instructions()):
        op, ins, outs = fn.instruction_id(k), fn.instruction_input(k), fn.instruction_output(k)
        if op == ca.OP_OUTPUT:
            row_lines.append(f"b{outs[0]}[{outs[1]}][q] = {ref[ins[0]]};")
            continue
        if op == ca.OP_INPUT:
            once = ins[0] in shared
            expression = f"in[{ins[0]}][g0 * stride[{ins[0]}] + {ins[1]}]" if once else f"a{ins[0]}[{ins[1]}][q]"
            if not once:
                gathered.add((ins[0], ins[1]))
                # x - x is 0 for a finite x, NaN otherwise: the entries read are checked in vector arithmetic
                row_lines += [f"w{outs[0]} = {expression};", f"nonfinite[q] += w{outs[0]} - w{outs[0]};"]
                ref[outs[0]], varies[outs[0]] = f"w{outs[0]}", True
                continue
        else:
            once = bool(shared) and not any(varies[i] for i in ins if i >= 0)
            expression = _expression(fn, k, ref)
        if once:
            once_lines.append(f"const double h{k} = {expression};")
            ref[outs[0]], varies[outs[0]] = f"h{k}", False
        else:
            row_lines.append(f"w{outs[0]} = {expression};")
            ref[outs[0]], varies[outs[0]] = f"w{outs[0]}", True
    return once_lines, row_lines, gathered


def _loop(fn: ca.Function, shared: set[int], summed: bool, indent: str) -> list[str]:
    """The loop over groups of rows (one group, the whole batch, for a kernel that is not summed) with
    what depends on the ``shared`` inputs alone computed once per group, then over each group's blocks."""
    once_lines, row_lines, gathered = _split(fn, shared)
    n_out = [fn.nnz_out(j) for j in range(fn.n_out())]
    written = sorted({int(line[1:line.index(" ")]) for line in row_lines if line.startswith("w")})
    inner = indent + "    "
    lines = [f"{indent}for (long g0 = 0; g0 < n; g0 += {'group' if summed else 'n'}) {{",
             f"{indent}  const long g1 = {'n - g0 < group ? n : g0 + group' if summed else 'n'};"]
    lines += [f"{indent}  {line}" for line in once_lines]
    lines += [f"{indent}  for (long p0 = g0; p0 < g1; p0 += PKM_BLOCK) {{",
              f"{inner}const long m = g1 - p0 < PKM_BLOCK ? g1 - p0 : PKM_BLOCK;"]
    for i in sorted({i for i, _ in gathered}):
        entries, k = sorted(e for j, e in gathered if j == i), fn.nnz_in(i)
        # a whole block of rows of k entries each: one pass over them, which the compiler vectorises as loads
        # and permutations (the general gather, whose last row repeats, is a gather instruction per entry)
        copies = " ".join(f"a{i}[{e}][q] = r{i}[q * {k} + {e}];" for e in entries)
        lines += [f"{inner}if (m == PKM_BLOCK && stride[{i}] == {k}) {{",
                  f"{inner}  const double *restrict r{i} = in[{i}] + p0 * {k};",
                  f"{inner}  for (long q = 0; q < PKM_BLOCK; ++q) {{ {copies} }}",
                  f"{inner}}} else {{",
                  *(f"{inner}  pkm_gather(a{i}[{e}], in[{i}] + {e}, stride[{i}], p0, m);" for e in entries),
                  f"{inner}}}"]
    # no "omp simd": with it GCC 12 vectorises no loop that converts a comparison to double; the vector
    # functions of the prelude's simd declarations are used without it
    lines.append(f"{inner}for (long q = 0; q < PKM_BLOCK; ++q) {{")
    if written:
        lines.append(f"{inner}  double " + ", ".join(f"w{k}" for k in written) + ";")
    lines += [f"{inner}  {line}" for line in row_lines]
    lines.append(f"{inner}}}")
    store = ("accumulate(out[{j}], {k}, b{j}[0], p0, m, group);" if summed
             else "scatter(out[{j}], {k}, b{j}[0], p0, m);")
    lines += [f"{inner}pkm_{store.format(j=j, k=k)}" for j, k in enumerate(n_out) if k]
    return [*lines, f"{indent}  }}", f"{indent}}}"]


SYMBOL = "pkm_kernel"  # the one function a kernel's translation unit exports


def shared_inputs(fn: ca.Function) -> set[int]:
    """The inputs of ``fn`` named in GROUP_SHARED (the mode, the design), those with entries."""
    return {i for i in range(fn.n_in()) if fn.name_in(i) in GROUP_SHARED and fn.nnz_in(i)}


def source(fn: ca.Function, summed: bool = False, rows: bool = False) -> str:
    """The translation unit of ``fn``'s kernel: :data:`PRELUDE` and the function :data:`SYMBOL` that
    evaluates ``fn`` over a batch (module docstring), or with ``summed``
    adds the sums of each output over consecutive groups of ``group`` rows, in row order, to the rows of
    ``out[j]`` (N / group rows of numel_j); a kernel that is not summed ignores ``group``.

    The inputs named in GROUP_SHARED (the mode, the design) are read once, and what depends on them alone
    is computed once, before the loop over the rows: by a summing kernel once per group, from the group's
    first row (they are the same on every row of a group: one design per group); by one that is not summed
    once per call, every one of them shared by the batch (stride 0), or with ``rows`` (a kernel of its own,
    compiled where a batch gives one of them per row) row by row."""
    if not emittable(fn):
        raise ValueError(f"{fn.name()}: not an SX function with dense ports and known operations")
    n_in = [fn.nnz_in(i) for i in range(fn.n_in())]
    n_out = [fn.nnz_out(j) for j in range(fn.n_out())]
    shared = set() if rows and not summed else shared_inputs(fn)
    once = "group" if summed else "call, the design shared by the batch" if shared else "call"
    lines = [
        PRELUDE,
        f"/* {fn.name()}: {fn.n_instructions()} instructions, {len(_split(fn, shared)[0])} once per {once}; "
        f"inputs {', '.join(fn.name_in())}; outputs {', '.join(fn.name_out())}"
        f"{' summed over the batch' if summed else ''} */",
        f"void {SYMBOL}(long n, long group, const double *const *in, const long *stride, "
        "double *const *out)",
        "{",
    ]
    lines.append("  double nonfinite[PKM_BLOCK] = {0};")
    lines += [f"  double a{i}[{k}][PKM_BLOCK];" for i, k in enumerate(n_in) if k and i not in shared]
    lines += [f"  double b{j}[{k}][PKM_BLOCK];" for j, k in enumerate(n_out) if k]
    lines += _loop(fn, shared, summed, "  ")
    lines.append(f"  for (long q = 0; q < PKM_BLOCK; ++q) if (nonfinite[q] != 0) out[{fn.n_out()}][0] = 1.;")
    return "\n".join([*lines, "}", ""])
