"""Issue 26, ``pkm explore``: ``python -m bench.explore [--json PATH] [--requests N] [--clicks N]``.

A server of the five-bar at the explorer's defaults (the atlas of the GCI over the MIW in Gao's space at 21 x 21
designs, three working modes) on a free port of 127.0.0.1, asked through urllib after one warm-up request of
each kind (the kernels compiled): ``requests`` atlases, cards and workspace maps at 128 x 128 and 256 x 256 poses
(base64 arrays, as the page asks), each for the next design of the atlas's grid; the wall time of each request,
its median and 95th percentile. Baseline in the same run: the same maps from a server on CasADi's interpreter
(``PKM_COMPILED=0``, ``pkm explore`` in a process of its own). Then the page in headless chromium (playwright,
/usr/bin/chromium): ``clicks`` clicks on atlas cells, each the time from the click event to the frame after its
128 x 128 map is drawn (the page's own ``window.pkmExplore.timings``); goal: under 100 ms. The load average
before and after is recorded: nothing asserts on time.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time
import urllib.parse
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np

from pkm.explore import serve

MECHANISM = "five_bar"
ATLAS_RESOLUTION = 21
MAPS = (128, 256)
GOAL_MS = 100.0
CHROMIUM = "/usr/bin/chromium"
ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--no-first-run"]
CELL = """([i, j]) => {
  const gd = document.getElementById("atlas"), L = gd._fullLayout, a = window.pkmExplore.atlas;
  const box = gd.getBoundingClientRect();
  return {x: box.left + L._size.l + L.xaxis.l2p(a.u[i]), y: box.top + L._size.t + L.yaxis.l2p(a.v[j])};
}"""

SHOWN = """([clicks, design]) => { const s = window.pkmExplore;
  return s.timings.length > clicks && Boolean(s.card) && s.card.design.every((p) => p.value === design[p.name]); }"""


def _get(url: str) -> int:
    with urllib.request.urlopen(url, timeout=600) as response:
        return len(response.read())


def _summary(seconds: list[float], size: int) -> dict[str, Any]:
    ms = np.array(seconds) * 1000
    return {"median_ms": float(np.median(ms)), "p95_ms": float(np.percentile(ms, 95)), "requests": len(ms),
            "bytes": size}


def _designs(url: str) -> list[str]:
    """Every design of the atlas's grid with a value in the first mode, as the page's design field."""
    with urllib.request.urlopen(url + "api/atlas", timeout=600) as response:
        atlas = json.loads(response.read())
    values = np.array(atlas["values"][atlas["modes"][0]], dtype=float)
    return [",".join(f"{k}={v!r}" for k, v in {**atlas["held"], **atlas["designs"][i][j]}.items())
            for i, j in np.argwhere(np.isfinite(values))]


def _timed(url: str, endpoint: str, fields: list[dict[str, str]]) -> dict[str, Any]:
    """One warm-up request, then one per entry of ``fields``."""
    size = _get(url + f"api/{endpoint}?" + urllib.parse.urlencode(fields[0]))
    seconds = []
    for f in fields:
        start = time.perf_counter()
        _get(url + f"api/{endpoint}?" + urllib.parse.urlencode(f))
        seconds.append(time.perf_counter() - start)
    return _summary(seconds, size)


def _maps(url: str, designs: list[str], requests: int) -> dict[str, Any]:
    return {f"map_{n}": _timed(url, "map", [{"design": designs[k % len(designs)], "resolution": str(n),
                                               "arrays": "base64"} for k in range(requests)]) for n in MAPS}


def _interpreted(designs: list[str], requests: int) -> dict[str, Any]:
    """The maps from ``pkm explore`` on the interpreter, in a process of its own."""
    env = {**os.environ, "PKM_COMPILED": "0"}
    run = subprocess.Popen([sys.executable, "-m", "pkm.cli", "explore", MECHANISM, "--no-browser"],
                           stdout=subprocess.PIPE, text=True, env=env)
    try:
        url = re.search(r"http://127\.0\.0\.1:\d+/", run.stdout.readline())[0]
        answer = _maps(url, designs, requests)
        stop = urllib.request.Request(url + "api/stop", data=b"{}", headers={"Content-Type": "application/json"})
        urllib.request.urlopen(stop, timeout=60).read()
        run.wait(timeout=60)
        return answer
    finally:
        if run.poll() is None:
            run.terminate()


def clickable(atlas: dict[str, Any], mode: str, optimum: dict[str, Any] | None) -> list[tuple[int, int]]:
    """The atlas's nodes with a value in ``mode``, the best first, but those next to the optimum's marker (a click
    there shows the optimum)."""
    values = np.array(atlas["values"][mode], dtype=float)
    nodes = [(int(i), int(j)) for i, j in np.argwhere(np.isfinite(values))]
    if optimum and optimum.get("problem"):
        a, b = (int(np.argmin(np.abs(np.array(atlas[axis]) - optimum[axis]))) for axis in ("u", "v"))
        nodes = [n for n in nodes if max(abs(n[0] - a), abs(n[1] - b)) > 1]
    return sorted(nodes, key=lambda n: -values[n])


def _clicks(url: str, clicks: int) -> dict[str, Any]:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page(viewport={"width": 1400, "height": 1000})
        page.goto(url)
        page.wait_for_function("window.pkmExplore && window.pkmExplore.drawn.card >= 1 && window.pkmExplore.optimum",
                               timeout=300_000)
        atlas = page.evaluate("window.pkmExplore.atlas")
        nodes = clickable(atlas, page.evaluate("window.pkmExplore.mode"), page.evaluate("window.pkmExplore.optimum"))
        for k in range(clicks + 1):
            i, j = nodes[(7 * k) % len(nodes)]
            point = page.evaluate(CELL, [i, j])
            page.mouse.click(point["x"], point["y"])
            page.wait_for_function(SHOWN, arg=[k, {**atlas["held"], **atlas["designs"][i][j]}], timeout=60_000)
        timings = page.evaluate("window.pkmExplore.timings")[1:]
        resolution = page.evaluate("window.pkmExplore.map.u.length")
        version = browser.version
        browser.close()
    return {"clicks": len(timings), "map_resolution": resolution, "median_ms": statistics.median(timings),
            "p95_ms": float(np.percentile(timings, 95)), "max_ms": max(timings), "chromium": version}


def run(*, requests: int = 100, clicks: int = 30, log: Any = print) -> dict[str, Any]:
    before = os.getloadavg()
    server = serve(MECHANISM, resolution=ATLAS_RESOLUTION, map_resolution=MAPS[0])
    try:
        designs = _designs(server.url)
        log(f"{len(designs)} designs")
        timed = {"atlas": _timed(server.url, "atlas", [{}] * requests),
                 "card": _timed(server.url, "card", [{"design": designs[k % len(designs)]} for k in range(requests)]),
                 **_maps(server.url, designs, requests)}
        log("server: " + ", ".join(f"{k} {v['median_ms']:.1f} ms" for k, v in timed.items()))
        interpreted = _interpreted(designs, requests)
        log("interpreter: " + ", ".join(f"{k} {v['median_ms']:.1f} ms" for k, v in interpreted.items()))
        browser = _clicks(server.url, clicks)
        log(f"click to drawn map: {browser['median_ms']:.1f} ms median")
    finally:
        server.shutdown()
    return {"command": "python -m bench.explore --json docs/benchmarks/explore.json", "mechanism": MECHANISM,
            "atlas_resolution": ATLAS_RESOLUTION, "goal_ms": GOAL_MS, "server": timed, "interpreter": interpreted,
            "browser": browser, "cpus": os.cpu_count(),
            "load_average": {"before": [round(x, 2) for x in before],
                             "after": [round(x, 2) for x in os.getloadavg()]}}


def markdown(data: dict[str, Any]) -> str:
    """The docs/benchmarks.md section of a run."""
    lines = [f"Command: `{data['command']}` ({data['mechanism']}, {data['cpus']} CPUs, load average "
             f"{data['load_average']['before'][0]:.2f} before and {data['load_average']['after'][0]:.2f} after the "
             f"run; each request after one warm-up of its kind, the kernels compiled).", "",
             "| request | median | 95th percentile | requests | answer | interpreter: median | 95th percentile |",
             "|---|---|---|---|---|---|---|"]
    names = {"atlas": f"atlas, {data['atlas_resolution']} x {data['atlas_resolution']} designs, 3 modes",
             "card": "card (every global index over the MIW)", "map_128": "map, 128 x 128 poses",
             "map_256": "map, 256 x 256 poses"}
    for key, name in names.items():
        t = data["server"][key]
        slow = data["interpreter"].get(key)
        base = f"{slow['median_ms']:.1f} ms | {slow['p95_ms']:.1f} ms" if slow else "- | -"
        lines.append(f"| {name} | {t['median_ms']:.1f} ms | {t['p95_ms']:.1f} ms | {t['requests']} | "
                     f"{t['bytes'] / 1024:.0f} KiB | {base} |")
    b = data["browser"]
    lines += ["", f"Click on an atlas cell to its {b['map_resolution']} x {b['map_resolution']} map drawn, in headless "
                  f"chromium {b['chromium']} ({b['clicks']} clicks): median {b['median_ms']:.1f} ms, 95th percentile "
                  f"{b['p95_ms']:.1f} ms, at most {b['max_ms']:.1f} ms (goal: under {data['goal_ms']:g} ms).", "",
              "The server computes one request at a time (CasADi's functions are not called from two threads at "
              "once). A map's answer holds its values, the two singularity determinants and the region's mask as "
              "base64 arrays, and their curves: the same work on both paths but the local index and the "
              "determinants, which make the interpreter's map " + " and ".join(
                  f"{data['interpreter'][k]['median_ms'] / data['server'][k]['median_ms']:.1f}x" for k in names
                  if k in data["interpreter"]) + " slower (medians, 128 and 256 poses per axis). A click's time is "
              "the page's own measure (`window.pkmExplore.timings`: from the click event to the frame after plotly.js "
              "has drawn the map); the card and the atlas's marker follow the map."]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.explore", description=__doc__)
    parser.add_argument("--json", help="write the run here (default: print only)")
    parser.add_argument("--requests", type=int, default=100, help="requests of each kind (default 100)")
    parser.add_argument("--clicks", type=int, default=30, help="clicks in the browser (default 30)")
    args = parser.parse_args(argv)
    data = run(requests=args.requests, clicks=args.clicks, log=lambda text: print(text, file=sys.stderr))
    if args.json:
        Path(args.json).write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
    print(markdown(data))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
