"""pkm show: a design card writes every file it promises (a PNG and an SVG per working mode, report.json and
report.md), its table holds the global indices the API gives, a described machine's linkage closes at the
drawn pose, and the MIC a region placement returns is inside the workspace and touches its boundary."""

from __future__ import annotations

import json

import numpy as np
import pytest

import pkm
from pkm.cli import main


def test_a_card_writes_its_maps_and_reports_and_tabulates_the_apis_indices(tmp_path, capsys):
    folder = tmp_path / "card"
    assert main(["show", "delta", "--mode", "elbow_out", "--plane", "x,z", "--held", "y=0", "--resolution", "31",
                 "--out", str(folder), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for name in ("workspace_elbow_out.png", "workspace_elbow_out.svg", "report.json", "report.md"):
        assert (folder / name).stat().st_size > 0, name
    report = json.loads((folder / "report.json").read_text())
    assert report["design"][0]["unit"] == "m"
    m = pkm.load("delta")
    gci = next(r for r in report["global_indices"] if r["index"] == "gci")
    assert gci["value"] == pytest.approx(float(m.global_index("gci", region="task", mode="elbow_out")), rel=1e-12)
    assert sorted(data["files"]) == sorted(str(folder / p.name) for p in folder.iterdir())
    assert "| gci | elbow_out |" in (folder / "report.md").read_text()


def test_the_linkage_drawn_closes_on_the_platform_at_the_pose():
    m = pkm.load("delta")
    pose = np.array([0.05, -0.02, -0.55])
    legs = m.linkage(pose, mode="elbow_out")
    assert len(legs) == 3
    d = m.design()
    for leg in legs:
        np.testing.assert_allclose(np.linalg.norm(leg[1] - leg[0]), d["L_a"], rtol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(leg[2] - leg[1]), d["L_b"], rtol=1e-12)
        np.testing.assert_allclose(np.linalg.norm(leg[2, :2] - pose[:2]), d["r"], rtol=1e-12)
    assert pkm.load("five_bar").linkage([0.0, 9.0]) == []


def test_the_mic_is_inside_the_workspace_and_touches_its_boundary():
    m = pkm.load("five_bar")
    placed = m.region_placement("miw")
    centre, (radius,) = np.array(placed["centre"]), placed["size"]
    angles = np.linspace(0, 2 * np.pi, 721)[:-1]
    ring = np.column_stack([np.cos(angles), np.sin(angles)])
    assert m.reachable(centre + (1 - 1e-6) * radius * ring, mode="out_out").all()
    assert not m.reachable(centre + (1 + 1e-3) * radius * ring, mode="out_out").all()


def test_compare_writes_cards_and_one_table_whose_csv_is_its_json(tmp_path, capsys):
    import csv

    folder = tmp_path / "compared"
    assert main(["compare", "five_bar", "--design", "r3=0.2", "--design", "r3=0.8", "--mode", "out_out",
                 "--resolution", "21", "--out", str(folder), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for name in ("comparison.json", "comparison.csv", "comparison.md", "design_1/report.json",
                 "design_2/workspace_out_out.svg"):
        assert (folder / name).stat().st_size > 0, name
    with open(folder / "comparison.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == len(data["rows"])
    for row, want in zip(rows, data["rows"], strict=True):
        assert (row["index"], row["mode"]) == (want["index"], want["mode"])
        assert [float(row["design_1"]), float(row["design_2"])] == pytest.approx(want["values"], rel=1e-15)
    gci = next(r for r in data["rows"] if r["index"] == "gci")
    assert gci["best"] == int(np.argmax(gci["values"]))


def test_compare_needs_two_designs(capsys):
    assert main(["compare", "five_bar", "--design", "r3=0.2", "--out", "unused"]) == 2
    assert "at least two designs" in capsys.readouterr().err


def test_an_atlas_over_two_parameters_holds_the_others_at_the_given_design(tmp_path):
    out = tmp_path / "atlas"
    assert main(["atlas", "five_bar", "gci", "--axes", "r1=0.8:1.4,r2=0.8:1.4", "--design", "r3=0.2",
                 "--resolution", "5", "--pose-resolution", "8", "--executor", "serial", "--out", str(out)]) == 0
    (npz,) = out.glob("*.npz")
    with np.load(npz) as data:
        metadata = json.loads(str(data["metadata"]))
        values = data["values_out_out"]
    assert metadata["held"]["r3"] == 0.2
    m = pkm.load("five_bar")
    middle = m.global_index("gci", {"r1": 1.1, "r2": 1.1, "r3": 0.2}, mode="out_out", resolution=8)
    assert values[2, 2] == pytest.approx(float(middle), rel=1e-12)


@pytest.mark.parametrize(("axes", "condition"), [
    ("r1=0.8:1.4,r1=0.8:1.4", "r1 is given twice"),
    ("r1=1.4:0.8,r2=0.8:1.4", "lower < upper"),
    ("r1=-1:1.4,r2=0.8:1.4", "within the parameter's bounds"),
])
def test_bad_atlas_axes_exit_2_naming_the_condition(axes, condition, tmp_path, capsys):
    assert main(["atlas", "five_bar", "gci", "--axes", axes, "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert condition in err
    assert len(err.strip().splitlines()) == 1


def test_eval_reads_poses_from_csv_and_npy_and_writes_a_csv_equal_to_its_json(tmp_path, capsys):
    import csv

    poses = np.array([[0.0, 1.5], [0.1, 1.4], [3.0, 3.0]])
    lines = [",".join(str(float(v)) for v in p) for p in poses]
    (tmp_path / "poses.csv").write_text("\n".join(["x [m],y [m]", *lines]) + "\n")
    np.save(tmp_path / "poses.npy", poses)
    outputs = []
    for name in ("poses.csv", "poses.npy"):
        out = tmp_path / name.replace(".", "_")
        assert main(["eval", "five_bar", "--poses", str(tmp_path / name), "--out", str(out), "--json"]) == 0
        data = json.loads(capsys.readouterr().out)
        outputs.append(data)
        with open(out / "eval.csv") as handle:
            rows = list(csv.DictReader(handle))
        assert [[float(r["x [m]"]), float(r["y [m]"])] for r in rows] == poses.tolist()
        for row, want in zip(rows, data["poses"], strict=True):
            assert bool(int(row["reachable"])) == want["reachable"]
            if want["reachable"]:
                assert float(row["inverse_condition_f [-]"]) == want["inverse_condition_f"]
                assert float(row["theta1 [rad]"]) == want["actuators"]["theta1"]
    assert outputs[0]["poses"] == outputs[1]["poses"]


def test_index_writes_a_csv_row_equal_to_its_json(tmp_path, capsys):
    import csv

    assert main(["index", "five_bar", "gci", "--region", "miw", "--resolution", "8", "--out", str(tmp_path),
                 "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    with open(tmp_path / "index.csv") as handle:
        (row,) = list(csv.DictReader(handle))
    assert float(row["value [-]"]) == data["value"]
    assert float(row["r1 [m]"]) == data["design"]["r1"]
    assert data["placement"]["shape"] == "disc"


@pytest.mark.parametrize(("text", "condition"), [
    ("a,b\n0,1\n", "a header of the pose's coordinates x, y"),
    ("x,y\n0,1,2\n0\n", "rows of 2 values"),
    ("x,y\nzero,1\n", "a readable .npy or CSV file of numbers"),
])
def test_a_bad_poses_file_exits_2_naming_it(tmp_path, capsys, text, condition):
    path = tmp_path / "poses.csv"
    path.write_text(text)
    assert main(["eval", "five_bar", "--poses", str(path)]) == 2
    err = capsys.readouterr().err
    assert condition in err
    assert len(err.strip().splitlines()) == 1
