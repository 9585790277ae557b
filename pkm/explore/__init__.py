"""``pkm explore``: an atlas in the browser that shows the design under the cursor.

A local server (:mod:`pkm.explore.server`, 127.0.0.1 only) serves one page and a JSON API
(:mod:`pkm.explore.api`): the atlas of a global index over a design space or two parameters per working
mode, and for a design its workspace map with the singularity curves and the region, the linkage at a pose
and its card. The page draws with plotly.js from the installed plotly package (``pip install
'pkm[explore]'``), so that it loads nothing from outside the machine. :func:`export_html`
(:mod:`pkm.explore.export`) writes the page with a precomputed atlas and grid of designs as one
self-contained file.

>>> import pkm
>>> from pkm.explore import serve
>>> server = serve(pkm.mechanisms()[0])                    # doctest: +SKIP
>>> server.url                                             # doctest: +SKIP
'http://127.0.0.1:40123/'
>>> server.shutdown()                                      # doctest: +SKIP
"""

from __future__ import annotations

from typing import Any

from pkm.explore.api import Explorer, RequestError
from pkm.explore.export import export_html
from pkm.explore.server import Server, require_plotly
from pkm.mechanism import Mechanism
from pkm.spec.machine import resolve_name

__all__ = ["Explorer", "RequestError", "Server", "explorer", "export_html", "require_plotly", "serve"]


def explorer(mechanism: Mechanism | str, **defaults: Any) -> Explorer:
    """The API of ``mechanism`` (an object, a registered name or a description file) with the requests'
    ``defaults`` (:class:`Explorer`)."""
    mech = resolve_name(mechanism) if isinstance(mechanism, str) else mechanism
    return Explorer(mech, **defaults)


def serve(mechanism: Mechanism | str, *, port: int = 0, verbose: bool = False, **defaults: Any) -> Server:
    """Serve the explorer of ``mechanism`` on 127.0.0.1 (``port`` 0: a free port) in a thread of its own and
    return the running :class:`Server` (``.url``, ``.shutdown()``); ``defaults`` as :class:`Explorer` takes
    them."""
    return Server(explorer(mechanism, **defaults), port=port, verbose=verbose).start()
