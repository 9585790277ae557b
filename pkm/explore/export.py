"""The explorer as one self-contained HTML file (``pkm explore ... --html out.html``): the page with plotly.js,
its script and style inlined and the answers of the API embedded, for reports and for readers without
Python.

The atlas is the one the explorer's defaults ask for; the cards are those of a grid of designs over its chart
(``grid`` x ``grid`` nodes spread over the chart, each moved to the nearest node with a value): for each and
each mode of the atlas, the card, the workspace map (without the arrays the page draws as curves) and the linkage
at the card's pose, as the server would answer them. The page shows, on a click on the atlas, the card of the
nearest precomputed design.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np

from pkm import io
from pkm.errors import check_integer
from pkm.explore.api import MAX_MAP, Explorer
from pkm.explore.server import asset, plotly_js

GRID = 5  # precomputed designs per chart axis
MAP_RESOLUTION = 64  # poses per axis of the precomputed maps
STYLE = '<link rel="stylesheet" href="explore.css">'
PLOTLY = '<script src="plotly.min.js"></script>'
SCRIPT = '<script src="explore.js"></script>'
UNDRAWN = ("singular", "region_inside")  # a map's arrays the page draws as curves, left out of the file


def grid_nodes(atlas: dict[str, Any], grid: int) -> list[tuple[int, int]]:
    """``grid`` x ``grid`` chart nodes spread evenly over the atlas's grid, each the nearest node (in grid
    steps) whose design has a value in some mode; without repeats."""
    finite = np.zeros((len(atlas["u"]), len(atlas["v"])), dtype=bool)
    for values in atlas["values"].values():
        finite |= np.isfinite(np.asarray(values, dtype=float))
    candidates = np.argwhere(finite & np.asarray(atlas["inside"]))
    if not len(candidates):
        return []
    nodes: list[tuple[int, int]] = []
    for a in np.linspace(0, len(atlas["u"]) - 1, grid):
        for b in np.linspace(0, len(atlas["v"]) - 1, grid):
            i, j = candidates[np.argmin(np.hypot(candidates[:, 0] - a, candidates[:, 1] - b))]
            if (int(i), int(j)) not in nodes:
                nodes.append((int(i), int(j)))
    return nodes


def precompute(explorer: Explorer, *, grid: int = GRID, map_resolution: int = MAP_RESOLUTION) -> dict[str, Any]:
    """What the exported page shows: the mechanism, the atlas of the explorer's defaults, its optimum and the
    cards of :func:`grid_nodes`, each as the API answers it."""
    grid = check_integer("grid", grid, 1, 21)
    map_resolution = check_integer("map_resolution", map_resolution, 3, MAX_MAP)
    meta = explorer.handle("mechanism", {})
    atlas = explorer.handle("atlas", {})
    optimum = explorer.handle("optimum", {}) if atlas["problem"] else None
    index = next(i["local"] for i in meta["global_indices"] if i["name"] == atlas["index"])
    entries = []
    for i, j in grid_nodes(atlas, grid):
        design = {**atlas["held"], **atlas["designs"][i][j]}
        text = ",".join(f"{k}={v!r}" for k, v in design.items())
        modes = {}
        for mode in atlas["modes"]:
            fields = {"design": text, "mode": mode, "region": atlas["region"], "index": index}
            card = explorer.handle("card", fields)
            answer = explorer.handle("map", {**fields, "resolution": str(map_resolution), "arrays": "base64"})
            shown = {k: v for k, v in answer.items() if k not in UNDRAWN}
            pose = ",".join(repr(card["pose"][p["name"]]) for p in meta["pose"])
            linkage = explorer.handle("linkage", {"design": text, "mode": mode, "pose": pose,
                                                  "plane": ",".join(shown["axes"])})
            modes[mode] = {"card": card, "map": shown, "linkage": linkage}
        entries.append({"node": [i, j], "design": design, "modes": modes})
    return {"mechanism": meta, "atlas": atlas, "optimum": optimum, "entries": entries,
            "map_resolution": map_resolution}


def page(data: dict[str, Any]) -> str:
    """The page with its assets inlined and ``data`` embedded (as JSON the page reads instead of the API)."""
    html = asset("index.html").decode()
    plotly, script = (text.replace("</script", "<\\/script") for text in (plotly_js().decode(),
                                                                         asset("explore.js").decode()))
    compact = json.dumps(json.loads(io.to_json(data)), separators=(",", ":"))  # NaN as null, as the API sends it
    embedded = compact.replace("</", "<\\/")
    parts = {
        STYLE: f"<style>\n{asset('explore.css').decode()}</style>",
        PLOTLY: f"<script>{plotly}</script>",
        SCRIPT: f'<script type="application/json" id="pkm-static">{embedded}</script>\n<script>{script}</script>',
    }
    for tag, inlined in parts.items():
        head, found, tail = html.partition(tag)
        if not found:
            raise RuntimeError(f"the page index.html lacks {tag}, which the export inlines")
        html = head + inlined + tail
    return html


def export_html(explorer: Explorer, path: str | os.PathLike, *, grid: int = GRID,
                map_resolution: int = MAP_RESOLUTION) -> Path:
    """Write the explorer's page with :func:`precompute` 's data into ``path``, atomically (a temporary file
    beside it, renamed into place)."""
    html = page(precompute(explorer, grid=grid, map_resolution=map_resolution))
    return io.atomic_write(Path(path), lambda tmp: tmp.write_text(html, encoding="utf-8"))
