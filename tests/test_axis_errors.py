"""A Delta's drive axes in its error model (issue 42: joint axis directions): each arm's axis turned about its zero
direction and towards it by two error angles (``error_model(m, axes=True)``), exact rotations of the axis and the
arm's frame; the error Jacobian's columns against central differences of the perturbed machine's closed loops,
tilts planted in a machine recovered by calibration, and the command's option."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

import pkm
from pkm.accuracy import calibrate
from pkm.cli import main

TILTS = tuple(f"e_axis{k}_{side}" for k in (1, 2, 3) for side in ("zero", "normal"))


@pytest.fixture(scope="module")
def delta():
    m = pkm.load("delta")
    return m, m.error_model(axes=True)


def _task(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    radius, angle = 0.12 * np.sqrt(rng.uniform(size=n)), rng.uniform(0, 2 * np.pi, n)
    return np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.55, -0.45, n)])


def test_the_tilts_are_angles_whose_columns_are_the_closed_loops_central_differences(delta):
    """Two angles per arm, in rad, beside the other errors; at zero error the machine is the nominal one; each
    tilt's column of E equals the pose moved by 1e-6 rad either way, the loops closed at the same actuated joints,
    to 1e-8 of E's largest entry; a tolerance given as one length leaves the angles at 0."""
    m, model = delta
    tilts = [p for p in model.parameters if p.name.startswith("e_axis")]
    assert tuple(p.name for p in tilts) == TILTS
    assert {p.unit for p in tilts} == {"rad"}
    assert len(model.names) == len(m.error_model().names) + 6
    x = _task(4, 1)
    np.testing.assert_allclose(model.machine.inverse_kinematics(x, model.design()), m.inverse_kinematics(x),
                               atol=1e-14)
    E = model.jacobian(x)
    q = m.inverse_kinematics(x)
    for name in TILTS:
        k = model.names.index(name)
        moved = [model.closed(q, x, model.design(None, {name: sign * 1e-6})) for sign in (1, -1)]
        np.testing.assert_allclose(E[:, :, k], (moved[0] - moved[1]) / 2e-6, rtol=0, atol=1e-8 * np.abs(E).max())
    assert np.abs(E[:, :, [model.names.index(n) for n in TILTS]]).max() > 1e-3  # a tilt moves the platform
    assert all(w == 0 for n, w in zip(model.names, model.widths(1e-5), strict=True) if n in TILTS)


def test_planted_tilts_are_recovered_from_measured_poses(delta):
    """A machine built with its arms' axes tilted by up to 2 mrad and its arms 0.3 mm long: calibrated from the
    poses it reaches at 40 commanded joint sets, the tilts and lengths are recovered to 1e-9."""
    m, model = delta
    planted = {"e_axis1_zero": 2e-3, "e_axis2_normal": -1.5e-3, "e_axis3_zero": -0.8e-3, "e_axis3_normal": 1e-3,
               "e_arm1": 3e-4, "e_arm2": -2e-4}
    x = _task(40, 2)
    q = m.inverse_kinematics(x)
    measured = model.closed(q, x, model.design(None, planted))
    chosen = [*TILTS, "e_arm1", "e_arm2", "e_arm3"]
    found = calibrate(model, q, measured, parameters=chosen)
    for name in chosen:
        assert found.errors[name] == pytest.approx(planted.get(name, 0.0), abs=1e-9)
    assert found.rms_after < 1e-12


def test_pkm_calibrate_takes_the_axes(tmp_path, capsys, delta):
    m, model = delta
    x = _task(30, 3)
    q = m.inverse_kinematics(x)
    measured = model.closed(q, x, model.design(None, {"e_axis2_zero": 1e-3}))
    data = tmp_path / "measured.csv"
    with open(data, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow([*m.actuator_names, *m.pose_names])
        writer.writerows(np.hstack([q, measured]).tolist())
    assert main(["calibrate", "delta", str(data), "--axes", "--parameters", ",".join(TILTS), "--out",
                 str(tmp_path / "out")]) == 0
    found = json.loads((tmp_path / "out" / "calibration.json").read_text())
    assert found["errors"]["e_axis2_zero"] == pytest.approx(1e-3, abs=1e-9)
    assert "e_axis2_zero" in capsys.readouterr().out
