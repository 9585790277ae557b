"""pkm.homotopy against an independent solver: fkSGP's elimination template (Martyushev 2025, vendored in
bench/fksgp). At random generic 6-6 instances every one of the 40 paths arrives, pkm's real poses close every leg
and are fkSGP's real poses as sets (the same count, each R and t within 1e-8, fkSGP's after Newton steps on the leg
equations: its template alone left up to 1e-5 m of leg error at some random instances), and the pose the leg lengths
came from is among them; at Dietmaier's geometry both find all 40 real poses, the same ones."""

from __future__ import annotations

import numpy as np
import pytest

from bench.assemblies import fksgp_poses, pose_distance, spatial_instances, spatial_poses
from pkm import homotopy

INSTANCES = 20
SEED = 20261129
SAME = 1e-8  # largest entry of R and t [m] by which two poses may differ
CLOSED = 1e-9  # largest leg length error [m] of a pose pkm finds

# Dietmaier's 6-6 geometry with 40 real poses (ARK 1998), as fkSGP's python/genSGP.py (sgpType 100) lists it:
# base points, platform points, leg lengths (not squared)
DIETMAIER_BASE = [[0, 0, 0], [1.107915, 0, 0], [0.549094, 0.756063, 0], [0.735077, -0.223935, 0.525991],
                  [0.514188, -0.526063, -0.368418], [0.590473, 0.094733, -0.205018]]
DIETMAIER_PLATFORM = [[0, 0, 0], [0.542805, 0, 0], [0.956919, -0.528915, 0], [0.665885, -0.353482, 1.402538],
                      [0.478359, 1.158742, 0.107672], [-0.137087, -0.235121, 0.353913]]
DIETMAIER_LENGTHS = [1, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071]


def test_the_real_poses_of_random_instances_are_fksgps():
    a, b, radii2, rotation0, t0 = spatial_instances(INSTANCES, SEED)
    rotation, t, real, arrived = spatial_poses(a, b, radii2)
    assert arrived.all()
    residuals = homotopy.pose_residual(rotation, t, a[:, None], b[:, None], np.sqrt(radii2)[:, None])
    assert np.all(residuals[real] <= CLOSED)
    for k in range(INSTANCES):
        mine_rotation, mine_t = rotation[k][real[k]], t[k][real[k]]
        assert pose_distance(mine_rotation, mine_t, *fksgp_poses(a[k], b[k], radii2[k])) <= SAME, k
        apart = np.maximum(np.max(np.abs(mine_rotation - rotation0[k]), axis=(1, 2)),
                           np.max(np.abs(mine_t - t0[k]), axis=1))
        assert np.min(apart) <= SAME, k


def test_dietmaiers_geometry_has_40_real_poses_in_both():
    a, b = np.array(DIETMAIER_BASE), np.array(DIETMAIER_PLATFORM)
    radii2 = np.array(DIETMAIER_LENGTHS) ** 2
    rotation, t, real, arrived = spatial_poses(a[None], b[None], radii2[None])
    assert arrived.all()
    assert real.sum() == homotopy.PATHS
    reference_rotation, reference_t = fksgp_poses(a, b, radii2)
    assert len(reference_rotation) == homotopy.PATHS
    assert pose_distance(rotation[0], t[0], reference_rotation, reference_t) <= SAME


def test_the_compiled_tracker_ends_every_path_where_numpys_does(monkeypatch):
    """pkm/_track.c against pkm.homotopy.track on the same paths: the same arrivals and the same ends (both
    polished by Newton at s = 1) to 1e-9 of the point's size."""
    from pkm import compiled

    if compiled.written_kernel(homotopy.TRACKER)[0] is None:
        pytest.skip(f"the compiled path is off: {compiled.written_kernel(homotopy.TRACKER)[1]}")
    a, b, radii2, _, _ = spatial_instances(3, SEED + 1)
    ends, arrived = homotopy.solve(a, b, radii2)
    monkeypatch.setattr(compiled, "written_kernel", lambda _source: (None, "off in this test"))
    numpy_ends, numpy_arrived = homotopy.solve(a, b, radii2)
    assert arrived.all()
    assert numpy_arrived.all()
    size = np.maximum(np.abs(numpy_ends).max(axis=-1, keepdims=True), 1.0)
    assert np.all(np.abs(ends - numpy_ends) <= 1e-9 * size)


def test_a_singular_matrix_fails_its_own_path_alone():
    """numpy's batched solve raises for the whole batch where one matrix is singular; the tracker's solve gives NaN
    in that row (its path fails there) and the others' solutions."""
    rng = np.random.default_rng(1)
    a = rng.normal(size=(3, 8, 8)) + 1j * rng.normal(size=(3, 8, 8))
    a[1] = 0
    b = rng.normal(size=(3, 8)) + 0j
    x = homotopy._solved(a, b)
    assert np.all(np.isnan(x[1]))
    np.testing.assert_allclose(np.einsum("rij,rj->ri", a[[0, 2]], x[[0, 2]]), b[[0, 2]], atol=1e-12)
