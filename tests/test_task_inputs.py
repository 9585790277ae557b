"""Nothing runs from a task file, and every input of one is answered: an expression is read into pkm's own
tree (never Python's evaluator), a field of the wrong type, a bound beyond a sane magnitude, a baseline too
large to evaluate, a file that is not UTF-8 TOML and a poses file that is not an array of finite real
numbers are each refused with a ProblemError (or PkmError) naming the field or file and the condition;
`pkm design` then exits 2 with one line. Every IPOPT solve stops at a stated iteration and time limit."""

from __future__ import annotations

import ast
import inspect
import re
import time
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

import pkm
from pkm import io
from pkm.cli import main
from pkm.errors import PkmError
from pkm.synthesis import designer, driver
from pkm.synthesis.designer import MAX_BASELINE_POINTS, MAX_BOUND, ProblemError, design_problem, read_problem

TASK = """
mechanism = "five_bar"
task = {poses = [[-0.1, 1.4], [0.0, 1.4], [0.1, 1.4]]}
variables = {r1 = [1.0, 1.4], r2 = [0.8, 1.2]}
fixed = {r3 = 0.8}
mode = "out_out"
constraints = [{index = "inverse_condition_f_min", lower = 0.05}]
baseline = {kind = "grid", size = 5}
resolution = 4
"""


def _task(tmp_path: Path, change: str = "") -> Path:
    """The task with the line of ``change``'s key replaced by it (or ``change`` added)."""
    key = change.split(" = ", maxsplit=1)[0]
    text = "\n".join(line for line in TASK.splitlines() if not (change and line.startswith(f"{key} =")))
    path = tmp_path / "task.toml"
    path.write_text(f"{text}\n{change}\n")
    return path


def _refused(path, capsys, pattern: str) -> str:
    """``pkm design`` on the task: exit 2, one line on stderr matching ``pattern``; the line."""
    start = time.perf_counter()
    assert main(["design", str(path)]) == 2
    assert time.perf_counter() - start < 10
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert re.search(pattern, err), err
    return err


def test_the_task_read_by_these_tests_is_valid(tmp_path):
    problem = read_problem(_task(tmp_path))
    assert problem.variable_names == ("r1", "r2")


@pytest.mark.parametrize("expression", [
    """r1 + 0*cos("__import__('os').system('touch PWNED')")""",
    "r1 + __import__('os').system('touch PWNED')",
    "r1 + (lambda: 0)()",
    "9**9**9**9",
    "10**10**8",
    "r1**10**8",
])
@pytest.mark.parametrize("field", ["constraints", "derived"])
def test_an_expression_that_would_run_code_or_hang_is_refused_quickly(tmp_path, capsys, monkeypatch, expression,
                                                                      field):
    monkeypatch.chdir(tmp_path)
    literal = f"'''{expression}'''"
    change = (f"constraints = [{{expression = {literal}, upper = 3.0}}]" if field == "constraints"
              else f"derived = {{m1 = {literal}}}")
    path = _task(tmp_path, change)
    name = r"constraints\[0\]" if field == "constraints" else r"derived\.m1"
    with pytest.raises(ProblemError, match=rf"problem field {name} violates: arithmetic of the design parameters"):
        read_problem(path)
    _refused(path, capsys, rf"^pkm: error: problem field {name} violates")
    assert not (tmp_path / "PWNED").exists()


def test_the_designer_never_evaluates_text_as_python():
    """No call of eval, exec or compile in the designer: expressions are pkm.expressions' trees."""
    tree = ast.parse(inspect.getsource(designer))
    calls = {node.func.id for node in ast.walk(tree) if isinstance(node, ast.Call) and isinstance(node.func, ast.Name)}
    assert not calls & {"eval", "exec", "compile", "__import__"}
    assert not hasattr(designer, "FUNCTIONS")
    assert not hasattr(designer, "NUMPY")


def test_an_expression_has_the_same_value_on_numbers_and_on_casadi_symbols():
    """A derived parameter and an expression constraint of every function: numpy on numbers, CasADi on
    symbols, both equal to the closed form."""
    problem = design_problem("five_bar", task={"poses": [[0.0, 1.4]]}, variables={"r1": (1.0, 1.4), "r2": (0.8, 1.2)},
                             derived={"m1": "0.9852 * r1 + sin(pi / 6) * atan(r2) - sqrt(r2**2) / tan(1)"},
                             constraints=[("acos(r2 / 2) + asin(r1 / 2) - cos(r1) * -r2", -10.0, 10.0)],
                             mode="out_out", baseline=("grid", 3), resolution=4)
    names = problem.mechanism.parameter_names()
    r1, r2 = 1.1, 0.9
    m1 = 0.9852 * r1 + np.sin(np.pi / 6) * np.arctan(r2) - np.sqrt(r2**2) / np.tan(1)
    assert float(problem.design([r1, r2])[names.index("m1")]) == pytest.approx(m1, rel=1e-14)
    w = ca.SX.sym("w", 2)
    symbolic = ca.Function("design", [w], [problem.design([w[0], w[1]])])
    assert float(symbolic([r1, r2])[names.index("m1")]) == pytest.approx(m1, rel=1e-14)
    constraint = problem.constraints[0].expression
    expected = np.arccos(r2 / 2) + np.arcsin(r1 / 2) + np.cos(r1) * r2
    values = {n: float(v) for n, v in zip(names, problem.design([r1, r2]), strict=True)}
    assert float(constraint(values)) == pytest.approx(expected, rel=1e-14)
    x = {n: ca.SX.sym(n) for n in names}
    value = ca.Function("c", list(x.values()), [constraint(x)])(*values.values())
    assert float(value) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize(("change", "field"), [
    ("task = 0", "task"),
    ("task = [1, 2]", "task"),
    ('task = {poses = [[0.0, 1.4]], name = "a b"}', "task.name"),
    ('task = {poses = [[0.0, 1.4]], name = 3}', "task.name"),
    ('task = {file = 3}', "task.file"),
    ("fixed = 0", "fixed"),
    ('fixed = ""', "fixed"),
    ("fixed = [0.8]", "fixed"),
    ('fixed = {r3 = "0.8"}', "fixed.r3"),
    ("fixed = {r3 = true}", "fixed.r3"),
    ("fixed = {r3 = nan}", "fixed.r3"),
    ("fixed = {q9 = 0.8}", "fixed"),
    ("derived = 0", "derived"),
    ('derived = "m1 = r1"', "derived"),
    ("derived = {m1 = 0.5}", "derived.m1"),
    ("variables = 0", "variables"),
    ("variables = []", "variables"),
    ("variables = {}", "variables"),
    ('variables = {r1 = "a"}', "variables.r1"),
    ('variables = {r1 = ["1.0", 1.4]}', "variables.r1"),
    ("variables = {r1 = [true, 1.4]}", "variables.r1"),
    ("variables = {r1 = [1.0, inf]}", "variables.r1"),
    ("variables = {r1 = [1.0, 1.4, 1.5]}", "variables.r1"),
    ("variables = {q9 = [1.0, 1.4]}", "variables"),
    ('encoder = "x"', "encoder"),
    ("encoder = [0.001]", "encoder"),
    ('encoder = [0.001, "0.001"]', "encoder"),
    ("encoder = [0.001, -0.001]", "encoder"),
    ('constraints = [{index = "inverse_condition_f_min", lower = "0.05"}]', r"constraints[0].lower"),
    ('constraints = [{index = "inverse_condition_f_min", lower = true}]', r"constraints[0].lower"),
    ('constraints = [{index = "inverse_condition_f_min", lower = nan}]', r"constraints[0].lower"),
    ('constraints = [{index = "inverse_condition_f_min", lower = inf}]', r"constraints[0].lower"),
    ('constraints = [{index = "inverse_condition_f_min", upper = -inf}]', r"constraints[0].upper"),
    ('constraints = [{index = "inverse_condition_f_min", lower = 1e308}]', r"constraints[0].lower"),
    ('constraints = [{index = "inverse_condition_f_min", lower = 1e16}]', r"constraints[0].lower"),
    ('constraints = [{expression = "r1 + r2", upper = -1e16}]', r"constraints[0].upper"),
    ('constraints = [{index = "inverse_condition_f_min", lower = [0.05]}]', r"constraints[0].lower"),
    ("constraints = [{index = 0, lower = 0.05}]", r"constraints[0].index"),
    ("constraints = [{expression = 0, upper = 1.0}]", r"constraints[0].expression"),
    ('constraints = [{expression = ["r1"], upper = 1.0}]', r"constraints[0].expression"),
    ("constraints = [0]", r"constraints[0]"),
    ("constraints = 0", "constraints"),
    ("constraints = {index = 0}", "constraints"),
    ('name = "my task"', "name"),
    ('name = "a__b"', "name"),
    ('name = "a._b"', "name"),
    ('name = "5bar"', "name"),
    ('name = "fünf"', "name"),
    ("name = 0", "name"),
    ("doc = 0", "doc"),
    ("mode = 0", "mode"),
    ('mode = "sideways"', "mode"),
    ("mechanism = 0", "mechanism"),
    ('mechanism = "a\\u0000.toml"', "mechanism"),
    ('task = {file = "a\\u0000.csv"}', "task.file"),
    ('mechanism = "six_bar"', "mechanism"),
    ("objective = 0", "objective"),
    ("objective = {}", "objective"),
    ('objective = {gci = "1"}', "objective.gci"),
    ("objective = {gci = 1e300}", "objective.gci"),
    ("resolution = 1.5", "resolution"),
    ("resolution = true", "resolution"),
    ("resolution = 1000", "resolution"),
    ("baseline = 0", "baseline"),
    ('baseline = {kind = 0, size = 5}', "baseline.kind"),
    ('baseline = {kind = "brute", size = 5}', "baseline.kind"),
    ('baseline = {kind = "grid", size = true}', "baseline.size"),
    ('baseline = {kind = "grid", size = 5.0}', "baseline.size"),
    ('baseline = {kind = "grid", size = 1001}', "baseline.size"),
    ('baseline = {kind = "monte_carlo", size = 1000000000}', "baseline.size"),
    ('baseline = {kind = "grid", size = 5, seed = 1}', "baseline"),
    ('trajectory = {waypoints = [[0.0, 1.4], [0.1, 1.4]], v_max = "1", a_max = 5.0}', "trajectory.v_max"),
    ("trajectory = {waypoints = [[0.0, 1.4], [0.1, 1.4]], v_max = 1.0, a_max = true}", "trajectory.a_max"),
    ("trajectory = {waypoints = [[0.0, 1.4], [0.1, 1.4]], v_max = -1.0, a_max = 5.0}", "trajectory"),
    ('trajectory = {waypoints = "ab", v_max = 1.0, a_max = 5.0}', "trajectory.waypoints"),
    ("trajectory = 0", "trajectory"),
])
def test_a_task_field_of_the_wrong_type_or_magnitude_is_refused_naming_it(tmp_path, capsys, change, field):
    path = _task(tmp_path, change)
    with pytest.raises(ProblemError, match=f"problem field {re.escape(field)} violates: "):
        read_problem(path)
    _refused(path, capsys, f"^pkm: error: problem field {re.escape(field)} violates: ")


@pytest.mark.parametrize(("change", "field"), [
    (f'name = "{"x y" * 10_000}"', "name"),
    (f'variables = {{{"x" * 10_000} = [1.0, 1.4]}}', "variables"),
    (f'fixed = {{{"x" * 10_000} = "a"}}', "fixed.xxx"),
    (f"{'x' * 10_000} = 1", "xxx"),
])
def test_an_echoed_value_or_key_is_shortened(tmp_path, capsys, change, field):
    err = _refused(_task(tmp_path, change), capsys, f"problem field {field}")
    assert len(err) < 400


def test_a_baseline_is_bounded_by_its_count_of_designs():
    """At most MAX_BASELINE_POINTS designs: a grid's nodes (size^variables), Monte Carlo's samples; the
    bound itself is allowed."""
    given = {"task": {"poses": [[0.0, 1.4]]}, "variables": {"r1": (1.0, 1.4), "r2": (0.8, 1.2)}, "constraints": []}
    side = round(MAX_BASELINE_POINTS ** 0.5)
    assert design_problem("five_bar", baseline=("grid", side), **given).baselines[0].resolution == side
    assert design_problem("five_bar", baseline=("monte_carlo", MAX_BASELINE_POINTS), **given).baselines
    for baseline in (("grid", side + 1), ("monte_carlo", MAX_BASELINE_POINTS + 1)):
        with pytest.raises(ProblemError, match=rf"baseline\.size violates: an integer >= 2 with .* <= "
                                               rf"{MAX_BASELINE_POINTS}"):
            design_problem("five_bar", baseline=baseline, **given)


def test_a_bound_is_a_number_within_the_sane_magnitude_or_infinite_for_none():
    """From Python a bound of +-inf on its own side means none; a finite one beyond MAX_BOUND is refused."""
    task = {"poses": [[0.0, 1.4]]}
    variables = {"r1": (1.0, 1.4)}
    problem = design_problem("five_bar", task=task, variables=variables,
                             constraints=[("r1 + r2", -np.inf, MAX_BOUND), ("r1", -MAX_BOUND, np.inf)])
    assert [(c.lower, c.upper) for c in problem.constraints][:2] == [(-np.inf, MAX_BOUND), (-MAX_BOUND, np.inf)]
    for bounds, field in (((2 * MAX_BOUND, np.inf), "lower"), ((np.inf, np.inf), "lower"),
                          ((0.0, -np.inf), "upper"), ((0.0, np.nan), "upper"), ((np.bool_(True), 1.0), "lower")):
        with pytest.raises(ProblemError, match=rf"constraints\[0\]\.{field} violates: a finite number"):
            design_problem("five_bar", task=task, variables=variables, constraints=[("r1 + r2", *bounds)])


def test_a_task_file_that_is_not_utf8_toml_is_refused_naming_the_file(tmp_path, capsys):
    cases = {"latin1.toml": ('mechanism = "f\xfcnf"\n'.encode("latin-1"), "UTF-8 text; byte 14 is not"),
             "broken.toml": (b"mechanism = \n", r"TOML \("),
             "deep.toml": (b"a = " + b"[" * 100_000 + b"]" * 100_000 + b"\n", "TOML"),
             "folder.toml": (None, "cannot be read"),
             "missing.toml": (False, "cannot be read"),
             "nul\0.toml": (False, "cannot be read")}
    for name, (content, condition) in cases.items():
        path = tmp_path / name
        if content is None:
            path.mkdir()
        elif content is not False:
            path.write_bytes(content)
        with pytest.raises(ProblemError, match=f"problem file {re.escape(repr(str(path)))} .*{condition}"):
            read_problem(path)
        _refused(path, capsys, f"^pkm: error: problem file .*{re.escape(repr(name)[1:-1])}")


def test_read_toml_raises_the_given_error_type(tmp_path):
    class OwnError(PkmError):
        pass

    path = tmp_path / "a.toml"
    path.write_bytes(b"\xff")
    with pytest.raises(OwnError, match=r"description file .* violates: UTF-8 text"):
        io.read_toml(path, OwnError, "description file")
    path.write_text('a = 1\nb = "\u00e9"\n', encoding="utf-8")
    assert io.read_toml(path, OwnError) == {"a": 1, "b": "\u00e9"}


NAMES = ("x", "y")
BAD_ARRAYS = {
    "text": (np.array([["0.1", "1.4"]]), "dtype <U3"),
    "dates": (np.array([["2020-01-01", "2020-01-02"]], dtype="datetime64[D]"), "dtype datetime64"),
    "records": (np.zeros(3, dtype=[("x", float), ("y", float)]), r"dtype \["),
    "complex": (np.array([[0.1 + 1j, 1.4]]), "dtype complex128"),
    "booleans": (np.ones((3, 2), dtype=bool), "dtype bool"),
    "nan": (np.array([[0.1, 1.4], [np.nan, 1.4]]), r"finite numbers; row 1 is \[nan, 1.4\]"),
    "inf": (np.array([[0.1, np.inf]]), r"finite numbers; row 0"),
    "shape": (np.zeros((2, 3)), r"rows of 2 values"),
}


@pytest.mark.parametrize("kind", sorted(BAD_ARRAYS))
def test_a_npy_poses_file_that_is_not_finite_real_numbers_is_refused(tmp_path, kind):
    array, condition = BAD_ARRAYS[kind]
    path = tmp_path / "poses.npy"
    np.save(path, array)
    with pytest.raises(PkmError, match=rf"poses file '.*poses\.npy' violates: .*{condition}"):
        io.read_poses(path, NAMES)
    with pytest.raises(ProblemError, match=r"problem field task\.file violates: poses file"):
        design_problem("five_bar", task={"file": str(path)}, variables={"r1": (1.0, 1.4)})


@pytest.mark.parametrize(("text", "condition"), [
    ("x,y,z\n0.1,1.4\n", "a header of the pose's coordinates x, y, exactly; got 'x, y, z'"),
    ("x [m],y [m],z [m]\n0.1,1.4,0.0\n", "a header of the pose's coordinates x, y, exactly"),
    ("y,x\n0.1,1.4\n", "a header of the pose's coordinates x, y, exactly; got 'y, x'"),
    ("x,y\n0.1,nan\n", r"finite numbers; row 0 is \[0.1, nan\]"),
    ("x,y\n0.1,1.4\n\n-inf,1.4\n", r"finite numbers; row 1"),
    ("x,y\n0.1,1.4\n0.1,one\n", "a readable .npy or CSV file of numbers; line 3 is '0.1,one'"),
    ("x,y\n0.1,1.4,2.0\n", r"rows of 2 values \(x, y\); line 2 has 3"),
    ("x,y\n", "rows of 2 values"),
])
def test_a_csv_poses_file_with_another_header_or_non_finite_poses_is_refused(tmp_path, text, condition):
    path = tmp_path / "poses.csv"
    path.write_text(text)
    with pytest.raises(PkmError, match=f"poses file '.*poses.csv' violates: {condition}"):
        io.read_poses(path, NAMES)


def test_a_poses_file_of_integers_or_with_units_is_read(tmp_path):
    np.save(tmp_path / "poses.npy", np.array([[0, 1], [1, 2]], dtype=np.int16))
    assert io.read_poses(tmp_path / "poses.npy", NAMES).tolist() == [[0.0, 1.0], [1.0, 2.0]]
    (tmp_path / "poses.csv").write_text("x [m],y [m]\n0.1,1.4\n\n0.2,1.4\n")
    assert io.read_poses(tmp_path / "poses.csv", NAMES).tolist() == [[0.1, 1.4], [0.2, 1.4]]


def test_every_ipopt_solve_has_an_iteration_and_a_time_limit(tmp_path):
    problem = read_problem(_task(tmp_path))
    options = driver.ipopt_options(problem, verbose=False, max_iter=None, tol=None, print_level=None)["ipopt"]
    assert options["max_iter"] == problem.max_iter <= driver.MAX_ITER
    assert options["max_wall_time"] == options["max_cpu_time"] == driver.MAX_WALL_TIME


def test_a_solve_stopped_by_its_time_limit_reports_its_status(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(driver, "MAX_WALL_TIME", 1e-6)
    path = _task(tmp_path)
    with pytest.raises(driver.SynthesisError, match=r"Maximum_(Wall|Cpu)Time_Exceeded"):
        pkm.synthesize(read_problem(path), progress=False, starts=1)
    assert main(["design", str(path), "--starts", "1"]) == 1
    captured = capsys.readouterr()
    assert re.search("^pkm: computation failed: .*Maximum_(Wall|Cpu)Time_Exceeded", captured.err)
    assert re.search("Maximum_(Wall|Cpu)Time_Exceeded after", captured.out)
