"""``pkm explore``'s JSON API through urllib against a server on a free port of 127.0.0.1: every answer is what
pkm computes by its own code paths (the atlas of ``pkm atlas``, the card of ``pkm show``, the local index at the
map's poses), a bad request is a 400 naming its field, anything else a one-line 500; the command, the stop
request, Ctrl-C and the static export."""

from __future__ import annotations

import base64
import http.client
import json
import math
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from importlib import resources
from typing import Any

import numpy as np
import pytest
from helpers import watch_atlas

import pkm
from pkm.atlas import compute_atlas
from pkm.card import design_card
from pkm.cli import main
from pkm.explore import Explorer, api, serve

pytest.importorskip("plotly", reason="pkm explore needs plotly (pip install 'pkm[explore]')")

DESIGN = {"r1": 0.5, "r2": 0.9, "r3": 0.6}
DESIGN_TEXT = "r1=0.5,r2=0.9,r3=0.6"
MODE = "out_in"


def _request(url: str, *, data: bytes | None = None, headers: dict[str, str] | None = None) -> tuple[int, dict]:
    request = urllib.request.Request(url, data=data, headers=headers or {})
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            return response.status, json.loads(response.read())
    except urllib.error.HTTPError as error:
        return error.code, json.loads(error.read())


@pytest.fixture(scope="module")
def server():
    running = serve("five_bar", resolution=9, map_resolution=32)
    yield running
    running.shutdown()


@pytest.fixture(scope="module")
def five_bar():
    return pkm.load("five_bar")


def get(server, endpoint: str, **fields: str) -> dict:
    status, data = _request(server.url + f"api/{endpoint}?" + urllib.parse.urlencode(fields))
    assert status == 200, data
    return data


def decode(array: dict) -> np.ndarray:
    assert array["dtype"] == "float64"
    return np.frombuffer(base64.b64decode(array["data"]), dtype="<f8").reshape(array["shape"])


def test_the_server_listens_on_the_loopback_address_only(server):
    assert server.url.startswith("http://127.0.0.1:")
    assert server._httpd.server_address[0] == "127.0.0.1"


def test_mechanism_metadata_has_parameters_with_units_and_bounds_modes_indices_and_regions(server, five_bar):
    meta = get(server, "mechanism")
    assert [p["name"] for p in meta["parameters"]] == list(five_bar.parameter_names())
    r1 = meta["parameters"][0]
    assert (r1["unit"], r1["lower"], r1["upper"], r1["default"]) == ("m", 0.0, None, five_bar.parameters[0].default)
    assert [m["name"] for m in meta["modes"]] == list(five_bar.modes)
    assert {i["name"]: i["local"] for i in meta["global_indices"]}["gci"] == "inverse_condition_f"
    assert [r["name"] for r in meta["regions"]] == list(five_bar.region_names())
    assert meta["defaults"] == {"index": "gci", "region": "miw", "space": "gao1998", "resolution": 9,
                                "map_resolution": 32}
    assert "five_bar.max_gci_miw" in meta["problems"]


def test_the_atlas_is_pkm_atlas_with_its_designs_and_checked_best(server, five_bar):
    data = get(server, "atlas")
    space = five_bar.design_spaces["gao1998"]
    atlas = compute_atlas(five_bar, five_bar.global_spec("gci"), space=space, region="miw", resolution=9,
                          progress=False, executor="serial")
    assert data["modes"] == list(atlas.modes)
    for mode in atlas.modes:
        np.testing.assert_array_equal(np.array(data["values"][mode], dtype=float), atlas.values[mode])
        assert data["best"][mode]["design"] == pytest.approx(atlas.checked[mode].design)
    np.testing.assert_array_equal(data["inside"], atlas.inside)
    i, j = np.argwhere(atlas.inside)[len(np.argwhere(atlas.inside)) // 2]
    expected = space.designs(five_bar.parameters, space.from_chart(atlas.u[i], atlas.v[j]))
    shown = {**data["held"], **data["designs"][i][j]}
    assert [shown[p] for p in five_bar.parameter_names()] == pytest.approx(expected.tolist())
    assert data["designs"][0][0] is None
    assert not atlas.inside[0, 0]
    assert data["problem"] == "five_bar.max_gci_miw"


def test_an_atlas_over_two_parameters_holds_the_design_given_and_agrees_with_global_index(server, five_bar):
    data = get(server, "atlas", axes="r1=0.5:1.5,r2=0.5:1.5", design="r3=0.6", index="gci_2", mode=MODE,
               resolution="5")
    assert data["axes"] == [["r1", 0.5, 1.5], ["r2", 0.5, 1.5]]
    assert data["held"]["r3"] == 0.6
    assert data["modes"] == [MODE]
    values = np.array(data["values"][MODE], dtype=float)
    i, j = np.unravel_index(np.nanargmax(values), values.shape)
    design = {**data["held"], **data["designs"][i][j]}
    direct = five_bar.global_index("gci_2", design, region="miw", mode=MODE, resolution=data["pose_resolution"])
    assert values[i, j] == pytest.approx(float(direct), rel=1e-12)


def test_the_card_is_the_card_of_pkm_show(server, five_bar):
    data = get(server, "card", design=DESIGN_TEXT, mode=MODE, region="miw")
    card = design_card(five_bar, five_bar.design(DESIGN, partial=True), modes=[MODE], region="miw", resolution=3)
    assert {p["name"]: (p["value"], p["unit"]) for p in data["design"]}["r1"] == (0.5, "m")
    assert [(r["index"], r["unit"], r["resolution"]) for r in data["global_indices"]] == \
           [(r["index"], r["unit"], r["resolution"]) for r in card.indices]
    assert [r["value"] for r in data["global_indices"]] == pytest.approx([r["value"] for r in card.indices])
    assert data["placement"]["shape"] == "disc"
    assert data["mode"] == MODE


def test_the_map_is_the_local_index_at_its_poses_with_singularity_curves_and_the_region(server, five_bar):
    listed = get(server, "map", design=DESIGN_TEXT, mode=MODE, resolution="40")
    encoded = get(server, "map", design=DESIGN_TEXT, mode=MODE, resolution="40", arrays="base64")
    values = decode(encoded["values"])
    np.testing.assert_array_equal(np.array(listed["values"], dtype=float), values)
    U, V = np.meshgrid(listed["u"], listed["v"], indexing="ij")
    poses = np.stack([U.ravel(), V.ravel()], axis=1)
    expected = five_bar.local_index("inverse_condition_f", poses, DESIGN, mode=MODE).reshape(U.shape)
    np.testing.assert_array_equal(values, expected)
    assert np.isfinite(values).sum() > 100
    det = decode(encoded["singular"]["det_type2"])
    assert encoded["curves"]["det_type2"], "the map crosses a type II singularity"
    assert np.nanmin(det) < 0 < np.nanmax(det)
    placement = five_bar.region_placement("miw", five_bar.design(DESIGN, partial=True))
    outline = np.concatenate(encoded["region_outline"])
    radius = np.hypot(*(outline - placement["centre"]).T)
    step = listed["u"][1] - listed["u"][0]
    assert np.all(np.abs(radius - placement["size"][0]) < step)


def test_the_certification_is_pkm_certify_with_its_boxes_in_the_pose_plane(server, five_bar):
    """The page's certification of a region: the verdict and counts of Mechanism.certify at the design and mode,
    and its boxes, outline and witnesses as pkm certify draws them (certificate_drawing)."""
    from pkm.certify import certificate_drawing

    data = get(server, "certify", design=DESIGN_TEXT, mode=MODE, region="miw")
    design = five_bar.design(DESIGN, partial=True)
    found = five_bar.certify("miw", design, mode=MODE, seconds=api.CERTIFY_SECONDS)
    drawing = certificate_drawing(five_bar, "miw", found, design)
    assert (data["verdict"], data["boxes"], data["mode"]) == (found.verdict, found.boxes, MODE)
    assert data["plane"] == ["x", "y"]
    assert data["undecided"] == pytest.approx(found.undecided)
    assert {state: len(boxes) for state, boxes in data["cells"].items()} == found.as_dict()["cells"]
    for state, boxes in drawing.cells.items():
        np.testing.assert_allclose(np.array(data["cells"][state]).reshape(-1, 4, 2), boxes)
    np.testing.assert_allclose(data["outline"], drawing.outline)
    assert len(data["points"]) == len(found.witnesses)
    assert sum(map(len, data["cells"].values())) > 10


def test_a_certification_is_cancelled_between_its_boxes():
    explorer = Explorer(pkm.load("five_bar"))
    boxes, check = [], explorer._check_open

    def cancel_at_ten(*progress: int) -> None:
        if progress:
            boxes.append(progress[0])
            if progress[0] == 10:
                explorer.cancel()
        check()

    explorer._check_open = cancel_at_ten
    with pytest.raises(api.CancelledError, match="at the page's request"):
        explorer.handle("certify", {"design": DESIGN_TEXT, "mode": MODE, "region": "miw"})
    assert boxes[-1] == 10


def test_the_map_of_a_spatial_machine_is_a_plane_section_and_its_linkage_projects_onto_it():
    delta = pkm.load("delta")
    explorer = Explorer(delta, resolution=3, map_resolution=12)
    data = explorer.handle("map", {"plane": "x,z", "held": "y=0.01", "resolution": "12"})
    U, V = np.meshgrid(data["u"], data["v"], indexing="ij")
    poses = np.stack([U.ravel(), np.full(U.size, 0.01), V.ravel()], axis=1)
    expected = delta.local_index(data["index"], poses, mode=data["mode"]).reshape(U.shape)
    np.testing.assert_array_equal(np.asarray(data["values"], dtype=float), expected)
    assert data["held"] == {"y": 0.01}
    pose = poses[np.flatnonzero(np.isfinite(expected.ravel()))[0]]
    linkage = explorer.handle("linkage", {"pose": ",".join(map(repr, pose.tolist())), "plane": "x,z"})
    legs = delta.linkage(pose, mode=linkage["mode"])
    assert linkage["reachable"]
    np.testing.assert_array_equal(np.array(linkage["legs"]), np.array(legs))
    np.testing.assert_array_equal(np.array(linkage["projected"]), np.array(legs)[:, :, [0, 2]])


def test_the_linkage_answers_the_actuators_and_says_when_there_is_no_drawing(server, five_bar):
    data = get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,1.2")
    q = five_bar.inverse_kinematics([0.1, 1.2], DESIGN, mode=MODE)
    assert list(data["actuators"].values()) == pytest.approx(q.tolist())
    assert data["reachable"]
    assert np.array(data["legs"]) == pytest.approx(np.array(five_bar.linkage([0.1, 1.2], DESIGN, mode=MODE)))
    assert [leg[-1] for leg in data["projected"]] == [pytest.approx([0.1, 1.2])] * 2
    away = get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,9")
    assert not away["reachable"]
    assert away["legs"] == []
    assert away["projected"] is None


def test_the_linkage_answer_carries_every_assembly_at_its_joints(server, five_bar):
    """The five-bar's two assemblies at the joints of the pose: each one's linkage is the five-bar's in its mode at
    its pose, the pose's own among them as ``current``; out of reach, none."""
    data = get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,1.2")
    every = data["assemblies"]
    found = five_bar.every_assembly(list(data["actuators"].values()), DESIGN)
    assert (every["count"], every["bound"], every["failed"], every["reason"]) == (2, 2, 0, None)
    assert len(every["legs"]) == len(every["projected"]) == len(every["assemblies"]) == found.counts[0] == 2
    for row, legs, projected, pose in zip(every["assemblies"], every["legs"], every["projected"], found.poses[0],
                                          strict=True):
        assert list(row["pose"].values()) == pytest.approx(pose.tolist())
        np.testing.assert_allclose(np.array(legs), np.array(five_bar.linkage(pose, DESIGN, mode=row["mode"])))
        assert [leg[-1] for leg in projected] == [pytest.approx(pose.tolist())] * 2
    current = every["assemblies"][every["current"]]
    assert (list(current["pose"].values()), current["mode"]) == (pytest.approx([0.1, 1.2]), MODE)
    other = every["assemblies"][1 - every["current"]]["pose"]
    assert abs(other["x"] - 0.1) + abs(other["y"] - 1.2) > 0.1
    assert get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,9")["assemblies"] is None


def test_a_pose_out_of_reach_is_said_out_of_reach_and_has_no_linkage(server):
    away = get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,9")
    assert away["reason"] == f"pose x = 0.1, y = 9 is out of reach in mode {MODE}"
    assert (away["reachable"], away["legs"], away["projected"]) == (False, [], None)
    assert get(server, "linkage", design=DESIGN_TEXT, mode=MODE, pose="0.1,1.2")["reason"] is None
    stewart = Explorer(pkm.load("stewart"), resolution=3, map_resolution=8)
    far = stewart.handle("linkage", {"pose": "5,5,5,0,0,0"})
    assert not far["reachable"]
    assert far["reason"].startswith("pose x = 5, y = 5, z = 5, roll = 0")
    assert (far["legs"], far["projected"]) == ([], None), "the skeleton of a pose out of reach is no linkage"


def test_the_optimum_of_the_mechanisms_problem_is_placed_on_the_chart(server):
    atlas = get(server, "atlas")
    optimum = get(server, "optimum")
    assert optimum["problem"] == "five_bar.max_gci_miw"
    assert optimum["status"] == "Solve_Succeeded"
    assert optimum["on_chart"]
    best = atlas["best"][optimum["mode"]]
    assert optimum["verified_objective"] >= best["value"] - 1e-3
    assert get(server, "optimum", region="reachable")["problem"] is None


BAD = [
    ("atlas?index=no_such_index", "index", None),
    ("atlas?mode=no_such_mode", "mode", None),
    ("atlas?resolution=2", "resolution", None),
    ("atlas?resolution=many", "resolution", None),
    ("atlas?space=no_such_space", "space", None),
    ("atlas?axes=r1=0.5:1.5", "axes", None),
    ("atlas?axes=r1=0.5:1.5,r9=0.1:0.2", "axes", None),
    ("atlas?space=gao1998&axes=r1=0.5:1.5,r2=0.5:1.5", "axes", None),
    ("atlas?region=no_such_region", "region", None),
    ("atlas?unknown=1", "unknown", None),
    ("atlas?index=gci&index=gci", "index", None),
    ("card?design=r1=-0.5", "design", "r1"),
    ("card?design=r9=0.5", "design", "r9"),
    ("card?design=r1=abc", "design", None),
    ("card?mode=no_such_mode", "mode", None),
    ("card?indices=gci,no_such_index", "indices", None),
    ("map?resolution=257", "resolution", None),
    ("map?index=no_such_index", "index", None),
    ("map?plane=x,x", "plane", None),
    ("map?held=x=0.1", "held", None),
    ("map?arrays=png", "arrays", None),
    ("linkage?pose=0.1", "pose", None),
    ("linkage?pose=0.1,nan", "pose", None),
    ("optimum?problem=no_such_problem", "problem", None),
    ("certify?region=reachable", "region", None),
    ("certify?properties=singularity,no_such_property", "properties", None),
    ("certify?seconds=0", "seconds", None),
    ("certify?properties=collisions", "properties", None),
]


@pytest.mark.parametrize(("query", "field", "parameter"), BAD)
def test_a_bad_request_is_a_400_naming_its_field(server, query, field, parameter):
    status, data = _request(server.url + "api/" + query)
    assert status == 400
    assert data["field"] == field
    assert data.get("parameter") == parameter
    assert "\n" not in data["error"]
    assert "Traceback" not in data["error"]


def test_an_unknown_path_is_a_404_and_an_unexpected_failure_a_one_line_500(server, monkeypatch, capsys):
    assert _request(server.url + "api/no_such_endpoint")[0] == 404
    assert _request(server.url + "no_such_file")[0] == 404

    def broken(_fields):
        raise RuntimeError("a failure\nover two lines")

    monkeypatch.setattr(server.explorer, "_card", broken)
    status, data = _request(server.url + "api/card")
    assert status == 500
    assert data == {"error": "RuntimeError: a failure over two lines"}
    assert capsys.readouterr().err.strip() == "pkm explore: card failed: RuntimeError: a failure over two lines"


def test_a_request_by_another_host_name_is_refused(server):
    status, data = _request(server.url + "api/mechanism", headers={"Host": "example.com"})
    assert status == 403
    assert data["field"] == "Host"


def test_the_page_and_plotly_come_from_this_machine(server):
    with urllib.request.urlopen(server.url) as response:
        html = response.read().decode()
    assert '<script src="plotly.min.js"></script>' in html
    assert "http" not in html
    with urllib.request.urlopen(server.url + "plotly.min.js") as response:
        assert response.read() == (resources.files("plotly") / "package_data" / "plotly.min.js").read_bytes()
    with urllib.request.urlopen(server.url + "explore.js") as response:
        assert "https://" not in response.read().decode()


def test_the_stop_request_stops_the_server():
    running = serve("five_bar")
    stop = running.url + "api/stop"
    assert _request(stop, data=b"{}")[0] == 400  # a form's content type: not from the page
    assert _request(stop, data=b"{}", headers={"Content-Type": "application/json"}) == (200, {"stopped": True})
    running._thread.join(timeout=10)
    assert not running._thread.is_alive()
    with pytest.raises(urllib.error.URLError):
        urllib.request.urlopen(running.url + "api/mechanism", timeout=5)
    running.shutdown()


def _atlas_in_flight(monkeypatch) -> tuple[Any, threading.Event, list, threading.Thread]:
    """A server computing an atlas of lambda_e at 81 x 81 designs (seconds) for a request in a thread: the
    server, the event set when the atlas ends, the request's answers and its thread, once the atlas began."""
    running = serve("five_bar", index="lambda_e", resolution=81)
    started, ended = watch_atlas(monkeypatch)
    answers = []
    asking = threading.Thread(target=lambda: answers.append(_request(running.url + "api/atlas")))
    asking.start()
    assert started.wait(timeout=120), "the atlas began"
    assert not ended.is_set(), "the atlas of lambda_e at 81 x 81 designs takes seconds"
    return running, ended, answers, asking


def test_the_stop_request_cancels_the_computation_in_flight(monkeypatch):
    running, ended, answers, asking = _atlas_in_flight(monkeypatch)
    stop = time.monotonic()
    assert _request(running.url + "api/stop", data=b"{}", headers={"Content-Type": "application/json"})[0] == 200
    asking.join(timeout=30)
    running._thread.join(timeout=30)
    status, data = answers[0]
    assert status == 503
    assert data["error"].endswith("computation cancelled")
    assert ended.is_set()
    assert time.monotonic() - stop < 5
    assert not running._thread.is_alive()
    assert running.explorer.closed
    with pytest.raises(api.CancelledError):
        running.explorer.handle("map", {})
    running.shutdown()


def test_the_cancel_request_cancels_the_computation_in_flight_and_the_server_goes_on(monkeypatch):
    """The page's cancel: the atlas in flight is answered 409 within seconds and the next request is served."""
    running, _, answers, asking = _atlas_in_flight(monkeypatch)
    cancelled = time.monotonic()
    json_type = {"Content-Type": "application/json"}
    assert _request(running.url + "api/cancel", data=b"{}", headers=json_type) == (200, {"cancelled": True})
    asking.join(timeout=30)
    assert answers[0] == (409, {"error": "computation cancelled at the page's request", "field": None})
    assert time.monotonic() - cancelled < 5
    assert not running.explorer.closed
    assert _request(running.url + "api/mechanism")[1]["name"] == "five_bar"
    assert _request(running.url + "api/cancel", data=b"{}")[0] == 400
    running.shutdown()


def test_a_connection_kept_open_is_refused_once_the_server_stopped():
    running = serve("five_bar")
    kept = http.client.HTTPConnection("127.0.0.1", running.port, timeout=30)
    kept.request("GET", "/api/mechanism")
    first = kept.getresponse()
    assert (first.status, json.loads(first.read())["name"]) == (200, "five_bar")
    _request(running.url + "api/stop", data=b"{}", headers={"Content-Type": "application/json"})
    running._thread.join(timeout=30)
    kept.request("GET", "/api/mechanism")
    response = kept.getresponse()
    assert (response.status, json.loads(response.read())) == (503, {"error": "the server has stopped",
                                                                    "field": None})
    assert response.getheader("Connection") == "close"
    kept.close()
    running.shutdown()


def test_the_command_serves_until_the_page_stops_it(capsys):
    result = []
    thread = threading.Thread(target=lambda: result.append(main(["explore", "five_bar", "--no-browser", "--json"])))
    thread.start()
    deadline = time.monotonic() + 60
    while not (out := capsys.readouterr().out) and time.monotonic() < deadline:
        time.sleep(0.05)
    url = json.loads(out)["url"]
    assert _request(url + "api/mechanism")[1]["name"] == "five_bar"
    _request(url + "api/stop", data=b"{}", headers={"Content-Type": "application/json"})
    thread.join(timeout=30)
    assert result == [0]


def test_the_command_stops_on_ctrl_c():
    start = ("import runpy, signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
             "sys.argv = ['pkm', *sys.argv[1:]]; runpy.run_module('pkm.cli', run_name='__main__')")
    run = subprocess.Popen([sys.executable, "-c", start, "explore", "five_bar", "--no-browser"],
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = run.stdout.readline()
    assert "http://127.0.0.1:" in line
    run.send_signal(signal.SIGINT)
    _, err = run.communicate(timeout=30)
    assert run.returncode == 130
    assert err.strip().splitlines() == ["pkm: interrupted"]


def test_without_plotly_the_command_says_how_to_install_it(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "plotly", None)
    assert main(["explore", "five_bar", "--no-browser"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.splitlines() == [err]
    assert "pip install 'pkm[explore]'" in err


def test_bad_defaults_of_the_command_exit_2_in_one_line(capsys):
    assert main(["explore", "five_bar", "--index", "no_such_index", "--no-browser"]) == 2
    assert capsys.readouterr().err.startswith("pkm: error: unknown index 'no_such_index'")
    assert main(["explore", "five_bar", "--space", "gao1998", "--axes", "r1=0.5:1.5,r2=0.5:1.5"]) == 2
    assert main(["explore", "five_bar", "--port", "70000", "--no-browser"]) == 2


def test_the_static_export_is_one_file_with_the_atlas_and_the_cards(tmp_path, capsys):
    out = tmp_path / "atlas.html"
    assert main(["explore", "five_bar", "--html", str(out), "--resolution", "5", "--grid", "2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["html"] == str(out)
    assert [p.name for p in tmp_path.iterdir()] == ["atlas.html"]
    html = out.read_text()
    assert "plotly.js v" in html
    assert "<script src=" not in html
    assert "<link " not in html
    start = html.index('<script type="application/json" id="pkm-static">') + len(
        '<script type="application/json" id="pkm-static">')
    data = json.loads(html[start : html.index("</script>", start)])
    atlas = data["atlas"]
    assert (atlas["index"], atlas["region"], atlas["resolution"]) == ("gci", "miw", 5)
    assert 1 <= len(data["entries"]) <= 4
    entry = data["entries"][0]
    i, j = entry["node"]
    assert entry["design"] == {**atlas["held"], **atlas["designs"][i][j]}
    card = entry["modes"][atlas["modes"][0]]["card"]
    assert {p["name"]: p["value"] for p in card["design"]}["r1"] == entry["design"]["r1"]
    assert all(math.isfinite(r["value"]) for r in card["global_indices"] if r["index"] == "gci")
