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
