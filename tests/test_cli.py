"""The command line: outputs, exit statuses and one-line errors without tracebacks."""

from __future__ import annotations

import json
import re
import subprocess
import sys

import numpy as np
import pytest

import pkm
from pkm.cli import main


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "pkm.cli", *args], capture_output=True, text=True, check=False)


def test_list_json_names_the_five_bar_and_its_indices(capsys):
    assert main(["list", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert "five_bar" in data["mechanisms"]
    assert {"gci", "gamma_max", "gamma_min"} <= set(data["indices"])
    names = [p["name"] for p in data["mechanisms"]["five_bar"]["parameters"]]
    assert names[:3] == ["r1", "r2", "r3"]
    assert {"m1", "m2", "k1", "k2", "j1", "j2"} <= set(names)
    five_bar = data["mechanisms"]["five_bar"]
    assert five_bar["pose"] == {"x": "m", "y": "m"}
    assert five_bar["actuators"] == {"theta1": "rad", "theta2": "rad"}
    assert {"gci", "gamma_max", "gamma_min", "dynamic_dexterity", "lambda_e"} <= set(five_bar["indices"])
    assert "kappa_d_mean" not in five_bar["indices"]
    assert {"effort_peak", "energy", "positioning_error"} <= set(five_bar["trajectory_quantities"])
    assert "effort_peak" not in data["mechanisms"]["passive_leg"]["trajectory_quantities"]
    assert data["indices"]["gci"] == {"doc": data["indices"]["gci"]["doc"], "reduce": "mean", "sense": "max"}
    assert (data["indices"]["lambda_e"]["reduce"], data["indices"]["kappa_d_mean"]["sense"]) == ("min", "min")
    assert data["problems"]["five_bar.max_gci_miw"]["variables"] == ["u", "v"]
    assert data["problems"]["slider_gantry.min_kappa_d_task"]["variables"] == ["l", "d1"]
    assert {"gao1998", "lara_molina2016", "wu2008"} <= set(data["papers"])


def test_eval_reports_inverse_kinematics_and_local_indices(capsys):
    assert main(["eval", "five_bar", "--pose", "0.1,1.5", "--design", "r1=1.2,r2=1.0,r3=0.8", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)["poses"][0]
    assert 0 < row["inverse_condition_f"] <= 1
    assert len(row["q"]) == 4


def test_index_with_gradient_on_the_miw(capsys):
    assert main(["index", "five_bar", "gci", "--region", "miw", "--gradient", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert 0 < data["value"] < 1
    assert set(data["gradient"]) == {p.name for p in pkm.load("five_bar").parameters}
    assert all(data["gradient"][k] == 0 for k in ("m1", "m2", "k1", "j1"))
    assert data["points"] == 4 * data["resolution"] ** 2


def test_index_over_a_region_holding_a_singularity_says_why_it_is_undefined(capsys):
    """A folded leg inside the passive leg's workspace region (r < R): the index is NaN with the reason."""
    assert main(["index", "passive_leg", "gci", "--region", "workspace", "--resolution", "4",
                 "--design", "R=1,r=0.8,l_a=1.0,l_b=1.2", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["value"] is None or data["value"] != data["value"]
    assert "region_margins" in data["undefined"]
    assert main(["index", "passive_leg", "gci", "--region", "workspace", "--resolution", "4", "--json"]) == 0
    assert "undefined" not in json.loads(capsys.readouterr().out)


def test_synth_writes_its_result_and_beats_the_grid(tmp_path, capsys):
    args = ["synth", "five_bar.max_gci_miw", "--resolution", "5", "--out", str(tmp_path), "--json"]
    assert main([*args, "--max-iter", "100", "--tol", "1e-9"]) == 0
    data = json.loads((tmp_path / "five_bar.max_gci_miw.json").read_text())
    assert data == json.loads(capsys.readouterr().out)
    assert data["objective"] >= data["baseline_objective"]
    assert (data["options"]["max_iter"], data["options"]["tol"]) == (100, 1e-9)
    assert list(data["variables"]) == ["u", "v"]


def test_synth_prints_the_variables_by_name_and_each_baseline(capsys):
    assert main(["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1"]) == 0
    out = capsys.readouterr().out
    assert "variables: u = " in out
    assert ", v = " in out
    assert "design: r1 = " in out
    assert "baseline grid (" in out


def test_synth_that_does_not_converge_exits_1_with_the_reason(capfd):
    assert main(["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1", "--max-iter", "0"]) == 1
    err = capfd.readouterr().err
    assert "Traceback" not in err
    assert "computation failed: IPOPT did not converge" in err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["index", "nobot", "gci"], "unknown mechanism 'nobot'"),
        (["index", "five_bar", "nope"], "unknown index 'nope'"),
        (["index", "five_bar", "gci", "--design", "r9=1"], "unknown design parameter(s) r9"),
        (["index", "five_bar", "gci", "--design", "r1=nan"], "r1 = nan is not finite"),
        (["index", "five_bar", "gci", "--design", "r1=0.1,r2=0.1,r3=1"], "cannot be assembled"),
        (["index", "five_bar", "gci", "--mode", "sideways"], "unknown five_bar working mode"),
        (["eval", "five_bar", "--pose", "9,9", "--strict"], "out of reach"),
        (["synth", "no.such"], "unknown synthesis problem"),
        (["synth", "five_bar.max_gci_miw", "--tol", "0"], "tol = 0.0 violates tol > 0"),
        (["synth", "five_bar.max_gci_miw", "--print-level", "13"], "print_level = 13 violates"),
        (["reproduce", "nobody2000"], "unknown paper"),
        (["frobnicate"], "invalid choice"),
    ],
)
def test_bad_input_exits_2_with_one_line(args, needle, capfd):
    assert main(args) == 2
    err = capfd.readouterr().err
    assert "Traceback" not in err
    assert len(err.strip().splitlines()) == 1
    assert needle in err


def test_console_entry_exits_2_with_one_line():
    """The module entry point (a fresh interpreter) as well as ``main``: bad input is one line, no traceback."""
    proc = run("index", "five_bar", "gci", "--design", "r1=nan")
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1
    assert "r1 = nan is not finite" in proc.stderr


def test_sweep_writes_chunks_an_index_and_figures_and_an_atlas_leaves_no_chunks(tmp_path, capsys):
    assert main(["sweep", "five_bar", "--indices", "gci,gamma_max", "--region", "miw", "--resolution", "5",
                 "--pose-resolution", "2", "--executor", "serial", "--out", str(tmp_path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    folder = tmp_path / data["folder"].split("/")[-1]
    listing = json.loads((folder / "index.json").read_text())
    assert listing["indices"] == ["gci", "gamma_max"]
    assert {c["file"] for c in listing["chunks"]} == {f"chunks/{p.name}" for p in (folder / "chunks").glob("*.npz")}
    first = [c for c in listing["chunks"] if c["mode"] == listing["modes"][0]]
    inside = int(np.sum(listing["inside"]))
    assert [c["start"] for c in first] == list(np.cumsum([0] + [c["count"] for c in first[:-1]]))
    assert sum(c["count"] for c in first) == inside
    for name in ("gci", "gamma_max"):
        assert (folder / f"{name}.png").stat().st_size > 1000
        with np.load(folder / f"{name}.npz") as atlas:
            assert np.isfinite(atlas[f"values_{listing['modes'][0]}"]).any()
    assert main(["atlas", "five_bar", "gci", "--region", "miw", "--resolution", "5", "--pose-resolution", "2",
                 "--out", str(tmp_path)]) == 0
    assert not (tmp_path / ".pkm-chunks").exists()


def test_a_negative_coordinate_is_a_value_not_an_option(capsys):
    assert main(["eval", "passive_leg", "--pose", "-0.2,1.1", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["poses"][0]["pose"] == [-0.2, 1.1]


def test_a_design_parameter_given_twice_is_bad_input(capfd):
    assert main(["eval", "five_bar", "--design", "r1=1.0,r1=1.2"]) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert err == ["pkm: error: design parameter r1 is given twice"]


def test_ctrl_c_is_one_line_and_exit_130(monkeypatch, capfd):
    def interrupted(_name):
        raise KeyboardInterrupt

    monkeypatch.setattr(pkm.registry, "mechanism", interrupted)
    assert main(["eval", "five_bar", "--pose", "0,1.5"]) == 130
    assert capfd.readouterr().err.strip().splitlines() == ["pkm: interrupted"]


def test_a_closed_stdout_gives_no_traceback():
    proc = subprocess.Popen([sys.executable, "-m", "pkm.cli", "list", "--json"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    proc.stdout.close()
    _, err = proc.communicate(timeout=60)
    assert proc.returncode in (0, 1)
    assert b"Traceback" not in err
    assert b"BrokenPipeError" not in err


def test_an_out_that_is_a_file_or_under_one_is_refused_before_any_work(tmp_path, capfd):
    afile = tmp_path / "a_file"
    afile.write_text("mine")
    for out in (afile, afile / "below"):
        assert main(["atlas", "five_bar", "gci", "--resolution", "5", "--out", str(out)]) == 2
        assert "is a file" in capfd.readouterr().err
    assert afile.read_text() == "mine"


def test_atlases_of_other_spaces_or_modes_do_not_overwrite_each_other(tmp_path, capsys):
    common = ["atlas", "five_bar", "gci", "--region", "miw", "--resolution", "5", "--pose-resolution", "2",
              "--out", str(tmp_path), "--json"]
    assert main([*common, "--modes", "out_out"]) == 0
    first = json.loads(capsys.readouterr().out)["npz"]
    assert main([*common, "--modes", "in_in"]) == 0
    second = json.loads(capsys.readouterr().out)["npz"]
    assert first != second
    assert {p.name for p in tmp_path.glob("*.npz")} == {first.split("/")[-1], second.split("/")[-1]}


def test_eval_reports_an_unreachable_pose_with_a_mask_unless_strict(capfd):
    assert main(["eval", "five_bar", "--pose", "0,1.5", "--pose", "10,10", "--json"]) == 0
    rows = json.loads(capfd.readouterr().out)["poses"]
    assert [r["reachable"] for r in rows] == [True, False]
    assert rows[1]["q"] == [None] * 4
    assert rows[0]["inverse_condition_f"] > 0
    assert main(["eval", "five_bar", "--pose", "10,10", "--strict"]) == 2
    assert "out of reach" in capfd.readouterr().err


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["atlas", "five_bar", "gci", "--resolution", "100000"], "resolution = 100000 violates"),
        (["atlas", "five_bar", "gci", "--pose-resolution", "100000"], "pose_resolution = 100000 violates"),
        (["index", "five_bar", "gci", "--resolution", "100000"], "resolution = 100000 violates"),
        (["synth", "five_bar.max_gci_miw", "--starts", "100000"], "starts = 100000 violates"),
        (["synth", "five_bar.max_gci_miw", "--max-iter", "100000000000"], "max_iter = 100000000000 violates"),
    ],
)
def test_resolutions_and_counts_too_large_for_memory_are_refused(args, needle, capfd):
    assert main(args) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert needle in err[0]


def test_non_finite_counts_are_pkms_error():
    from pkm.errors import check_integer

    for value in (float("inf"), float("nan"), 1e400):
        with pytest.raises(pkm.PkmError, match="violates"):
            check_integer("starts", value, 1)


def test_json_with_verbose_keeps_ipopts_log_out_of_stdout(capfd):
    assert main(["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1", "--verbose", "--json"]) == 0
    captured = capfd.readouterr()
    assert json.loads(captured.out)["problem"] == "five_bar.max_gci_miw"
    assert "iter" in captured.err


def test_a_reproduction_keeps_the_users_own_files_in_its_folder(tmp_path):
    from pkm import io

    target = tmp_path / "gao1998"
    target.mkdir()
    (target / "notes.txt").write_text("mine")
    (target / "report.md").write_text("an old report")
    with io.staged_folder(target) as stage:
        (stage / "report.md").write_text("new")
        (stage / "figures").mkdir()
        (stage / "figures" / "a.png").write_text("png")
    assert (target / "notes.txt").read_text() == "mine"
    assert (target / "report.md").read_text() == "new"
    assert (target / "figures" / "a.png").read_text() == "png"
    assert [p.name for p in tmp_path.iterdir()] == ["gao1998"]
    def interrupted() -> None:
        with io.staged_folder(target) as stage:
            (stage / "report.md").write_text("half")
            raise RuntimeError

    with pytest.raises(RuntimeError):
        interrupted()
    assert (target / "report.md").read_text() == "new"
    assert [p.name for p in tmp_path.iterdir()] == ["gao1998"]


def test_outputs_follow_the_umask_not_private_to_the_user(tmp_path):
    import os
    import stat

    from pkm import io

    previous = os.umask(0o022)
    try:
        path = io.write_text(tmp_path / "report.json", "{}")
    finally:
        os.umask(previous)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


def test_a_staging_folder_left_by_a_killed_run_is_removed_by_the_next(tmp_path):
    from pkm import io

    finished = subprocess.Popen(["true"])  # a process that has ended: its pid names no live process
    finished.wait()
    abandoned = tmp_path / f".gao1998.{finished.pid}.x1y2"
    abandoned.mkdir()
    (abandoned / "report.json").write_text("{")
    with io.staged_folder(tmp_path / "gao1998") as stage:
        assert stage.name.startswith(".gao1998.")
        (stage / "report.json").write_text("{}")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gao1998"]


def test_a_failed_synthesis_writes_its_record_with_the_last_iterate_in_design_parameters(tmp_path, capfd):
    args = ["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1", "--max-iter", "1",
            "--out", str(tmp_path), "--json"]
    assert main(args) == 1
    captured = capfd.readouterr()
    record = json.loads(captured.out)
    assert record == json.loads((tmp_path / "five_bar.max_gci_miw.json").read_text())
    assert record["status"] == "Maximum_Iterations_Exceeded"
    assert {"r1", "r2", "r3"} <= set(record["design"])
    assert list(record["variables"]) == ["u", "v"]
    assert "IPOPT did not converge" in captured.err
    assert "design {'r1'" in captured.err
    assert "Traceback" not in captured.err


def test_synthesis_progress_callback_and_summary():
    calls = []
    result = pkm.synthesize("five_bar.max_gci_miw", resolution=2, starts=1, baseline_resolution=5,
                            progress=lambda done, total: calls.append((done, total)))
    total = 1 + 2 + len(result.baselines)
    assert calls[-1] == (total, total)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    text = str(result)
    assert text.startswith(f"five_bar.max_gci_miw: {result.status}")
    assert f"verified {result.verified_objective:.6g}" in text
    assert f"r1 = {result.design['r1']:.6g}" in text


def test_progress_bar_draws_on_a_terminal_only():
    import io

    from pkm.progress import Progress

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    piped, terminal = io.StringIO(), Terminal()
    for stream in (piped, terminal):
        with Progress(4, "work", stream=stream) as bar:
            bar.advance(2)
    assert piped.getvalue() == ""
    assert "work [" in terminal.getvalue()
    assert "2/4" in terminal.getvalue()


def test_each_module_of_the_commands_package_is_a_listed_command_and_the_parallel_ones_take_a_scheduler():
    import pkgutil

    from pkm.cli import build_parser, commands

    names = [command.__name__.rpartition(".")[2] for command in commands.COMMANDS]
    assert sorted(names) == sorted(m.name for m in pkgutil.iter_modules(commands.__path__))
    parsers = build_parser()._subparsers._group_actions[0].choices
    assert list(parsers) == names
    for name, command in zip(names, commands.COMMANDS, strict=True):
        assert parsers[name].description == command.HELP
        assert parsers[name].get_default("func") is command.run
        options = {o for action in parsers[name]._actions for o in action.option_strings}
        assert ("--scheduler" in options) is command.PARALLEL, name
        assert "--json" in options


def test_every_option_has_help_with_its_default_and_reproduce_lists_every_paper(capsys):
    from pkm import registry
    from pkm.cli import build_parser

    parser = build_parser()
    commands = parser._subparsers._group_actions[0].choices
    for name, sub in commands.items():
        sub.format_help()
        for action in sub._actions:
            if action.dest == "help":
                continue
            assert action.help, (name, action.dest)
            if action.option_strings and action.dest not in ("json",):
                assert "default" in action.help, (name, action.dest, action.help)
    with pytest.raises(SystemExit):
        main(["reproduce", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for key, module in registry.papers().items():
        assert f"{key}: {' '.join(module.TITLE.split())}" in text
    with pytest.raises(SystemExit):
        main(["index", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "five_bar: reachable, miw" in text
    assert "e.g. --region miw" in text
    assert "out_out (OABCD)" in text


def test_units_come_from_the_mechanism_the_gantrys_sliders_in_metres(capsys):
    assert main(["eval", "slider_gantry", "--pose", "0,0.9"]) == 0
    text = capsys.readouterr().out
    assert "q1 = " in text
    assert " m, q2 = " in text
    assert re.search(r"q\d = [^,]* rad", text) is None  # the sliders in metres (the elastic frequency in rad/s)
    assert main(["eval", "slider_gantry", "--pose", "0,0.9", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["units"]["actuators"] == {"q1": "m", "q2": "m"}
    assert set(data["poses"][0]["actuators"]) == {"q1", "q2"}
    assert main(["list"]) == 0
    text = capsys.readouterr().out
    assert "design spaces: gao1998, lara_molina2016" in text
    assert "actuators: q1 [m], q2 [m]" in text
    assert "  gao1998: Gao" in text


def test_index_units_follow_the_mechanisms_coordinates(capsys):
    assert pkm.load("five_bar").index_unit("velocity_max") == "m/rad"
    assert pkm.load("slider_gantry").index_unit("gamma_max") == "m/m"
    assert pkm.load("ups_pu").index_unit("region_measure") == "m rad^2"
    assert pkm.load("five_bar").index_unit("region_measure") == "m^2"
    assert pkm.load("five_bar").index_unit("manipulability") == "(m/rad)^2"
    assert pkm.load("five_bar").index_unit("jacobian_determinant") == "(rad/m)^2"
    assert main(["eval", "slider_gantry", "--pose", "0,0.5", "--json"]) == 0
    units = json.loads(capsys.readouterr().out)["units"]
    assert units["actuators"] == {"q1": "m", "q2": "m"}
    assert units["indices"]["velocity_max"] == "m/m"
    assert main(["index", "five_bar", "gamma_min", "--region", "miw", "--resolution", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["unit"] == "m/rad"


def _reproduction_under_way(out) -> subprocess.Popen:
    """A quick nam2006 reproduction (seconds long) run by the console script, once its staging folder
    exists."""
    import time

    # a test runner's worker may ignore SIGINT, which its children inherit: the child takes Python's handler
    start = ("import runpy, signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
             "sys.argv = ['pkm', *sys.argv[1:]]; runpy.run_module('pkm.cli', run_name='__main__')")
    run = subprocess.Popen([sys.executable, "-c", start, "reproduce", "nam2006", "--quick", "--out", str(out)],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while not list(out.glob(".nam2006.*")) and time.monotonic() < deadline and run.poll() is None:
        time.sleep(0.05)
    assert run.poll() is None, "the reproduction finished before it could be stopped"
    return run


def test_an_interrupted_reproduction_leaves_its_folder_as_it_was(tmp_path):
    import signal

    out = tmp_path / "out"
    (out / "nam2006").mkdir(parents=True)
    (out / "nam2006" / "notes.txt").write_text("mine")
    run = _reproduction_under_way(out)
    run.send_signal(signal.SIGINT)
    _, err = run.communicate(timeout=60)
    assert run.returncode == 130, err
    assert err.strip().splitlines() == ["pkm: interrupted"]
    assert sorted(p.name for p in out.iterdir()) == ["nam2006"]
    assert sorted(p.name for p in (out / "nam2006").iterdir()) == ["notes.txt"]


def test_a_killed_reproduction_writes_nothing_and_the_next_run_cleans_up(tmp_path):
    import signal

    from pkm import io

    out = tmp_path / "out"
    run = _reproduction_under_way(out)
    run.send_signal(signal.SIGKILL)
    run.communicate(timeout=60)
    assert not (out / "nam2006" / "report.json").exists()
    assert len(list(out.glob(".nam2006.*"))) == 1  # what the killed process held
    with io.staged_folder(out / "nam2006") as stage:
        (stage / "report.json").write_text("{}")
    assert sorted(p.name for p in out.iterdir()) == ["nam2006"]
    assert (out / "nam2006" / "report.json").read_text() == "{}"


def test_list_says_which_evaluation_path_is_active(capsys, monkeypatch):
    from pkm import compiled

    assert main(["list", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["evaluation"] == compiled.status()
    monkeypatch.setenv("PKM_COMPILED", "0")
    compiled.reset()
    try:
        assert main(["list"]) == 0
        text = capsys.readouterr().out
        assert main(["list", "--json"]) == 0
        evaluation = json.loads(capsys.readouterr().out)["evaluation"]
    finally:
        monkeypatch.undo()
        compiled.reset()
    assert evaluation["path"] == "interpreter"
    assert evaluation["reason"] == "disabled by PKM_COMPILED=0"
    assert "evaluation: CasADi's interpreter (disabled by PKM_COMPILED=0)" in text
    assert "this process: 0 evaluations compiled, 0 on the interpreter" in text


def test_build_compiles_a_mechanisms_kernels_ahead_of_time(capsys):
    """Into the suite's cache (the contract suite compiles the same kernels, so none is compiled twice)."""
    from pkm import compiled
    from pkm.catalogue import kernels

    if compiled.status()["path"] != "compiled":
        pytest.skip(f"the compiled path is off: {compiled.status()['reason']}")
    assert main(["build", "slider_gantry", "--json"]) == 0
    first = json.loads(capsys.readouterr().out)["mechanisms"]["slider_gantry"]
    compiled.reset()
    assert main(["build", "slider_gantry"]) == 0
    second = capsys.readouterr().out
    count = len(kernels(pkm.load("slider_gantry")))
    assert (first["cached"] + first["compiled"], first["interpreted"]) == (count, 0)
    assert f"slider_gantry: {count} kernels in the cache, 0 compiled, 0 left on the interpreter" in second


def test_build_of_an_unknown_mechanism_exits_2(capsys):
    assert main(["build", "nonsense"]) == 2
    assert "nonsense" in capsys.readouterr().err


def _swallowed_interrupt(check) -> None:
    """A block in which Ctrl-C comes and is caught below, as CasADi does; ``check`` runs after it."""
    import contextlib
    import os
    import signal

    from pkm.interrupts import interruptible

    with interruptible():
        with contextlib.suppress(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
        check()


def test_an_interrupt_caught_below_still_ends_the_block():
    """CasADi catches Ctrl-C inside an IPOPT solve or a graph operation and carries on: pkm remembers it,
    raises it at the next task or staged output, and at the end of the block at the latest, also where the
    block fails because the interrupt stopped a solve; a failure without an interrupt stays that failure."""
    import signal

    from pkm.errors import ComputationError
    from pkm.interrupts import check_interrupted, interruptible

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            _swallowed_interrupt(check_interrupted)
        with pytest.raises(KeyboardInterrupt):
            _swallowed_interrupt(lambda: None)
        check_interrupted()  # forgotten once the block has raised it

        def failed() -> None:  # the solve the interrupt stopped fails: the interrupt, not the failure, ends the run
            raise ComputationError("IPOPT: User_Requested_Stop")

        with pytest.raises(KeyboardInterrupt):
            _swallowed_interrupt(failed)
        with pytest.raises(ComputationError, match="no interrupt"), interruptible():
            raise ComputationError("no interrupt")
    finally:
        signal.signal(signal.SIGINT, previous)


@pytest.mark.parametrize("command", ["synth five_bar.max_gci_miw", "reproduce gao1998 --quick",
                                     "atlas five_bar gci --resolution 5",
                                     "sweep five_bar --indices gci --resolution 5"])
def test_an_out_folder_that_cannot_be_written_exits_2_before_any_work(command, capsys, tmp_path):
    """/proc takes no new folder, whoever asks (root included)."""
    import time

    start = time.perf_counter()
    assert main([*command.split(), "--out", "/proc/pkm-out/run"]) == 2
    assert time.perf_counter() - start < 2.0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "--out '/proc/pkm-out/run' violates: a folder this user can write" in err[0]
    # the trial leaves nothing behind: a command refused after it created no folder
    assert main(["synth", "no_such.problem", "--out", str(tmp_path / "new" / "folder")]) == 2
    assert not (tmp_path / "new").exists()
