"""Machines as data (issue 24, first part): the 3-RRR, the Delta and the 6-UPS Stewart-Gough platform from
their descriptions agree with independent numpy models (tests/oracles.py, themselves checked against
robsynth); forward kinematics by continuation returns the pose; bad descriptions name the field."""

from __future__ import annotations

import copy
import re
import tomllib

import numpy as np
import oracles
import pytest
from helpers import FIVE_BAR_OF_RR_LEGS as FIVE_BAR
from helpers import PRR3, RPR3, assert_five_bar_gci, assert_five_bar_torques, assert_forward_kinematics_returns_the_pose

import pkm
from pkm.errors import SingularityWarning
from pkm.models.described import DESCRIPTIONS
from pkm.spec.schema import DescriptionError, describe

N = 200


@pytest.fixture(scope="module")
def machines():
    return {name: pkm.load(str(path)) for name, path in DESCRIPTIONS.items()}


def _within(mech, rng, lower, upper, mode):
    x = rng.uniform(lower, upper, size=(4 * N, len(lower)))
    return x[mech.reachable(x, mode=mode)][:N]


def test_the_3rrr_is_the_numpy_model_in_every_mode(machines):
    m, rng = machines["rrr3"], np.random.default_rng(1)
    design = dict(m.design())
    for mode in m.working_modes:
        x = _within(m, rng, [-0.2, -0.2, -0.5], [0.2, 0.2, 0.5], mode.name)
        assert len(x) > N // 2
        signs = list(mode.signs)
        np.testing.assert_allclose(np.angle(np.exp(1j * (m.inverse_kinematics(x, mode=mode.name)
                                                         - oracles.rrr3_ik(x, design, signs)))), 0, atol=1e-12)
        np.testing.assert_allclose(m.jacobian(x, mode=mode.name), oracles.rrr3_jacobian(x, design, signs),
                                   atol=1e-10)


def test_the_delta_is_the_numpy_model_elbow_out(machines):
    """The oracle's branch +1 (elbow out) is the description's sign -1, its mode elbow_out."""
    m, rng = machines["delta"], np.random.default_rng(2)
    design = dict(m.design())
    x = _within(m, rng, [-0.2, -0.2, -0.7], [0.2, 0.2, -0.3], "elbow_out")
    assert len(x) > N // 2
    np.testing.assert_allclose(m.inverse_kinematics(x), oracles.delta_ik(x, design, 1), atol=1e-12)
    np.testing.assert_allclose(m.jacobian(x), oracles.delta_jacobian(x, design, 1), atol=1e-10)


def test_the_stewart_platform_is_the_numpy_model(machines):
    m, rng = machines["stewart"], np.random.default_rng(3)
    design = dict(m.design())
    x = _within(m, rng, [-0.1, -0.1, 0.8, -0.2, -0.2, -0.2], [0.1, 0.1, 1.2, 0.2, 0.2, 0.2], m.modes[0])
    assert len(x) > N // 2
    np.testing.assert_allclose(m.inverse_kinematics(x), oracles.sgp_ik(x, design), atol=1e-12)
    np.testing.assert_allclose(m.jacobian(x), oracles.sgp_jacobian(x, design), atol=1e-10)


@pytest.mark.parametrize(("name", "lower", "upper"), [
    ("rrr3", [-0.1, -0.1, -0.2], [0.1, 0.1, 0.2]),
    ("delta", [-0.1, -0.1, -0.6], [0.1, 0.1, -0.35]),
    ("stewart", [-0.05, -0.05, 0.9, -0.1, -0.1, -0.1], [0.05, 0.05, 1.1, 0.1, 0.1, 0.1]),
])
def test_forward_kinematics_returns_the_pose_about_home_in_the_assembly_of_its_signature(machines, name, lower,
                                                                                      upper):
    """Each configuration's signature (the elbow sides, the sign of the type-II determinant) names the
    assembly mode whose solutions hold it."""
    m, rng = machines[name], np.random.default_rng(4)
    assert_forward_kinematics_returns_the_pose(m, _within(m, rng, lower, upper, m.modes[0])[:40])


def _raw(name: str) -> dict:
    return tomllib.loads(DESCRIPTIONS[name].read_text())


def _broken(name: str, change) -> dict:
    raw = copy.deepcopy(_raw(name))
    change(raw)
    return raw


@pytest.mark.parametrize(("change", "field"), [
    (lambda r: r["legs"].update(kind="RPRX"), "legs.kind"),
    (lambda r: r["parameters"][0].pop("lower"), "parameters[0].lower"),
    (lambda r: r["legs"].update(count=2), "legs"),
    (lambda r: r["legs"].update(proximal="l9"), "legs.proximal"),
    (lambda r: r.update(colour="red"), "colour"),
    (lambda r: r["parameters"][1].update(name="R_b"), "parameters[1].name"),
    (lambda r: r["legs"].update(base=[["0", "0"]]), "legs.base"),
    (lambda r: r.update(frame="spatial"), "legs.kind"),
    (lambda r: r["legs"].update(axis=[1, 0]), "legs.axis"),
    (lambda r: r["legs"].pop("distal"), "legs.distal"),
    (lambda r: r["legs"]["base"].update(radius="R_b"), "legs.base.radius"),
])
def test_a_bad_description_names_its_field(change, field):
    with pytest.raises(DescriptionError, match=re.escape(f"description field {field} violates")):
        describe(_broken("rrr3", change))


def test_a_home_pose_that_does_not_assemble_is_refused():
    raw = _broken("rrr3", lambda r: r.update(home=[5, 5, 0]))
    with pytest.raises(DescriptionError, match=r"home pose .* does not assemble .* leg 1 reach outer = -"):
        pkm.load(raw)


PRR2 = {
    "name": "prr2", "doc": "two sliders on the x axis, a link from each to a point", "frame": "planar_point",
    "home": [0, 0.6],
    "parameters": [
        {"name": "a", "default": 0.5, "lower": 0.0, "upper": 2, "unit": "m", "doc": "half the slides' distance"},
        {"name": "l", "default": 1.0, "lower": 0.1, "upper": 5, "unit": "m", "doc": "links"},
    ],
    "legs": {"kind": "PRR", "count": 2, "base": [["-a", 0], ["a", 0]], "platform": [[0, 0], [0, 0]], "distal": "l",
             "axis": [1, 0]},
}


def test_a_home_pose_beyond_a_legs_stroke_is_refused_naming_the_leg_its_joint_its_range_and_the_mode():
    """Leg 2's slider reaches the home pose at 0.3 m or -1.3 m from its origin, both outside its stroke."""
    legs = [{**PRR2["legs"], "count": 1, "base": [[end, 0]], "platform": [[0, 0]], "range": stroke}
            for end, stroke in (("-a", [-1, 2]), ("a", [0.5, 1]))]
    with pytest.raises(DescriptionError) as refused:
        pkm.load({**PRR2, "name": "prr2_short_stroke", "legs": legs})
    message = str(refused.value)
    assert "in its first working mode ahead_ahead" in message
    assert "leg 2's actuated joint q2 = 0.3 m lies outside its range [0.5, 1] m" in message
    assert "leg 1" not in message


def test_a_2prrs_first_working_mode_is_not_the_one_with_both_sliders_at_one_point():
    """Both sliders ahead of (or behind) the point on one line meet there: the links coincide and the platform
    turns about them with the sliders held (type II). The modes in which the home pose is regular come first;
    a description that names its modes keeps their order."""
    home = PRR2["home"]
    with pytest.warns(SingularityWarning, match="ahead_ahead"):
        m = pkm.load(PRR2)
    assert m.modes == ("ahead_behind", "behind_ahead", "ahead_ahead", "behind_behind")
    assert m.singular_types(home) == [[]]
    sliders = m.inverse_kinematics(home) + np.array([-0.5, 0.5])
    np.testing.assert_allclose(sliders, [0.8, -0.8], atol=1e-12)
    for mode in ("ahead_ahead", "behind_behind"):
        assert m.singular_types(home, mode=mode) == [["type II"]]
        assert m.local_index("singularity_margin_type2", home, mode=mode) < 1e-12
    named = {**PRR2, "name": "prr2_named", "modes": {"both_ahead": [1, 1], "apart": [1, -1]}}
    with pytest.warns(SingularityWarning, match="both_ahead"):
        assert pkm.load(named).modes == ("both_ahead", "apart")


def test_the_five_bar_described_in_twenty_lines_is_the_hand_derived_one():
    """Every kinematic function of the hand-written module (IK per mode, J, J_f, Psi, both determinants)
    from the description, to 1e-12 at 1000 random poses per mode."""
    from pkm.batch import evaluate

    described, hand = pkm.load(FIVE_BAR), pkm.load("five_bar")
    rng = np.random.default_rng(5)
    design = hand.design()
    small = np.array([design[n] for n in ("r1", "r2", "r3")])
    for mode in hand.modes:
        signs = described.working_mode(mode).signs
        assert signs == hand.working_mode(mode).signs
        x = rng.uniform(-2.0, 2.0, size=(4000, 2))
        x = x[hand.reachable(x, design, mode=mode)][:1000]
        assert len(x) == 1000
        q = hand.inverse_kinematics(x, design, mode=mode, passive=True)
        np.testing.assert_allclose(described.inverse_kinematics(x, small, mode=mode, passive=True), q, atol=1e-12)
        mine = evaluate(described.functions["first_order"], q, x, small)
        theirs = evaluate(hand.functions["first_order"], q, x, design.vector())
        for name, a, b in zip(hand.functions["first_order"].name_out(), mine, theirs, strict=True):
            scale = np.maximum(1.0, np.abs(b).reshape(len(b), -1).max(axis=1))[:, None, None]
            np.testing.assert_allclose(a / scale, b / scale, atol=1e-12, err_msg=f"{mode}: {name}")


def test_the_five_bar_described_has_the_hand_derived_global_indices_and_synthesis_optimum():
    """Over the same disc (the hand model's MIW at the default design, fixed), the GCI and its design
    gradient agree to 1e-10, and the synthesis of the GCI over it in (r1, r2) reaches the same optimum."""
    from pkm.synthesis.designer import design_problem

    hand, described = pkm.load("five_bar"), pkm.load(FIVE_BAR)
    task, design = assert_five_bar_gci(described)
    variables = {"r1": (1.0, 1.4), "r2": (0.8, 1.2)}
    optima = [pkm.synthesize(design_problem(m, task=task, variables=variables, constraints=(), mode="out_out",
                                            fixed={"r3": design["r3"]}, baseline=("grid", 5), resolution=6),
                             progress=False, starts=2)
              for m in (described, hand)]
    assert abs(optima[0].verified_objective - optima[1].verified_objective) <= 1e-9
    for name in variables:
        assert abs(optima[0].variables[name] - optima[1].variables[name]) <= 1e-6


def _with_bodies(description: dict, values: dict) -> dict:
    """The five-bar's description with the hand-written model's links as bodies (the design's masses,
    centres and moments: Lara-Molina eqs. 13-19)."""
    m1, m2, c1, c2, g1, g2 = (values[n] for n in ("m1", "m2", "c1", "c2", "g1", "g2"))
    bodies = {"proximal": {"mass": m1, "centre": f"{c1!r} * r1", "inertia": f"{g1 * m1!r} * r1**2"},
              "distal": {"mass": m2, "centre": f"{c2!r} * r2", "inertia": f"{g2 * m2!r} * r2**2"}}
    return {**description, "name": "five_bar_with_bodies", "legs": {**description["legs"], "bodies": bodies}}


def test_the_five_bar_described_with_bodies_has_the_hand_derived_inertia_matrices():
    """M_t = P^T M P (M of the bodies' kinetic energy in all coordinates, P = [Psi; J_f]) composed at run time
    equals the hand-written Lagrange model's Psi^T M Psi, and M_w = J^T M_t J its, to 1e-12 at 1000 poses per
    mode; M_t is symmetric positive definite."""
    from pkm.batch import evaluate

    hand = pkm.load("five_bar")
    design = hand.design()
    described = pkm.load(_with_bodies(FIVE_BAR, dict(design)))
    small = np.array([design[n] for n in ("r1", "r2", "r3")])
    rng = np.random.default_rng(6)
    for mode in hand.modes:
        x = rng.uniform(-2.0, 2.0, size=(4000, 2))
        x = x[hand.reachable(x, design, mode=mode)][:1000]
        q = hand.inverse_kinematics(x, design, mode=mode, passive=True)
        mine = evaluate(described.functions["inertia"], q, x, small)
        theirs = evaluate(hand.functions["inertia"], q, x, design.vector())
        for k, name in enumerate(("M_t", "M_w")):
            scale = np.maximum(1.0, np.abs(theirs[k]).reshape(len(x), -1).max(axis=1))[:, None, None]
            np.testing.assert_allclose(mine[k] / scale, theirs[k] / scale, atol=1e-12, err_msg=f"{mode}: {name}")
        assert np.all(np.linalg.eigvalsh(mine[0]) > 0)
    assert "dynamic_dexterity" in described.local_indices()


def test_bodies_must_be_given_for_every_leg_and_name_known_fields():
    broken = _with_bodies(FIVE_BAR, dict(pkm.load("five_bar").design()))
    legs = broken["legs"]
    with pytest.raises(DescriptionError, match=re.escape("description field legs.bodies.elbow violates")):
        describe({**broken, "legs": {**legs, "bodies": {**legs["bodies"], "elbow": {"mass": 1}}}})
    with pytest.raises(DescriptionError, match=re.escape("description field legs.bodies.distal.mass violates")):
        describe({**broken, "legs": {**legs, "bodies": {**legs["bodies"], "distal": {"centre": 0.1}}}})


def test_the_stewart_platforms_legs_are_equal_at_home_and_its_indices_hold_for_6_x_6(machines):
    """At the home pose of the symmetric 6-UPS every leg has the length of one closed form; the indices
    whose formulas hold for any n are offered (the Frobenius condition number, the determinants), those in
    closed form up to 3 x 3 are not, and |det J_f| |det J| = 1."""
    m = machines["stewart"]
    d = dict(m.design())
    height = 1.0
    apart = -d["theta_b"] / 2 + (np.pi / 3 - d["theta_p"] / 2)
    expected = np.sqrt(height**2 + d["R_b"] ** 2 + d["r_p"] ** 2 - 2 * d["R_b"] * d["r_p"] * np.cos(apart))
    np.testing.assert_allclose(m.inverse_kinematics([0, 0, height, 0, 0, 0]), expected, rtol=1e-12)
    assert set(m.local_indices()) >= {"inverse_condition_f", "manipulability", "jacobian_determinant"}
    assert "velocity_max" not in m.local_indices()
    x = np.array([[0.0, 0.0, 1.0, 0.0, 0.0, 0.0], [0.05, -0.02, 1.05, 0.1, -0.05, 0.2]])
    product = m.local_index("manipulability", x) * m.local_index("jacobian_determinant", x)
    np.testing.assert_allclose(product, 1.0, rtol=1e-10)
    assert np.all((m.local_index("inverse_condition_f", x) > 0) & (m.local_index("inverse_condition_f", x) <= 1))


def test_the_five_bar_described_with_bodies_has_the_hand_derived_inverse_dynamics():
    """Lagrange's equations of the bodies in all coordinates, projected by virtual work (pkm.spec), against
    the hand-written chain model's torques on the actuated joints, to 1e-10 of the largest, in every mode."""
    hand = pkm.load("five_bar")
    design = hand.design()
    described = pkm.load(_with_bodies(FIVE_BAR, dict(design)))
    small = [design[n] for n in ("r1", "r2", "r3")]
    rng = np.random.default_rng(7)
    for mode in hand.modes:
        x = rng.uniform(-2.0, 2.0, size=(2000, 2))
        assert_five_bar_torques(described, small, x[hand.reachable(x, design, mode=mode)][:200], mode, rng)


def test_the_power_of_the_actuators_is_the_rate_of_the_energy_with_gravity():
    """tau . q_dot = d(T + V)/dt along a motion of the Delta with its bodies and gravity (central
    differences of the energy, relative 1e-6), and the symmetric pose below the base's centre needs equal
    torques to hold the weight."""
    raw = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    m = pkm.load({**raw, "name": "delta_with_gravity", "gravity": [0, 0, -9.81]})
    from pkm.batch import evaluate

    rng = np.random.default_rng(8)
    x = _within(m, rng, [-0.15, -0.15, -0.7], [0.15, 0.15, -0.4], "elbow_out")[:50]
    x_dot, x_ddot = rng.normal(size=(2, len(x), 3))
    power = np.sum(m.inverse_dynamics(x, x_dot, x_ddot) * np.einsum("nij,nj->ni", m.jacobian(x), x_dot), axis=1)

    def energy(pose, rate):
        q = m.inverse_kinematics(pose, passive=True)
        kinetic, potential = evaluate(m.functions["energy"], q, pose, rate, m.design().vector())
        return kinetic[:, 0, 0] + potential[:, 0, 0]

    h = 1e-5
    rate = (energy(x + h * x_dot + h**2 / 2 * x_ddot, x_dot + h * x_ddot)
            - energy(x - h * x_dot + h**2 / 2 * x_ddot, x_dot - h * x_ddot)) / (2 * h)
    np.testing.assert_allclose(power, rate, rtol=1e-6, atol=1e-9)
    held = m.inverse_dynamics([0.0, 0.0, -0.5], np.zeros(3), np.zeros(3))
    np.testing.assert_allclose(held, held[0], rtol=1e-12)
    assert held[0] != 0


def _attachments(design: dict, radius: str, x: np.ndarray) -> np.ndarray:
    """The platform's joints in the base frame (N, 3 legs, 2) for poses (N, 3) on a circle pattern."""
    angles = np.pi / 2 + 2 * np.pi * np.arange(3) / 3
    local = design[radius] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    c, s = np.cos(x[:, 2])[:, None], np.sin(x[:, 2])[:, None]
    return x[:, None, :2] + np.stack([c * local[:, 0] - s * local[:, 1], s * local[:, 0] + c * local[:, 1]], axis=2)


@pytest.mark.parametrize("description", [RPR3, PRR3], ids=["RPR", "PRR"])
def test_rpr_and_prr_legs_solve_their_closed_forms_and_their_forward_kinematics(description):
    """The 3-RPR's legs have the length |C - A|; a 3-PRR's sliders put each link's end at C; J equals central
    differences of the inverse kinematics; the forward kinematics returns every pose in some assembly."""
    m = pkm.load(description)
    d = dict(m.design())
    angles = np.pi / 2 + 2 * np.pi * np.arange(3) / 3
    base = d["R"] * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    rng = np.random.default_rng(9)
    box = m.workspace_box(m.design().vector())
    for mode in m.modes[:2]:
        x = rng.uniform(box[:, 0], box[:, 1], size=(20000, 3))
        x = x[m.reachable(x, mode=mode)][:100]
        assert len(x) == 100
        q = m.inverse_kinematics(x, mode=mode)
        joints = _attachments(d, "r", x)
        if description is RPR3:
            np.testing.assert_allclose(q, np.linalg.norm(joints - base, axis=2), atol=1e-12)
        else:
            ends = base + q[:, :, None] * np.array([-1.0, 0.0])
            np.testing.assert_allclose(np.linalg.norm(joints - ends, axis=2), d["l"], atol=1e-12)
        step, regular = 1e-6, x[m.local_index("inverse_condition_f", x, mode=mode) > 0.05]
        fd = np.stack([(m.inverse_kinematics(regular + step * e, mode=mode)
                        - m.inverse_kinematics(regular - step * e, mode=mode)) / (2 * step) for e in np.eye(3)], axis=2)
        J = m.jacobian(regular, mode=mode)
        assert np.all(np.abs(fd - J) <= 1e-6 * np.abs(J).max(axis=(1, 2), keepdims=True))
        errors = np.stack([np.linalg.norm(m.forward_kinematics(q, assembly=a) - x, axis=1) for a in m.assemblies])
        assert np.nanmin(np.where(np.isnan(errors), np.inf, errors), axis=0).max() < 1e-9


def test_the_3rpr_with_bodies_has_a_positive_definite_inertia_and_the_power_of_its_energy():
    m = pkm.load(RPR3)
    from pkm.batch import evaluate

    rng = np.random.default_rng(10)
    x = _within(m, rng, [-0.2, -0.2, -0.4], [0.2, 0.2, 0.4], "single")[:40]
    assert np.all(np.linalg.eigvalsh(m.inertia_matrix(x, space="actuated")) > 0)
    x_dot, x_ddot = rng.normal(size=(2, len(x), 3))
    power = np.sum(m.inverse_dynamics(x, x_dot, x_ddot) * np.einsum("nij,nj->ni", m.jacobian(x), x_dot), axis=1)

    def kinetic(pose, rate):
        q = m.inverse_kinematics(pose, passive=True)
        return evaluate(m.functions["energy"], q, pose, rate, m.design().vector())[0][:, 0, 0]

    h = 1e-5
    rate = (kinetic(x + h * x_dot + h**2 / 2 * x_ddot, x_dot + h * x_ddot)
            - kinetic(x - h * x_dot + h**2 / 2 * x_ddot, x_dot - h * x_ddot)) / (2 * h)
    np.testing.assert_allclose(power, rate, rtol=1e-6, atol=1e-9)


def test_a_condition_of_the_design_refuses_a_design_that_violates_it_naming_it():
    raw = _raw("rrr3")
    raw.update(name="rrr3_with_a_condition", conditions=[{"margin": "l1 + l2 - (R_b - r_p)",
                                                          "doc": "the legs reach the centre"}])
    m = pkm.load(raw)
    assert m.design({**m.design(), "l1": 0.3, "l2": 0.5})["l1"] == 0.3
    violated = "the legs reach the centre (l1 + l2 - (R_b - r_p) > 0)"
    with pytest.raises(pkm.errors.DesignError, match=re.escape(violated)):
        m.design({**m.design(), "l1": 0.2, "l2": 0.3})
    for bad, field in (([{"doc": "no margin"}], "conditions[0].margin"), ([{"margin": "l9"}], "conditions[0].margin"),
                       ([{"margin": "l1", "colour": "red"}], "conditions[0].colour")):
        with pytest.raises(DescriptionError, match=re.escape(f"description field {field} violates")):
            describe({**raw, "conditions": bad})


def test_a_seed_table_is_kept_beside_the_derived_module_and_read_back_by_a_later_process(monkeypatch):
    """The first forward kinematics at a design searches its seeds and keeps them in the cache; a later process (its
    tables and solutions in memory cleared) reads them back and finds the same assemblies without searching; a file
    that cannot be read is searched again and replaced; another design has a table of its own, and beyond
    SEEDS_STORED tables the oldest is removed."""
    from pkm import kinematics
    from pkm.spec import seeds

    m = pkm.load(_raw("rrr3") | {"name": "rrr3_kept_seeds"})
    store = m.forward.seeds.store
    for old in store.parent.glob(f"{store.name}.seeds.*.npz"):
        old.unlink()
    kinematics._SOLUTIONS.clear()
    seeds._SEED_TABLES.clear()
    q = m.inverse_kinematics(np.array([[0.05, -0.02, 0.1], [-0.1, 0.04, -0.2]]))
    first = m.forward_kinematics(q, assembly=m.assemblies[0])
    (kept,) = store.parent.glob(f"{store.name}.seeds.*.npz")
    search, searched = seeds.Seeds._configurations, []
    monkeypatch.setattr(seeds.Seeds, "_configurations", lambda self, *a: searched.append(1) or search(self, *a))
    for damage in (None, b"not a table"):
        if damage is not None:
            kept.write_bytes(damage)
        seeds._SEED_TABLES.clear()
        kinematics._SOLUTIONS.clear()
        np.testing.assert_array_equal(m.forward_kinematics(q, assembly=m.assemblies[0]), first)
    assert searched == [1]
    assert np.load(kept)["groups"] > 0
    m.forward_kinematics(q, {**m.design(), "l1": 0.62}, assembly=m.assemblies[0])
    assert len(list(store.parent.glob(f"{store.name}.seeds.*.npz"))) == 2
    monkeypatch.setattr(seeds, "SEEDS_STORED", 2)
    m.forward_kinematics(q, {**m.design(), "l1": 0.64}, assembly=m.assemblies[0])
    left = list(store.parent.glob(f"{store.name}.seeds.*.npz"))
    assert len(left) == 2
    assert kept not in left  # the oldest removed
