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

import pkm
from pkm.models.described import DESCRIPTIONS
from pkm.spec import DescriptionError, describe

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
    x = np.column_stack([rng.uniform(-0.1, 0.1, (N, 2)), rng.uniform(0.8, 1.2, N), rng.uniform(-0.2, 0.2, (N, 3))])
    np.testing.assert_allclose(m.inverse_kinematics(x), oracles.sgp_ik(x, design), atol=1e-12)
    np.testing.assert_allclose(m.jacobian(x), oracles.sgp_jacobian(x, design), atol=1e-10)


@pytest.mark.parametrize(("name", "lower", "upper"), [
    ("rrr3", [-0.1, -0.1, -0.2], [0.1, 0.1, 0.2]),
    ("delta", [-0.1, -0.1, -0.6], [0.1, 0.1, -0.35]),
    ("stewart", [-0.05, -0.05, 0.9, -0.1, -0.1, -0.1], [0.05, 0.05, 1.1, 0.1, 0.1, 0.1]),
])
def test_forward_kinematics_by_continuation_returns_the_pose_about_home(machines, name, lower, upper):
    m, rng = machines[name], np.random.default_rng(4)
    x = _within(m, rng, lower, upper, m.modes[0])[:40]
    q = m.inverse_kinematics(x)
    np.testing.assert_allclose(m.forward_kinematics(q, assembly=m.assemblies[0]), x, atol=1e-9)


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
])
def test_a_bad_description_names_its_field(change, field):
    with pytest.raises(DescriptionError, match=re.escape(f"description field {field} violates")):
        describe(_broken("rrr3", change))


def test_a_home_pose_that_does_not_assemble_is_refused():
    raw = _broken("rrr3", lambda r: r.update(home=[5, 5, 0]))
    with pytest.raises(DescriptionError, match=r"home pose .* does not assemble"):
        pkm.load(raw)
