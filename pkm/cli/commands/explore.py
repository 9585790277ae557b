"""``pkm explore``: an atlas in the browser (:mod:`pkm.explore`, docs/explore.md)."""

from __future__ import annotations

import argparse
import sys

from pkm import io
from pkm.cli.arguments import example, integer, listed
from pkm.cli.common import RESULT, check_file, emit, load_mechanism

HELP = ("an atlas in the browser: click or hover a design to see its workspace map, singularities, region, linkage "
        "and card (a local server on 127.0.0.1; needs pip install 'pkm[explore]')")
PARALLEL = False


def options(p: argparse.ArgumentParser) -> None:
    """The atlas (mechanism, index, region, design space or axes, design, problem, resolutions), the server's
    port and browser, or the page as one file."""
    listed(p, "mechanism", key="mechanism")
    example(p, "--index", help="global index of the atlas (default: the mechanism's first, see pkm list); e.g. "
                               "{index}")
    example(p, "--region", help="region of the atlas and the cards (default: the mechanism's first parametrised "
                                "one, else reachable); e.g. {region}")
    listed(p, "--space", key="space")
    example(p, "--axes", help="two design parameters with bounds instead of a design space (default: the first "
                              "design space, else the first two parameters at half to 1.5 times their defaults): "
                              "name=lower:upper,name=lower:upper; e.g. {axes}")
    example(p, "--design", help="the parameters off the atlas's chart, name=value in SI (default: the defaults); "
                                "e.g. {parameter}")
    p.add_argument("--problem", help="a synthesis problem whose optimum the atlas marks: a registered name or a "
                                     "task file (default: a registered problem of the mechanism that optimises "
                                     "the index over the region); e.g. my_task.toml")
    p.add_argument("--resolution", type=integer, default=21, help="design grid nodes per chart axis (default 21, 3 to "
                                                                  "81); e.g. 41")
    p.add_argument("--map-resolution", type=integer, default=128, help="poses per axis of the workspace maps "
                                                                       "(default 128, 3 to 256); e.g. 256")
    p.add_argument("--port", type=integer, default=0, help="port on 127.0.0.1 (default 0: a free port); e.g. 8765")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser (default: open one)")
    p.add_argument("--html", help="write the page with a precomputed atlas and grid of cards as one "
                                  "self-contained file instead of serving it (default: serve); e.g. atlas.html")
    p.add_argument("--grid", type=integer, default=5, help="with --html, precomputed designs per chart axis (default "
                                                           "5, 1 to 21); e.g. 7")


def run(args: argparse.Namespace) -> None:
    """The explorer (:mod:`pkm.explore`): a local server and its page until Ctrl-C or the page's stop
    request, or with ``--html`` the page with its data as one file."""
    from pkm.explore import Explorer, Server, export_html, require_plotly

    require_plotly()
    check_file("--html", args.html)
    m = load_mechanism(args.mechanism)
    problem = args.problem
    if problem and problem.endswith(".toml"):
        from pkm.synthesis.designer import read_problem

        problem = read_problem(problem)
    design = io.read_design(args.design) if args.design and args.design.endswith(RESULT) else args.design
    explorer = Explorer(m, index=args.index, region=args.region, space=args.space, axes=args.axes,
                        design=design, problem=problem, resolution=args.resolution,
                        map_resolution=args.map_resolution)
    if args.html is not None:
        path = export_html(explorer, args.html, grid=args.grid)
        emit(args, {"mechanism": m.name, "html": str(path)}, f"wrote {path}")
        return
    server = Server(explorer, port=args.port)
    emit(args, {"mechanism": m.name, "url": server.url},
         f"pkm explore: {m.name} at {server.url} (Ctrl-C or the page's stop button ends it)")
    sys.stdout.flush()
    if not args.no_browser:
        import webbrowser

        webbrowser.open(server.url)
    server.serve_forever()
    print("pkm explore: stopped", file=sys.stderr)
