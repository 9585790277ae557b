"""Machines as data, legs as serial chains of joints (``kind = "chain"``), each solved twice: by the closed
form of the subproblem its joints match and by Newton continuation (``newton = true``). The five-bar, the
3-RRR and the Delta described joint by joint give, both ways, the hand-derived five-bar's and the kinds'
closed forms (inverse kinematics on every branch, J, the GCI and its design gradient); the continued
inverse kinematics compiles to the interpreter's values; forward kinematics returns the pose; bad chains
name their field."""

from __future__ import annotations

import copy
import os
import re
import shutil
import tomllib
import zlib

import numpy as np
import pytest
from helpers import (
    EXAMPLES,
    FIVE_BAR_OF_CHAINS,
    assert_five_bar_gci,
    assert_five_bar_torques,
    assert_forward_kinematics_returns_the_pose,
    delta_and_its_chains_with_bodies,
    delta_of_chains,
    five_bar_of_chains_with_bodies,
    rrr3_of_chains,
)

import pkm
from pkm import compiled
from pkm.batch import evaluate, interpreted
from pkm.models.described import DESCRIPTIONS
from pkm.spec.schema import DescriptionError, describe

SOLVERS = ("closed", "newton")


def _newton(raw: dict) -> dict:
    """The description with every chain leg solved by Newton continuation."""
    out = copy.deepcopy(raw)
    out["name"] += "_newton"
    for table in out["legs"] if isinstance(out["legs"], list) else [out["legs"]]:
        table["newton"] = True
    return out


@pytest.fixture(scope="module")
def machines():
    raws = {"five_bar": FIVE_BAR_OF_CHAINS, "delta": delta_of_chains(), "rrr3": rrr3_of_chains()}
    return {(name, solver): pkm.load(raw if solver == "closed" else _newton(raw))
            for name, raw in raws.items() for solver in SOLVERS}


def test_a_chain_of_a_known_subproblem_has_its_closed_form_and_newton_is_asked_for(machines):
    for (name, solver), m in machines.items():
        assert ("continuation_start" in m.functions) == (solver == "newton"), name


def _wrapped(a: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * a))


@pytest.mark.parametrize("solver", SOLVERS)
def test_the_five_bar_of_chains_reaches_every_pose_of_every_mode_as_the_closed_form_does(machines, solver):
    """Every pose the hand-derived five-bar reaches in a mode, and no other, the chains reach in the mode of
    the same name, with the same actuated joints to 1e-12 and the same J and J_f to 1e-10."""
    m, hand = machines["five_bar", solver], pkm.load("five_bar")
    design = hand.design()
    small = np.array([design[n] for n in ("r1", "r2", "r3")])
    x = np.random.default_rng(7).uniform(-2.2, 2.2, size=(3000, 2))
    assert m.modes == hand.modes
    for mode in hand.modes:
        theirs = hand.inverse_kinematics(x, design, mode=mode)
        mine = m.inverse_kinematics(x, small, mode=mode)
        reached = np.isfinite(theirs).all(axis=1)
        assert reached.sum() > 1000
        np.testing.assert_array_equal(np.isfinite(mine).all(axis=1), reached)
        np.testing.assert_allclose(_wrapped(mine[reached] - theirs[reached]), 0, atol=1e-12)
        np.testing.assert_allclose(m.jacobian(x[reached], small, mode=mode),
                                   hand.jacobian(x[reached], design, mode=mode), rtol=1e-10, atol=1e-10)
        q = m.inverse_kinematics(x[reached], small, mode=mode, passive=True)
        _, J_f, *_ = evaluate(m.functions["first_order"], q, x[reached], small)
        _, their_J_f, *_ = evaluate(hand.functions["first_order"],
                                    hand.inverse_kinematics(x[reached], design, mode=mode, passive=True),
                                    x[reached], design.vector())
        np.testing.assert_allclose(J_f, their_J_f, rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("solver", SOLVERS)
def test_the_delta_of_chains_is_the_delta_description_elbow_out(machines, solver):
    m, delta = machines["delta", solver], pkm.load(str(DESCRIPTIONS["delta"]))
    x = np.random.default_rng(8).uniform([-0.3, -0.3, -0.8], [0.3, 0.3, -0.2], size=(3000, 3))
    design = {p.name: delta.design()[p.name] for p in m.parameters}
    theirs = delta.inverse_kinematics(x, mode="elbow_out")
    mine = m.inverse_kinematics(x, design)
    reached = np.isfinite(theirs).all(axis=1)
    assert reached.sum() > 1000
    np.testing.assert_array_equal(np.isfinite(mine).all(axis=1), reached)
    np.testing.assert_allclose(mine[reached], theirs[reached], atol=1e-12)
    np.testing.assert_allclose(m.jacobian(x[reached], design), delta.jacobian(x[reached], mode="elbow_out"),
                               rtol=1e-10, atol=1e-10)


@pytest.mark.parametrize("solver", SOLVERS)
def test_the_3rrr_of_chains_is_the_3rrr_in_every_mode(machines, solver):
    """The chains' joints are relative to each leg's frame (turned to its base joint): theta = turn + q1."""
    m, rrr3 = machines["rrr3", solver], pkm.load(str(DESCRIPTIONS["rrr3"]))
    turns = np.pi / 2 + 2 * np.pi * np.arange(3) / 3
    x = np.random.default_rng(11).uniform([-0.3, -0.3, -0.6], [0.3, 0.3, 0.6], size=(1500, 3))
    assert m.modes == rrr3.modes
    for mode in rrr3.modes:
        theirs = rrr3.inverse_kinematics(x, mode=mode)
        mine = m.inverse_kinematics(x, mode=mode)
        reached = np.isfinite(theirs).all(axis=1)
        assert reached.sum() > 300
        np.testing.assert_array_equal(np.isfinite(mine).all(axis=1), reached)
        np.testing.assert_allclose(_wrapped(mine[reached] + turns - theirs[reached]), 0, atol=1e-12)
        np.testing.assert_allclose(m.jacobian(x[reached], mode=mode), rrr3.jacobian(x[reached], mode=mode),
                                   rtol=1e-10, atol=1e-10)


def test_the_3rrr_of_chains_names_each_assembly_as_the_3rrr_does(machines):
    """An assembly mode's name (each leg's elbow side, the type-II determinant's sign, the rank) is the same
    configuration for the RR legs and for their chains: the chains' side, the sign of their closure's Jacobian
    in their joints, is the RR leg's sin(phi - theta). At the actuated joints of poses in two working modes,
    every assembly either machine finds is the same pose under the same name."""
    m, rrr3 = machines["rrr3", "closed"], pkm.load(str(DESCRIPTIONS["rrr3"]))
    assert m.assemblies == rrr3.assemblies
    turns = np.pi / 2 + 2 * np.pi * np.arange(3) / 3
    x = np.random.default_rng(12).uniform([-0.2, -0.2, -0.4], [0.2, 0.2, 0.4], size=(40, 3))
    found = 0
    for mode in ("left_left_left", "right_left_right"):
        theirs = rrr3.inverse_kinematics(x, mode=mode)
        reached = np.isfinite(theirs).all(axis=1)
        for name in rrr3.assemblies:
            mine = m.forward_kinematics(theirs[reached] - turns, assembly=name)
            want = rrr3.forward_kinematics(theirs[reached], assembly=name)
            np.testing.assert_array_equal(np.isfinite(mine).all(axis=1), np.isfinite(want).all(axis=1))
            both = np.isfinite(want).all(axis=1)
            np.testing.assert_allclose(_wrapped(mine[both] - want[both]), 0, atol=1e-9)
            found += int(both.sum())
    assert found > 40


@pytest.mark.parametrize("solver", SOLVERS)
def test_the_chains_gci_and_its_design_gradient_are_the_closed_forms(machines, solver):
    """Through the Newton steps the design gradient is the implicit function's: over a fixed disc the GCI
    and its gradient in (r1, r2, r3) agree with the hand-derived five-bar's to 1e-10 and 1e-9."""
    assert_five_bar_gci(machines["five_bar", solver])


def test_the_continued_inverse_kinematics_compiles_to_the_interpreters_values(machines, monkeypatch, tmp_path):
    """Where the Newton steps diverge the joints are NaN, so that the kernel passes its check against the
    interpreter (at random, mostly unreachable inputs) and gives the interpreter's values to 1e-12."""
    if not (shutil.which("cc") or shutil.which("gcc")) or os.environ.get("PKM_COMPILED") == "0":
        pytest.skip("no C compiler, or the interpreter is asked for")
    monkeypatch.setenv("PKM_CACHE_DIR", str(tmp_path))
    compiled.reset()
    try:
        fn = machines["five_bar", "newton"].functions["inverse_kinematics"]
        assert compiled.kernel(fn, work=compiled.price(fn.n_instructions())) is not None
        x = np.random.default_rng(9).uniform(-2.2, 2.2, size=(500, 2))
        design, mode = machines["five_bar", "newton"].design().vector(), np.array([1.0, -1.0])
        for a, b in zip(evaluate(fn, x, mode, design), interpreted(fn, x, mode, design), strict=True):
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
    finally:
        compiled.reset()


@pytest.mark.parametrize("solver", SOLVERS)
def test_forward_kinematics_of_chains_returns_the_pose(machines, solver):
    m = machines["delta", solver]
    x = np.random.default_rng(10).uniform([-0.1, -0.1, -0.6], [0.1, 0.1, -0.35], size=(60, 3))
    assert_forward_kinematics_returns_the_pose(m, x[m.reachable(x)][:30])


def _broken(change) -> dict:
    raw = copy.deepcopy(delta_of_chains())
    change(raw)
    return raw


@pytest.mark.parametrize(("change", "field"), [
    (lambda r: r["legs"]["joints"][1].update(actuated=True), "legs.joints[1].actuated"),
    (lambda r: r["legs"]["joints"][0].update(type="H"), "legs.joints[0].type"),
    (lambda r: r["legs"]["joints"][0].update(actuated=False), "legs.joints"),
    (lambda r: r["legs"]["joints"].insert(1, {"type": "R", "axis": [1, 0, 0]}), "legs.joints"),
    (lambda r: r["legs"].update(branches={"down": [0.0, 2.3]}), "legs.branches.down"),
    (lambda r: r["legs"]["joints"][2].update(actuated=True), "legs.joints[2]"),
    (lambda r: r["legs"]["joints"][1].pop("axes"), "legs.joints[1].axes"),
    (lambda r: r["legs"]["joints"][0].update(stroke=1), "legs.joints[0].stroke"),
])
def test_a_bad_chain_names_its_field(change, field):
    with pytest.raises(DescriptionError, match=re.escape(f"description field {field} violates")):
        describe(_broken(change))


def test_a_seed_that_does_not_close_its_leg_is_refused_naming_its_branch():
    raw = _broken(lambda r: r["legs"].update(branches={"down": [0.0, 2.3, 0.0], "up": [9.0, 9.0, 9.0]}))
    raw["parameters"][3]["default"] = 0.1
    raw["legs"]["newton"] = True
    with pytest.raises(DescriptionError, match=r"leg 1\) branches\.(down|up) violates: a seed the leg closes from"):
        pkm.load(raw)


def test_the_hexas_closed_form_is_its_newton_continuation():
    """examples/hexa.toml (6-RUS, a spatial pose): the closed form (an arm's angle by the distance of its rod,
    the universal joint's two by Paden and Kahan's second subproblem) and Newton's method give the same
    joints, all 18, to 1e-12 where both reach, and reach the same poses."""
    raw = tomllib.loads((EXAMPLES / "hexa.toml").read_text())
    closed, newton = pkm.load(raw), pkm.load(_newton(raw))
    x = np.random.default_rng(12).uniform([-0.06, -0.06, 0.3, -0.15, -0.15, -0.3], [0.06, 0.06, 0.4, 0.15, 0.15, 0.3],
                                          size=(200, 6))
    design, mode = closed.design().vector(), np.ones(1)
    q, reach = interpreted(closed.functions["inverse_kinematics"], x, mode, design)
    q_newton, reach_newton = interpreted(newton.functions["inverse_kinematics"], x, mode, design)
    mine, theirs = (np.all(r[..., 0] >= 0, axis=1) & np.isfinite(v[..., 0]).all(axis=1)
                    for r, v in ((reach, q), (reach_newton, q_newton)))
    assert mine.sum() > 150
    np.testing.assert_array_equal(mine, theirs)
    np.testing.assert_allclose(_wrapped(q[mine, :, 0] - q_newton[mine, :, 0]), 0, atol=1e-12)


@pytest.mark.parametrize("solver", SOLVERS)
def test_chain_bodies_give_the_hand_derived_five_bars_inertia_and_inverse_dynamics(solver):
    """M_t and M_w to 1e-12 and the actuated joints' torques to 1e-10 of the largest, in every mode."""
    hand = pkm.load("five_bar")
    design = hand.design()
    raw = five_bar_of_chains_with_bodies(dict(design))
    m = pkm.load(raw if solver == "closed" else _newton(raw))
    small = np.array([design[n] for n in ("r1", "r2", "r3")])
    rng = np.random.default_rng(13)
    for mode in hand.modes:
        x = rng.uniform(-2.0, 2.0, size=(1000, 2))
        x = x[hand.reachable(x, design, mode=mode)][:200]
        mine = [m.inertia_matrix(x, small, mode=mode, space=space) for space in ("actuated", "task")]
        theirs = [hand.inertia_matrix(x, design, mode=mode, space=space) for space in ("actuated", "task")]
        for a, b in zip(mine, theirs, strict=True):
            scale = np.maximum(1.0, np.abs(b).reshape(len(x), -1).max(axis=1))[:, None, None]
            np.testing.assert_allclose(a / scale, b / scale, atol=1e-12, err_msg=mode)
        assert_five_bar_torques(m, small, x, mode, rng)


def test_chain_bodies_in_space_give_the_delta_descriptions_dynamics():
    """The Delta of chains with the description's bodies and gravity: its task-space inertia and its torques
    along random motions equal the Delta description's (R_parallelogram legs) to 1e-10."""
    delta, chains = (pkm.load(raw) for raw in delta_and_its_chains_with_bodies())
    rng = np.random.default_rng(14)
    x = rng.uniform([-0.15, -0.15, -0.7], [0.15, 0.15, -0.4], size=(600, 3))
    x = x[delta.reachable(x, mode="elbow_out")][:200]
    assert len(x) > 100
    np.testing.assert_allclose(chains.inertia_matrix(x, space="task"),
                               delta.inertia_matrix(x, mode="elbow_out", space="task"), rtol=1e-10, atol=1e-10)
    x_dot, x_ddot = rng.normal(size=(2, len(x), 3))
    np.testing.assert_allclose(chains.inverse_dynamics(x, x_dot, x_ddot),
                               delta.inverse_dynamics(x, x_dot, x_ddot, mode="elbow_out"), rtol=1e-10, atol=1e-10)


def test_a_rotor_is_only_on_the_actuated_joint_and_a_body_names_its_fields():
    raw = delta_of_chains()
    raw["legs"]["joints"][1]["rotor"] = 0.1
    with pytest.raises(DescriptionError, match=re.escape("description field legs.joints[1].rotor violates")):
        describe(raw)
    raw = delta_of_chains()
    raw["legs"]["joints"][0]["body"] = {"mass": 1, "centre": [0, 0]}
    with pytest.raises(DescriptionError, match=re.escape("description field legs.joints[0].body.centre violates")):
        describe(raw)


def test_a_synthesis_over_the_delta_of_chains_reaches_the_delta_descriptions_optimum(machines):
    """The same machine, its legs as chains in closed form or as the R_parallelogram kind: the GCI over the
    task in (L_a, L_b) reaches the same verified optimum."""
    from pkm.synthesis.designer import design_problem

    chains, delta = machines["delta", "closed"], pkm.load(str(DESCRIPTIONS["delta"]))
    variables = {"L_a": (0.2, 0.3), "L_b": (0.5, 0.7)}
    optima = [pkm.synthesize(design_problem(m, task="task", variables=variables, mode=mode, baseline=("grid", 3),
                                            resolution=4), progress=False, starts=2)
              for m, mode in ((chains, "single"), (delta, "elbow_out"))]
    assert abs(optima[0].verified_objective - optima[1].verified_objective) <= 1e-9
    for name in variables:
        assert abs(optima[0].variables[name] - optima[1].variables[name]) <= 1e-6


def _parameters(**values: float) -> list[dict]:
    return [{"name": k, "default": v, "lower": 0.01, "upper": 5.0, "unit": "m", "doc": k} for k, v in values.items()]


def _circles(frame: str, home: list, joints: list, branches: dict, **values: float) -> dict:
    """Three chain legs on the circles R (base) and r (platform), named by their joints: the same name in every
    process (``hash`` of a string changes with PYTHONHASHSEED, so that each run derived all four again)."""
    return {"name": f"chains_{zlib.crc32(str(joints).encode()) % 10**8}", "frame": frame, "home": home,
            "parameters": _parameters(**values),
            "legs": {"kind": "chain", "count": 3, "base": {"circle": "R", "start": "pi/2"},
                     "platform": {"circle": "r", "start": "pi/2"}, "joints": joints, "branches": branches}}


SUBPROBLEMS = {
    "RP, planar": _circles("planar", [0, 0, 0], [{"type": "R"}, {"type": "P", "axis": [1, 0], "actuated": True}],
                           {"out": [3.1, 0.6]}, R=1.0, r=0.4),
    "PR, planar": _circles("planar", [0, 0, 0], [{"type": "P", "axis": [0, 1], "actuated": True},
                                                 {"type": "R", "link": ["l", 0]}],
                           {"up": [0.57, -2.46], "down": [-0.57, 2.46]}, R=1.0, r=0.3, l=0.9),
    "PU, spatial": _circles("spatial_point", [0, 0, -0.8],
                            [{"type": "P", "axis": [0, 0, 1], "actuated": True},
                             {"type": "U", "axes": [[0, 1, 0], [1, 0, 0]], "link": [0, 0, "-L"]}],
                            {"above": [-0.23, 0.34, 0.0], "below": [-1.37, 2.8, 0.0]}, R=0.3, r=0.1, L=0.6),
    "UP, spatial": _circles("spatial_point", [0, 0, 0.8],
                            [{"type": "U", "axes": [[1, 0, 0], [0, 1, 0]]},
                             {"type": "P", "axis": [0, 0, 1], "actuated": True}],
                            {"only": [0.0, -0.25, 0.83]}, R=0.3, r=0.1),
}


@pytest.mark.parametrize("name", list(SUBPROBLEMS))
def test_every_closed_form_of_a_chain_is_its_newton_continuation(name):
    """The subproblems the closed forms match that the machines above do not (an R pointing an actuated P in
    the plane, an actuated P then an R, an actuated P then a U in space, a U pointing an actuated P): on
    every mode, the closed form and Newton's method reach the same poses with the same joints to 1e-12."""
    raw = SUBPROBLEMS[name]
    closed, newton = pkm.load(raw), pkm.load(_newton(raw))
    assert "continuation_start" not in closed.functions
    box = closed.workspace_box(closed.design().vector())
    x = np.random.default_rng(15).uniform(box[:, 0], box[:, 1], size=(400, closed.n_out))
    design = closed.design().vector()
    for mode in closed.working_modes:
        q, reach = interpreted(closed.functions["inverse_kinematics"], x, np.array(mode.signs), design)
        q_newton, reach_newton = interpreted(newton.functions["inverse_kinematics"], x, np.array(mode.signs), design)
        mine, theirs = (np.all(r[..., 0] >= 0, axis=1) & np.isfinite(v[..., 0]).all(axis=1)
                        for r, v in ((reach, q), (reach_newton, q_newton)))
        assert mine.sum() > 40, mode.name
        np.testing.assert_array_equal(mine, theirs, err_msg=mode.name)
        np.testing.assert_allclose(_wrapped(q[mine, :, 0] - q_newton[mine, :, 0]), 0, atol=1e-12, err_msg=mode.name)
