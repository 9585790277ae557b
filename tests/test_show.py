"""pkm show: a design card writes every file it promises (a PNG and an SVG per working mode, report.json and
report.md), its table holds the global indices the API gives, a described machine's linkage closes at the
drawn pose, every assembly at that pose's actuated joints is counted and drawn (or said not listed), and the MIC a
region placement returns is inside the workspace and touches its boundary."""

from __future__ import annotations

import copy
import json

import numpy as np
import pytest
from helpers import FIVE_BAR_OF_CHAINS

import pkm
from pkm import figures
from pkm.cli import main
from pkm.cli.commands import show
from pkm.errors import PkmError


def test_a_card_writes_its_maps_and_reports_and_tabulates_the_apis_indices(tmp_path, capsys):
    folder = tmp_path / "card"
    assert main(["show", "delta", "--mode", "elbow_out", "--plane", "x,z", "--held", "y=0", "--resolution", "31",
                 "--out", str(folder), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    for name in ("workspace_elbow_out.png", "workspace_elbow_out.svg", "report.json", "report.md"):
        assert (folder / name).stat().st_size > 0, name
    report = json.loads((folder / "report.json").read_text())
    assert {k: v for k, v in data.items() if k != "files"} == report  # the JSON printed is report.json's
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


def _saved(monkeypatch) -> dict:
    """The figures ``pkm.figures.save`` is given, by file name."""
    saved, save = {}, figures.save

    def collect(fig, path, *, dpi):
        saved[path.name] = fig
        return save(fig, path, dpi=dpi)

    monkeypatch.setattr(figures, "save", collect)
    return saved


@pytest.mark.parametrize(("name", "mode", "count"), [("five_bar", "out_in", 2), ("rrr3", "left_left_left", 2)])
def test_show_counts_and_draws_every_assembly_at_the_linkages_joints(name, mode, count, tmp_path, capsys,
                                                                     monkeypatch):
    """One panel per assembly at the actuated joints of the card's pose in its mode, each panel the assembly's
    linkage (every leg's points as drawn), the count and the bound in the text, the JSON and the report. One
    run, in text: the JSON that --json prints is report.json's (the test of the delta's card above)."""
    saved = _saved(monkeypatch)
    folder = tmp_path / "card"
    assert main(["show", name, "--mode", mode, "--resolution", "11", "--out", str(folder)]) == 0
    text = capsys.readouterr().out
    report = json.loads((folder / "report.json").read_text())
    data = report["assemblies"]
    m = pkm.load(name)
    pose = np.array(list(report["pose"].values()))
    joints = m.inverse_kinematics(pose, mode=mode)
    found = m.every_assembly(joints)
    assert (data["count"], data["bound"], data["failed"], data["mode"]) == (count, found.bound, 0, mode)
    assert (data["failures"], data["method"]) == (found.failures, found.method)
    assert list(data["joints"].values()) == pytest.approx(joints.tolist())
    line = f"{count} real assemblies at the joints of the linkage's pose (mode {mode}; at most {found.bound}; "
    assert line in text
    assert line in (folder / "report.md").read_text()
    assert "![" + name + " assemblies](assemblies.png)" in (folder / "report.md").read_text()
    for suffix in ("png", "svg"):
        assert (folder / f"assemblies.{suffix}").stat().st_size > 0
    panels = saved["assemblies.png"].axes
    assert len(panels) == count == found.counts[0]
    for k, (ax, row, at) in enumerate(zip(panels, data["assemblies"], found.poses[0, :count], strict=True), 1):
        assert ax.get_title() == f"assembly {k}: {row['mode']}"
        assert list(row["pose"].values()) == pytest.approx(at.tolist())
        legs = m.linkage(at, mode=row["mode"])
        drawn = [np.asarray(line.get_xydata()) for line in ax.get_lines()]
        assert len(drawn) == len(legs)
        for points, leg in zip(drawn, legs, strict=True):
            np.testing.assert_allclose(points, leg[:, :2], atol=1e-12)
        np.testing.assert_allclose(m.inverse_kinematics(at, mode=row["mode"]), joints, atol=1e-9)


def test_show_says_in_one_line_where_pkm_cannot_list_the_assemblies(tmp_path, capsys, monkeypatch):
    """A planar point machine whose actuated revolutes each point a passive slider (the point on two lines): show
    lists its one assembly, where the lines meet; where every_assembly refuses a machine, show says so in one line
    and draws no assemblies' figure."""
    raw = copy.deepcopy(FIVE_BAR_OF_CHAINS)
    raw.update(name="five_bar_of_sliders", doc="two actuated revolutes at the base ends, each pointing a slider",
               home=[0, 1.0])
    for leg, branches in zip(raw["legs"], ({"out": [1.0, 1.2]}, {"out": [2.1, 1.2]}), strict=True):
        leg["joints"] = [{"type": "R", "actuated": True}, {"type": "P", "axis": [1, 0]}]
        leg["branches"] = branches
    m = pkm.load(raw)
    monkeypatch.setattr(show, "load_mechanism", lambda _name: m)
    assert main(["show", "sliders", "--resolution", "11", "--out", str(tmp_path / "listed")]) == 0
    lines = [t for t in capsys.readouterr().out.splitlines() if "assembl" in t]
    assert lines == ["1 real assemblies at the joints of the linkage's pose (mode single; at most 2; two curves' "
                     "intersection)"]
    refusal = f"mechanism {m.name} violates: a mechanism whose complete forward kinematics pkm knows"

    def refused(*_args, **_kwargs):
        raise PkmError(refusal)

    monkeypatch.setattr(m, "every_assembly", refused)
    folder = tmp_path / "card"
    assert main(["show", "sliders", "--resolution", "11", "--out", str(folder)]) == 0
    lines = [t for t in capsys.readouterr().out.splitlines() if "assembl" in t]
    assert lines == [f"every assembly at the joints of the linkage's pose (mode single): not listed ({refusal})"]
    assert not list(folder.glob("assemblies.*"))
    data = json.loads((folder / "report.json").read_text())["assemblies"]
    assert (data["count"], data["assemblies"]) == (None, [])
    assert data["reason"] == f"not listed ({refusal})"


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
