"""``pkm explore``'s page in a real headless browser: Debian's chromium driven by playwright, every request to an
address other than 127.0.0.1 aborted (and counted: there must be none). A click on an atlas cell shows that
cell's design in the card and a workspace map whose values are ``Mechanism.local_index`` at the map's poses;
hovering shows a design; the index selector recomputes the atlas and the map; the Certify button draws the region's
certified boxes over the map; the static export opens with the
network blocked and shows the atlas and a card. The plots' titles clear plotly's mode bar, the held parameters'
placeholders fit their inputs, a tooltip over a gap of a map shows no value, a pose out of reach under the pointer
says so, and the stop button stops the server with the atlas it was computing.

Without playwright or /usr/bin/chromium these tests are skipped, unless ``PKM_REQUIRE_BROWSER=1`` (CI sets it):
then they fail."""

from __future__ import annotations

import importlib.util
import os
import re
import threading
import time
from pathlib import Path
from urllib.parse import urlsplit

import numpy as np
import pytest
from helpers import watch_atlas

import pkm
from bench.explore import ARGS, CELL, CHROMIUM, clickable
from pkm.explore import export_html, serve

LOADED = "window.pkmExplore && window.pkmExplore.drawn.map >= 1 && window.pkmExplore.drawn.card >= 1"
SHOWN_MAP = """() => {
  const m = window.pkmExplore.map;
  return {u: m.u, v: m.v, held: m.held, axes: m.axes, mode: m.mode, index: m.index, design: m.design,
          values: m.values.map((row) => row.map((x) => (Number.isFinite(x) ? x : null)))};
}"""
SHOWS = """(design) => { const c = window.pkmExplore.card;
  return Boolean(c) && c.design.every((p) => p.value === design[p.name]); }"""
CARD_DESIGN = """() => Object.fromEntries(Array.from(document.querySelectorAll("#card-design td[data-param]"))
  .map((td) => [td.dataset.param, Number(td.dataset.value)]))"""
PIXEL = """([id, x, y]) => {
  const gd = document.getElementById(id), L = gd._fullLayout, box = gd.getBoundingClientRect();
  return {x: box.left + L._size.l + L.xaxis.l2p(x), y: box.top + L._size.t + L.yaxis.l2p(y)};
}"""
TOOLTIPS = "(id) => Array.from(document.querySelectorAll(`#${id} .hoverlayer .hovertext`)).map((e) => e.textContent)"
TITLE_AND_MODE_BAR = """(id) => [".gtitle", ".modebar"].map((selector) => {
  const b = document.querySelector(`#${id} ${selector}`).getBoundingClientRect();
  return [b.left, b.top, b.right, b.bottom];
})"""
PLACEHOLDERS = """() => {
  const context = document.createElement("canvas").getContext("2d");
  return Array.from(document.querySelectorAll("#held input")).filter((el) => el.value === "").map((el) => {
    const style = getComputedStyle(el);
    context.font = style.font;
    return [el.dataset.param, context.measureText(el.placeholder).width,
            el.clientWidth - parseFloat(style.paddingLeft) - parseFloat(style.paddingRight)];
  });
}"""


def _missing() -> str | None:
    for package in ("playwright", "plotly"):
        if importlib.util.find_spec(package) is None:
            return f"the Python package {package} is not installed (pip install -e '.[test]')"
    if not Path(CHROMIUM).exists():
        return f"{CHROMIUM} is missing (apt-get install chromium)"
    return None


@pytest.fixture(scope="module")
def browser():
    missing = _missing()
    if missing and os.environ.get("PKM_REQUIRE_BROWSER") == "1":
        pytest.fail(f"PKM_REQUIRE_BROWSER=1 but {missing}")
    if missing:
        pytest.skip(missing)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def server():
    running = serve("five_bar", resolution=9, map_resolution=48)
    yield running
    running.shutdown()


def _open(browser):
    """A page whose requests to anywhere but this machine are aborted; ``page.blocked`` lists them and
    ``page.errors`` its uncaught errors."""
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    opened = context.new_page()
    opened.blocked, opened.errors = [], []

    def local_only(route):
        parts = urlsplit(route.request.url)
        if parts.scheme in ("file", "data", "blob") or parts.hostname == "127.0.0.1":
            route.continue_()
        else:
            opened.blocked.append(route.request.url)
            route.abort()

    def record(error):  # playwright wraps a listener in attributes that a builtin method cannot take
        opened.errors.append(error)

    opened.route("**/*", local_only)
    opened.on("pageerror", record)
    return opened


@pytest.fixture
def page(browser):
    """A page of its own (a context of its own), closed after the test."""
    opened = _open(browser)
    yield opened
    opened.context.close()
    assert opened.errors == []


@pytest.fixture(scope="module")
def server_page(browser, server):
    opened = _open(browser)
    opened.goto(server.url)
    opened.wait_for_function(LOADED, timeout=60_000)
    yield opened
    opened.context.close()


@pytest.fixture(scope="module")
def busy_state(browser):
    state = {}
    yield state
    if state:
        state["server"].shutdown()
        state["page"].context.close()


@pytest.fixture
def busy(busy_state, browser):
    """A server whose atlas (lambda_e at 81 x 81 designs) is computed long enough to be cancelled or stopped,
    and a page for it, kept for the next test: the cancel test leaves the server serving and the stop test, after
    it, loads the page from the same address (a second load of plotly's script from one address is a quarter of
    the first) and stops it; a test that finds the server stopped starts another."""
    if not busy_state or busy_state["server"].explorer.closed:
        if busy_state:
            busy_state["server"].shutdown()
        busy_state["server"] = serve("five_bar", index="lambda_e", resolution=81, map_resolution=48)
    if "page" not in busy_state:
        busy_state["page"] = _open(browser)
    page = busy_state["page"]
    before = len(page.errors)
    yield busy_state["server"], page
    assert page.errors[before:] == []


@pytest.fixture
def loaded(server_page):
    """The module server's page, loaded once (each load is about a second of plotly's script in chromium) and
    shared by the tests that read it and point at it, in this order: the titles, the pose out of reach, then the
    click, which changes the index; each test's uncaught errors are checked after it."""
    before = len(server_page.errors)
    yield server_page
    assert server_page.errors[before:] == []


def _design(atlas: dict, node: tuple[int, int]) -> dict[str, float]:
    return {**atlas["held"], **atlas["designs"][node[0]][node[1]]}


def _assert_map_is_the_local_index(mech, shown: dict) -> None:
    U, V = np.meshgrid(shown["u"], shown["v"], indexing="ij")
    names = list(mech.pose_names)
    poses = np.zeros((U.size, len(names)))
    for k, name in enumerate(names):
        poses[:, k] = U.ravel() if name == shown["axes"][0] else V.ravel() if name == shown["axes"][1] else \
            shown["held"][name]
    expected = mech.local_index(shown["index"], poses, shown["design"], mode=shown["mode"]).reshape(U.shape)
    np.testing.assert_array_equal(np.array(shown["values"], dtype=float), expected)
    assert np.isfinite(expected).sum() > 50


def _hover(page, plot: str, u: float, v: float) -> str:
    """The tooltip of the plot at (u, v) of its axes."""
    page.mouse.move(0, 0)
    page.wait_for_function(f"(id) => ({TOOLTIPS})(id).length === 0", arg=plot)
    point = page.evaluate(PIXEL, [plot, u, v])
    page.mouse.move(point["x"], point["y"])
    page.wait_for_function(f"(id) => ({TOOLTIPS})(id).length === 1", arg=plot)
    return page.evaluate(TOOLTIPS, plot)[0]


def _wait(page, event: threading.Event, timeout: float) -> bool:
    """Wait for an event of the server's threads while playwright serves the page (its routes run in this
    thread): whether it came within ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not event.is_set() and time.monotonic() < deadline:
        page.wait_for_timeout(20)
    return event.is_set()


def test_the_titles_clear_the_mode_bar_and_the_held_placeholders_fit(loaded):
    page = loaded
    for plot in ("atlas", "map"):
        title, bar = page.evaluate(TITLE_AND_MODE_BAR, plot)
        apart = title[2] <= bar[0] or bar[2] <= title[0] or title[3] <= bar[1] or bar[3] <= title[1]
        assert apart, f"the {plot}'s title {title} overlaps its mode bar {bar}"
    placeholders = page.evaluate(PLACEHOLDERS)
    assert placeholders, "five_bar's masses follow the chart of Gao's space"
    for name, needed, room in placeholders:
        assert needed <= room, f"the placeholder of {name} needs {needed:.0f} px of {room:.0f}"


def test_a_pose_out_of_reach_under_the_pointer_says_so_and_gaps_show_no_value(loaded):
    page = loaded
    shown = page.evaluate("(() => { const m = window.pkmExplore.map; return {u: m.u, v: m.v, z: m.z, "
                          "index: m.index}; })()")
    z = np.array(shown["z"], dtype=float)
    inner = np.zeros_like(z, dtype=bool)
    inner[2:-2, 2:-2] = True
    gap = np.argwhere(np.isnan(z) & inner)[0]
    reached = np.argwhere(np.isfinite(z) & inner)[len(np.argwhere(np.isfinite(z) & inner)) // 2]
    tooltip = _hover(page, "map", shown["u"][gap[1]], shown["v"][gap[0]])
    assert tooltip.endswith("out of reach")
    assert shown["index"] not in tooltip
    page.wait_for_function("document.getElementById('map-note').textContent.includes('is out of reach in mode')")
    assert "no drawing" not in page.inner_text("#map-note")
    tooltip = _hover(page, "map", shown["u"][reached[1]], shown["v"][reached[0]])
    assert re.search(rf"{shown['index']} [0-9.e-]+$", tooltip), tooltip
    page.wait_for_function("!document.getElementById('map-note').textContent.includes('out of reach')")
    page.wait_for_function("document.getElementById('map-note').textContent.includes('2 real assemblies at these "
                           "joints')")
    assert "other assemblies at these joints" in page.inner_text("#map-note")
    atlas = page.evaluate("window.pkmExplore.atlas")
    assert atlas["designs"][0][0] is None
    assert _hover(page, "atlas", atlas["u"][0], atlas["v"][0]).endswith("outside the design space")


def test_a_click_on_the_atlas_shows_that_design_its_map_and_card(loaded, tmp_path):
    page = loaded
    five_bar = pkm.load("five_bar")
    page.wait_for_function("window.pkmExplore.optimum", timeout=60_000)
    assert "optimum of five_bar.max_gci_miw" in page.inner_text("#atlas-note")
    atlas = page.evaluate("window.pkmExplore.atlas")
    mode = page.evaluate("window.pkmExplore.mode")
    shown = tuple(page.evaluate("window.pkmExplore.shown.node"))
    nodes = [n for n in clickable(atlas, mode, page.evaluate("window.pkmExplore.optimum")) if n != shown]
    clicked, hovered = nodes[0], nodes[1]

    point = page.evaluate(CELL, list(hovered))
    page.mouse.move(point["x"], point["y"])
    page.wait_for_function(SHOWS, arg=_design(atlas, hovered))
    assert page.evaluate("window.pkmExplore.shown.node") == list(hovered)

    clicks = page.evaluate("window.pkmExplore.timings.length")
    point = page.evaluate(CELL, list(clicked))
    page.mouse.click(point["x"], point["y"])
    page.wait_for_function(f"window.pkmExplore.timings.length > {clicks}")
    expected = _design(atlas, clicked)
    page.wait_for_function(SHOWS, arg=expected)
    assert page.evaluate("window.pkmExplore.clicked.node") == list(clicked)
    assert page.evaluate(CARD_DESIGN) == expected
    assert page.inner_text("#card-indices").count("\n") >= 2
    shown_map = page.evaluate(SHOWN_MAP)
    assert shown_map["design"] == pytest.approx({**five_bar.design(expected, partial=True)})
    assert (shown_map["index"], shown_map["mode"]) == ("inverse_condition_f", mode)
    _assert_map_is_the_local_index(five_bar, shown_map)

    # the pointer off the atlas: the new index's atlas is laid out anew and its cells move (30 px at 1400 x 1000),
    # so a pointer left on the clicked cell would hover the next one and, a moment later, show its design
    page.mouse.move(0, 0)
    page.select_option("#index", "gamma_max")
    page.wait_for_function("window.pkmExplore.atlas.index === 'gamma_max' && window.pkmExplore.map.index === "
                           "'velocity_max'", timeout=60_000)
    shown_map = page.evaluate(SHOWN_MAP)
    assert shown_map["design"] == pytest.approx({**five_bar.design(expected, partial=True)})
    _assert_map_is_the_local_index(five_bar, shown_map)
    assert page.evaluate(CARD_DESIGN) == expected

    page.screenshot(path=str(tmp_path / "explore.png"), full_page=True)
    assert (tmp_path / "explore.png").stat().st_size > 20_000
    assert page.evaluate("window.pkmExplore.errors") == []
    assert page.blocked == []


def test_certify_draws_the_regions_boxes_over_the_map(loaded):
    """The Certify button: the region certified at the shown design and mode (Mechanism.certify's verdict and
    boxes), its proved and undecided boxes drawn over the map in the pose's plane, the verdict in the status."""
    page = loaded
    five_bar = pkm.load("five_bar")
    page.click("#certify")
    page.wait_for_function("window.pkmExplore.drawn.certified >= 1", timeout=60_000)
    shown = page.evaluate("window.pkmExplore.certified.answer")
    design, mode = page.evaluate("window.pkmExplore.design"), page.evaluate("window.pkmExplore.mode")
    found = five_bar.certify(shown["region"], five_bar.design(design, partial=True), mode=mode, seconds=10)
    assert (shown["verdict"], shown["boxes"], shown["mode"]) == (found.verdict, found.boxes, mode)
    traces = page.evaluate("Array.from(document.getElementById('map').data, (t) => t.name)")
    drawn = {name.split(" (")[0]: name for name in traces if name and name.split(" (")[0] in ("proved", "undecided")}
    counts = found.as_dict()["cells"]
    assert drawn == {state: f"{state} ({n} boxes)" for state, n in counts.items() if n}
    assert f"{found.verdict} ({found.boxes} boxes" in page.inner_text("#status")
    assert f"certified: {found.verdict}, {counts['proved']} boxes proved" in page.inner_text("#map-note")
    assert page.evaluate("window.pkmExplore.errors") == []


def test_cancel_stops_the_atlas_in_flight_and_the_page_goes_on(busy, monkeypatch):
    """The Cancel button, shown while the atlas is computed: the server cancels it (not an error on the page),
    and the page then draws the atlas of another index."""
    running, page = busy
    started, ended = watch_atlas(monkeypatch)
    page.goto(running.url)
    assert _wait(page, started, 120), "the page asked for its atlas"
    assert page.is_visible("#cancel")
    page.click("#cancel")
    page.wait_for_function("document.getElementById('status').textContent.includes('cancelled')")
    assert _wait(page, ended, 5), "the atlas of lambda_e at 81 x 81 designs was cancelled"
    assert page.evaluate("window.pkmExplore.errors") == []
    assert not page.is_visible("#cancel")
    page.select_option("#index", "gci")
    page.wait_for_function("window.pkmExplore.drawn.atlas >= 1", timeout=60_000)
    assert not running.explorer.closed


def test_stop_server_cancels_the_atlas_in_flight_and_the_page_says_stopped(busy, monkeypatch):
    running, page = busy
    started, ended = watch_atlas(monkeypatch)
    page.goto(running.url)
    assert _wait(page, started, 120), "the page asked for its atlas"
    page.click("#stop")
    page.wait_for_function("document.getElementById('status').textContent.includes('stopped')")
    assert _wait(page, ended, 5), "the atlas of lambda_e at 81 x 81 designs was cancelled"
    running._thread.join(timeout=30)
    assert not running._thread.is_alive()
    page.wait_for_timeout(500)
    assert page.inner_text("#status") == "the server has stopped; close this page"
    assert page.evaluate("window.pkmExplore.drawn.atlas") == 0
    assert page.evaluate("window.pkmExplore.errors") == []
    assert page.is_disabled("#stop")
    assert page.is_disabled("#index")


def test_the_static_export_shows_the_atlas_and_a_card_offline(page, server, tmp_path):
    path = export_html(server.explorer, tmp_path / "atlas.html", grid=2, map_resolution=24)
    page.goto(path.as_uri())
    page.wait_for_function(LOADED, timeout=60_000)
    assert page.evaluate("window.pkmExplore.static")
    assert page.evaluate("document.querySelectorAll('#atlas .hm image').length") >= 1
    atlas = page.evaluate("window.pkmExplore.atlas")
    entries = page.evaluate("JSON.parse(document.getElementById('pkm-static').textContent).entries")
    first = page.evaluate(CARD_DESIGN)
    assert first in [e["design"] for e in entries]
    target = entries[-1] if first == entries[0]["design"] else entries[0]
    point = page.evaluate(CELL, target["node"])
    page.mouse.click(point["x"], point["y"])
    page.wait_for_function(SHOWS, arg=target["design"])
    assert page.evaluate("window.pkmExplore.clicked.node") == target["node"]
    assert page.evaluate(CARD_DESIGN) == target["design"] == _design(atlas, tuple(target["node"]))
    assert page.inner_text("#card-indices").count("\n") >= 2
    assert page.blocked == []
