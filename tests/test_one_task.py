"""One task, every command (issue "Trust the answer", item 8): every command that takes a region or a problem
takes a task file, and every command that takes a design takes a result file; the region is the task's and
the design the result's, and a file of another mechanism or one that records no design is refused in one
line (exit 2)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import pkm
from pkm.cli import main

TASK = Path(__file__).resolve().parent.parent / "docs" / "tasks" / "five_bar.toml"  # a disc at (0, 1.4), r 0.25


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """The task file and the result file ``pkm design`` writes for it."""
    folder = tmp_path_factory.mktemp("one_task")
    task = folder / "task.toml"
    task.write_text(TASK.read_text())
    assert main(["design", str(task), "--out", str(folder / "results")]) == 0
    result = folder / "results" / "five_bar.my_disc.json"
    return task, result, json.loads(result.read_text())


def _json(capsys, argv: list[str]) -> dict:
    assert main([*argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_index_takes_the_task_region_and_the_result_design(files, capsys):
    task, result, record = files
    data = _json(capsys, ["index", "five_bar", "gci", "--region", str(task), "--design", str(result), "--mode",
                          "out_out"])
    assert data["design"] == pytest.approx(record["design"], rel=1e-15)
    assert data["placement"]["centre"] == pytest.approx([0.0, 1.4])
    assert data["placement"]["size"] == pytest.approx([0.25])
    assert data["value"] == pytest.approx(record["verified_objective"], rel=1e-6)


def test_eval_and_export_take_the_result_design(files, capsys, tmp_path):
    _, result, record = files
    data = _json(capsys, ["eval", "five_bar", "--design", str(result), "--pose", "0.0,1.4"])
    m = pkm.load("five_bar")
    expected = m.inverse_kinematics([0.0, 1.4], record["design"], mode=m.modes[0])
    assert data["design"] == pytest.approx(record["design"], rel=1e-15)
    assert data["poses"][0]["q"][: m.n_act] == pytest.approx(np.ravel(expected).tolist(), rel=1e-12)
    exported = _json(capsys, ["export", "five_bar", "--design", str(result), "--out", str(tmp_path / "urdf")])
    assert exported["design"] == pytest.approx(record["design"], rel=1e-15)


def test_show_compare_and_atlas_take_the_task_region(files, capsys, tmp_path):
    task, result, _ = files
    # the maps at a coarse resolution: the region and the design read are the point here
    card = _json(capsys, ["show", "five_bar", "--region", str(task), "--design", str(result), "--mode", "out_out",
                          "--resolution", "11", "--out", str(tmp_path / "card")])
    assert card["region"] == "task"
    assert card["placement"]["centre"] == pytest.approx([0.0, 1.4])
    both = _json(capsys, ["compare", "five_bar", "--region", str(task), "--design", str(result), "--design",
                          "r1=1.2,r2=1.0", "--mode", "out_out", "--resolution", "11", "--out",
                          str(tmp_path / "compare")])
    assert len(both["designs"]) == 2
    atlas = _json(capsys, ["atlas", "five_bar", "gci", "--region", str(task), "--axes", "r1=1:1.4,r2=0.8:1.2",
                           "--resolution", "5", "--modes", "out_out", "--out", str(tmp_path / "atlas")])
    assert "_task_" in atlas["npz"]
    with np.load(atlas["npz"]) as saved:
        assert json.loads(str(saved["metadata"]))["region"] == "task"


def test_synth_and_pareto_take_the_task_file(files, capsys):
    task, _, record = files
    synth = _json(capsys, ["synth", str(task)])
    assert synth["problem"] == "five_bar.my_disc"
    assert synth["design"] == pytest.approx(record["design"], rel=1e-6)
    # at a fixed resolution, unpolished: the problem read is the point here (tests/test_pareto.py polishes)
    front = _json(capsys, ["pareto", str(task), "--secondary", "inverse_condition_f_min", "--points", "3",
                           "--resolution", "4", "--baselines", ""])
    assert front["problem"] == "five_bar.my_disc"
    assert len(front["points"]) >= 2


def test_a_file_of_another_mechanism_or_without_a_design_is_refused_in_one_line(files, capsys, tmp_path):
    task, _, _ = files
    assert main(["index", "rrr3", "gci", "--region", str(task)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "five_bar" in err
    assert "rrr3" in err
    empty = tmp_path / "empty.json"
    empty.write_text('{"problem": "x"}')
    assert main(["eval", "five_bar", "--design", str(empty), "--pose", "0,1.4"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "design" in err


def test_the_explorer_draws_its_atlas_over_the_task_region_of_its_problem(files):
    """``pkm explore --problem task.toml``: the atlas is over the task's region (it was over the mechanism's
    first region, with a colour scale that ended below the task optimum it marked), and the optimum it marks
    is no worse than any node of it."""
    from pkm.explore import Explorer
    from pkm.synthesis.designer import read_problem

    task, _, _ = files
    explorer = Explorer(pkm.load("five_bar"), problem=read_problem(task), axes="r1=1:1.4,r2=0.8:1.2", resolution=7,
                        design={"r3": 0.8})
    assert explorer.defaults["region"] == "task"
    atlas = explorer.handle("atlas", {"mode": "out_out"})
    assert atlas["region"] == "task"
    optimum = explorer.handle("optimum", {})
    values = np.array(atlas["values"]["out_out"], dtype=float)
    assert np.nanmax(values) <= optimum["verified_objective"] + 1e-6
