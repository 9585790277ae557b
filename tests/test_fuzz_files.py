"""Generated bad files and requests (issue "Nothing runs from a file"): machine descriptions, task files and the
explorer's HTTP requests are answered with a result or with pkm's own error, never with a traceback, a hang,
a second line of error or a server error.

What is drawn, and how many:

* descriptions, 2,500: the shipped ones (``pkm/models/described/*.toml``, ``examples/delta_chains.toml``)
  mutated one to three times: a value replaced by junk of every TOML type (expressions such as ``1/0``,
  ``sqrt(-1)``, ``tan(pi/2)``, ``9**9**9``, ``~a``, ``__import__("os")``, integer literals beyond a float, or of
  the description's own parameters; huge, unicode and control-character text; numbers at their edges, 0,
  -1, 1e308, nan, inf; booleans; dates; lists and nested tables), a field deleted, added (known, unknown or
  named with control characters), renamed or duplicated, a parameter renamed alone or everywhere (to ``x``,
  ``y``, ``pi``, ``cos``, ``neg``, another parameter's name), a count, a kind, a frame, a mode or a range
  set to a value of its kind. :func:`pkm.schema.describe` returns or raises
  :class:`pkm.schema.DescriptionError`. The first 15 it accepts whose geometry changed are derived (in a
  thread, the derivation's subprocess on the other core) and loaded, and their inverse kinematics at the home
  pose in every working mode returns or raises :class:`PkmError` or :class:`ComputationError`;
* task files, 300: those of ``docs/tasks`` mutated the same way (mechanisms, regions, pose files broken or
  missing, objectives, constraints, derived parameters, baselines, trajectories), written as TOML or broken
  TOML (cut short, not UTF-8, a BOM, a key twice, nested too deep). :func:`read_problem` builds the problem
  (nothing solved) or raises :class:`PkmError`;
* the command line, 250 runs in-process: ``pkm design`` on 100 more task files (``--starts -1``, refused
  after the file is read and before any solve) and ``pkm eval`` on 150 description files (those
  ``describe`` refuses, all but a few: an accepted one would be derived); each exits with 0, 1 or 2,
  without a traceback, with one line on standard error for 2 (a third of them hold a field named with a line
  break, which an error must not echo as it is), and writes nothing outside ``--out``;
* the explorer's server (``pkm explore``, one per test), 300 raw requests over sockets: 100 one at a time,
  half well-formed HTTP with junk fields for each endpoint, half junk throughout (methods, targets, HTTP
  versions, Host and Content-Length headers malformed ('abc', '1.5', '-1', '99999999999999999999'), missing
  or repeated, too many or too long headers, junk JSON bodies), sent whole, after a kept-alive valid request,
  or in part with the connection closed or reset; and 4 bursts of 50 simultaneous connections, three of each
  left half-sent and open. Every answer is a whole HTTP answer below 500 (a method the server does not offer
  gets 501, an HTTP newer than 1.x 505: the protocol's answers), every valid request its 200, the server
  prints no failure and answers a valid request at the end.

3,050 generated files and 300 requests in all; hypothesis runs derandomized (a fixed seed), the files ten to an
example, and nothing is written in the test's folder but its own files.
"""

from __future__ import annotations

import datetime
import io
import json
import math
import os
import pickle
import random
import re
import socket
import struct
import threading
import time
import tomllib
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import redirect_stderr, redirect_stdout, suppress
from functools import cache
from pathlib import Path
from typing import Any
from urllib.parse import quote

import numpy as np
import pytest
from helpers import fuzz
from hypothesis import given, note
from hypothesis import strategies as st

from pkm import expressions
from pkm.cli import main
from pkm.errors import ComputationError, PkmError
from pkm.explore.api import FIELDS
from pkm.spec import machine, schema
from pkm.synthesis.designer import PROBLEM_FIELDS, read_problem

ROOT = Path(__file__).resolve().parent.parent
DESCRIPTION_FILES = [*sorted((ROOT / "pkm" / "models" / "described").glob("*.toml")), ROOT / "examples" /
                     "delta_chains.toml"]
DESCRIPTIONS = {path.stem: tomllib.loads(path.read_text()) for path in DESCRIPTION_FILES}
TASK_FILES = sorted((ROOT / "docs" / "tasks").glob("*.toml"))
TASKS = {path.stem: tomllib.loads(path.read_text()) for path in TASK_FILES}
LOADED_AT_MOST = 15  # accepted mutated descriptions that are derived and loaded (about a second each)
PER_EXAMPLE = 10  # files drawn in one hypothesis example (which costs half a millisecond of its own: seeding, records)


# ---- junk of every TOML type ------------------------------------------------------------------------------

EXPRESSIONS = [
    "1/0", "sqrt(-1)", "tan(pi/2)", "9**9**9", "~a", '"x"', '__import__("os")', "__import__('os').system('x')",
    "1e999", "10**10**8", "0**-1", "(-8)**(1/3)", "acos(2)", "asin(-1.5)", "0/0", "nan", "inf", "-inf", "True",
    "None", "", " ", "(", ")", "1 +", "a.b", "a[0]", "lambda: 0", "[1]", "{}", "cos", "cos(1, 2)", "cos(x=1)",
    "cos()", "pi(1)", "f(1)", "exp(1)", "log(0)", "1 if 1 else 0", "1 < 2", "not 1", "1 and 2", "2 % 3", "2 // 3",
    "2 @ 3", "2 ^ 3", "2 << 3", "(x := 1)", "*a", "a, b", "1j", "sqrt(1j)", "'a'", 'b"x"', "...", "\x00", "1\n2",
    "\t1", "\u0661", "2\u00b2", "\uff58", "\u03c0", "\u00e9", "x" * 1001, "-" * 500 + "1", "(" * 200 + "1" + ")" * 200,
    "+".join(["1"] * 600), "1" * 400, "1" + "0" * 400, "0x10", "0b1", "1_0", "1e-400", "pi**pi**pi**pi", "neg(1)",
    "neg", "pi", "x", "y", "z", "phi", "q1", "atan(1e308)*1e308", "2**64", "2**65", "2**-65", "-(2**64)", "pi/2",
    "0", "-1", "1e308*10", "sin(1e308)", "tan(1e300)", "sqrt(0)", "1/sqrt(0)", "acos(1)", "0**0", "(-1)**0.5",
    "cos(cos(cos(cos(1))))", "((((((((((((((((((((((1))))))))))))))))))))))", "2**2**2**2**2", "1e308+1e308",
    "9" * 309, "1" * 308 + ".0", "0." + "0" * 400 + "1", "2**1023*2", "-" + "9" * 400, "1e-324", "4.9e-324",
]
NUMBERS = [0, -0.0, 1, -1, 0.5, -0.5, 2, 3, 6, 12, 13, 64, 65, 1e-300, 5e-324, 1e15, 1e16, 1e308, -1e308,
           math.nan, math.inf, -math.inf, 2**53, 2**53 + 1, 2**63 - 1, -(2**63), 1.0, 3.0, 0.9, 1.5, 1000000]
DATES = [datetime.datetime(1979, 5, 27, 7, 32), datetime.date(1979, 5, 27), datetime.time(7, 32),
         datetime.datetime(1979, 5, 27, 7, 32, tzinfo=datetime.UTC)]
TEXTS = ["", " ", "x", "\u00fc\u00f1\u00ef", "\U0001f600", "a" * 65, "a" * 2001, "x" * 100_000, "R b", "1a",
         "__class__", "legs ", "reachable", "assembled", "tangent", "radial", "disc", "box", "chain", "RR", "UPS",
         "spatial", "planar", "\x7f", "\\", '"', "'", "\n", "a.b", "five_bar", "gci", "task", "nothing.toml"]
KEYS = [*sorted({"name", "doc", "frame", "parameters", "conditions", "legs", "home", "characteristic_length", "modes",
               "regions", "platform", "gravity", "default", "lower", "upper", "unit", "kind", "count", "base",
               "proximal", "distal", "axis", "zero", "range", "bodies", "cone", "arm", "rod", "joints", "branches",
               "turn", "newton", "type", "link", "actuated", "body", "axes", "rotor", "circle", "start", "pairs",
               "mass", "centre", "inertia", "shape", "coordinates", "size", "margin", "slider", "cylinder", "piston",
               *PROBLEM_FIELDS, "poses", "file", "index", "expression", "joint", "joint_range", "effort",
               "waypoints", "v_max", "a_max", "durations", "weight"}),
        "", "x", "\u00fc", "a b", "__class__", "1", "a" * 100, "Name"]
CONTROL_KEYS = ["a\nb", "\r\n", "x\ty", "\x1b[2J", "\u2028", "a\x00b", "\n" * 3]  # keys an error may echo
KEYS += CONTROL_KEYS
scalars = st.one_of(
    st.sampled_from(EXPRESSIONS), st.sampled_from(NUMBERS), st.sampled_from(TEXTS), st.booleans(),
    st.sampled_from(DATES), st.text(max_size=12), st.integers(-(2**63), 2**63 - 1),
    st.floats(allow_nan=True, allow_infinity=True),
)
LISTS = [[], [0], [[]], ["a", 1], [math.nan], [0, 0], [0, 0, 0], [1, -1], [1, 1, 1], [-1, -1, -1],
         ["pi", "0"], [0.0, 1.4], [[0.0, 1.4], [0.1, 1.4]], [0] * 10_000, [[[[[[[[[[1]]]]]]]]]], [{}], [{"a": 1}],
         [True, False], [DATES[0]]]
TABLES = [{}, {"a": 1}, {"circle": "R"}, {"circle": "1", "start": "0", "pairs": "0.3"}, {"mass": 1},
          {"mass": "1", "centre": 0, "inertia": 0}, {"": ""}, {"x": {"y": {"z": 1}}}, {"kind": "RR"},
          {"shape": "disc", "centre": [0, 0], "size": [1]}, {"type": "R"}, {"type": "S"}, {"poses": [[0.0, 1.4]]},
          {"waypoints": [[0.0, 1.4], [0.1, 1.4]], "v_max": 1.0, "a_max": 1.0},
          {"waypoints": [[0.0, 1.4], [0.1, 1.4]], "durations": [1.0]}, {"joint": "theta1"}, {"effort": [0, -1]}]
junk_values = st.recursive(
    scalars | st.sampled_from(LISTS) | st.sampled_from(TABLES),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.sampled_from(KEYS) | st.text(max_size=4),
                                                                inner, max_size=3),
    max_leaves=6,
)


@cache
def parametric(names: tuple[str, ...]) -> st.SearchStrategy[str]:
    """Expressions of a description's own parameters that are undefined, zero, huge or complex at its
    defaults, or fine (built once per parameter list: drawing is what varies)."""
    templates = ["{p}/0", "1/({p}-{p})", "sqrt(-{p})", "{p}**65", "{p}**64", "{p}**(1/2)", "{p}*1e308*1e308",
                 "acos({p}+2)", "tan(pi/2*{p}/{p})", "-{p}", "0*{p}", "{p}**{p}**{p}", "{p} - {p}", "{p}",
                 "2*{p}", "{p} + {q}", "{p}/{q}", "sqrt({p} - {q})", "asin({p}*100)", "{p}(1)", "{p}.real",
                 "{p}[0]", "{p}**-70", "(-{p})**0.5", "log({p})", "{p} + undefined_name", "{p} + " + "9" * 400,
                 "{p}*1e-400", "{p}**2**6", "cos({p})**-64"]
    return st.tuples(st.sampled_from(templates), st.sampled_from(names), st.sampled_from(names)).map(
        lambda t: t[0].format(p=t[1], q=t[2]))


@cache
def junk_or_parametric(names: tuple[str, ...]) -> st.SearchStrategy[Any]:
    return junk_values | parametric(names)


@cache
def expression_like(names: tuple[str, ...]) -> st.SearchStrategy[str]:
    return parametric(names) | st.sampled_from(EXPRESSIONS)


PARAMETER_NAMES = ["x", "y", "z", "phi", "pi", "cos", "sin", "tan", "sqrt", "asin", "acos", "atan", "neg", "e",
                   "q1", "", "1a", "a" * 65, "\u00fc", "\u03c0", "R b", "__class__", "__import__", "reachable",
                   "True", "None", "lambda", "if", "R", "r", "L_a", "r_p", "l1", "theta"]


# ---- mutating a document (a TOML table as Python data) -----------------------------------------------------

Location = tuple[Any, ...]


def locations(value: Any, prefix: Location = (), out: dict[Location, Any] | None = None) -> dict[Location, Any]:
    """Every value of a document by its location: its keys and indices from the top."""
    out = {} if out is None else out
    if isinstance(value, dict):
        items = value.items()
    elif isinstance(value, list) and len(value) <= 100:
        items = enumerate(value)
    else:
        return out
    for key, item in items:
        out[(*prefix, key)] = item
        locations(item, (*prefix, key), out)
    return out


def fresh(document: Any) -> Any:
    """A copy of a shipped document to mutate, or of a value to put in one (pickle's copy is deepcopy's, ten
    times faster on the long lists of junk)."""
    return pickle.loads(pickle.dumps(document))


def at(document: Any, location: Location) -> Any:
    for key in location:
        document = document[key]
    return document


def tables(values: dict[Location, Any]) -> list[Location]:
    """The tables of a document by :func:`locations`, the top one first."""
    return [()] + [s for s, v in values.items() if isinstance(v, dict)]


def pick(rng: random.Random, spots: list[Location]) -> Location:
    """One of ``spots``, each top-level field as likely as another (a description's parameters hold most of
    its values)."""
    groups: dict[Any, list[Location]] = {}
    for spot in spots:
        groups.setdefault(spot[:1], []).append(spot)
    return rng.choice(groups[rng.choice(list(groups))])


def rename_parameter(rng: random.Random, document: dict[str, Any], names: tuple[str, ...]) -> tuple:
    """A parameter renamed in every text of the document, its uses included (to a pose coordinate's name,
    a function's, a constant's, or another parameter's)."""
    old, new = rng.choice(names), rng.choice(PARAMETER_NAMES + list(names))
    word = re.compile(rf"\b{re.escape(old)}\b")

    def renamed(value: Any) -> Any:
        if isinstance(value, str):
            return word.sub(new, value)
        if isinstance(value, dict):
            return {k: renamed(v) for k, v in value.items()}
        return [renamed(v) for v in value] if isinstance(value, list) else value

    document.update(renamed(document))
    return ("rename everywhere", old, new)


OPERATIONS = ["replace", "replace", "expression", "delete", "add", "rename", "duplicate", "name", "everywhere",
              "structure", "structure"]


def mutate(draw, document: dict[str, Any], names: Sequence[str], *, loud: bool = False) -> list[tuple]:
    """One to three mutations of ``document`` in place, the mutations returned (the reproducer); ``loud``:
    a third of the time a field named with control characters too (which an error on the command line, one
    line, must not echo as they are). The values are hypothesis's draws; the operations and places come from
    one generator seeded by a draw (a draw costs hypothesis some 25 microseconds, and a case makes about twenty
    choices of place)."""
    names = tuple(names)
    rng = draw(st.randoms(use_true_random=True))
    done = []
    for _ in range(rng.randint(1, 3)):
        values = locations(document)
        operation = rng.choice(OPERATIONS)
        if operation in ("replace", "delete") and values:
            spot = pick(rng, list(values))
            parent = at(document, spot[:-1])
            if operation == "delete":
                del parent[spot[-1]]
                done.append(("delete", spot))
            else:
                parent[spot[-1]] = value = fresh(draw(junk_or_parametric(names)))
                done.append(("replace", spot, value))
        elif operation == "expression" and (expressions_at := [
                s for s, v in values.items() if isinstance(v, str | int | float) and not isinstance(v, bool)]):
            spot = pick(rng, expressions_at)
            at(document, spot[:-1])[spot[-1]] = value = draw(expression_like(names))
            done.append(("replace", spot, value))
        elif operation == "add":
            spot = pick(rng, tables(values))
            key, value = rng.choice(KEYS), fresh(draw(junk_or_parametric(names)))
            at(document, spot)[key] = value
            done.append(("add", (*spot, key), value))
        elif operation == "rename" and (inner := tables(values)[1:]):
            spot = pick(rng, inner)
            table = at(document, spot)
            if table:
                old = rng.choice(list(table))
                new = rng.choice(KEYS)
                table[new] = table.pop(old)
                done.append(("rename", (*spot, old), new))
        elif operation == "duplicate" and (lists := [s for s, v in values.items() if isinstance(v, list) and v]):
            spot = pick(rng, lists)
            items = at(document, spot)
            items.append(fresh(rng.choice(items)))
            done.append(("duplicate", spot))
        elif operation == "name" and (named := [s for s in values if s[-1] == "name" and (
                len(s) == 1 or isinstance(values[s[:-1]], dict))]):
            spot = rng.choice(named)
            at(document, spot[:-1])["name"] = value = rng.choice(PARAMETER_NAMES + list(names))
            done.append(("replace", spot, value))
        elif operation == "everywhere" and names:
            done.append(rename_parameter(rng, document, names))
        elif operation == "structure":
            done += structure(rng, document, values)
    if loud and not rng.randrange(3):
        spot = pick(rng, tables(locations(document)))
        key = rng.choice(CONTROL_KEYS)
        at(document, spot)[key] = 1
        done.append(("add", (*spot, key), 1))
    return done


STRUCTURE = {
    "count": [0, 1, 2, 3, 4, 5, 6, 7, 12, 13, -1, 2**63 - 1, 1.0, 3.0, True, "3", math.nan],
    "frame": ["planar_point", "planar", "spatial_point", "spatial", "Planar", "", 2],
    "kind": ["RR", "RPR", "PRR", "R_parallelogram", "UPS", "chain", "rr", ""],
    "type": ["R", "P", "U", "S", "parallelogram", "X", ""],
    "shape": ["disc", "rectangle", "box", "cylinder", "sphere", ""],
    "actuated": [True, False, 1, "true"],
    "newton": [True, False, 0],
    "modes": [{}, {"a": [1]}, {"a": [1, -1, 1]}, {"a": [1.0, 1.0, 1.0]}, {"a": [True, True, True]},
              {"a": [2, 2, 2]}, {"": [1, 1, 1]}, {"a": [1, 1, 1], "b": [1, 1, 1]}, [1, 1, 1]],
    "home": [[], [0], [0, 0], [0, 0, 0], [0, 0, -0.45], [0, 0, 1.0, 0, 0, 0], [0, 0, 100], ["nan", 0, 0],
             [0, 0, 0, 0, 0, 0, 0], "0,0,0"],
    "axis": ["x", "y", "z", "phi", "tangent", "radial", [0, 0, 0], [0, 0, 1], [0, 1], [1, 0], ""],
    "zero": ["radial", "tangent", [0, 0, 0], [1, 0, 0]],
    "coordinates": [["x"], ["x", "y"], ["x", "x"], ["x", "y", "z"], ["y", "x"], ["x", "y", "phi"], ["q1", "y"]],
    "range": [[0, 0], [1, 0], ["-pi", "pi"], [0], [0, 1, 2], ["l_max", "l_min"], [-1e308, 1e308]],
    "pairs": ["0", "pi", "2*pi", "-1", 0],
    "branches": [{}, {"a": []}, {"a": [0, 0, 0]}, {"a": [0, 2.3, 0], "b": [0, -2.3, 0], "c": [0, 0, 0]},
                 {"1a": [0, 0, 0]}, {"a": [math.nan, 0, 0]}],
    "joints": [[], [{"type": "S"}], [{"type": "R", "actuated": True}], [{"type": "P", "axis": [1, 0, 0]}]],
    "size": [[0], [0, 0], [-1, 1], [1e308, 1e308, 1e308], [0.1, 0.1, 0.1]],
    "centre": [[0, 0], [0, 0, 0], [math.inf, 0, 0], 0],
    "default": [0, -1, 1e308, 5, 10, math.nan],
    "lower": [0, -1, 1e308, -1e308, 5, math.inf],
    "upper": [0, -1, 1e308, 0.01, 5, math.inf],
    "resolution": [1, 2, 64, 65, 0, -1, 2.5, True, "8"],
    "mechanism": ["five_bar", "delta", "stewart", "rrr3", "nothing", "", "five_bar.toml", "x.toml", ".toml",
                  str(ROOT / "examples" / "delta_chains.toml"), "bad_description.toml", "\x00.toml", "/", "..toml"],
    "file": ["five_bar_path.csv", "empty.csv", "nan.csv", "header.csv", "wide.csv", "text.csv", "bad.npy",
             "missing.csv", ".", "/dev/null", "five_bar_path.toml", "\x00", "", "x" * 300],
    "objective": ["gci", "kappa_d_mean", "workspace_margin_min", "nothing", "effort_peak", "energy",
                  "inverse_condition_f_min", "inverse_condition_f_max", {}, {"gci": 1.0, "nothing": 1.0},
                  {"gci": math.nan}, {"gci": 1e16}],
    "variables": [{}, {"r1": [1.0, 1.4]}, {"r1": [1.4, 1.0]}, {"r1": [0, 1e308]}, {"nothing": [0, 1]},
                  {"r1": [1.0, 1.4, 1.8]}, {"r1": 1.0}, {"r1": ["a", "b"]}],
    "baseline": [{"kind": "grid", "size": 1001}, {"kind": "grid", "size": 2}, {"kind": "monte_carlo",
                 "size": 1000001}, {"kind": "x"}, {"size": True}, {"kind": "grid", "size": 2.0}],
    "task": ["task", "miw", "reachable", "assembled", "nothing", {"file": "five_bar_path.csv"},
             {"poses": []}, {"poses": [[0.0, 1.4], [0.1]]}, {"shape": "disc", "centre": [0, 1.4], "size": [0]},
             {"shape": "cylinder", "centre": [0, 0, 0], "size": [0.1, 0.1], "axis": "q"}],
    "constraints": [[], [{}], [{"index": "gci", "expression": "r1"}], [{"expression": "r1 + r2", "upper": 1e16}],
                    [{"joint": "nothing", "upper": 1.0}], [{"joint_range": "theta1", "upper": -1.0}],
                    [{"effort": [0.0], "upper": 1.0}], [{"index": "gci", "lower": 1.0, "upper": 0.0}],
                    [{"expression": "__import__('os')", "lower": 0}], [{"index": "gci_min", "lower": math.nan}],
                    [{"expression": "r1 + " + "9" * 400, "upper": 1.0}], [{"expression": "r1**1e9", "upper": 1.0}]],
    "derived": [{}, {"r3": "r1 + r2"}, {"r1": "r2"}, {"r3": "1/0"}, {"r3": "sqrt(-1)"}, {"nothing": "1"},
                {"r3": "r3"}, {"r3": "__import__('os')"}, {"r3": 1.0}, {"r3": "1" + "0" * 400}],
    "trajectory": [{"waypoints": [[0.0, 1.4], [0.1, 1.4]], "v_max": 1.0, "a_max": 1.0},
                   {"waypoints": [[0.0, 1.4], [0.1, 1.4]], "durations": [0.0]},
                   {"waypoints": [[0.0, 1.4]], "v_max": 1.0, "a_max": 1.0},
                   {"waypoints": [[0.0, 1.4], [0.1, 1.4]], "v_max": 0.0, "a_max": -1.0},
                   {"waypoints": [[0.0, 1.4], [0.0, 1.4]], "durations": [1.0]}, {}],
    "encoder": [[1e-3, 1e-3], [0, 0], [1e-3], [-1, 1]],
    "mode": ["out_out", "elbow_out", "nothing", "", 1],
}


def structure(rng: random.Random, document: dict[str, Any], values: dict[Location, Any]) -> list[tuple]:
    """A field that shapes the rest (a count, a kind, a frame, a mode, a file's field) set to a value of its
    own kind, valid or not (``values``: the document's :func:`locations`)."""
    spots = [s for s in values if isinstance(s[-1], str) and s[-1] in STRUCTURE]
    spot = pick(rng, spots) if spots and rng.randrange(5) else (rng.choice(sorted(STRUCTURE)),)
    value = fresh(rng.choice(STRUCTURE[spot[-1]]))
    at(document, spot[:-1])[spot[-1]] = value
    return [("replace", spot, value)]


# ---- descriptions ------------------------------------------------------------------------------------------

@pytest.fixture
def folder(tmp_path):
    """The test's working folder, which must stay as the test leaves it (nothing written by pkm)."""
    here = Path.cwd()
    os.chdir(tmp_path)
    yield tmp_path
    os.chdir(here)


def files(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")}


def home_pose(description: schema.Description) -> np.ndarray:
    design = {p["name"]: p["default"] for p in description.data["parameters"]}
    return np.array([float(expressions.evaluate(h, design)) for h in description.data["home"]])


def shape(data: Any) -> Any:
    """A normalised description without its name and texts: what its derivation and kinematics read."""
    if isinstance(data, dict):
        return {k: shape(v) for k, v in data.items() if k not in ("doc", "unit", "key")}
    return [shape(v) for v in data] if isinstance(data, list) else data


SHIPPED = {repr(shape({**schema.describe(raw).data, "name": ""})) for raw in DESCRIPTIONS.values()}


def derive_and_solve(raw: dict[str, Any]) -> None:
    """The mechanism of an accepted description, loaded, and its inverse kinematics at the home pose in every
    working mode: a result or pkm's own error."""
    try:
        mech = machine.load(raw)
        x = home_pose(mech.description)
        for mode in mech.modes:
            mech.inverse_kinematics(x, mode=mode)
    except (PkmError, ComputationError):
        pass


def test_mutated_descriptions_are_described_or_refused_and_the_first_accepted_load(folder):
    """The first accepted descriptions whose geometry changed are derived and solved in a thread of their own
    (the derivation is a subprocess, on the other core) while the fuzzing goes on."""
    loads: list[tuple[str, Any]] = []

    with ThreadPoolExecutor(max_workers=1) as pool:

        def one(data) -> None:
            name = data.draw(st.sampled_from(sorted(DESCRIPTIONS)))
            raw = fresh(DESCRIPTIONS[name])
            names = [p["name"] for p in raw["parameters"]]
            case = f"{name} mutated: {mutate(data.draw, raw, names)!r}"
            note(case)
            try:
                description = schema.describe(raw)
                json.loads(json.dumps(description.data))  # the derivation reads it as JSON
                assert len(description.key) == 64
            except schema.DescriptionError:
                return
            if len(loads) < LOADED_AT_MOST and repr(shape({**description.data, "name": ""})) not in SHIPPED:
                loads.append((case, pool.submit(derive_and_solve, fresh(raw))))

        @fuzz(2500 // PER_EXAMPLE)
        @given(st.data())
        def check(data):
            for _ in range(PER_EXAMPLE):
                one(data)

        check()
        for case, load in loads:
            try:
                load.result(timeout=machine.DERIVATION_SECONDS + 60)
            except Exception as exc:
                raise AssertionError(f"{case}: loading raised {exc!r}") from exc
    assert len(loads) == LOADED_AT_MOST  # mutations that keep a description valid are among those drawn
    assert files(folder) == set()


# ---- task files --------------------------------------------------------------------------------------------

def toml_string(text: str) -> str:
    """A TOML basic string: control characters, quotes and backslashes escaped."""
    escaped = "".join(f"\\u{ord(c):04X}" if ord(c) < 0x20 or ord(c) == 0x7F else "\\" + c if c in '"\\' else c
                      for c in text)
    return f'"{escaped}"'


def toml_value(value: Any) -> str:
    """A value as TOML text: inline arrays and tables, every key quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, datetime.datetime | datetime.date | datetime.time):
        return value.isoformat()
    if isinstance(value, list):
        return "[" + ", ".join(map(toml_value, value)) + "]"
    return "{" + ", ".join(f"{toml_string(k)} = {toml_value(v)}" for k, v in value.items()) + "}"


def toml_document(document: dict[str, Any]) -> str:
    return "".join(f"{toml_string(k)} = {toml_value(v)}\n" for k, v in document.items())


def test_the_toml_writer_writes_what_tomllib_reads():
    for document in [*TASKS.values(), *DESCRIPTIONS.values(), {"a": [DATES, TEXTS, NUMBERS, LISTS, TABLES]},
                     dict.fromkeys(CONTROL_KEYS, 1)]:
        assert repr(tomllib.loads(toml_document(document))) == repr(document)  # nan as nan


POSES_FILES = {"empty.csv": "", "nan.csv": "x [m],y [m]\nnan,1.4\n", "header.csv": "x [m],y [m]\n",
               "wide.csv": "x,y,z\n0,1.4,0\n", "text.csv": "x,y\na,b\n", "bad.npy": "\x93NUMPY junk"}


def task_folder(folder: Path) -> None:
    """The files a task may name: the path of docs/tasks, broken pose files and a description refused."""
    (folder / "five_bar_path.csv").write_text((ROOT / "docs" / "tasks" / "five_bar_path.csv").read_text())
    for name, text in POSES_FILES.items():
        (folder / name).write_text(text)
    (folder / "bad_description.toml").write_text('name = "bad"\nframe = "planar"\n')
    (folder / "out").mkdir()
    (folder / "task.toml").write_text("")  # each case's file


def broken(draw, text: str) -> str | bytes:
    """The file's text, or cut short, with bytes that are not UTF-8, a BOM, a key twice, a table nested too
    deep or a line of junk."""
    how = draw(st.sampled_from(["as is"] * 6 + ["cut", "bytes", "bom", "twice", "deep", "junk"]))
    if how == "cut":
        return text[: draw(st.integers(0, max(len(text) - 1, 0)))]
    if how == "bytes":
        return text.encode() + b"\xff\xfe\x80"
    if how == "bom":
        return "\ufeff" + text
    if how == "twice":
        return text + text.splitlines()[0] + "\n" if text else text
    if how == "deep":
        return text + "deep = " + "[" * 5000 + "]" * 5000 + "\n"
    if how == "junk":
        return text + draw(st.sampled_from(["[", "x", "= 1", "[[a]]\n[a]", "a = 1979-13-45", '"\\q" = 1']))
    return text


def write(path: Path, text: str | bytes) -> None:
    """A case's file, a new one where the last case's was (ext4 writes back a file cut short and rewritten in
    place at its close: a millisecond or more a case while the disk is busy)."""
    path.unlink(missing_ok=True)
    path.write_bytes(text if isinstance(text, bytes) else text.encode())


def task_case(draw, folder: Path, *, loud: bool = False) -> tuple[Path, list[tuple]]:
    """A task file of docs/tasks mutated (:func:`mutate`) and written as TOML (or broken TOML) in ``folder``."""
    name = draw(st.sampled_from(sorted(TASKS)))
    document = fresh(TASKS[name])
    names = sorted({*document.get("variables", {}), *document.get("fixed", {}), *document.get("derived", {})})
    mutations = mutate(draw, document, names or ["x"], loud=loud)
    text = broken(draw, toml_document(document))
    path = folder / "task.toml"
    write(path, text)
    return path, [name, *mutations, text[-60:]]


def test_mutated_task_files_build_a_problem_or_are_refused(folder):
    task_folder(folder)
    before = files(folder)

    @fuzz(300 // PER_EXAMPLE)
    @given(st.data())
    def check(data):
        for _ in range(PER_EXAMPLE):
            path, case = task_case(data.draw, folder)
            note(f"task file: {case!r}")
            with suppress(PkmError):
                read_problem(path)

    check()
    assert files(folder) == before


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with redirect_stdout(out), redirect_stderr(err):
        try:
            status = main(argv)
        except SystemExit as exc:
            status = exc.code
    return status, out.getvalue(), err.getvalue()


def check_cli(case: Any, status: int, out: str, err: str) -> None:
    """An exit status of 0, 1 or 2, no traceback, and one line on standard error for 2."""
    assert status in (0, 1, 2), (case, status, err)
    assert "Traceback" not in err + out, (case, err)
    if status == 2:
        assert err.startswith("pkm"), (case, err)
        assert len(err.splitlines()) == 1, (case, err)  # a line break of any kind (\r, \u2028) echoed is one more


def test_pkm_design_answers_mutated_task_files_with_an_exit_status_and_one_line(folder):
    task_folder(folder)
    before = files(folder)

    @fuzz(100 // PER_EXAMPLE)
    @given(st.data())
    def check(data):
        for _ in range(PER_EXAMPLE):
            path, case = task_case(data.draw, folder, loud=True)
            note(f"task file: {case!r}")
            argv = ["design", str(path), "--starts", "-1", "--out", str(folder / "out"),
                    *data.draw(st.sampled_from([[], ["--json"], ["--resolution", "4"], ["--resolution", "x"]]))]
            check_cli(case, *run_cli(argv))
            assert {f for f in files(folder) - before if not f.startswith("out/")} == set()

    check()


def test_pkm_eval_answers_mutated_description_files_with_an_exit_status_and_one_line(folder):
    """A description file where a command names a mechanism; those it refuses (the first test derives
    accepted ones)."""
    path = folder / "machine.toml"
    path.write_text("")

    @fuzz(150 // PER_EXAMPLE)
    @given(st.data())
    def check(data):
        for _ in range(PER_EXAMPLE):
            name = data.draw(st.sampled_from(sorted(DESCRIPTIONS)))
            raw = fresh(DESCRIPTIONS[name])
            case = (name, mutate(data.draw, raw, [p["name"] for p in raw["parameters"]], loud=True))
            note(f"{case!r}")
            text = broken(data.draw, toml_document(raw))
            write(path, text)
            try:
                schema.read(path)
                continue
            except schema.DescriptionError:
                pass
            argv = ["eval", str(path), "--pose", "0,0,0", *data.draw(st.sampled_from([[], ["--json"]]))]
            check_cli(case, *run_cli(argv))

    check()
    assert files(folder) == {"machine.toml"}


# ---- the explorer's server ---------------------------------------------------------------------------------

TIMEOUT = 20.0  # seconds a connection waits for the server's answer: longer is a hang
FIELD_NAMES = ["index", "region", "space", "axes", "design", "resolution", "mode", "problem", "indices", "plane",
               "held", "arrays", "pose", "x", ""]
FIELD_VALUES = ["", "gci", "gci_2", "miw", "reachable", "assembled", "out_out", "out_in", "nothing", "r1=0.5",
                "r1=0.5,r2=0.9,r3=0.6", "r1=1e308", "r1=nan", "r1=-1", "r1=", "=", "r1=0.5:1.5,r2=0.5:1.5",
                "r1=1:0,r2=0:1", "3", "4", "81", "82", "256", "257", "2", "0", "-1", "1e9", "nan", "inf",
                "99999999999999999999", "0,1.4", "-0.3,1.9", "nan,nan", "0", "x,y", "y,x", "x,x", "base64", "list",
                "x=0.1", "\u00fc", "9" * 1000, "%00", "%ZZ", "a" * 10_000]
PATHS = ["/", "/explore.js", "/explore.css", "/favicon.ico", "/api/", "/api", "/api/nothing", "/api/stop",
         "/api/stop?x=1", "//api/mechanism", "*", "http://127.0.0.1/api/mechanism", "/%00", "/../../etc/passwd",
         "/api/../explore.js", "/api/mechanism/", "/API/mechanism", "/api/mechanism#x", "", "/?" + "a" * 70_000,
         "/api/map?" + "&".join(["design=r1%3D0.5"] * 2), "/api/\u00fc"]
METHODS = ["GET", "GET", "GET", "POST", "POST", "HEAD", "PUT", "DELETE", "OPTIONS", "PATCH", "TRACE", "CONNECT",
           "get", "G E T", "X" * 100, "\u0413\u0415\u0422", ""]
VERSIONS = ["HTTP/1.1", "HTTP/1.1", "HTTP/1.1", "HTTP/1.0", "HTTP/0.9", "HTTP/2.0", "HTTP/1.1.1", "HTTP/x.y", "",
            "http/1.1", "HTTP/01.1", "HTTP/1.10", "HTTP/" + "1" * 11 + ".1", "HTTP/1.1 x"]
LENGTHS = ["abc", "1.5", "-1", "99999999999999999999", "", "0x10", " 2 ", "+2", "\u0662", "9" * 5000, "65537", "0",
           "1"]
BODIES = [b"", b"{}", b"[]", b"null", b'{"a":', b"\xff\xfe", b'{"stop": true}', b"x" * 70_000, b"GET / HTTP/1.1\r\n",
          b'{"a": ' * 1000, b"\x00" * 10]


def target(draw) -> str:
    """A request's target: a known or junk path, or an endpoint with drawn fields (mostly its own), encoded or
    raw."""
    if not draw(st.integers(0, 3)):
        return draw(st.sampled_from(PATHS))
    endpoint = draw(st.sampled_from([*FIELDS, "nothing", ""]))
    names = st.sampled_from(FIELDS.get(endpoint) or FIELD_NAMES) if draw(st.integers(0, 3)) else st.sampled_from(
        FIELD_NAMES)
    fields = draw(st.lists(st.tuples(names, st.sampled_from(FIELD_VALUES) | st.text(max_size=8)), max_size=4))
    encode = draw(st.sampled_from([lambda v: quote(v, safe=""), lambda v: v]))
    return f"/api/{endpoint}?" + "&".join(f"{encode(k)}={encode(v)}" for k, v in fields)


def request(draw, port: int) -> dict[str, Any]:
    """A raw request: its bytes, and how much of it is sent before the connection is closed or reset. Half
    are well-formed HTTP with junk in the target and the body only (they reach the endpoints' fields), half
    junk throughout."""
    path, body = target(draw), draw(st.sampled_from(BODIES))
    if draw(st.booleans()):
        method, version, host = draw(st.sampled_from(["GET", "GET", "GET", "POST"])), "HTTP/1.1", f"127.0.0.1:{port}"
        length, junk = ("right" if method == "POST" else None), False
    else:
        method, version = draw(st.sampled_from(METHODS)), draw(st.sampled_from(VERSIONS))
        host = draw(st.sampled_from([f"127.0.0.1:{port}"] * 4 + [f"localhost:{port}", "127.0.0.1", "evil.example",
                                                                  "", None, "twice"]))
        length, junk = draw(st.sampled_from(["right"] * 3 + [None, "more", "less", "twice", "differ"] + LENGTHS)), True
    headers: list[tuple[str, str | None]] = []
    if host == "twice":
        headers += [("Host", f"127.0.0.1:{port}"), ("Host", "evil.example")]
    elif host is not None:
        headers.append(("Host", host))
    stated = {"right": str(len(body)), "more": str(len(body) + 10), "less": str(max(len(body) - 1, 0))}
    if length in ("twice", "differ"):
        headers += [("Content-Length", str(len(body))), ("Content-Length", str(len(body) + (length == "differ")))]
    elif length is not None:
        headers.append(("Content-Length", stated.get(length, length)))
    headers += [] if not junk else draw(st.lists(st.sampled_from([
        ("Content-Type", "application/json"), ("Content-Type", "text/plain"), ("Connection", "close"),
        ("Connection", "keep-alive"), ("Connection", "\u00fc"), ("Expect", "100-continue"),
        ("Transfer-Encoding", "chunked"), ("X-Junk", "a" * 70_000), ("", "empty name"), ("No colon", None),
        (" Folded", "x\r\n continued"), ("X", "\x00"), ("Content-Type", "application/json; charset=\u00fc"),
    ]), max_size=3))
    headers += [("X-Many", str(k)) for k in range(draw(st.sampled_from([0, 0, 0, 101])) if junk else 0)]
    if is_stop(method, path, headers):  # a valid stop request would end the server
        headers = [(k, "text/plain" if k.lower() == "content-type" else v) for k, v in headers]
    line = " ".join(p for p in (method, path, version) if p)
    head = line + "\r\n" + "".join(f"{k}\r\n" if v is None else f"{k}: {v}\r\n" for k, v in headers) + "\r\n"
    data = head.encode("utf-8") + body
    ending = draw(st.sampled_from(["answer"] * 6 + ["close early", "reset early", "connect only",
                                                    "after a valid one"]))
    return {"data": data, "method": method, "line": line, "ending": ending,
            "cut": draw(st.integers(0, max(len(data) - 1, 0)))}


def is_stop(method: str, path: str, headers: list[tuple[str, str | None]]) -> bool:
    content = [v for k, v in headers if k.lower() == "content-type"]
    return method == "POST" and "stop" in path and any((v or "").startswith("application/json") for v in content)


def send(port: int, case: dict[str, Any]) -> tuple[bytes, bool] | None:
    """The request sent as ``case`` says: what the server answered and whether it reset the connection (None
    where the client left early)."""
    with socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT) as sock:
        ending = case["ending"]
        if ending == "connect only":
            return None
        if ending in ("close early", "reset early"):
            sock.sendall(case["data"][: case["cut"]])
            if ending == "reset early":
                sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            return None
        if ending == "after a valid one":  # the connection kept alive, then the drawn request on it
            sock.sendall(valid(port, keep_alive=True)["data"])
            first, reset = receive(sock, once=True)
            assert not reset, first[:300]
            assert statuses(first, "GET") == [200], first[:300]
        try:
            sock.sendall(case["data"])
            sock.shutdown(socket.SHUT_WR)
        except OSError:
            pass  # the server answered and closed before reading all of it (a refused length, a long line)
        return receive(sock)


def receive(sock: socket.socket, *, once: bool = False) -> tuple[bytes, bool]:
    """Everything the server sends until it closes (or, with ``once``, until one answer is complete), and
    whether it reset the connection (which may lose the end of an answer: closing with a request unread)."""
    chunks = []
    while True:
        try:
            chunk = sock.recv(65536)
        except ConnectionResetError:
            return b"".join(chunks), True
        except TimeoutError:
            raise AssertionError(f"a hang: no answer within {TIMEOUT:g} s after {b''.join(chunks)[:200]!r}") from None
        if not chunk:
            return b"".join(chunks), False
        chunks.append(chunk)
        if once and complete(b"".join(chunks)):
            return b"".join(chunks), False


def complete(data: bytes) -> bool:
    head, separator, body = data.partition(b"\r\n\r\n")
    length = re.search(rb"(?im)^content-length:\s*(\d+)", head)
    return bool(separator) and length is not None and len(body) >= int(length.group(1))


STATUS = re.compile(rb"HTTP/1\.[01] (\d{3}) [^\r\n]*\r\n")


def statuses(data: bytes, method: str, *, cut: bool = False) -> list[int]:
    """The statuses of the answers in ``data``, each checked whole (the last may be ``cut`` short by a reset):
    a status line, headers and a body of the stated length (none for HEAD); an answer without a status line is
    HTTP/0.9's (the standard library's to a request line without a version it reads), its status the error
    page's, or 500 for a JSON error without a field."""
    found = []
    while data:
        match = STATUS.match(data)
        if match is None:
            error = re.search(rb"Error code: (\d{3})", data)
            if error:
                found.append(int(error.group(1)))
            elif data.lstrip().startswith(b"{") and not cut:
                answer = json.loads(data)
                found.append(500 if set(answer) == {"error"} else 200)
            return found
        status = int(match.group(1))
        head, separator, rest = data.partition(b"\r\n\r\n")
        found.append(status)
        if not separator and cut:
            return found
        assert separator, f"an answer's headers end: {data[:200]!r}"
        if 100 <= status < 200:
            data = rest
            continue
        length = re.search(rb"(?im)^content-length:\s*(\d+)\s*$", head)
        assert length, f"an answer states its length: {data[:200]!r}"
        size = 0 if method == "HEAD" or status in (204, 304) else int(length.group(1))
        assert len(rest) >= size or cut, f"an answer of {size} bytes, {len(rest)} received"
        data = rest[size:]
    return found


def protocol(status: int, case: dict[str, Any]) -> bool:
    """Whether ``status`` is the protocol's own answer: 501 to a method the server does not offer, 505 to an
    HTTP newer than 1.x."""
    words = case["line"].split()
    return (status == 501 and words[:1] not in (["GET"], ["POST"])) or (status == 505 and len(words) >= 3)


def check_answer(case: dict[str, Any], sent: tuple[bytes, bool] | None) -> list[int]:
    """The statuses of the server's answers to ``case``, each a whole HTTP answer below 500 (or the
    protocol's)."""
    if sent is None:
        return []
    answer, reset = sent
    found = statuses(answer, case["method"], cut=reset)
    for status in found:
        assert status < 500 or protocol(status, case), (status, case["data"][:300], answer[:300])
    return found


def valid(port: int, *, keep_alive: bool = False) -> dict[str, Any]:
    """A request for the mechanism, as the page's first."""
    line = "GET /api/mechanism HTTP/1.1"
    connection = "keep-alive" if keep_alive else "close"
    return {"data": f"{line}\r\nHost: 127.0.0.1:{port}\r\nConnection: {connection}\r\n\r\n".encode(),
            "method": "GET", "line": line, "ending": "answer", "cut": 0}


def answers(port: int) -> bool:
    sent = send(port, valid(port))
    return sent is not None and check_answer(valid(port), sent) == [200] and b'"five_bar"' in sent[0]


@pytest.fixture
def server(capfd):
    pytest.importorskip("plotly", reason="pkm explore needs plotly (pip install 'pkm[explore]')")
    from pkm.explore import serve

    running = serve("five_bar", resolution=3, map_resolution=8)
    yield running
    deadline = time.monotonic() + 2
    while any("process_request_thread" in t.name for t in threading.enumerate()) and time.monotonic() < deadline:
        time.sleep(0.02)
    running.shutdown()
    printed = capfd.readouterr().err.splitlines()
    failures = [line for line in printed if line.startswith("pkm explore") or "Traceback" in line
                or "Exception in thread" in line]
    assert failures == [], printed


def test_the_explore_server_answers_drawn_raw_requests_below_500_and_keeps_answering(server):
    port = server.port

    @fuzz(100)
    @given(st.data())
    def check(data):
        case = request(data.draw, port)
        check_answer(case, send(port, case))

    check()
    assert answers(port)


def test_the_explore_server_answers_50_simultaneous_connections(server):
    port = server.port

    @fuzz(4)
    @given(st.lists(st.just("valid") | st.just("drawn"), min_size=50, max_size=50), st.data())
    def check(kinds, data):
        cases = [valid(port) if kind == "valid" else request(data.draw, port) for kind in kinds]
        held = []
        for case in cases[:3]:  # connections left half-sent and open while the others are answered
            sock = socket.create_connection(("127.0.0.1", port), timeout=TIMEOUT)
            sock.sendall(case["data"][: case["cut"]])
            held.append(sock)
        try:
            with ThreadPoolExecutor(max_workers=len(cases)) as pool:
                received = list(pool.map(lambda c: send(port, c), cases[3:]))
        finally:
            for sock in held:
                sock.close()
        for case, sent in zip(cases[3:], received, strict=True):
            found = check_answer(case, sent)
            if case["data"] == valid(port)["data"]:
                assert found == [200], sent
        assert answers(port)

    check()
