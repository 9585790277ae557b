"""Atlases of global indices over Gao's normalised design space (Gao 1998 Figs. 4-9)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.atlas import Atlas, compute_atlas, default_modes
from pkm.cli import main

RES, POSE_RES = 7, 12
GCI = registry.global_index("gci")


@pytest.fixture(scope="module")
def mech() -> pkm.Mechanism:
    return pkm.load("five_bar")


@pytest.fixture(scope="module")
def gao(mech):
    return mech.design_spaces["gao1998"]


@pytest.fixture(scope="module")
def gci(mech, gao) -> Atlas:
    return compute_atlas(mech, GCI, space=gao, modes=("out_out", "out_in"), resolution=RES, pose_resolution=POSE_RES)


@pytest.fixture(scope="module")
def gci_miw(mech, gao) -> Atlas:
    modes = ("out_out", "in_in")
    return compute_atlas(mech, GCI, space=gao, region="miw", modes=modes, resolution=RES, pose_resolution=3)


def _design(mech, atlas: Atlas, i: int, j: int) -> dict[str, float]:
    space = atlas.space
    return mech.design_dict(space.designs(mech.parameters, space.from_chart(atlas.u[i], atlas.v[j])))


def test_shapes_and_masks(gci, gao):
    u, v, inside = gao.chart_grid(RES)
    assert gci.index is GCI
    assert gci.space is gao
    assert gci.modes == ("out_out", "out_in")
    np.testing.assert_array_equal(gci.u, u)
    np.testing.assert_array_equal(gci.v, v)
    np.testing.assert_array_equal(gci.inside, inside)
    assert 0 < inside.sum() < inside.size
    for mode in gci.modes:
        assert gci.values[mode].shape == gci.points[mode].shape == (RES, RES)
        assert np.isnan(gci.values[mode][~inside]).all()
        assert (gci.points[mode][~inside] == 0).all()
    assert gci.evaluations == inside.sum() * POSE_RES**2 * 2
    assert gci.wall_time > 0


def test_values_inside_are_finite_and_in_range(gci, mech, gao):
    for mode in gci.modes:
        z = gci.values[mode][gci.inside]
        assert np.isfinite(z).all()
        assert ((z > 0) & (z <= 1)).all()
        assert (gci.points[mode][gci.inside] > 0).all()
    gamma = {
        name: compute_atlas(
            mech, registry.global_index(name), space=gao, modes="out_out", resolution=5, pose_resolution=8
        ).values["out_out"]
        for name in ("gamma_max", "gamma_min")
    }
    inside = np.isfinite(gamma["gamma_max"])
    assert (gamma["gamma_min"][inside] >= 0).all()
    assert (gamma["gamma_min"][inside] <= gamma["gamma_max"][inside]).all()


@pytest.mark.parametrize("mode", ["out_out", "out_in"])
def test_node_equals_global_index(gci, mech, mode):
    for i, j in np.argwhere(gci.inside)[::5]:
        expected = mech.global_index("gci", _design(mech, gci, i, j), mode=mode, resolution=POSE_RES)
        assert gci.values[mode][i, j] == pytest.approx(expected, rel=1e-12)
        assert gci.points[mode][i, j] == expected.points


def test_parametrised_node_equals_global_index(gci_miw, mech):
    assert gci_miw.singularity_margin is None
    nodes = [(i, j) for i, j in np.argwhere(gci_miw.inside) if np.isfinite(gci_miw.values["in_in"][i, j])]
    assert nodes
    for i, j in nodes[::3]:
        design = _design(mech, gci_miw, i, j)
        expected = mech.global_index("gci", design, region="miw", mode="in_in", resolution=3)
        assert gci_miw.values["in_in"][i, j] == pytest.approx(expected, rel=1e-9)
        assert gci_miw.points["in_in"][i, j] == expected.points == 36
    # The MIW lies above the base line, so Gao's eq. 26 (out_out == in_in) does not hold over it.
    both = np.isfinite(gci_miw.values["in_in"]) & np.isfinite(gci_miw.values["out_out"])
    assert np.abs(gci_miw.values["in_in"][both] - gci_miw.values["out_out"][both]).max() > 0.05


def test_gao_mode_symmetry_over_the_reachable_region(mech, gao):
    """Gao eqs. 26-27: eta(OABCD) = eta(OA'BC'D) and eta(OABC'D) = eta(OA'BCD)."""
    atlas = compute_atlas(mech, GCI, space=gao, modes=mech.modes, resolution=5, pose_resolution=10)
    inside = atlas.inside
    np.testing.assert_allclose(atlas.values["in_in"][inside], atlas.values["out_out"][inside], rtol=1e-9)
    np.testing.assert_allclose(atlas.values["in_out"][inside], atlas.values["out_in"][inside], rtol=1e-9)


def test_default_modes_are_the_distinct_ones(mech, gao, monkeypatch):
    monkeypatch.setattr(type(mech), "distinct_modes", {"reachable": ("out_out", "out_in")})
    calls = []
    atlas = compute_atlas(mech, GCI, space=gao, resolution=4, pose_resolution=4,
                          progress=lambda done, total: calls.append((done, total)))
    assert atlas.modes == ("out_out", "out_in")
    assert calls[-1] == (atlas.inside.sum() * 2, atlas.inside.sum() * 2)
    # Gao's equalities hold over the reachable workspace only; a region not listed keeps every mode.
    assert default_modes(mech, "miw") == mech.modes
    monkeypatch.setattr(type(mech), "distinct_modes", {"miw": ("out_out", "in_in")})
    assert default_modes(mech, "miw") == ("out_out", "in_in")
    assert default_modes(mech, "reachable") == mech.modes


def test_best_is_the_largest_node(gci, gao):
    for mode in gci.modes:
        best = gci.best(mode)
        z = gci.values[mode]
        assert best.value == np.nanmax(z)
        i, j = np.argwhere(z == best.value)[0]
        assert (best.u, best.v) == (gci.u[i], gci.v[j])
        np.testing.assert_allclose(gao.to_chart(best.coordinates), (best.u, best.v))
        assert sum(best.coordinates[:2]) * 2 + best.coordinates[2] == pytest.approx(4)
    assert gci.best("OABC'D") == gci.best("out_in")
    assert gci.best() == gci.best("out_out")
    many = int(np.median(gci.points["out_out"][gci.inside]))
    best = gci.best("out_out", min_points=many)
    i, j = np.flatnonzero(gci.u == best.u)[0], np.flatnonzero(gci.v == best.v)[0]
    assert gci.points["out_out"][i, j] >= many
    assert best.value == np.nanmax(np.where(gci.points["out_out"] >= many, gci.values["out_out"], np.nan))
    with pytest.raises(pkm.ComputationError, match="no node"):
        gci.best("out_out", min_points=POSE_RES**2 + 1)


def test_save_npz_round_trips(gci, tmp_path):
    path = gci.save_npz(tmp_path / "gci.npz")
    assert [p.name for p in tmp_path.iterdir()] == ["gci.npz"]
    with np.load(path) as data:
        np.testing.assert_array_equal(data["u"], gci.u)
        np.testing.assert_array_equal(data["v"], gci.v)
        np.testing.assert_array_equal(data["inside"], gci.inside)
        for mode in gci.modes:
            np.testing.assert_array_equal(data[f"values_{mode}"], gci.values[mode])
            np.testing.assert_array_equal(data[f"points_{mode}"], gci.points[mode])
        meta = json.loads(str(data["metadata"]))
    assert meta == json.loads(json.dumps(gci.metadata()))
    assert (meta["mechanism"], meta["index"], meta["sense"], meta["space"]) == ("five_bar", "gci", "max", "gao1998")
    assert meta["chart_axes"] == ["u", "v"]
    assert meta["modes"] == list(gci.modes)
    assert meta["pose_resolution"] == POSE_RES
    assert meta["evaluations"] == gci.evaluations


def test_failed_write_leaves_nothing(gci, tmp_path, monkeypatch):
    def fail(*_args, **_kwargs):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez_compressed", fail)
    with pytest.raises(OSError, match="disk full"):
        gci.save_npz(tmp_path / "gci.npz")
    assert list(tmp_path.iterdir()) == []


def test_plot_writes_a_png(gci, gci_miw, tmp_path):
    for atlas in (gci, gci_miw):
        path = atlas.plot(tmp_path / f"{atlas.region}.png")
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert path.stat().st_size > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["miw.png", "reachable.png"]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"region": "disc"}, "unknown five_bar region 'disc'"),
        ({"modes": ("out_out", "up")}, "unknown five_bar working mode 'up'"),
        ({"modes": ("out_out", "OABCD")}, "none repeated"),
        ({"modes": ()}, "at least one working mode"),
        ({"resolution": 2}, "resolution = 2 violates"),
        ({"resolution": 4.5}, "resolution = 4.5 violates"),
        ({"pose_resolution": 1}, "pose_resolution = 1 violates"),
        ({"singularity_margin": 1.0}, "singularity_margin = 1.0 violates"),
    ],
)
def test_bad_input(mech, gao, kwargs, match):
    kwargs = {"resolution": 4, **kwargs}
    with pytest.raises(pkm.PkmError, match=match):
        compute_atlas(mech, GCI, space=gao, **kwargs)


def test_unknown_index_and_design_space_are_named(mech, capsys):
    """compute_atlas takes objects: the names become them in the registry, the mechanism and the CLI."""
    with pytest.raises(pkm.UnknownNameError, match="unknown index 'speed'"):
        registry.global_index("speed")
    with pytest.raises(pkm.UnknownNameError, match="unknown index 'speed'"):
        mech.global_spec("speed")
    with pytest.raises(pkm.PkmError, match="kappa_d"):
        compute_atlas(mech, registry.global_index("kappa_d_mean"), space=gao, resolution=4)
    assert main(["atlas", "five_bar", "gci", "--space", "lara", "--resolution", "4"]) == 2
    assert "unknown five_bar design space 'lara'" in capsys.readouterr().err


def test_unknown_names_are_unknown_name_errors(mech, gao, gci):
    with pytest.raises(pkm.UnknownNameError):
        compute_atlas(mech, GCI, space=gao, region="disc")
    with pytest.raises(pkm.UnknownNameError, match="in_in"):
        gci.best("in_in")


CHECKED_RES = 11  # a chart whose best raw nodes (gci, gamma_min) hold a sliver of a workspace at 16 poses per axis


@pytest.fixture(scope="module")
def checked(mech, gao):
    """gci and gamma_min in out_out over the reachable region at pose resolutions 16 and 32."""
    return {
        (name, pose_res): compute_atlas(mech, registry.global_index(name), space=gao, modes="out_out",
                                        resolution=CHECKED_RES, pose_resolution=pose_res, executor="serial")
        for name in ("gci", "gamma_min")
        for pose_res in (16, 32)
    }


@pytest.mark.parametrize("name", ["gci", "gamma_min"])
def test_the_reported_best_is_stable_under_a_doubling_of_the_pose_resolution(checked, mech, name):
    coarse, fine = checked[name, 16].checked["out_out"], checked[name, 32].checked["out_out"]
    tolerance = checked[name, 16].checks.tolerance
    assert coarse.found
    assert fine.found
    assert coarse.design == fine.design
    assert fine.value == pytest.approx(coarse.value, rel=tolerance)
    # its value converged: from the last resolution checked to its double it moved by less than the tolerance
    last, before = (mech.global_index(name, coarse.design, mode="out_out", resolution=r)
                    for r in coarse.resolutions[-1:-3:-1])
    assert (float(last), float(before)) == pytest.approx(coarse.values[-1:-3:-1], rel=1e-12)
    assert coarse.values[-1] == coarse.value
    assert abs(coarse.values[-1] - coarse.values[-2]) < tolerance * abs(coarse.value)
    assert coarse.resolutions[0] == 16
    assert coarse.resolutions[1] == 32


@pytest.mark.parametrize("name", ["gci", "gamma_min"])
def test_a_degenerate_region_is_never_the_best(checked, name):
    atlas = checked[name, 16]
    raw = atlas.best("out_out")
    i, j = np.flatnonzero(atlas.u == raw.u)[0], np.flatnonzero(atlas.v == raw.v)[0]
    assert atlas.points["out_out"][i, j] < atlas.checks.min_points  # the grid's own best is a sliver
    best = atlas.checked["out_out"]
    assert (best.u, best.v) != (raw.u, raw.v)
    assert best.points >= atlas.checks.min_points
    assert best.fraction >= atlas.checks.min_fraction
    k, m = np.flatnonzero(atlas.u == best.u)[0], np.flatnonzero(atlas.v == best.v)[0]
    assert atlas.points["out_out"][k, m] >= atlas.checks.min_points


def test_the_best_is_given_in_design_parameters_and_chart_coordinates(checked, mech, gao, tmp_path):
    atlas = checked["gci", 16]
    best = atlas.checked["out_out"]
    assert list(best.design) == list(mech.parameter_names())
    coordinates = gao.from_chart(best.u, best.v)
    assert list(best.coordinates.values()) == pytest.approx(coordinates)
    np.testing.assert_allclose(mech.design_vector(best.design), gao.designs(mech.parameters, coordinates))
    assert f"r1 = {best.design['r1']:.4g}" in str(best)
    assert "out_out" in str(atlas)
    with np.load(atlas.save_npz(tmp_path / "gci.npz")) as data:
        saved = json.loads(str(data["metadata"]))["best"]["out_out"]
    assert saved["design"] == best.design
    assert (saved["u"], saved["v"], saved["value"]) == (best.u, best.v, best.value)


def test_no_best_when_no_candidate_converges_says_why(mech, gao):
    from pkm.atlas import Checks

    atlas = compute_atlas(mech, registry.global_index("gamma_max"), space=gao, modes="out_out", resolution=5,
                          pose_resolution=8, checks=Checks(tolerance=1e-9, refinements=1))
    best = atlas.checked["out_out"]
    assert not best.found
    assert "converged to 0.00%" in best.reason
    assert "(8, 16)" in best.reason
    assert best.design == {}
    assert best.to_dict()["value"] is None
    assert str(best).startswith("no best gamma_max in out_out: none of the")
    sliver = compute_atlas(mech, GCI, space=gao, modes="out_out", resolution=5, pose_resolution=8,
                           checks=Checks(min_fraction=0.99))
    assert "no admissible design's region" in sliver.checked["out_out"].reason


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"tolerance": 0}, "tolerance = 0 violates"),
        ({"min_fraction": 1.0}, "min_fraction = 1.0 violates"),
        ({"min_points": 0}, "min_points = 0 violates"),
        ({"refinements": 9}, "refinements = 9 violates"),
    ],
)
def test_bad_checks_are_pkms_error(kwargs, match):
    from pkm.atlas import Checks

    with pytest.raises(pkm.PkmError, match=match):
        Checks(**kwargs)


def test_cli_atlas_reports_the_checked_best_in_design_parameters(tmp_path, capsys):
    args = ["atlas", "five_bar", "gci", "--modes", "out_out", "--resolution", str(CHECKED_RES),
            "--pose-resolution", "16", "--executor", "serial", "--out", str(tmp_path)]
    assert main([*args, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    best = data["best"]["out_out"]
    assert best["found"]
    assert best["points"] >= data["checks"]["min_points"]
    assert {"r1", "r2", "r3"} <= set(best["design"])
    assert {"u", "v", "coordinates"} <= set(best)
    assert main(args) == 0
    text = capsys.readouterr().out
    assert f"best gci in out_out: {best['value']:.6g} at chart" in text
    assert f"r1 = {best['design']['r1']:.4g}" in text


def test_an_atlas_reports_progress_as_done_and_total(mech, gao):
    seen = []
    atlas = compute_atlas(
        mech, GCI, space=gao, modes=("out_out",), resolution=5, pose_resolution=8,
        progress=lambda done, total: seen.append((done, total)),
    )
    total = int(atlas.inside.sum())
    assert seen[-1] == (total, total)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


def test_a_fixed_task_region_is_not_held_to_a_share_of_the_workspace():
    """The Delta's task cylinder is the same at every design and small against the workspace box: the size check
    (Checks.min_fraction) is for regions the design places and sizes, so the atlas still reports its best design,
    which is the largest node among those that converge."""
    from pkm.design_space import parameter_plane, parse_axes

    m = pkm.load("delta")
    space = parameter_plane(m.parameters, parse_axes("L_a=0.25:0.45,L_b=0.6:0.9", "--axes"))
    atlas = compute_atlas(m, registry.global_index("gci"), space=space, region="task", modes="elbow_out",
                          resolution=7, executor="serial", progress=False)
    best = atlas.checked["elbow_out"]
    assert best.found, best.reason
    assert "a fixed region" in best.reason
    assert np.isnan(best.fraction)
    assert best.value >= np.nanmax(atlas.values["elbow_out"]) - 0.01 * abs(best.value)
