"""Input at the limits, refused before any work with pkm's own error naming the option and the violated condition
(on the command line exit 2 with one line, no traceback, the user's value echoed capped), and the explorer's server
answering malformed, truncated and simultaneous requests without a traceback."""

from __future__ import annotations

import http.client
import json
import socket
import struct
import threading
import time

import pytest

import pkm
from pkm.card import design_card
from pkm.cli import build_parser, main
from pkm.errors import PkmError
from pkm.workspace_map import MAX_RESOLUTION, workspace_slice

HUGE = "x" * 10_000  # a value far longer than any error line should be
LONGEST_LINE = 400  # characters of an error line that echoes HUGE, capped


def _error_line(capfd: pytest.CaptureFixture[str]) -> str:
    err = capfd.readouterr().err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err[:2000]
    return lines[0]


# --- the command line ---------------------------------------------------------------------------------------------

# the least each command that takes --out needs besides it to get past its options
OUT_COMMANDS = {
    "eval": ["eval", "five_bar", "--pose", "0.1,1.5"],
    "fk": ["fk", "five_bar", "--joints", "1.5,1.2"],
    "certify": ["certify", "delta", "--properties", "limits"],
    "index": ["index", "five_bar", "gci"],
    "atlas": ["atlas", "five_bar", "gci"],
    "sweep": ["sweep", "five_bar", "--indices", "gci"],
    "synth": ["synth", "five_bar.max_gci_miw"],
    "pareto": ["pareto", "five_bar.max_gci_miw", "--secondary", "gamma_max"],
    "show": ["show", "five_bar"],
    "compare": ["compare", "five_bar", "--design", "r1=1.1", "--design", "r1=1.2"],
    "design": ["design", "task.toml"],
    "tolerance": ["tolerance", "task.toml"],
    "calibrate": ["calibrate", "rrr3", "data.csv"],
    "export": ["export", "five_bar"],
    "reproduce": ["reproduce", "gao1998", "--quick"],
}


def test_every_command_that_takes_out_is_covered():
    commands = build_parser()._subparsers._group_actions[0].choices
    taking = {name for name, sub in commands.items() if any("--out" in a.option_strings for a in sub._actions)}
    assert taking == set(OUT_COMMANDS)


@pytest.mark.parametrize("command", sorted(OUT_COMMANDS))
def test_an_empty_out_is_refused_before_any_work_and_writes_nothing(command, tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    start = time.perf_counter()
    assert main([*OUT_COMMANDS[command], "--out", ""]) == 2
    assert time.perf_counter() - start < 5.0
    assert "--out '' violates: a path to a folder (it is empty)" in _error_line(capfd)
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("args", [
    ["show", "five_bar"],
    ["compare", "five_bar", "--design", "r1=1.1", "--design", "r1=1.2"],
])
def test_a_map_resolution_beyond_its_bound_is_refused_before_any_work(args, tmp_path, capfd):
    start = time.perf_counter()
    assert main([*args, "--resolution", "100000", "--out", str(tmp_path / "card")]) == 2
    assert time.perf_counter() - start < 5.0
    line = _error_line(capfd)
    assert "resolution = 100000 violates" in line
    assert f"<= {MAX_RESOLUTION}" in line
    assert not (tmp_path / "card").exists()


def test_the_maps_resolution_bound_is_stated_in_the_help(capsys):
    for command in ("show", "compare"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        assert f"3 to {MAX_RESOLUTION}" in " ".join(capsys.readouterr().out.split())


@pytest.mark.parametrize(("call", "condition"), [
    (lambda m: workspace_slice(m, resolution=100_000), f"<= {MAX_RESOLUTION}"),
    (lambda m: workspace_slice(m, resolution=2.5), "an integer"),
    (lambda m: design_card(m, resolution=100_000), f"<= {MAX_RESOLUTION}"),
    (lambda m: workspace_slice(m, held={"x": 0.1}), "held coordinate 'x' violates: a coordinate off the plane x, y"),
])
def test_the_maps_options_are_checked_where_every_map_is_made(call, condition):
    with pytest.raises(PkmError, match=condition):
        call(pkm.load("five_bar"))


@pytest.mark.parametrize(("held", "needle"), [
    ("z=nan", "held coordinate z = nan violates: a finite number"),
    ("z=inf", "held coordinate z = inf violates: a finite number"),
    ("q=0.1", "held coordinate 'q' violates: one of x, y, z"),
    ("x=0.1", "held coordinate 'x' violates: a coordinate off the plane x, y"),
])
def test_a_held_coordinate_is_a_finite_value_of_a_pose_coordinate_off_the_plane(held, needle, tmp_path, capfd):
    assert main(["show", "delta", "--held", held, "--out", str(tmp_path / "card")]) == 2
    assert needle in _error_line(capfd)
    assert not (tmp_path / "card").exists()


def test_a_held_coordinate_of_the_five_bar_is_refused_whatever_its_value(tmp_path, capfd):
    """The five-bar's pose is its plane: ``--held x=nan`` once drew the card and exited 0."""
    assert main(["show", "five_bar", "--held", "x=nan", "--out", str(tmp_path / "card")]) == 2
    assert "held coordinate 'x' violates" in _error_line(capfd)


@pytest.mark.parametrize(("html", "needle"), [
    ("file/page.html", "--html 'file/page.html' violates: a file in a folder (or a path to one); 'file' is a file"),
    ("", "--html '' violates: a path to a file in a folder (it is empty)"),
    ("folder", "--html 'folder' violates: a file; it is a folder"),
    (HUGE, "--html 'xxx"),
])
def test_an_html_path_that_cannot_be_a_file_is_refused_before_any_work(html, needle, tmp_path, monkeypatch, capfd):
    pytest.importorskip("plotly", reason="pkm explore needs plotly (pip install 'pkm[explore]')")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "file").write_text("mine")
    (tmp_path / "folder").mkdir()
    assert main(["explore", "five_bar", "--html", html, "--grid", "1", "--resolution", "3"]) == 2
    line = _error_line(capfd)
    assert needle in line
    assert len(line) < LONGEST_LINE
    assert (tmp_path / "file").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file", "folder"]


def test_the_explorers_map_resolution_is_named_by_its_own_name(capfd):
    pytest.importorskip("plotly", reason="pkm explore needs plotly (pip install 'pkm[explore]')")
    assert main(["explore", "five_bar", "--map-resolution", "100000", "--no-browser"]) == 2
    assert "map_resolution = 100000 violates: an integer >= 3 and <= 256" in _error_line(capfd)


@pytest.mark.parametrize(("args", "needle"), [
    (["index", "five_bar", "gci", "--resolution", HUGE], "argument --resolution: 'xxx"),
    (["index", "five_bar", "gci", "--margin", HUGE], "argument --margin: 'xxx"),
    (["atlas", "five_bar", "gci", "--executor", HUGE], "argument --executor: invalid choice: 'xxx"),
    ([HUGE], "invalid choice: 'xxx"),
    (["list", HUGE], "unrecognized arguments: 'xxx"),
    (["eval", "five_bar", "--pose", HUGE], "--pose 'xxx"),
    (["eval", "five_bar", "--pose", "0.1,1.5", "--out", f"{HUGE}/{HUGE}"], "--out 'xxx"),
    (["show", "five_bar", "--plane", f"x,{HUGE}", "--out", "card"], "axes = ('x', 'xxx"),
    (["show", "delta", "--held", f"{HUGE}=1", "--out", "card"], "held coordinate 'xxx"),
])
def test_an_error_line_echoes_a_huge_value_capped(args, needle, tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    assert main(args) == 2
    line = _error_line(capfd)
    assert needle in line
    assert len(line) < LONGEST_LINE


@pytest.mark.parametrize(("value", "condition"), [("nan", "a finite number"), ("inf", "a finite number"),
                                                  ("1.5", "an integer")])
def test_an_options_number_is_a_finite_number_and_a_count_an_integer(value, condition, capfd):
    option = "--resolution" if condition == "an integer" else "--margin"
    assert main(["index", "five_bar", "gci", option, value]) == 2
    assert f"argument {option}: '{value}' violates: {condition}" in _error_line(capfd)


# --- the explorer's server ----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def server():
    pytest.importorskip("plotly", reason="pkm explore needs plotly (pip install 'pkm[explore]')")
    from pkm.explore import serve

    running = serve("five_bar", resolution=9, map_resolution=32)
    yield running
    running.shutdown()


def _connection(server) -> http.client.HTTPConnection:
    return http.client.HTTPConnection("127.0.0.1", server.port, timeout=30)


def _answers(server) -> bool:
    """Whether the server answers a request for the mechanism, as the page's first request."""
    connection = _connection(server)
    try:
        connection.request("GET", "/api/mechanism")
        response = connection.getresponse()
        return response.status == 200 and json.loads(response.read())["name"] == "five_bar"
    finally:
        connection.close()


def _quiet(server, capfd: pytest.CaptureFixture[str]) -> str:
    """What the server printed, once every request it was handling has ended."""
    deadline = time.monotonic() + 10
    while any("process_request_thread" in t.name for t in threading.enumerate()) and time.monotonic() < deadline:
        time.sleep(0.02)
    return capfd.readouterr().err


@pytest.mark.parametrize(("length", "status"), [
    ("abc", 400), ("1.5", 400), ("-1", 400), ("", 400), ("0x10", 400), (["2", "3"], 400),
    ("99999999999999999999", 413), ("9" * 5000, 413), ("65537", 413),
    (None, 411),
])
def test_a_post_with_a_malformed_content_length_is_answered_as_json_without_a_traceback(server, length, status,
                                                                                        capfd):
    connection = _connection(server)
    connection.putrequest("POST", "/api/stop")
    connection.putheader("Content-Type", "application/json")
    for value in [] if length is None else [length] if isinstance(length, str) else length:
        connection.putheader("Content-Length", value)
    connection.endheaders()
    response = connection.getresponse()
    data = json.loads(response.read())
    connection.close()
    assert response.status == status
    assert response.getheader("Connection") == "close"
    assert data["field"] == "Content-Length"
    assert "violates" in data["error"]
    assert len(data["error"]) < LONGEST_LINE
    assert _answers(server)  # and the stop request was not acted upon
    assert "Traceback" not in _quiet(server, capfd)


def test_a_content_length_is_read_as_a_count_whatever_its_leading_zeros(server, capfd):
    connection = _connection(server)
    connection.putrequest("POST", "/api/nothing")
    connection.putheader("Content-Length", "0" * 5000)
    connection.endheaders()
    response = connection.getresponse()
    data = json.loads(response.read())
    connection.close()
    assert (response.status, data["field"]) == (404, "path")
    assert "Traceback" not in _quiet(server, capfd)


def test_fifty_simultaneous_connections_each_get_an_answer(server, monkeypatch):
    """Fifty connections opened at once while the server is not accepting (a page's burst meeting a busy
    accept loop): the kernel completes each handshake only while the listen queue has room (socketserver's
    default of 5 left the rest to SYN retransmissions and resets), and each then gets its answer."""
    n = 50
    accepting = threading.Event()
    accept = server._httpd.get_request

    def paused() -> tuple[socket.socket, tuple[str, int]]:
        accepting.wait(timeout=60)
        return accept()

    monkeypatch.setattr(server._httpd, "get_request", paused)
    ready = threading.Barrier(n)
    clients: list[socket.socket | OSError | None] = [None] * n

    def connect(k: int) -> None:
        ready.wait()
        try:
            clients[k] = socket.create_connection(("127.0.0.1", server.port), timeout=5)
        except OSError as exc:
            clients[k] = exc

    threads = [threading.Thread(target=connect, args=(k,)) for k in range(n)]
    try:
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(timeout=30)
    finally:
        accepting.set()
    answers = []
    for client in clients:
        if not isinstance(client, socket.socket):
            answers.append(client)
            continue
        with client:
            client.settimeout(30)
            client.sendall(f"GET /favicon.ico HTTP/1.1\r\nHost: 127.0.0.1:{server.port}\r\n"
                           "Connection: close\r\n\r\n".encode())
            answers.append(client.recv(12))
    assert answers == [b"HTTP/1.1 204"] * n


def _reset(client: socket.socket) -> None:
    """Close with a reset (SO_LINGER 0), as a browser does to a request it no longer needs."""
    client.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
    client.close()


@pytest.mark.parametrize("sent", [
    b"GET /plotly.min.js HTTP/1.1\r\nHost: {host}\r\n\r\n",  # the answer's write meets a closed connection
    b"GET /api/mechan",  # half a request line
    b"GET /api/mechanism HTTP/1.1\r\nHost: {host}\r\nAcc",  # half the headers
    b"POST /api/stop HTTP/1.1\r\nHost: {host}\r\nContent-Type: application/json\r\nContent-Length: 10\r\n\r\n{",
])
@pytest.mark.parametrize("close", ["close", "reset"])
def test_a_client_that_leaves_early_leaves_no_traceback_and_the_server_answering(server, sent, close, capfd):
    client = socket.create_connection(("127.0.0.1", server.port), timeout=30)
    client.sendall(sent.replace(b"{host}", f"127.0.0.1:{server.port}".encode()))
    time.sleep(0.05)
    if close == "reset":
        _reset(client)
    else:
        client.close()
    err = _quiet(server, capfd)
    assert "Traceback" not in err
    assert "Error" not in err
    assert _answers(server)  # the half-sent stop request was not acted upon


def test_an_unknown_path_is_echoed_capped(server):
    connection = _connection(server)
    connection.request("GET", "/api/" + HUGE)
    response = connection.getresponse()
    data = json.loads(response.read())
    connection.close()
    assert response.status == 404
    assert len(data["error"]) < LONGEST_LINE


def test_a_held_coordinate_of_a_request_is_finite(server):
    from pkm.explore import Explorer, RequestError

    explorer = Explorer(pkm.load("delta"))
    with pytest.raises(RequestError, match="held coordinate z = nan violates: a finite number") as caught:
        explorer.handle("map", {"plane": "x,y", "held": "z=nan"})
    assert caught.value.field == "held"
