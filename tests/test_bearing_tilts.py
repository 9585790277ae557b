"""A revolute's bearing tilt stiffness in space (issue 40): the Delta's drive bearings as tilt springs across their
axes. Derived twice: with everything else near rigid (its compliance 1e-14 of the tilts'), the compliance K^-1 is
the drive axes' tilt columns of the error model E (issue 42: the same rotations of each arm's frame, the loops
closed at fixed drives) weighted by the tilt compliances, E_t diag(1/t) E_t^T; a Delta of chains (each arm a
revolute, its forearm a parallelogram) has the kind's stiffness; tilts are refused in the plane and in a list of the
wrong length."""

from __future__ import annotations

import copy
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import pkm
from pkm.spec.schema import DescriptionError, describe

ROOT = Path(__file__).resolve().parents[1]
TILT = 2e3  # [N m/rad] each drive bearing's tilt stiffness
STIFF = {"E": "1e27", "G": "4e26", "density": "2700"}  # beams this stiff bend by nothing measurable


def _delta(tilts: list[str]) -> dict:
    raw = tomllib.loads((ROOT / "examples" / "delta_elastic.toml").read_text())
    raw["name"] = "delta_tilted_bearings"
    raw["legs"]["elastic"] = {**raw["legs"]["elastic"], "material": STIFF, "drive": "1e18",
                              "beams": [{}, {"material": STIFF}], "tilts": tilts}
    return raw


def _poses() -> np.ndarray:
    rng = np.random.default_rng(11)
    radius, angle = 0.12 * np.sqrt(rng.uniform(size=6)), rng.uniform(0, 2 * np.pi, 6)
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.55, -0.45, 6)])


def test_the_drive_bearings_tilt_compliance_is_the_error_models_tilt_columns():
    m = pkm.load(_delta([str(TILT), "0", "0"]))
    model = pkm.load("delta").error_model(axes=True)
    x = _poses()
    K = m.stiffness(x)
    E = model.jacobian(x)[:, :, [model.names.index(f"e_axis{k}_{s}") for k in (1, 2, 3) for s in ("zero", "normal")]]
    for k in range(len(x)):
        want = E[k] @ E[k].T / TILT
        np.testing.assert_allclose(np.linalg.inv(K[k]), want, rtol=0, atol=1e-10 * np.abs(want).max())
    rigid = pkm.load(_delta(["0", "0", "0"]) | {"name": "delta_rigid_bearings"})
    assert np.linalg.eigvalsh(rigid.stiffness(x[0])).min() > 1e3 * np.linalg.eigvalsh(K[0]).max()


def test_a_delta_of_chains_has_the_kinds_tilt_stiffness():
    kind = pkm.load(_delta([str(TILT), "0", "0"]))
    raw = copy.deepcopy(_delta([str(TILT), "0", "0"]))
    legs = raw["legs"]
    raw["name"] = "delta_chains_tilted_bearings"
    raw["legs"] = {k: v for k, v in legs.items() if k not in ("kind", "arm", "rod", "range", "bodies")}
    raw["legs"] |= {"kind": "chain", "joints": [
        {"type": "R", "axis": [0, 1, 0], "actuated": True, "link": ["L_a", 0, 0]},
        {"type": "parallelogram", "axes": [[0, 1, 0], [0, 0, 1]], "link": ["L_b", 0, 0]}, {"type": "S"}],
        "branches": {"down": [0.0, 2.3, 0.0]}}
    raw.pop("conditions", None)
    for key in ("modes", "platform", "gravity"):
        raw.pop(key, None)
    chains = pkm.load(raw)
    x = _poses()
    np.testing.assert_allclose(chains.stiffness(x), kind.stiffness(x), rtol=1e-9)


@pytest.mark.parametrize(("tilts", "condition"), [
    (["1e3", "0"], "in space, a list of 3 expressions"),
    ("1e3", "in space, a list of 3 expressions"),
])
def test_tilts_of_the_wrong_length_are_refused_naming_the_field(tilts, condition):
    with pytest.raises(DescriptionError, match=re.escape(f"legs.elastic.tilts violates: {condition}")):
        describe(_delta(tilts))
