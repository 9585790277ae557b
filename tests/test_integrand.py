"""The point integrands of the global indices (pkm.regions.integrand): their kernels against CasADi's
interpreter, their sums and derivatives against the graph of the region's nodes built the other way
(the region's quadrature mapped through the fused pipeline and reduced in CasADi: the baseline of
bench.integrals), batches of designs against one design at a time."""

from __future__ import annotations

import re

import casadi as ca
import numpy as np
import pytest

import pkm
from bench.integrals import node_graph
from pkm import compiled
from pkm.batch import COMPILED_WORK, interpreted, total
from pkm.catalogue import integrands
from pkm.compiled.emit import GROUP_SHARED
from pkm.indices import epigraph_function
from pkm.regions import RegionIndex, node_quadrature, quadrature_function, quadrature_value
from pkm.regions.integrand import region_rows, sum_function
from pkm.regions.pipeline import pipeline
from pkm.regions.quadrature import epigraph_margins

RESOLUTION = 4


def _inputs(mech, integrand) -> list[np.ndarray]:
    nodes, weights = integrand.piece.reference(RESOLUTION, integrand.reduce)
    design = mech.design_vector(mech.design())
    signs = np.array(mech.working_mode(None).signs, dtype=float)
    names = integrand.function.name_in()
    values = {"u": nodes, "w": weights[:, None], "mode": signs, "design": design, "t": np.array([0.5])}
    return [values[n] for n in names]


@pytest.mark.parametrize("name", pkm.mechanisms())
def test_integrand_kernels_agree_with_the_interpreter(name):
    """Every integrand kernel exists and gives the interpreter's values, gradients and Hessians: sums to
    1e-12 of the sum of the magnitudes it adds, rows to 1e-12 of their largest entry, their derivatives
    to 1e-11 (a derivative through a linear solve, the 2-UPS-PU's wrench matrix, amplifies the vector maths'
    last-ulp differences by the matrix's conditioning), and 1e-9 at the rim of an extreme's rule, inset 1e-9
    from the region's boundary, where a mechanism may be singular and J's conditioning amplifies them the
    more; NaN where the interpreter has NaN."""
    if compiled.status()["path"] != "compiled":
        pytest.skip(f"the compiled path is off: {compiled.status()['reason']}")
    mech = pkm.load(name)
    catalogue = integrands(mech)
    assert compiled.build([(k.function, k.summed) for k in catalogue])["interpreted"] == 0
    for integrand in catalogue:
        fn = integrand.function
        assert compiled.kernel(fn, integrand.summed) is not None, fn.name()
        args = _inputs(mech, integrand)
        slow = interpreted(fn, *args)
        if integrand.summed:
            fast = total(fn, *args)
            for j, (got, rows) in enumerate(zip(fast, slow, strict=True)):
                want = rows.sum(axis=0)
                scale = np.maximum(1.0, np.abs(rows).sum(axis=0))
                assert np.array_equal(np.isnan(got), np.isnan(want)), f"{fn.name()}: {fn.name_out(j)}"
                error = np.nan_to_num(np.abs(got - want) / scale)
                assert np.all(error <= 1e-12), f"{fn.name()}: {fn.name_out(j)}: {error.max():.1e}"
        else:
            fast = pkm.batch.evaluate(fn, *args)
            _, weights = integrand.piece.reference(RESOLUTION, integrand.reduce)
            for j, (got, want) in enumerate(zip(fast, slow, strict=True)):
                tolerance = np.where(weights > 0, 1e-12 if j == 0 else 1e-11, 1e-9)
                assert np.array_equal(np.isnan(got), np.isnan(want)), f"{fn.name()}: {fn.name_out(j)}"
                scale = np.maximum(1.0, np.nanmax(np.abs(want.reshape(len(want), -1)), axis=1, initial=0.0))
                error = np.nanmax(np.nan_to_num(np.abs(got - want)).reshape(len(got), -1), axis=1) / scale
                assert np.all(error <= tolerance), f"{fn.name()}: {fn.name_out(j)}: {np.max(error / tolerance):.1e}"


@pytest.mark.parametrize(
    ("name", "index", "region"),
    [("five_bar", "gci", "miw"), ("five_bar", "dynamic_dexterity", "miw"), ("five_bar", "region_measure", "miw"),
     ("slider_gantry", "kappa_d_std", "task"), ("slider_gantry", "kappa_d_mean", "task"), ("ups_pu", "gci", "task")],
)
def test_global_indices_have_the_value_gradient_and_hessian_of_the_node_graph(name, index, region):
    """The reduction in CasADi (as IPOPT takes it) and numerically (quadrature_function: value and gradient)
    against the node graph."""
    mech = pkm.load(name)
    spec, where, branch = mech.global_spec(index), mech.region(region), mech.working_mode(None)
    d = ca.MX.sym("d", len(mech.parameter_names()))
    design = mech.design_vector(mech.design())
    results = []
    for value in (quadrature_value(RegionIndex(mech, spec, where, branch), d, resolution=RESOLUTION),
                  node_graph(mech, spec, where, branch, design=d, resolution=RESOLUTION)):
        gradient, hessian = ca.gradient(value, d), ca.hessian(value, d)[0]
        results.append([np.asarray(v) for v in ca.Function("f", [d], [value, gradient, hessian])(design)])
    numeric = quadrature_function(mech, spec, where, branch, RESOLUTION)(design)
    checks = [*zip(("value", "gradient", "hessian"), results[0], results[1], strict=True),
              *zip(("numeric value", "numeric gradient"), numeric, results[1][:2], strict=True)]
    for what, got, want in checks:
        scale = max(1e-300, float(np.max(np.abs(want))))
        assert np.max(np.abs(np.ravel(got) - np.ravel(want))) <= 1e-10 * scale, f"{index}: {what}"
    assert np.max(np.abs(results[0][1])) > 0


def test_epigraph_margins_have_the_values_and_jacobian_of_the_node_graph():
    mech = pkm.load("five_bar")
    spec, region, branch = mech.global_spec("lambda_e"), mech.region("miw"), mech.working_mode(None)
    d, t = ca.MX.sym("d", len(mech.parameter_names())), ca.MX.sym("t")
    points, _ = region.quadrature(mech.functions, d, RESOLUTION, spec.reduce)
    n = points.size2()
    _, _, _, _, *matrices = pipeline(mech, (spec.local,), matrices=True).map(n)(points, ca.DM(branch.signs), d)
    shapes = tuple((m.size1(), m.size2() // n) for m in matrices)
    margins = epigraph_function(spec.local, shapes, False).map(n)(*matrices, t)  # a margin per row, a node per column
    graph = ca.vec(margins.T)
    smooth = epigraph_margins(RegionIndex(mech, spec, region, branch), design=d, bound=t, resolution=RESOLUTION)
    z = ca.vertcat(d, t)
    point = [mech.design_vector(mech.design()), 1.2]
    got, want = ([np.asarray(v) for v in ca.Function("f", [d, t], [g, ca.jacobian(g, z)])(*point)]
                 for g in (smooth, graph))
    for a, b in zip(got, want, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * float(np.max(np.abs(b))))


def test_chosen_epigraph_rows_are_those_rows_of_every_row():
    """An exchange step's rows, evaluated at their nodes alone, with their derivatives."""
    mech = pkm.load("ups_pu")
    spec, region, branch = mech.global_spec("actuator_force_max"), mech.region("task"), mech.working_mode(None)
    index = RegionIndex(mech, spec, region, branch)
    kwargs = {"z": np.append(mech.design_vector(mech.design()), 2000.0), "resolution": RESOLUTION, "order": 2,
              "epigraph": True}
    every = region_rows(index, **kwargs)
    rows = np.random.default_rng(5).choice(len(every[0]), size=40, replace=False)
    chosen = region_rows(index, rows=tuple(rows.tolist()), **kwargs)
    for a, b in zip(chosen, every, strict=True):
        np.testing.assert_array_equal(a, b[rows])


def test_a_batch_of_designs_gives_each_designs_value():
    """Designs evaluated together (groups of nodes across the threads' chunks) and one at a time."""
    mech = pkm.load("five_bar")
    spec, region, branch = mech.global_spec("gci"), mech.region("miw"), mech.working_mode(None)
    rng = np.random.default_rng(3)
    base = mech.design_vector(mech.design())
    nodes = region.node_count(8, spec.reduce)
    instructions = sum_function(mech, spec.local, region.pieces()[0], spec.reduce, 0)[0].n_instructions()
    designs = np.tile(base, (2 * COMPILED_WORK // instructions // nodes + 3, 1))
    designs[:, :3] *= rng.uniform(0.95, 1.05, size=(len(designs), 3))
    together = node_quadrature(mech, spec, region, designs, branch=branch, resolution=8)
    alone = [node_quadrature(mech, spec, region, d, branch=branch, resolution=8)[0] for d in designs[::9]]
    np.testing.assert_allclose(together[::9], alone, rtol=1e-14)
    assert np.all(np.isfinite(together))


@pytest.mark.parametrize("order", [0, 1])
def test_one_designs_sums_split_over_threads_are_the_sums_on_one_thread(monkeypatch, order):
    """A design whose nodes are more work than one thread's share is split over the threads (partial
    sums added in chunk order): the same sums as one thread to round-off, every output."""
    from pkm import batch

    mech = pkm.load("five_bar")
    spec, region, branch = mech.global_spec("gci"), mech.region("miw"), mech.working_mode(None)
    piece = region.pieces()[0]
    fn, _ = sum_function(mech, spec.local, piece, spec.reduce, order)
    nodes, weights = piece.reference(100, spec.reduce)
    args = (nodes, weights[:, None], np.array(branch.signs, dtype=float), mech.design_vector(mech.design()))
    monkeypatch.setattr(batch, "THREADS", 2)
    assert len(batch._chunks(batch._layout(fn), len(nodes), len(nodes))) == 2
    split = total(fn, *args)
    monkeypatch.setattr(batch, "THREADS", 1)
    for a, b in zip(split, total(fn, *args), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-13, atol=0)


def test_the_architecture_states_the_compiled_paths_constants():
    from pathlib import Path

    from pkm.compiled import COMPILE_ROWS, COMPILE_WORK, MAX_INSTRUCTIONS
    from pkm.compiled.cache import LIMIT_MB
    from pkm.compiled.toolchain import SMALL
    from pkm.synthesis.model import EXCHANGE_LIMIT, EXCHANGE_ROWS

    text = " ".join((Path(__file__).parent.parent / "docs" / "architecture.md").read_text().split())
    assert f"more than {EXCHANGE_LIMIT} rows" in text
    assert f"it holds the {EXCHANGE_ROWS} rows of least margin of each output" in text
    assert f"adds the {EXCHANGE_ROWS} rows of each output" in text
    assert (f"reaches what its compile costs, 2^{COMPILE_WORK.bit_length() - 1} instructions times rows and "
            f"2^{COMPILE_ROWS.bit_length() - 1} rows per instruction of the graph") in text
    assert f"at most {LIMIT_MB} MiB" in text
    assert f"more than {MAX_INSTRUCTIONS:,} instructions" in text
    assert f"-O3 below {SMALL:,} instructions" in text
    assert f"2^{COMPILED_WORK.bit_length() - 1} instructions times rows" in text
    assert f"`{', '.join(f'`{name}`' for name in GROUP_SHARED)[1:]}" in text
    runner = Path(__file__).parent.parent / "pkm" / "compiled" / "_runner.c"
    spin = re.search(r"#define PKM_SPIN_NS (\d+)L", runner.read_text())
    assert f"for {int(spin[1]) / 1e6:g} ms before they sleep" in text
