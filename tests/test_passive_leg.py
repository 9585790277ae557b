"""The planar manipulator with two RRR legs and a passive RP leg of Nam and Park 2006: forward
kinematics (the degree-6 polynomial in l_c) against the inverse kinematics on every working mode, J
against finite differences and the paper's J_q^-1 J_x, the workspace boundaries of eqs. 12-13 against
the reach and the joint ranges they stand for, each kind of singularity where its condition holds, the
composed index of eq. 31 and its gradient, the indices' convergence and their refusal of singular
regions, bad input, and the paper's printed equations against the derived ones."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import random_design, reachable_poses

import pkm
from pkm.batch import evaluate
from pkm.errors import DesignError, PkmError, PoseError
from pkm.models.passive_leg import nam2006
from pkm.regions import quadrature, sampled_check

LENGTHS = ("R", "r", "l_a", "l_b")
FAMILY = {"R": 1.0, "r": 1.2, "l_a": 1.4, "l_b": 1.2}  # l_b - l_a = R - r (the defaults, Fig. 8c)
INNER = {"R": 1.0, "r": 1.2, "l_a": 1.6, "l_b": 1.2}  # l_b - l_a < R - r: l_cm is real near theta = 0
ADMISSIBLE = (1.4, 1.5)  # chart (r/R, l_b/R) of nam2006: no singularity or joint limit inside the region
TYPE2 = (1.2, 0.6)  # a type-2 singularity inside the region
FOLDED = (0.8, 1.2)  # r < R: a folded leg inside the region
INDICES = ("gci", "manipulability", "space_utilization", "jacobian_determinant")
CONDITIONING = 0.03  # |eq. 8 determinant| / (l_a + l_b)^2 below which forward_from_root loses accuracy


@pytest.fixture(scope="module")
def mech():
    return pkm.load("passive_leg")


def chart_design(mech, chart: tuple[float, float]) -> np.ndarray:
    return nam2006.chart_designs(mech, np.array([chart[0]]), np.array([chart[1]]))[0]


def ray(theta: float, lengths) -> np.ndarray:
    """Poses C = l_c (-sin theta, cos theta) (eq. 7), (N, 2)."""
    lengths = np.atleast_1d(np.asarray(lengths, dtype=float))
    return np.column_stack([-math.sin(theta) * lengths, math.cos(theta) * lengths])


def bisect(inside, a: float, b: float, steps: int = 60) -> float:
    """The point between a and b where the boolean ``inside`` changes, after asserting that it does."""
    at_a = inside(a)
    assert at_a != inside(b), f"no change between {a} and {b}"
    for _ in range(steps):
        c = 0.5 * (a + b)
        if inside(c) == at_a:
            a = c
        else:
            b = c
    return 0.5 * (a + b)


def eq8_determinant(l_c: np.ndarray, q_a: np.ndarray, d: dict) -> np.ndarray:
    """B2 C1 - B1 C2 of eq. 8 (as derived): the determinant of the linear pair forward_from_root solves for
    (cos theta, sin theta); small where two assemblies share nearly the same l_c."""
    R, r, l_a = d["R"], d["r"], d["l_a"]
    p1, p2 = q_a[:, 0], q_a[:, 1]
    B1 = R * r + l_a * r * np.cos(p1) + l_c * l_a * np.sin(p1)
    C1 = l_c * R + l_c * l_a * np.cos(p1) - l_a * r * np.sin(p1)
    B2 = R * r - l_a * r * np.cos(p2) + l_c * l_a * np.sin(p2)
    C2 = -l_c * R + l_c * l_a * np.cos(p2) + l_a * r * np.sin(p2)
    return B2 * C1 - B1 * C2


def allowed(conditioning: np.ndarray) -> np.ndarray:
    """The factor on a tolerance of forward_from_root's output: theta from eq. 8's pair carries the root's
    error over the determinant, itself over the determinant (the root's separation from its neighbour)."""
    return np.maximum(1.0, (CONDITIONING / conditioning) ** 2)


def real_root_count(coefficients: np.ndarray) -> int:
    """Real roots of a polynomial by numpy's own companion matrix."""
    roots = np.roots(coefficients)
    return int(np.sum(np.abs(roots.imag) <= 1e-7 * np.maximum(1.0, np.abs(roots))))


def wrapped(angle: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * angle))


# --- Forward kinematics against inverse kinematics ------------------------------------------------------


@pytest.fixture(scope="module", params=[0, 1, 2])
def case(request, mech):
    rng = np.random.default_rng(10 + request.param)
    design = random_design(mech, rng, names=LENGTHS)
    return design, {mode: reachable_poses(mech, design, mode, rng, count=16) for mode in mech.modes}


def test_every_real_root_closes_the_loops_and_the_ik_pose_is_among_them(mech, case):
    """Every refined root closes the loops to 1e-10 (l_a + l_b); the unrefined back-substitution
    (forward_from_root) to 1e-10 (l_a + l_b) where eq. 8's pair is well conditioned and no worse than
    1 / (B2 C1 - B1 C2)^2 elsewhere."""
    design, poses = case
    d, scale = design.vector(), design["l_a"] + design["l_b"]
    for mode, x in poses.items():
        q = mech.inverse_kinematics(x, design, mode=mode, passive=True)
        q_a = q[:, :2]
        fs = mech.forward_solutions(q_a, design)
        assert fs.l_c.shape == (len(x), 6)
        (c,) = evaluate(mech.functions["forward_polynomial"], q_a, d)
        np.testing.assert_array_equal(fs.count, [real_root_count(row) for row in c[:, :, 0]])
        np.testing.assert_array_equal(fs.count, np.isfinite(fs.l_c).sum(axis=1))
        assert np.all(fs.count % 2 == 0)  # complex roots of a real sextic come in pairs
        assert np.all(np.isfinite(fs.pose[:, :, 0]) == np.isfinite(fs.l_c))

        real = np.isfinite(fs.l_c)
        rows = np.nonzero(real)[0]
        roots = fs.l_c[real]
        x_r, q_r, _ = (v[:, :, 0] for v in evaluate(mech.functions["forward_refined"], roots[:, None],
                                                    q_a[rows], d))
        (h_r, _, _) = evaluate(mech.functions["constraint"], q_r, x_r, d)
        assert np.all(np.abs(h_r[:, :, 0]).max(axis=1) <= 1e-10 * scale), mode
        x_f, q_f, _ = (v[:, :, 0] for v in evaluate(mech.functions["forward_from_root"], roots[:, None],
                                                    q_a[rows], d))
        (h, _, _) = evaluate(mech.functions["constraint"], q_f, x_f, d)
        conditioning = np.abs(eq8_determinant(roots, q_a[rows], design)) / scale**2
        allowance = allowed(conditioning)
        assert np.all(np.abs(h[:, :, 0]).max(axis=1) <= 1e-10 * scale * allowance), mode

        distance = np.linalg.norm(fs.pose - x[:, None, :], axis=2)
        nearest = np.nanargmin(distance, axis=1)
        at = (np.arange(len(x)), nearest)
        cond_at = np.abs(eq8_determinant(fs.l_c[at], q_a, design)) / scale**2
        assert np.all(distance[at] <= 1e-9 * scale * allowed(cond_at)), mode
        np.testing.assert_allclose(fs.l_c[at], q[:, 5], atol=1e-9 * scale)
        assert np.all(np.abs(fs.theta[at] - q[:, 2]) <= 1e-9 * allowed(cond_at)), mode  # eq. 8 against eq. 1
        assert np.all(fs.modes[at] == mode)


def test_each_root_in_the_domain_gives_back_the_actuator_angles_in_its_mode(mech, case):
    """Roots with l_c > 0 and |theta| < pi/2 (y_c > 0, section 4); the others place C below the base."""
    design, poses = case
    scale = design["l_a"] + design["l_b"]
    for mode, x in poses.items():
        q_a = mech.inverse_kinematics(x, design, mode=mode)
        fs = mech.forward_solutions(q_a, design)
        checked = np.zeros(len(x), dtype=int)
        for root_mode in mech.modes:
            rows, cols = np.nonzero((fs.modes == root_mode) & (fs.l_c > 0) & (np.abs(fs.theta) < math.pi / 2))
            if not len(rows):
                continue
            back = mech.inverse_kinematics(fs.pose[rows, cols], design, mode=root_mode)
            cond = np.abs(eq8_determinant(fs.l_c[rows, cols], q_a[rows], design)) / scale**2
            error = np.abs(wrapped(back - q_a[rows])).max(axis=1)
            assert np.all(error <= 1e-8 * allowed(cond)), (mode, root_mode)
            np.add.at(checked, rows, 1)
        assert np.all(checked >= 1)  # the IK's own pose
        assert checked.sum() >= 1.5 * len(x)  # and other assemblies


def test_forward_kinematics_keeps_a_real_assembly_whose_eq8_pair_is_nearly_singular(mech):
    """Roots 2 and 3 have nearly the same l_c (0.78915, 0.78918) and different theta; root 3 is an out_in
    assembly above the base, away from singularities, that the IK of its pose confirms. theta from eq. 8's
    linear pair loses digits there (B2 C1 - B1 C2 is small); the Newton steps of forward_refined restore
    them."""
    design = mech.design({"R": 1.0, "r": 1.41, "l_a": 1.2, "l_b": 1.41})
    q_a = mech.inverse_kinematics([0.344, 0.686], design, mode="out_in")
    fs = mech.forward_solutions(q_a, design)
    assert fs.count == 4
    assert fs.modes[3] == "out_in"
    assert fs.pose[3, 1] > 0
    assert np.abs(mech.inverse_kinematics(fs.pose[3], design, mode="out_in") - q_a).max() < 1e-12
    assert np.all(np.isfinite(mech.forward_kinematics(q_a, design, assembly="root3")))


# --- First order --------------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1])
def test_jacobian_against_central_differences_and_the_papers_jq_inverse_jx(mech, seed):
    rng = np.random.default_rng(20 + seed)
    design = mech.design() if seed == 0 else random_design(mech, rng, names=LENGTHS)
    d, scale = design.vector(), design["l_a"] + design["l_b"]

    def regular(x, mode):
        s = mech.singularity_measures(x, design, mode=mode)
        return (np.abs(s["det_J_q"]) > 0.05 * (design["l_a"] * design["l_b"]) ** 2) & (
            np.abs(s["det_J_x"]) > 0.05 * scale**2)

    step = 1e-6 * scale
    for mode in mech.modes:
        x = reachable_poses(mech, design, mode, rng, count=20, where=lambda x, mode=mode: regular(x, mode))
        J = mech.jacobian(x, design, mode=mode)
        fd = np.empty_like(J)
        for k in range(2):
            e = np.zeros(2)
            e[k] = step
            change = mech.inverse_kinematics(x + e, design, mode=mode) - mech.inverse_kinematics(x - e, design,
                                                                                                  mode=mode)
            fd[:, :, k] = wrapped(change) / (2 * step)
        size = np.abs(J).max(axis=(1, 2), keepdims=True)
        assert np.all(np.abs(fd - J) <= 1e-6 * size), mode
        q = mech.inverse_kinematics(x, design, mode=mode, passive=True)
        J_q, J_x, *_ = evaluate(mech.functions["paper_first_order"], q, x, d)
        assert np.all(np.abs(np.linalg.solve(J_q, J_x) - J) <= 1e-10 * size), mode


# --- Workspace boundaries (eqs. 12-15) ------------------------------------------------------------------


@pytest.mark.parametrize("theta", [-1.2, -0.5, 0.0, 0.3, 1.0])
def test_outer_boundary_is_where_the_reach_ends_and_the_printed_one_is_half_of_it(mech, theta):
    design = mech.design(FAMILY)
    bound = mech.workspace_boundary(theta, design)
    l_CM = float(bound["l_CM"])
    for mode in mech.modes:  # the reach (eq. 6's discriminants) does not depend on the mode
        found = bisect(lambda L, mode=mode: bool(mech.reachable(ray(theta, L), design, mode=mode)[0]),
                       0.9 * l_CM, 1.1 * l_CM)
        assert found == pytest.approx(l_CM, abs=1e-9)
    assert float(bound["l_CM_printed"]) == pytest.approx(l_CM / 2, rel=1e-14)  # the eq. 12 deviation
    assert mech.reachable(ray(theta, 0.75 * l_CM), design, mode="out_out").all()  # beyond the printed bound


@pytest.mark.parametrize("theta", [-0.3, -0.1, 0.05, 0.2])
def test_inner_boundary_is_where_the_platform_joint_of_one_leg_reaches_its_range(mech, theta):
    """On Fig. 1's mode the angle b_i = d_i b_i C of the leg on the side the platform tilts to reaches pi
    at l_cm (its sine, the margin, crosses 0; leg 2 for theta > 0, leg 1 for theta < 0)."""
    design = mech.design(INNER)
    bound = mech.workspace_boundary(theta, design)
    assert float(bound["eq15"]) > 0
    l_cm = float(bound["l_cm"])
    margin = "angle_b2" if theta > 0 else "angle_b1"

    def inside(L):
        return bool(mech.region_margins(ray(theta, L), design, mode="out_out")[margin][0] >= 0)

    assert bisect(inside, l_cm - 0.05, l_cm + 0.05) == pytest.approx(l_cm, abs=1e-8)
    assert float(bound["l_cm_printed"]) == pytest.approx(l_cm / 2, rel=1e-14)


def test_inner_boundary_of_the_family_is_the_x_axis(mech):
    """With l_b - l_a = R - r the radicand of eq. 15 vanishes at theta = 0 and is negative elsewhere:
    the region reaches down to the x axis, but for a clearance of 1e-3 (l_a + l_b) around the origin."""
    design = mech.design(FAMILY)
    theta = np.array([-1.0, -0.3, -0.01, 0.01, 0.3, 1.0])
    bound = mech.workspace_boundary(theta, design)
    assert np.all(bound["eq15"] < 0)
    assert np.all(np.isnan(bound["l_cm"]))
    assert abs(float(mech.workspace_boundary(0.0, design)["eq15"])) < 1e-12
    lower, _ = evaluate(mech.functions["workspace_curves"], theta[:, None], design.vector())
    np.testing.assert_allclose(lower[:, 0, 0], 1e-3 * (design["l_a"] + design["l_b"]), rtol=1e-15)


# --- Singularities --------------------------------------------------------------------------------------


@pytest.mark.parametrize(("theta", "stretched"), [(0.3, 0), (-0.5, 1)])
def test_type1_singularity_at_the_outer_boundary_with_a_stretched_leg(mech, theta, stretched):
    design = mech.design(FAMILY)
    d, reach = design.vector(), design["l_a"] + design["l_b"]
    l_CM = float(mech.workspace_boundary(theta, design)["l_CM"])
    eps = np.array([1e-2, 1e-4, 1e-6, 1e-8])
    x = ray(theta, l_CM * (1 - eps))
    s = mech.singularity_measures(x, design, mode="out_out")
    ratio = np.abs(s["det_J_q"]) / np.sqrt(eps)  # det J_q ~ sqrt(l_CM - l_c)
    np.testing.assert_allclose(ratio[1:], ratio[-1], rtol=1e-2)
    assert abs(s["det_J_q"][-1]) < 1e-3 * (design["l_a"] * design["l_b"]) ** 2
    assert np.all(np.abs(s["det_J_x"]) > 0.2 * reach**2)  # not a type-2 singularity
    q = mech.inverse_kinematics(x, design, mode="out_out", passive=True)
    B1, _, b1, _, b2, _, B2 = (v[:, :, 0] for v in evaluate(mech.functions["joint_positions"], q, x, d))
    spans = [np.linalg.norm(b1 - B1, axis=1), np.linalg.norm(b2 - B2, axis=1)]
    assert spans[stretched][-1] == pytest.approx(reach, rel=1e-7)
    assert np.all(spans[1 - stretched] < 0.9 * reach)


def test_type2_singularity_inside_the_region_of_a_short_upper_link(mech):
    """On Fig. 1's mode of r = 1.2, l_b = 0.6, det J_x changes sign along the ray theta = -1.1 inside the
    region: there J_f grows as 1/distance and 1/kappa falls as the distance, while det J_q stays near its
    largest value (l_a l_b)^2."""
    design = chart_design(mech, TYPE2)
    d = mech.design_dict(design)
    theta = -1.1

    def positive(L):
        return bool(mech.singularity_measures(ray(theta, L), design, mode="out_out")["det_J_x"][0] > 0)

    l_star = bisect(positive, 0.10, 0.16)
    lower, upper = (float(v.ravel()[0]) for v in evaluate(mech.functions["workspace_curves"], [theta], design))
    assert lower < l_star < upper
    delta = np.array([1e-3, 1e-5, 1e-7])
    for side in (-1, 1):
        x = ray(theta, l_star * (1 + side * delta))
        norm_Jf = np.linalg.norm(mech.forward_jacobian(x, design, mode="out_out"), axis=(1, 2))
        np.testing.assert_allclose(norm_Jf * delta, norm_Jf[-1] * delta[-1], rtol=1e-2)
        inverse_condition = mech.local_index("inverse_condition_f", x, design, mode="out_out")
        np.testing.assert_allclose(inverse_condition / delta, inverse_condition[-1] / delta[-1], rtol=1e-2)
        assert inverse_condition[-1] < 1e-7
        s = mech.singularity_measures(x, design, mode="out_out")
        assert np.all(np.abs(s["det_J_q"]) > 0.5 * (d["l_a"] * d["l_b"]) ** 2)
        assert np.all(np.sign(s["det_J_x"]) == -side)
        generic = mech.singularity(x, design, mode="out_out")["det_type2"]
        np.testing.assert_allclose(generic / delta, generic[-1] / delta[-1], rtol=1e-2)  # the loop closure's too
        margins = mech.region_margins(x, design, mode="out_out")
        assert np.all(margins["angle_b1"] > 0.02)
        assert np.all(margins["angle_b2"] > 0.02)


def test_architecture_singularity_of_the_family_at_the_origin(mech):
    """With l_b - l_a = R - r both legs fold (|b_i - B_i| = |l_a - l_b|) as C reaches O: det J_q falls as
    y_c^2 and det J_x as y_c, on every working mode."""
    design = mech.design(FAMILY)
    y = np.array([1e-1, 1e-2, 1e-3, 1e-4, 1e-5])
    x = np.column_stack([0 * y, y])
    for mode in mech.modes:
        assert mech.reachable(x, design, mode=mode).all()
        s = mech.singularity_measures(x, design, mode=mode)
        np.testing.assert_allclose(s["det_J_q"][1:] / y[1:] ** 2, s["det_J_q"][-1] / y[-1] ** 2, rtol=2e-2)
        np.testing.assert_allclose(s["det_J_x"][1:] / y[1:], s["det_J_x"][-1] / y[-1], rtol=2e-2)
        assert abs(s["det_J_q"][-1]) < 1e-7 * abs(s["det_J_q"][0])
        assert abs(s["det_J_x"][-1]) < 1e-3 * abs(s["det_J_x"][0])


# --- The composed index (eq. 31) and the global indices --------------------------------------------------


def test_composed_index_gradient_against_central_differences(mech, monkeypatch):
    """The problem's objective equals eq. 31 composed from the etas; its chart gradient from the exact
    gradients of global_index agrees with central differences of the problem's objective."""
    from pkm.synthesis.model import ProblemModel

    reading = nam2006.SUPPORTED
    bounds = nam2006.extremes(reading, 7, 4)
    monkeypatch.setattr(nam2006, "extremes", lambda *_args, **_kwargs: bounds)
    model = ProblemModel(pkm.registry.problem("passive_leg.max_composed"))
    objective = model.function(nam2006.RESOLUTION)
    design = chart_design(mech, ADMISSIBLE)
    assert mech.design_dict(design)["l_a"] == pytest.approx(1.9)

    values, grads = [], []
    for name in reading.indices:
        value, grad = mech.global_index(name, design, region=reading.region, resolution=nam2006.RESOLUTION,
                                        gradient=True)
        values.append(float(value))
        grads.append(np.array([grad[p] for p in mech.parameter_names()]))
    np.testing.assert_allclose(values, nam2006.etas(mech, design[None, :])[0], rtol=1e-12)
    eta = float(nam2006.composed(np.array(values), bounds, reading.normalise))
    assert float(objective(np.array(ADMISSIBLE))[0]) == pytest.approx(eta, rel=1e-12)

    lo, hi = np.array(bounds).T
    hats = (np.array(values) - lo) / (hi - lo)
    # (r, l_b) -> (R, r, l_a, l_b, theta_max) with l_a = l_b + r - R: d/dr = (0, 1, 1, 0, 0), d/dl_b = (0, 0, 1, 1, 0)
    for k, direction in enumerate((np.array([0, 1, 1, 0, 0.0]), np.array([0, 0, 1, 1, 0.0]))):
        d_hats = np.array([g @ direction for g in grads]) / (hi - lo)
        exact = sum(d_hats[j] * np.prod(np.delete(hats, j)) for j in range(3))
        step = np.zeros(2)
        step[k] = 1e-4
        central = (float(objective(np.array(ADMISSIBLE) + step)[0])
                   - float(objective(np.array(ADMISSIBLE) - step)[0])) / 2e-4
        assert abs(exact) > 0.05
        assert central == pytest.approx(exact, rel=1e-5)


@pytest.mark.parametrize("name", INDICES)
def test_global_index_converges_with_resolution_and_reports_the_half_resolution_change(mech, name):
    """The rule splits at the kink of l_CM (theta = 0) and grades l_c towards the stretched legs, so the
    means converge fast: gci and manipulability to 1e-6 at resolution 8, space_utilization is exact (the
    integrand is smooth). |det J| (the literal eta_2) is unbounded where the folded-leg locus touches the
    origin and converges slowly; each value reports the change from half its resolution."""
    design = chart_design(mech, ADMISSIBLE)
    values = [mech.global_index(name, design, region="workspace", resolution=n) for n in (4, 8, 16, 32)]
    changes = np.abs(np.diff([float(v) for v in values]))
    tolerance = {"space_utilization": 1e-12, "jacobian_determinant": 1e-4}.get(name, 1e-6)
    assert changes[1:].max() < tolerance * abs(float(values[-1]))
    if name in ("gci", "manipulability"):
        assert changes[2] < changes[1] < changes[0] < 1e-4 * abs(float(values[-1]))
    for value, change in zip(values[1:], changes, strict=True):
        assert value.accuracy == pytest.approx(change, rel=1e-12, abs=1e-15)
        assert value.region == "workspace"
    assert all(np.isfinite(float(v)) and float(v) > 0 for v in values)


def test_space_utilization_converges_to_the_area_between_the_boundaries_per_the_footprint(mech):
    """Area = integral of (l_CM^2 - lower^2) / 2 dtheta with l_CM from eq. 12 written out here, split at the
    kink theta = 0; S of eq. 30. The region's rule is split there too: it is exact to round-off at every
    resolution."""
    design = chart_design(mech, ADMISSIBLE)
    d = mech.design_dict(design)
    R, r, reach = d["R"], d["r"], d["l_a"] + d["l_b"]
    hi = d["theta_max"]
    lower = 1e-3 * reach  # the family's inner boundary is the x axis; the region keeps clear of the origin
    nodes, weights = np.polynomial.legendre.leggauss(200)
    area = 0.0
    for a, b in ((-hi, 0.0), (0.0, hi)):
        t = (a + b) / 2 + (b - a) / 2 * nodes
        l_CM = -R * np.abs(np.sin(t)) + np.sqrt(reach**2 - (R * np.cos(t) - r) ** 2)
        area += (b - a) / 2 * np.sum(weights * (l_CM**2 - lower**2) / 2)
    footprint = (r + R) * math.sqrt(reach**2 - (R - r) ** 2)
    expected = area / footprint
    errors = [abs(float(mech.global_index("space_utilization", design, region="workspace", resolution=n))
                  - expected) for n in (4, 8, 16, 32)]
    assert max(errors) < 1e-12 * expected


@pytest.mark.parametrize(("chart", "margin"), [(FOLDED, "angle_b1"), (TYPE2, "type2")])
def test_indices_are_undefined_over_a_region_holding_a_singularity(mech, chart, margin):
    design = chart_design(mech, chart)
    region = mech.region("workspace")
    points, _ = region.quadrature(mech.functions, design, 4, "mean")
    assert np.nanmin(mech.region_margins(points, design, mode="out_out")[margin]) < 0
    for name in INDICES:
        for resolution in (4, 8):
            assert np.isnan(mech.global_index(name, design, region="workspace", resolution=resolution)), name
    assert np.all(np.isnan(nam2006.etas(mech, design[None, :], resolution=4)))


def test_indices_are_finite_over_an_admissible_region(mech):
    design = chart_design(mech, ADMISSIBLE)
    region = mech.region("workspace")
    points, _ = region.quadrature(mech.functions, design, 8, "mean")
    margins = mech.region_margins(points, design, mode="out_out")
    assert all(np.all(v > 0) for v in margins.values())
    for name in INDICES:
        value = mech.global_index(name, design, region="workspace", resolution=8)
        assert 0 < value < 10, name
    gci = mech.global_index("gci", design, region="workspace", resolution=8)
    assert gci < 1  # a mean of 1/kappa


# --- Bad input ------------------------------------------------------------------------------------------


def test_bad_input(mech):
    with pytest.raises(DesignError, match="l_a"):
        mech.design({**FAMILY, "l_a": 0.0})
    with pytest.raises(DesignError, match=r"eq\. 14"):
        mech.design({"R": 1.0, "r": 3.0, "l_a": 1.0, "l_b": 1.0})
    space = mech.design_spaces["nam2006"]
    with pytest.raises(DesignError, match=r"0\.5 <= r <= 2"):
        space.check([2.5, 1.0])
    with pytest.raises(DesignError, match=r"0\.5 <= r <= 2"):
        space.designs(mech.parameters, [2.5, 1.0], check=True)
    with pytest.raises(DesignError, match="l_a = l_b"):
        space.check([0.5, 0.5])
    with pytest.raises(PoseError, match="theta"):
        mech.workspace_boundary(math.pi / 2, FAMILY)
    with pytest.raises(PoseError, match="theta"):
        mech.workspace_boundary([0.1, -2.0], FAMILY)
    with pytest.raises(PoseError, match="out of reach"):
        mech.inverse_kinematics([0.1, -0.5], FAMILY, strict=True)
    assert not mech.reachable([0.1, -0.5], FAMILY)
    with pytest.raises(PoseError, match="shape"):
        mech.inverse_kinematics([0.1, 0.5, 0.0], FAMILY)
    with pytest.raises(PoseError, match="actuated joints"):
        mech.forward_solutions(np.zeros((3, 3)), FAMILY)
    with pytest.raises(PoseError, match="shape"):
        mech.singularity_measures(np.zeros((2, 3)), FAMILY)
    with pytest.raises(DesignError, match="design vector"):
        mech.inverse_kinematics([0.1, 0.5], [1.0, 1.2, 1.4])
    with pytest.raises(PkmError, match="reading"):
        nam2006.reading("printed")


# --- The paper's equations as printed and as derived ----------------------------------------------------


@pytest.mark.parametrize("mode", ["out_out", "out_in", "in_out", "in_in"])
def test_printed_equations_against_the_derived_ones(mech, mode):
    """eq. 6 with gamma_i - alpha_i in the denominator gives the IK's phi, as printed (r - alpha_i) it
    does not; eq. 11 as printed (no factor 4) differs from the derived one by 3 (B2 C1 - B1 C2)^2 and is
    nonzero at the IK's joints; eq. 24 as printed (2 r) misses half of the term 4 r n1 n2 of -2 l_c det J_x."""
    design = mech.design(FAMILY)
    d, scale = design.vector(), design["l_a"] + design["l_b"]
    rng = np.random.default_rng(30)
    x = reachable_poses(mech, design, mode, rng, count=20)
    q = mech.inverse_kinematics(x, design, mode=mode, passive=True)

    phi, phi_printed = evaluate(mech.functions["paper_inverse"], x, np.array(mech.working_mode(mode).signs), d)
    assert np.all(np.abs(wrapped(phi[:, :, 0] - q[:, :2])) < 1e-12)
    assert np.all(np.abs(wrapped(phi_printed[:, :, 0] - q[:, :2])).max(axis=1) > 1e-3)

    eq8, eq11, eq11_printed, eq9, eq9_printed = (v[:, :, 0] for v in evaluate(mech.functions["paper_forward"], q, d))
    assert np.all(np.abs(eq8) < 1e-12 * scale**2)
    assert np.all(np.abs(eq11) < 1e-13 * scale**8)
    det = eq8_determinant(q[:, 5], q[:, :2], design)
    np.testing.assert_allclose(eq11_printed - eq11, 3 * det[:, None] ** 2, rtol=1e-9, atol=1e-13 * scale**8)
    assert np.median(np.abs(eq11_printed)) > 1e-4 * scale**8
    assert np.all(np.abs(eq9) < 1e-12 * scale**2)
    assert np.median(np.abs(eq9_printed)) > 1e-2 * scale**2

    _, J_x, det_J_x, eq24, eq25 = evaluate(mech.functions["paper_first_order"], q, x, d)
    l_c, (U, n1, n2) = q[:, 5], eq25[:, :, 0].T
    np.testing.assert_allclose(det_J_x[:, 0, 0], -2 * l_c * np.linalg.det(J_x), rtol=1e-12, atol=1e-12 * scale**3)
    np.testing.assert_allclose(det_J_x[:, 0, 0], -2 * l_c * U + 4 * design["r"] * n1 * n2, atol=1e-12 * scale**3)
    np.testing.assert_allclose(eq24[:, 0, 0] - det_J_x[:, 0, 0], -2 * design["r"] * n1 * n2, atol=1e-12 * scale**3)
    assert np.median(np.abs(eq24[:, 0, 0] - det_J_x[:, 0, 0])) > 1e-3 * scale**3


@pytest.mark.parametrize("chart", [(1.1, 0.9), (1.15, 0.85), (1.55, 0.7), (1.8, 0.65)])
def test_a_design_whose_joint_limit_is_crossed_between_nodes_is_excluded_at_every_resolution(mech, chart):
    """These designs leave the joint range of angle b_i and meet det J_x = 0 in a corner of the region
    (|theta| near theta_max, l_c small) that the index's own nodes miss at low resolution; the guard's
    fixed rule with the region's rim sees it, whatever the index's resolution, and so does the check by
    sampling."""
    design = chart_design(mech, chart)
    for resolution in (2, 4, 8):
        assert np.isnan(mech.global_index("manipulability", design, region="workspace", resolution=resolution))
    spec = pkm.registry.global_index("manipulability")
    branch = mech.working_mode("out_out")
    assert np.isnan(sampled_check(mech, spec, mech.region("workspace"), design, branch=branch, resolution=40))
    admissible = chart_design(mech, ADMISSIBLE)
    assert np.isfinite(sampled_check(mech, spec, mech.region("workspace"), admissible, branch=branch,
                                     resolution=40))


def test_the_workspace_region_is_defined_on_fig1s_mode_only(mech):
    with pytest.raises(PkmError, match="out_out only"):
        mech.global_index("gci", region="workspace", mode="in_in")


def test_space_utilization_is_the_region_measure_per_the_footprint(mech):
    design = chart_design(mech, ADMISSIBLE)
    d = mech.design_dict(design)
    area = mech.global_index("region_measure", design, region="workspace")
    footprint = (d["r"] + d["R"]) * math.sqrt((d["l_a"] + d["l_b"]) ** 2 - (d["R"] - d["r"]) ** 2)
    assert float(mech.global_index("space_utilization", design, region="workspace")) == pytest.approx(
        float(area) / footprint, rel=1e-14)


@pytest.mark.parametrize("size", [1e-3, 1e3])
def test_forward_solutions_do_not_depend_on_the_scale_of_the_design(mech, size):
    """The near-double root of the test above, the design scaled: the same roots, scaled, every one
    closing its loops to round-off."""
    base = {"R": 1.0, "r": 1.41, "l_a": 1.2, "l_b": 1.41}
    unit = mech.forward_solutions(mech.inverse_kinematics([0.344, 0.686], base, mode="out_in"), base)
    scaled = {k: v * size for k, v in base.items()}
    q_a = mech.inverse_kinematics(np.array([0.344, 0.686]) * size, scaled, mode="out_in")
    fs = mech.forward_solutions(q_a, scaled)
    assert fs.count == unit.count == 4
    np.testing.assert_allclose(fs.l_c / size, unit.l_c, rtol=1e-9)
    assert np.nanmax(fs.residual) <= 1e-13 * (scaled["l_a"] + scaled["l_b"]) ** 2


def test_the_guards_rule_admits_what_a_four_times_denser_rule_admits(mech, monkeypatch):
    """Over a chart grid of the design space, the guard's fixed rule (interior, centre and rim at
    GUARD_RESOLUTION) and the same rule at four times the resolution accept the same designs."""
    u = np.linspace(0.5, 2.0, 11)
    U, V = np.meshgrid(u, u, indexing="ij")
    designs = nam2006.chart_designs(mech, U.ravel(), V.ravel())
    designs = designs[designs[:, 2] > 0]
    region, branch = mech.region("workspace"), mech.working_mode("out_out")
    coarse = quadrature.admissible(mech, region, designs, branch=branch)
    monkeypatch.setattr(quadrature, "GUARD_RESOLUTION", 4 * quadrature.GUARD_RESOLUTION)
    dense = quadrature.admissible(mech, region, designs, branch=branch)
    np.testing.assert_array_equal(coarse, dense)
    assert 0.3 < coarse.mean() < 0.9
