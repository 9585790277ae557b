"""pkm.workspace_map: a plane of the pose holds the local index where the mode reaches (NaN elsewhere), its
arrays and metadata save to npz, and bad planes name the condition."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pkm
from pkm.errors import PkmError
from pkm.workspace_map import workspace_slice


def test_a_slice_holds_the_local_index_where_the_mode_reaches(tmp_path):
    m = pkm.load("five_bar")
    s = workspace_slice(m, index="inverse_condition_f", resolution=21)
    U, V = np.meshgrid(s.u, s.v, indexing="ij")
    x = np.column_stack([U.ravel(), V.ravel()])
    want = np.where(m.reachable(x), m.local_index("inverse_condition_f", x), np.nan).reshape(U.shape)
    np.testing.assert_array_equal(np.isnan(s.values), np.isnan(want))
    np.testing.assert_allclose(s.values, want, rtol=1e-12)
    assert np.isfinite(s.values).any()
    assert np.isnan(s.values).any()
    with np.load(s.save(tmp_path / "slice.npz")) as saved:
        assert json.loads(str(saved["metadata"]))["axes"] == ["x", "y"]
        np.testing.assert_array_equal(saved["values"], s.values)


def test_a_slice_of_a_spatial_machine_holds_the_other_coordinates_and_shows_its_task():
    m = pkm.load("delta")
    s = workspace_slice(m, axes=("x", "y"), held={"z": -0.5}, region="task", resolution=15)
    assert s.held == {"z": -0.5}
    assert len(s.region_points) > 0
    assert np.all(np.abs(s.region_points) <= 0.15 + 1e-12)


@pytest.mark.parametrize(("options", "condition"), [
    ({"axes": ("x", "x")}, "two distinct pose coordinates"),
    ({"axes": ("x", "w")}, "two distinct pose coordinates"),
    ({"held": {"w": 0.0}}, "one of x, y"),
    ({"resolution": 2}, "resolution >= 3"),
])
def test_a_bad_plane_names_its_condition(options, condition):
    with pytest.raises(PkmError, match=condition):
        workspace_slice(pkm.load("five_bar"), **options)


@pytest.mark.parametrize("mode", ["out_out", "in_out"])
def test_a_hand_derived_mechanism_draws_its_linkage_from_its_structure(mode, tmp_path):
    """The five-bar has no generated skeleton: its linkage comes from its export structure, a chain O_i, A_i, P
    per proximal link (the base joints at (-+r3, 0), the elbows r1 from them and r2 from P, both ending at the
    pose), in the elbow branches of the mode; the map's figure draws it."""
    m = pkm.load("five_bar")
    design = m.design({"r1": 1.1, "r2": 0.9, "r3": 0.5})
    pose = np.array([0.1, 1.3])
    chains = m.linkage(pose, design, mode=mode)
    assert len(chains) == 2
    joints = m.inverse_kinematics(pose, design, mode=mode)
    for k, (chain, side) in enumerate(zip(chains, (-1.0, 1.0), strict=True)):
        base, elbow, end = chain[:, :2]
        np.testing.assert_allclose(base, [side * 0.5, 0.0], atol=1e-15)
        np.testing.assert_allclose(elbow - base, 1.1 * np.array([np.cos(joints[k]), np.sin(joints[k])]), atol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(end - elbow), 0.9, atol=1e-12)
        np.testing.assert_allclose(end, pose, atol=1e-12)
    assert m.linkage([0.0, 5.0], design, mode=mode) == []
    drawn = workspace_slice(m, design, mode=mode, resolution=21).plot(tmp_path / "map.png", linkage=chains)
    assert drawn.stat().st_size > 1000
