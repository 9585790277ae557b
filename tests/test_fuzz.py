"""Generated bad and edge inputs to the command line and the API (issue 13): pkm answers each one with
a result or with its own error, never with a traceback or Python's, numpy's or CasADi's error.

Properties: in-process ``pkm.cli.main`` and the real ``pkm`` executable exit with 0, 1 or 2 and print no
traceback, and a ``--json`` run that exits 0 or 1 prints valid JSON (when it prints); the API returns or
raises a :class:`pkm.PkmError` or :class:`pkm.ComputationError`, and an empty batch gives an empty result.
Hypothesis runs derandomized (a fixed seed), the generated cases ten to an example. Inputs: 600 command lines
of the eight commands with junk and edge values for every option (the scheduler's included), and for ``eval``
and ``index`` with each registered mechanism's own pose width, parameters, bounds, modes, indices and regions;
250 token soups, 400 API calls drawn from each mechanism's widths and names, and 24 listed command lines (4
run by the executable, 20 in-process): 1,274 in all.
Atlases, sweeps, syntheses and reproductions always carry one value they must refuse before any work
(their runs on valid input are tested in test_cli.py, test_atlas.py and test_reproduce.py).
"""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from contextlib import redirect_stderr, redirect_stdout
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from helpers import fuzz
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import pkm
from pkm import registry
from pkm.cli import main
from pkm.errors import ComputationError, PkmError

MECHANISMS = {name: pkm.load(name) for name in pkm.mechanisms()}
PER_EXAMPLE = 10  # cases drawn in one hypothesis example (which costs half a millisecond of its own: seeding, records)
PKM = Path(sys.executable).with_name("pkm")


# ---- values -----------------------------------------------------------------------------------------

EDGE_NUMBERS = ["0", "-0", "1", "-1", "0.5", "-0.3", "1e-300", "1e308", "-1e308", "1e400", "nan", "inf", "-inf",
                "99999999999999999999999", "2.5", "1e9", "0x10", "1_000"]
JUNK = ["", " ", ",", ",,", "=", "x", "None", "[1]", "{}", "--", "-", "a" * 200, "ünï", "r1", "r1=", "=1",
        "r1=1=2", "1,2,3,4,5", "-x", "--x", "'", '"', "\\", "\t"]
text = st.text(max_size=12).filter(lambda s: "\x00" not in s and not s.startswith("-h"))
junk = st.sampled_from(JUNK) | text
number_text = st.sampled_from(EDGE_NUMBERS) | st.floats(allow_nan=True, allow_infinity=True).map(repr)
names = {
    "mechanism": sorted(MECHANISMS),
    "index": sorted({i for m in MECHANISMS.values() for i in m.global_indices()}),
    "mode": sorted({b for m in MECHANISMS.values() for b in m.modes}),
    "region": sorted({r for m in MECHANISMS.values() for r in m.region_names()}),
    "space": sorted({s for m in MECHANISMS.values() for s in m.design_spaces}),
    "parameter": sorted({p.name for m in MECHANISMS.values() for p in m.parameters}),
    "problem": sorted(registry.problems()),
}


def named(kind: str) -> st.SearchStrategy[str]:
    """A name of ``kind`` known to some mechanism, or junk."""
    return st.sampled_from(names[kind]) | junk


design_text = st.one_of(
    st.lists(st.tuples(st.sampled_from(names["parameter"]) | junk, number_text | junk), max_size=4).map(
        lambda items: ",".join(f"{k}={v}" for k, v in items)
    ),
    junk,
)
pose_text = st.one_of(st.lists(number_text, min_size=1, max_size=4).map(",".join), junk)
count = st.sampled_from(["0", "1", "2", "3", "-1", "x", "1.5", "nan", "inf", "1e9", "4002", "1000000",
                         "99999999999999999999"])
refused_count = count.filter(lambda c: c not in ("3",))
refused_starts = st.sampled_from(["0", "-1", "x", "1001", "1e9", "nan", "99999999999999999999"])
fraction = st.sampled_from(["0", "0.5", "1", "-1", "2", "nan", "inf", "-inf", "x", "1e-300"])


# addresses pkm refuses before it tries to connect (a well-formed one would wait for a scheduler)
BAD_ADDRESSES = ["tcp://127.0.0.1", "tcp://127.0.0.1:http", "nonsense", "", "tcp://[::1]:x", "tcp://h:0",
                 "tcp://h:65536", "udp://h:1", "tcp://:8786", "tcp://h:8786/x", *JUNK[:6]]


def own(values) -> st.SearchStrategy[str]:
    """One of a mechanism's own names, or junk."""
    return st.sampled_from(sorted(values)) | junk


def own_pose(mech) -> st.SearchStrategy[str]:
    """A pose of the mechanism's width (numbers at their edges, inside its workspace box or not), or of
    another width."""
    box = mech.workspace_box(mech.design().vector())
    inside = st.tuples(*(st.floats(float(lo), float(hi)).map(repr) for lo, hi in box))
    edges = st.lists(number_text, min_size=mech.n_out, max_size=mech.n_out)
    return st.one_of(inside.map(",".join), edges.map(",".join), pose_text)


def own_design(mech) -> st.SearchStrategy[str]:
    """A design of the mechanism's own parameters with values from their bounds, edges and junk."""
    parameters = mech.parameters
    value = st.sampled_from(parameters).flatmap(lambda p: st.one_of(
        st.just(repr(p.default)), st.just(repr(p.lower)), st.just(repr(p.upper)), number_text, junk
    ).map(lambda v, p=p: f"{p.name}={v}"))
    return st.one_of(st.lists(value, max_size=3).map(",".join), design_text)


def option(flag: str, value: st.SearchStrategy[str]) -> st.SearchStrategy[list[str]]:
    """``[flag, value]``, ``[flag=value]`` or nothing."""
    return st.one_of(st.just([]), value.map(lambda v: [flag, v]), value.map(lambda v: [f"{flag}={v}"]))


def flag(name: str) -> st.SearchStrategy[list[str]]:
    return st.sampled_from([[], [name]])


def outs(folder: Path) -> st.SearchStrategy[list[str]]:
    """--out: a folder, an existing file or a path under one."""
    (folder / "file").write_text("mine\n")
    return st.sampled_from([[], ["--out", str(folder / "o")], ["--out", str(folder / "file")],
                            ["--out", str(folder / "file" / "sub")], ["--out", ""]])


def command_line(folder: Path) -> st.SearchStrategy[list[str]]:
    """A command with junk and edge values for its options, in a shuffled order."""

    def build(command: str, positionals: list[st.SearchStrategy[str]], options: list) -> st.SearchStrategy:
        parts = st.tuples(*positionals, *options, flag("--json"))
        return parts.flatmap(lambda p: st.permutations([
            *[[x] for x in p[: len(positionals)]], *p[len(positionals):]
        ])).map(lambda groups: [command, *[token for group in groups for token in group]])

    axes = junk | design_text.map(lambda t: t.replace("=", "=0.5:"))
    scheduler = option("--scheduler", st.sampled_from(BAD_ADDRESSES))
    grid = [option("--space", named("space")), option("--axes", axes),
            option("--region", named("region")), option("--modes", named("mode")),
            option("--pose-resolution", count), option("--tolerance", fraction), option("--min-points", count),
            option("--min-fraction", fraction), option("--executor", st.sampled_from(["auto", "serial", "x"])),
            outs(folder)]
    # a mechanism's own poses, designs and modes: its widths and names, values at their edges (each mechanism's
    # strategies built once, here: a strategy built in a flatmap is built and validated again at every draw)
    own_eval = {name: build("eval", [st.just(name)], [
        st.lists(option("--pose", own_pose(mech)), max_size=3).map(lambda ps: [t for p in ps for t in p]),
        option("--design", own_design(mech)), option("--mode", own(mech.modes)), flag("--strict"),
    ]) for name, mech in sorted(MECHANISMS.items())}
    own_index = {name: build("index", [st.just(name), own(mech.global_indices())], [
        option("--design", own_design(mech)), option("--mode", own(mech.modes)),
        option("--region", own(mech.region_names())),
        st.sampled_from(["2", "3"]).map(lambda r: ["--resolution", r]), flag("--gradient"),
    ]) for name, mech in sorted(MECHANISMS.items())}
    return st.one_of(
        build("list", [], []),
        build("eval", [named("mechanism")], [
            st.lists(option("--pose", pose_text), max_size=3).map(lambda ps: [t for p in ps for t in p]),
            option("--design", design_text), option("--mode", named("mode")), flag("--strict"),
        ]),
        st.sampled_from(sorted(MECHANISMS)).flatmap(own_eval.__getitem__),
        st.sampled_from(sorted(MECHANISMS)).flatmap(own_index.__getitem__),
        build("build", [junk.filter(lambda k: k not in MECHANISMS)], []),
        build("index", [named("mechanism"), named("index")], [
            option("--design", design_text), option("--mode", named("mode")), option("--region", named("region")),
            st.sampled_from(["1", "2", "3"]).map(lambda r: ["--resolution", r]) | option("--resolution", count),
            option("--margin", fraction), flag("--gradient"),
        ]),
        build("atlas", [named("mechanism"), named("index")],
              [refused_count.map(lambda r: ["--resolution", r]), *grid, scheduler]),
        build("sweep", [named("mechanism")],
              [st.lists(named("index"), max_size=3).map(lambda i: ["--indices", ",".join(i)]),
               refused_count.map(lambda r: ["--resolution", r]), *grid, scheduler]),
        build("synth", [named("problem")], [
            refused_starts.map(lambda s: ["--starts", s]),
            option("--resolution", count), option("--max-iter", count), option("--tol", fraction),
            option("--print-level", count), flag("--verbose"), outs(folder), scheduler,
            option("--set", design_text),
        ]),
        build("reproduce", [junk.filter(lambda k: k not in registry.papers() and k != "all")],
              [flag("--quick"), outs(folder), scheduler]),
    )


TOKENS = ["list", "eval", "index", "atlas", "synth", "reproduce", "sweep", "build", "--scheduler", "tcp://x",
          "--json", "--pose", "--design",
          "--mode", "--region", "--resolution", "--out", "--space", "--modes", "--version", "five_bar", "gci",
          "-0.3,1.9", "--", "-", "--strict", "--gradient", *JUNK[:12]]


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``pkm.cli.main(argv)`` in-process: its exit status, standard output and standard error."""
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as exc:  # argparse's --help and --version
            status = exc.code
    return status, out.getvalue(), err.getvalue()


def check_cli(argv: list[str], status: int, out: str, err: str) -> None:
    assert status in (0, 1, 2), (argv, status, err)
    assert "Traceback" not in err, (argv, err)
    assert "Traceback" not in out, (argv, out)
    if status == 2:
        assert err.startswith("pkm"), (argv, err)
        assert err.count("\n") == 1, (argv, err)
    # --version and --help answer in words whatever else the line holds
    informational = any(token in ("--version", "--help", "-h") for token in argv)
    if "--json" in argv and status in (0, 1) and (out or status == 0) and not informational:
        json.loads(out)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    here = Path.cwd()
    path = tmp_path_factory.mktemp("fuzz")
    os.chdir(path)  # a default --out lands here
    yield path
    os.chdir(here)


def test_the_commands_answer_junk_with_an_exit_status_and_one_line(folder):
    @fuzz(600 // PER_EXAMPLE)
    @given(st.lists(command_line(folder), min_size=PER_EXAMPLE, max_size=PER_EXAMPLE))
    def check(argvs):
        for argv in argvs:
            check_cli(argv, *run_cli(argv))

    check()


@fuzz(250 // PER_EXAMPLE)
@given(st.lists(st.lists(st.sampled_from(TOKENS) | text, max_size=6), min_size=PER_EXAMPLE, max_size=PER_EXAMPLE))
def test_token_soup_gets_an_exit_status_and_no_traceback(argvs):
    for argv in argvs:
        check_cli(argv, *run_cli(argv))


# ---- the API ----------------------------------------------------------------------------------------

scalars = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True), st.integers(min_value=-(10**400), max_value=10**400),
    st.booleans(), st.none(), st.text(max_size=3), st.complex_numbers(allow_nan=True), st.just([]),
    st.just({}),
)
dtypes = st.sampled_from([np.float64, np.int64, np.bool_, np.complex128, np.float32, np.uint8])


@cache
def arrays(width: int) -> st.SearchStrategy:
    """Arrays and array-likes for a parameter of ``width`` columns: good batches (N may be 0) and every
    kind of bad one (built once per width: a strategy is a description, drawing from it is what varies)."""
    good = st.integers(0, 3).flatmap(lambda n: hnp.arrays(
        np.float64, (n, width), elements=st.floats(-3, 3)
    )) | hnp.arrays(np.float64, width, elements=st.floats(-3, 3))
    return st.one_of(
        good,
        hnp.arrays(dtypes, hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=3)),
        st.recursive(scalars, lambda inner: st.lists(inner, max_size=3), max_leaves=8),
        st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=width, max_size=width),
        st.lists(st.floats(-1e300, 1e300), min_size=width, max_size=width),
        st.sampled_from([np.empty((0, width)), np.array([0.1, None] * width, dtype=object), "0.1,1.5",
                         {"x": 0.1}, {0.1, 1.5}, np.ones((1, width), dtype=object)]),
    )


@cache
def designs(mech) -> st.SearchStrategy:
    parameter = st.sampled_from([p.name for p in mech.parameters])
    value = scalars | st.floats(0.01, 5)
    return st.one_of(
        st.none(),
        st.dictionaries(parameter, value, max_size=3),
        st.dictionaries(parameter | scalars.filter(lambda k: isinstance(k, int | str | float)), value, max_size=3),
        st.lists(value, min_size=len(mech.parameters), max_size=len(mech.parameters)),
        arrays(len(mech.parameters)),
        st.sampled_from(["r1=1.2", b"r1", 3, mech.design().vector(), dict(mech.design())]),
    )


def name_like(values: list[str]) -> st.SearchStrategy:
    return _name_like(tuple(values))


@cache
def _name_like(values: tuple[str, ...]) -> st.SearchStrategy:
    junk_names = st.one_of(st.none(), st.text(max_size=6), st.lists(st.sampled_from(list(values)) | st.text(max_size=3),
                           max_size=2), st.dictionaries(st.text(max_size=3), st.integers(), max_size=2),
                           st.integers(), st.binary(max_size=3), st.just(np.array(values[:1])))
    return st.sampled_from(values) | junk_names


def api_call(draw, mech):
    """One public call of ``mech`` with generated arguments: (description, thunk)."""
    pose, q = arrays(mech.n_out), arrays(mech.n_act)
    design = draw(designs(mech))
    mode = draw(name_like(list(mech.modes)))
    method = draw(st.sampled_from([
        "inverse_kinematics", "forward_kinematics", "jacobian", "forward_jacobian", "psi", "singularity",
        "reachable", "local_index", "global_index", "inertia_matrix", "inverse_dynamics", "natural_frequencies",
        "simulate", "design", "statics", "load", "synthesize", "parse_design",
    ]))
    if method in ("inverse_kinematics", "jacobian", "forward_jacobian", "psi", "singularity", "reachable"):
        x = draw(pose)
        return x, lambda: getattr(mech, method)(x, design, mode=mode)
    if method == "forward_kinematics":
        x = draw(q)
        assembly, strict = draw(name_like(list(mech.assemblies))), draw(st.booleans())
        return x, lambda: mech.forward_kinematics(x, design, assembly=assembly, strict=strict)
    if method == "local_index":
        x, name = draw(pose), draw(name_like(list(mech.local_indices())))
        return x, lambda: mech.local_index(name, x, design, mode=mode)
    if method == "global_index":
        name, region = draw(name_like(list(mech.global_indices()))), draw(name_like(list(mech.region_names())))
        options = draw(st.fixed_dictionaries({}, optional={
            "resolution": st.sampled_from([1, 2, 3, 0, -1, 2.5, 10**9, float("inf"), float("nan"), "2", None, True]),
            "gradient": st.booleans(),
            "singularity_margin": st.sampled_from([0.0, 0.5, 1.0, -1.0, float("nan"), "x", None]),
        }))
        options.setdefault("resolution", 2)
        return None, lambda: mech.global_index(name, design, region=region, mode=mode, **options)
    if method == "inertia_matrix":
        x, space = draw(pose), draw(name_like(["task", "actuated", "mixed"]))
        return x, lambda: mech.inertia_matrix(x, design, mode=mode, space=space)
    if method == "inverse_dynamics":
        x, v, a = draw(pose), draw(pose), draw(pose)
        return x, lambda: mech.inverse_dynamics(x, v, a, design, mode=mode)
    if method == "natural_frequencies":
        x = draw(pose)
        return x, lambda: mech.natural_frequencies(x, design, mode=mode)
    if method == "simulate":
        z0 = draw(arrays(2 * mech.n_act))
        times = draw(st.sampled_from([[0.0], [0.1, 0.0], [], "0,1", [0.0, float("nan")], [[0.0, 1.0]], None]))
        method_name = draw(name_like(["adams", "bdf"]))
        return None, lambda: mech.simulate(design, z0=z0, z_dot0=z0, times=times, method=method_name)
    if method == "design":
        partial = draw(st.booleans())
        return None, lambda: mech.design(design, partial=partial)
    if method == "statics":
        if not hasattr(mech, "statics"):
            return None, lambda: None
        x = draw(pose)
        return x, lambda: mech.statics(x, np.zeros(6), design, mode=mode)
    if method == "load":
        name = draw(name_like(names["mechanism"]))
        return None, lambda: pkm.load(name)
    if method == "synthesize":
        problem = draw(name_like(names["problem"]))
        starts = draw(st.sampled_from([0, -1, 10**9, float("inf"), float("nan"), "2", None, 2.5, True]))
        return None, lambda: pkm.synthesize(problem, starts=starts)
    text_design = draw(design_text | scalars)
    return None, lambda: pkm.design.parse_design(text_design)


@fuzz(400 // PER_EXAMPLE)
@given(st.data())
def test_the_api_answers_junk_with_a_result_or_its_own_error(data):
    for _ in range(PER_EXAMPLE):
        mech = MECHANISMS[data.draw(st.sampled_from(sorted(MECHANISMS)))]
        x, call = api_call(data.draw, mech)
        try:
            result = call()
        except (PkmError, ComputationError):
            continue
        if isinstance(x, np.ndarray) and x.dtype == np.float64 and x.ndim == 2 and len(x) == 0:
            assert all(len(a) == 0 for a in (result.values() if isinstance(result, dict) else [result])
                       if isinstance(a, np.ndarray))


# ---- the executable ---------------------------------------------------------------------------------

# the console script: version, a success in JSON, input refused by argparse and by pkm (each run is mostly the
# interpreter's start-up; what the script adds to main is the same for every command line)
EXECUTABLE_RUNS = [
    ["--version"], ["eval", "five_bar", "--pose", "-0.3,1.9", "--json"], ["list", "--color"],
    ["synth", "five_bar.max_gci_miw", "--starts", "0", "--json"],
]
LISTED_RUNS = [
    ["--help"], [], ["eval", "five_bar", "--pose", "3,3", "--strict"],
    ["eval", "five_bar", "--pose", "nan,1", "--json"], ["eval", "six_bar", "--pose", "0,1"],
    ["index", "five_bar", "gci", "--region", "miw", "--resolution", "2", "--gradient", "--json"],
    ["eval", "--help"], ["eval", "five_bar", "--pose", "0.1,1.5,2"], ["eval", "five_bar", "--pose", "3,3", "--json"],
    ["eval", "five_bar", "--pose", "0.1,1.5", "--design", "r1=1e308"],
    ["eval", "five_bar", "--pose", "0.1,1.5", "--design", "r1=1,r1=2", "--json"],
    ["eval", "five_bar", "--pose", "0.1,1.5", "--mode", "sideways"],
    ["index", "five_bar", "gci", "--resolution", "99999999999999999999"],
    ["index", "five_bar", "gci", "--region", "moon", "--json"], ["index", "five_bar", "gci", "--margin", "nan"],
    ["atlas", "five_bar", "gci", "--resolution", "2", "--json"], ["atlas", "five_bar", "gci", "--space", "x"],
    ["sweep", "five_bar", "--indices", "gci,nothing", "--resolution", "3"], ["synth", "nothing"],
    ["reproduce", "gao1998x", "--json"],
]


@pytest.mark.parametrize("argv", LISTED_RUNS, ids=lambda argv: " ".join(argv) or "(no arguments)")
def test_listed_command_lines_answer_with_an_exit_status_and_one_line(argv, folder):
    check_cli(argv, *run_cli(argv))


def test_the_executable_answers_with_an_exit_status_and_no_traceback(tmp_path):
    """The console script itself, two runs at a time (each is mostly interpreter start-up): version, a success,
    input refused by argparse and by pkm; the other listed command lines run in-process."""

    def run(argv: list[str]) -> subprocess.CompletedProcess:
        return subprocess.run([str(PKM), *argv], cwd=tmp_path, capture_output=True, text=True, timeout=120,
                              check=False)

    with ThreadPoolExecutor(max_workers=2) as pool:
        for argv, done in zip(EXECUTABLE_RUNS, pool.map(run, EXECUTABLE_RUNS), strict=True):
            check_cli(argv, done.returncode, done.stdout, done.stderr)
