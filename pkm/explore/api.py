"""The explorer's JSON API: each endpoint is a function of a request's fields (the query string's
``name=value`` pairs) that answers a JSON-ready dict, computed by the code paths of ``pkm atlas``
(:func:`pkm.atlas.compute_atlas`), ``pkm show`` (:func:`pkm.card.design_card`) and the workspace maps
(:func:`pkm.workspace_map.workspace_slice`).

A field that is missing takes the explorer's default (what ``pkm explore`` was started with); a field that
is malformed, unknown to the endpoint or names what the mechanism does not have raises
:class:`RequestError`, which names the field (the server answers it with HTTP 400). Arrays are nested lists
(NaN as null), or with ``arrays=base64`` objects ``{"dtype": "float64", "shape": [...], "data": ...}``: the
array's little-endian bytes in base64, row-major, NaN kept (a 256 x 256 map encodes in milliseconds).

The explorer computes one request at a time; :meth:`Explorer.close` cancels the computation in flight and every
later one (:class:`CancelledError`), as its server does when it stops.
"""

from __future__ import annotations

import base64
import math
import reprlib
import threading
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import replace
from typing import Any

import casadi as ca
import numpy as np

from pkm import figures, registry
from pkm.atlas import compute_atlas, default_modes
from pkm.card import design_card, region_centre
from pkm.design import Design, parse_design
from pkm.design_space import DesignSpace, parameter_plane, parse_axes
from pkm.drawn_assemblies import assemblies_at_pose
from pkm.errors import PkmError, check_integer
from pkm.mechanism import Mechanism
from pkm.regions.shapes import PlacedRegion
from pkm.workspace_map import WorkspaceSlice, check_plane, plane_columns, workspace_slice

ATLAS_RESOLUTION = 21  # chart nodes per axis of an atlas by default
MAX_ATLAS = 81  # the most an atlas request may ask for: a page's atlas answers within seconds
MAP_RESOLUTION = 128  # poses per axis of a workspace map by default
MAX_MAP = 256
CARD_RESOLUTION = 32  # poses per axis of the card's own map (the page draws the map endpoint's)
AXIS_SPAN = 0.5  # default axes without a design space: each parameter's default times 1 -/+ this
SAMPLED = ("reachable", "assembled")  # the sampled regions, which have no nodes or placement to draw
ENCODINGS = ("list", "base64")
CERTIFY_SECONDS = 10  # a certification's time budget by default (the page waits for it)
MAX_CERTIFY = 120  # the most a request may give it: the explorer computes one request at a time

FIELDS = {
    "mechanism": (),
    "atlas": ("index", "region", "space", "axes", "design", "resolution", "mode"),
    "optimum": ("problem", "index", "region", "space", "axes", "design"),
    "card": ("design", "mode", "region", "index", "indices", "resolution"),
    "map": ("design", "mode", "index", "plane", "held", "region", "resolution", "arrays"),
    "linkage": ("design", "mode", "pose", "plane"),
    "certify": ("design", "mode", "region", "properties", "seconds"),
}


class CancelledError(Exception):
    """A computation of an :class:`Explorer` that was closed (its server stopped) before or while it ran: not a
    PkmError, which a request's field would be blamed for."""


class RequestError(PkmError):
    """A request field that is malformed or names what the mechanism does not have: ``field`` names it,
    ``parameter`` the design parameter where one is at fault."""

    def __init__(self, field: str, message: str, parameter: str | None = None) -> None:
        super().__init__(message)
        self.field = field
        self.parameter = parameter

    def to_dict(self) -> dict[str, Any]:
        out = {"error": str(self), "field": self.field}
        return {**out, "parameter": self.parameter} if self.parameter else out


@contextmanager
def blame(field: str) -> Iterator[None]:
    """A PkmError raised in the block as a :class:`RequestError` of ``field``."""
    try:
        yield
    except RequestError:
        raise
    except PkmError as exc:
        raise RequestError(field, str(exc)) from None


def encode(values: np.ndarray, arrays: str) -> Any:
    """An array as the request's ``arrays`` encoding asks: the array itself (nested lists in JSON) or base64."""
    if arrays == "list":
        return values
    data = np.ascontiguousarray(values, dtype="<f8")
    return {"dtype": "float64", "shape": list(data.shape), "data": base64.b64encode(data.tobytes()).decode()}


def colour_limits(values: Sequence[np.ndarray]) -> dict[str, float] | None:
    """The colour limits the figures of pkm take (:func:`pkm.figures.robust_limits`) over the finite values of
    ``values``; None where none is finite."""
    finite = np.concatenate([np.ravel(v) for v in values])
    if not np.isfinite(finite).any():
        return None
    limits = figures.robust_limits(finite)
    return {"min": limits.vmin, "max": limits.vmax}


def level_curves(u: np.ndarray, v: np.ndarray, values: np.ndarray, level: float) -> list[np.ndarray]:
    """The curves (each (k, 2) in (u, v)) where ``values`` (len(u), len(v); NaN where undefined) crosses
    ``level``, by contourpy (matplotlib's contouring)."""
    from contourpy import contour_generator

    if not np.isfinite(values).any():
        return []
    return list(contour_generator(x=u, y=v, z=np.ma.masked_invalid(values.T)).lines(level))


def _text(values: Mapping[str, float]) -> str:
    """``name=value,...`` with each value's shortest exact repr."""
    return ",".join(f"{k}={float(v)!r}" for k, v in values.items())


class Explorer:
    """The API of one mechanism: :meth:`handle` answers a request to an endpoint of :data:`FIELDS`.

    The keyword arguments are the defaults of the requests' fields, in their text form or as objects:
    ``index`` a global index (the mechanism's first by default), ``region`` (its first parametrised region,
    else the sampled workspace), ``space`` a design space name or ``axes`` two parameters with bounds
    (``"a=lo:hi,b=lo:hi"`` or ``[(a, lo, hi), (b, lo, hi)]``; by default the first design space, else the first
    two required parameters at their defaults times 1 -/+ AXIS_SPAN), ``design`` the values of the parameters
    off the atlas's chart, ``problem`` a synthesis problem whose optimum the atlas marks (a registered name or a
    :class:`pkm.synthesis.Problem`, whose task region, where it is not one of the mechanism's, is offered by its
    name and is the default region; by default a registered problem of the mechanism that optimises the index
    over the region), ``resolution`` the atlas's nodes per axis and ``map_resolution`` the maps' poses per axis.
    Every default is checked as a request's field would be (:class:`RequestError`). Computations run one at a
    time (CasADi's functions are not called from two threads at once); :meth:`close` cancels them."""

    def __init__(
        self,
        mechanism: Mechanism,
        *,
        index: str | None = None,
        region: str | None = None,
        space: str | None = None,
        axes: str | Sequence[tuple[str, float, float]] | None = None,
        design: str | Mapping[str, float] | None = None,
        problem: Any = None,
        resolution: int = ATLAS_RESOLUTION,
        map_resolution: int = MAP_RESOLUTION,
    ) -> None:
        self.mechanism = mech = mechanism
        self._lock = threading.Lock()
        self._closed = threading.Event()
        self._cancelled = threading.Event()
        self._optima: dict[str, dict[str, Any]] = {}
        if space and axes:
            raise RequestError("axes", "space and axes violate: one or the other")
        if not isinstance(axes, str | None):
            axes = ",".join(f"{name}={lower!r}:{upper!r}" for name, lower, upper in axes)
        if not space and not axes:
            if mech.design_spaces:
                space = next(iter(mech.design_spaces))
            else:
                axes = self._default_axes()
        self._task_regions: dict[str, Any] = {}
        self.problem = self._given_problem(problem)
        self.defaults: dict[str, str] = {
            "index": index or next(iter(mech.global_indices()), ""),
            "region": region or next(iter(self._task_regions), None) or next(iter(mech.regions), "reachable"),
            "design": design if isinstance(design, str | None) else _text(design),
            "resolution": str(resolution),
            "map_resolution": str(map_resolution),
            **({"space": space} if space else {"axes": axes}),
        }
        self.defaults = {k: v for k, v in self.defaults.items() if v}
        fields = self._fields("atlas", {})
        self._index(fields)
        self._region(fields)
        self._space(fields)
        self._integer(fields, "resolution", 3, MAX_ATLAS)
        self._integer(self.defaults, "map_resolution", 3, MAX_MAP)

    def _default_axes(self) -> str:
        chosen = [p for p in self.mechanism.parameters if p.required and p.default != 0][:2]
        if len(chosen) < 2:
            raise RequestError("axes", f"the {self.mechanism.name} has no design space and fewer than two parameters "
                                       "with a default to span: give axes")
        spans = []
        for p in chosen:
            ends = sorted(p.default * (1 + s * AXIS_SPAN) for s in (-1, 1))
            spans.append((p.name, max(ends[0], p.lower), min(ends[1], p.upper)))
        return ",".join(f"{n}={lo!r}:{hi!r}" for n, lo, hi in spans)

    def _given_problem(self, problem: Any) -> Any:
        if problem is None:
            return None
        if isinstance(problem, str):
            with blame("problem"):
                problem = registry.problem(problem)
        if problem.mechanism.name != self.mechanism.name:
            raise RequestError("problem", f"problem {problem.name} violates: a problem of the {self.mechanism.name} "
                                          f"(it is of the {problem.mechanism.name})")
        quantity = problem.quantities.get(problem.objective.quantity) if problem.objective.quantity else None
        region = getattr(quantity, "region", None)
        if region is not None and not any(region is r for r in self.mechanism.regions.values()):
            name = region.name if region.name not in self.mechanism.region_names() else f"{problem.name} task"
            self._task_regions[name] = region
        return problem

    def close(self, *, timeout: float | None = None) -> bool:
        """Cancel the computation in flight and every later one: each raises :class:`CancelledError` after its
        current step (an atlas's chunk of designs, a synthesis's stage or start), as it ends where it has no steps
        (a map, a card, a linkage), or before it starts. Waits up to ``timeout`` seconds (None: as long as it
        takes) for the computation in flight to end; whether it did."""
        self._closed.set()
        if not self._lock.acquire(timeout=-1 if timeout is None else timeout):
            return False
        self._lock.release()
        return True

    def cancel(self) -> None:
        """Cancel the computation in flight (it raises :class:`CancelledError` after its current step); the
        explorer answers the next request as before."""
        self._cancelled.set()

    @property
    def closed(self) -> bool:
        """Whether :meth:`close` was called: the explorer computes nothing more."""
        return self._closed.is_set()

    def _check_open(self, *_progress: int) -> None:
        """CancelledError once :meth:`close` was called, or :meth:`cancel` since the computation in flight took its
        turn; a computation's ``progress(done, total)``."""
        if self._closed.is_set():
            raise CancelledError(f"the explorer of the {self.mechanism.name} was closed (its server stopped): "
                                 "computation cancelled")
        if self._cancelled.is_set():
            raise CancelledError("computation cancelled at the page's request")

    @contextmanager
    def _turn(self) -> Iterator[None]:
        """The block's turn to compute, one at a time; cancelled where the explorer is closed when its turn comes
        or by the time it ends."""
        with self._lock:
            self._cancelled.clear()
            self._check_open()
            yield
            self._check_open()

    def handle(self, endpoint: str, fields: Mapping[str, str]) -> dict[str, Any]:
        """The answer of ``endpoint`` to a request's ``fields``."""
        if endpoint not in FIELDS:
            raise RequestError("endpoint", f"unknown endpoint {reprlib.repr(endpoint)}; known: {', '.join(FIELDS)}")
        handler: Callable[[dict[str, str]], dict[str, Any]] = getattr(self, f"_{endpoint}")
        return handler(self._fields(endpoint, fields))

    def _fields(self, endpoint: str, fields: Mapping[str, str]) -> dict[str, str]:
        """The request's fields over the defaults; an unknown or repeated field refused."""
        known = FIELDS[endpoint]
        for name, value in fields.items():
            if name not in known:
                raise RequestError(name, f"unknown field {reprlib.repr(name)} of {endpoint}; known: "
                                         f"{', '.join(known) or 'none'}")
            if not isinstance(value, str):
                raise RequestError(name, f"{name} violates: one value")
        defaults = {k: v for k, v in self.defaults.items() if k in known}
        if endpoint in ("map", "card") and "resolution" in known:
            defaults["resolution"] = self.defaults["map_resolution"] if endpoint == "map" else str(CARD_RESOLUTION)
        if endpoint == "certify":
            defaults["seconds"] = str(CERTIFY_SECONDS)
        if "space" in fields or "axes" in fields:
            defaults.pop("space", None)
            defaults.pop("axes", None)
        return {**defaults, **fields}

    # fields

    def _integer(self, fields: Mapping[str, str], name: str, lower: int, upper: int) -> int:
        text = fields[name]
        try:
            value = int(text)
        except ValueError:
            raise RequestError(name, f"{name} = {reprlib.repr(text)} violates: an integer >= {lower} and "
                                     f"<= {upper}") from None
        with blame(name):
            return check_integer(name, value, lower, upper)

    def _index(self, fields: Mapping[str, str]) -> str:
        """A global index the mechanism can evaluate."""
        name = fields.get("index", "")
        if name not in self.mechanism.global_indices():
            raise RequestError("index", f"unknown index {reprlib.repr(name)} of the {self.mechanism.name}; known: "
                                        f"{', '.join(self.mechanism.global_indices())}")
        return name

    def _local(self, fields: Mapping[str, str]) -> str:
        """A local index the mechanism can evaluate, or the local index of one of its global indices."""
        name = fields.get("index", "")
        if name in self.mechanism.local_indices():
            return name
        if name in self.mechanism.global_indices():
            return registry.global_index(name).local.name
        raise RequestError("index", f"unknown index {reprlib.repr(name)} of the {self.mechanism.name}; known: local "
                                    f"{', '.join(self.mechanism.local_indices())} or global "
                                    f"{', '.join(self.mechanism.global_indices())}")

    def _region(self, fields: Mapping[str, str]) -> str | Any:
        """The region by name: the mechanism's, or the task region of the explorer's problem (a task file's)."""
        name = fields.get("region", "")
        if name in self._task_regions:
            return self._task_regions[name]
        with blame("region"):
            self.mechanism.region(name)
        return name

    def _mode(self, fields: Mapping[str, str]) -> str:
        with blame("mode"):
            return self.mechanism.working_mode(fields.get("mode")).name

    def _values(self, fields: Mapping[str, str], field: str = "design") -> dict[str, float]:
        """Design values by name, each a known parameter within its bounds."""
        with blame(field):
            values = parse_design(fields.get(field, ""))
        known = {p.name: p for p in self.mechanism.parameters}
        for name, value in values.items():
            if name not in known:
                raise RequestError(field, f"unknown design parameter {reprlib.repr(name)}; expected "
                                          f"{', '.join(known)}", name)
            try:
                known[name].check(value)
            except PkmError as exc:
                raise RequestError(field, str(exc), name) from None
        return values

    def _design(self, fields: Mapping[str, str]) -> Design:
        values = self._values(fields)
        with blame("design"):
            return self.mechanism.design(values, partial=True)

    def _space(self, fields: Mapping[str, str]) -> tuple[DesignSpace, list[tuple[str, float, float]] | None]:
        """The atlas's design space: a named one (the ``design`` values off its chart held instead of its base
        or the defaults) or the plane of ``axes``."""
        mech = self.mechanism
        if "space" in fields and "axes" in fields:
            raise RequestError("axes", "space and axes violate: one or the other")
        held = self._values(fields)
        if "axes" in fields:
            with blame("axes"):
                axes = parse_axes(fields["axes"])
                return parameter_plane(mech.parameters, axes, base=held), axes
        name = fields.get("space", "")
        if name not in mech.design_spaces:
            raise RequestError("space", f"unknown design space {reprlib.repr(name)} of the {mech.name}; known: "
                                        f"{', '.join(mech.design_spaces) or 'none (give axes)'}")
        space = mech.design_spaces[name]
        extra = {k: v for k, v in held.items() if k not in space.parameters}
        return (replace(space, base={**space.base, **extra}) if extra else space), None

    def _plane(self, fields: Mapping[str, str]) -> tuple[str, str]:
        names = self.mechanism.pose_names
        plane = tuple(t.strip() for t in fields.get("plane", ",".join(names[:2])).split(","))
        if len(plane) != 2 or len(set(plane)) != 2 or not set(plane) <= set(names):
            raise RequestError("plane", f"plane = {reprlib.repr(fields.get('plane'))} violates: two distinct pose "
                                        f"coordinates of the {self.mechanism.name} ({', '.join(names)})")
        return plane

    def _held(self, fields: Mapping[str, str], plane: tuple[str, str]) -> dict[str, float] | None:
        if not fields.get("held"):
            return None
        with blame("held"):
            held = parse_design(fields["held"], "held coordinates", "pose coordinate", PkmError)
            return check_plane(self.mechanism, axes=plane, held=held)[1]

    def _pose(self, fields: Mapping[str, str]) -> np.ndarray:
        n = self.mechanism.n_out
        try:
            pose = np.array([float(v) for v in fields.get("pose", "").split(",")])
        except ValueError:
            pose = np.array([])
        if pose.shape != (n,) or not np.all(np.isfinite(pose)):
            raise RequestError("pose", f"pose = {reprlib.repr(fields.get('pose'))} violates: {n} finite numbers, "
                                       f"comma-separated ({', '.join(self.mechanism.pose_names)})")
        return pose

    def _arrays(self, fields: Mapping[str, str]) -> str:
        encoding = fields.get("arrays", "list")
        if encoding not in ENCODINGS:
            raise RequestError("arrays", f"arrays = {reprlib.repr(encoding)} violates: one of {', '.join(ENCODINGS)}")
        return encoding

    # endpoints

    def _mechanism(self, _fields: Mapping[str, str]) -> dict[str, Any]:
        mech = self.mechanism
        return {
            "name": mech.name,
            "doc": mech.doc,
            "parameters": [{"name": p.name, "default": p.default, "lower": p.lower, "upper": p.upper, "unit": p.unit,
                            "doc": p.doc, "required": p.required} for p in mech.parameters],
            "modes": [{"name": b.name, "aliases": list(b.aliases), "doc": b.doc} for b in mech.working_modes],
            "pose": [{"name": n, "unit": u} for n, u in zip(mech.pose_names, mech.pose_units, strict=True)],
            "regions": [{"name": name, "sampled": name in SAMPLED,
                         "modes": list(default_modes(mech, self._task_regions.get(name, name)))}
                        for name in [*self._task_regions, *mech.region_names()]],
            "design_spaces": [{"name": s.name, "doc": s.doc, "chart_axes": list(s.chart_axes),
                               "chart_labels": list(s.chart_labels), "parameters": list(s.parameters)}
                              for s in mech.design_spaces.values()],
            "global_indices": [{"name": name, "unit": mech.index_unit(name), "sense": registry.global_index(name).sense,
                                "doc": registry.global_index(name).doc, "local": registry.global_index(name).local.name}
                               for name in mech.global_indices()],
            "local_indices": [{"name": name, "unit": mech.index_unit(name)} for name in mech.local_indices()],
            "problems": [p.name for p in self._problems()],
            "defaults": {k: v for k, v in self.defaults.items() if k != "map_resolution"}
                        | {"resolution": int(self.defaults["resolution"]),
                           "map_resolution": int(self.defaults["map_resolution"])},
        }

    def _problems(self, index: str | None = None, region: str | None = None) -> list[Any]:
        """The caller's problem, else the registered problems of the mechanism (optimising ``index`` over
        ``region`` where given)."""
        if self.problem is not None:
            return [self.problem]
        mech = self.mechanism
        out = []
        for p in registry.problems().values():
            quantity = p.quantities.get(p.objective.quantity) if p.objective.quantity else None
            if p.mechanism is not mech or quantity is None:
                continue
            if index is not None and quantity.index.name != index:
                continue
            if region is not None and quantity.region is not mech.region(region):
                continue
            out.append(p)
        return out

    def _atlas(self, fields: Mapping[str, str]) -> dict[str, Any]:
        mech = self.mechanism
        index, region = self._index(fields), self._region(fields)
        space, axes = self._space(fields)
        resolution = self._integer(fields, "resolution", 3, MAX_ATLAS)
        modes = (self._mode(fields),) if "mode" in fields else default_modes(mech, region)
        with self._turn(), blame("mode"):
            atlas = compute_atlas(mech, mech.global_spec(index), space=space, modes=modes, region=region,
                                  resolution=resolution, progress=self._check_open, executor="serial")
        U, V = np.meshgrid(atlas.u, atlas.v, indexing="ij")
        designs = space.designs(mech.parameters, space.from_chart(U[atlas.inside], V[atlas.inside]))
        names = mech.parameter_names()
        moving = [k for k, p in enumerate(names) if p in space.parameters or np.ptp(designs[:, k]) > 0]
        grid: list[list[dict[str, float] | None]] = [[None] * len(atlas.v) for _ in atlas.u]
        for (i, j), row in zip(np.argwhere(atlas.inside), designs[:, moving], strict=True):
            grid[i][j] = dict(zip([names[k] for k in moving], row.tolist(), strict=True))
        held = {p: float(designs[0, k]) for k, p in enumerate(names) if k not in moving}
        problems = self._problems(index, region)
        return {
            **atlas.metadata(),
            "unit": mech.index_unit(index),
            "axes": [list(a) for a in axes] if axes else None,
            "polygon": [list(p) for p in space.polygon],
            "u": atlas.u, "v": atlas.v,
            "values": atlas.values, "points": atlas.points, "limits": colour_limits(list(atlas.values.values())),
            "inside": atlas.inside, "admissible": atlas.admissible,
            "varied": list(space.parameters), "designs": grid, "held": held,
            "problem": problems[0].name if problems else None,
        }

    def _optimum(self, fields: Mapping[str, str]) -> dict[str, Any]:
        """The optimum of the synthesis problem (``problem``, else the one the atlas marks) and where it lies on
        the atlas's chart."""
        from matplotlib.path import Path as PolygonPath

        from pkm.synthesis import SynthesisError, synthesize

        mech = self.mechanism
        space, _ = self._space(fields)
        if "problem" in fields:
            problem = self._given_problem(fields["problem"])
        else:
            problems = self._problems(self._index(fields), self._region(fields))
            if not problems:
                return {"problem": None, "reason": f"no synthesis problem of the {mech.name} optimises "
                                                   f"{fields.get('index')} over {fields.get('region')}"}
            problem = problems[0]
        if problem.name not in self._optima:
            with self._turn():
                try:
                    result = synthesize(problem, progress=self._check_open, executor="serial")
                except SynthesisError as exc:
                    if exc.result is None:
                        raise
                    result = exc.result
                    failed = str(exc)
                else:
                    failed = None
            self._optima[problem.name] = {
                "problem": problem.name, "doc": problem.doc, "mode": result.mode, "sense": result.sense,
                "status": result.status, "failed": failed, "design": result.design,
                "objective": result.objective, "verified_objective": result.verified_objective,
                "unit": result.objective_unit}
        found = self._optima[problem.name]
        c, _ = space.from_design(mech.design_vector(found["design"]))
        u, v = (float(t) for t in space.to_chart(c))
        on_chart = bool(PolygonPath(np.array(space.polygon)).contains_point((u, v)))
        return {**found, "u": u, "v": v, "on_chart": on_chart}

    def _card(self, fields: Mapping[str, str]) -> dict[str, Any]:
        mech = self.mechanism
        design, mode = self._design(fields), self._mode(fields)
        region, index = self._region(fields), self._local(fields)
        names = [t.strip() for t in fields["indices"].split(",") if t.strip()] if fields.get("indices") else None
        for name in names or ():
            if name not in mech.global_indices():
                raise RequestError("indices", f"unknown index {reprlib.repr(name)} of the {mech.name}; known: "
                                              f"{', '.join(mech.global_indices())}")
        resolution = self._integer(fields, "resolution", 3, MAX_MAP)
        with self._turn(), blame("design"):
            card = design_card(mech, design, modes=[mode], region=region, index=index, indices=names,
                               resolution=resolution)
        return {**card.to_dict(), "mode": mode}

    def _map(self, fields: Mapping[str, str]) -> dict[str, Any]:
        mech = self.mechanism
        design, mode = self._design(fields), self._mode(fields)
        region, index = self._region(fields), self._local(fields)
        plane = self._plane(fields)
        held = self._held(fields, plane)
        resolution = self._integer(fields, "resolution", 3, MAX_MAP)
        arrays = self._arrays(fields)
        with self._turn(), blame("design"):
            _, centre = region_centre(mech, design, region)
            if centre is not None:
                at_centre = {n: float(c) for n, c in zip(mech.pose_names, centre, strict=True) if n not in plane}
                held = at_centre | (held or {})
            s = workspace_slice(mech, design, index=index, mode=mode, axes=plane, held=held,
                                region=None if region in SAMPLED else region, resolution=resolution)
            inside = region_section(s, region)
        units = dict(zip(mech.pose_names, mech.pose_units, strict=True))
        return {
            **s.metadata(),
            "resolution": resolution,
            "axis_units": [units[a] for a in plane],
            "pose_names": list(mech.pose_names),
            "u": s.u, "v": s.v,
            "values": encode(s.values, arrays),
            "limits": colour_limits([s.values]),
            "singular": {k: encode(d, arrays) for k, d in s.singular.items()},
            "curves": {k: level_curves(s.u, s.v, d, 0.0) for k, d in s.singular.items()},
            "region_points": s.region_points,
            "region_inside": None if inside is None else encode(inside.astype(float), arrays),
            "region_outline": None if inside is None else level_curves(s.u, s.v, inside.astype(float), 0.5),
        }

    def _linkage(self, fields: Mapping[str, str]) -> dict[str, Any]:
        mech = self.mechanism
        design, mode, pose, plane = self._design(fields), self._mode(fields), self._pose(fields), self._plane(fields)
        with self._turn(), blame("pose"):
            q = mech.inverse_kinematics(pose, design, mode=mode)
            reachable = bool(np.all(np.isfinite(q)))
            legs = mech.linkage(pose, design, mode=mode) if reachable else []
            singular = mech.singular_types(pose[None], design, mode=mode)[0] if reachable else []
            every = assemblies_at_pose(mech, pose, design, mode=mode) if reachable else None
        columns = plane_columns(plane, legs)
        named = dict(zip(mech.pose_names, pose.tolist(), strict=True))
        if not reachable:
            reason = f"pose {', '.join(f'{n} = {v:.6g}' for n, v in named.items())} is out of reach in mode {mode}"
        elif not legs:
            reason = f"the {mech.name} has no drawing of its linkage"
        elif columns is None:
            reason = f"the linkage is not drawn in the plane {', '.join(plane)}"
        else:
            reason = None
        return {
            "pose": named,
            "mode": mode,
            "reachable": reachable,
            "reason": reason,
            "singular": singular,
            "actuators": dict(zip(mech.actuator_names, q.tolist(), strict=True)),
            "legs": legs,
            "plane": list(plane),
            "projected": None if columns is None else [leg[:, columns] for leg in legs],
            "assemblies": None if every is None else {
                **every.summary(mech), "legs": every.legs,
                "projected": None if columns is None else [[leg[:, columns] for leg in drawn] for drawn in every.legs]},
        }

    def _certify(self, fields: Mapping[str, str]) -> dict[str, Any]:
        """The region certified at the design in the mode (:meth:`pkm.Mechanism.certify`; ``properties`` a comma
        list, by default its singularity and limits), within ``seconds``: the certificate and its boxes, outline and
        witnesses in the plane of the pose's first two coordinates (:func:`pkm.certify.certificate_drawing`)."""
        from pkm.certify import certificate_drawing, checked

        mech = self.mechanism
        design, mode, region = self._design(fields), self._mode(fields), self._region(fields)
        if region in SAMPLED:
            raise RequestError("region", f"region {region} violates: a parametrised region to certify (a sampled "
                                         "one has no boxes)")
        with blame("region"):
            checked(mech, region, design, mode=mode)
        names = [t.strip() for t in fields.get("properties", "singularity,limits").split(",") if t.strip()]
        with blame("properties"):
            checked(mech, region, design, properties=names, mode=mode)
        seconds = self._integer(fields, "seconds", 1, MAX_CERTIFY)
        with self._turn(), blame("design"):
            found = mech.certify(region, design, mode=mode, properties=names, seconds=seconds,
                                 progress=self._check_open)
            drawing = certificate_drawing(mech, region, found, design)
        return {
            **found.as_dict(),
            "plane": list(mech.pose_names[:2]),
            "cells": {state: boxes.tolist() for state, boxes in drawing.cells.items()},
            "outline": drawing.outline.tolist(),
            "points": drawing.witnesses.tolist(),
        }


def region_section(section: WorkspaceSlice, region: str | Any) -> np.ndarray | None:
    """Where the poses of a workspace map lie inside a placed region (a disc, rectangle, box or cylinder in the
    pose's own coordinates) at the map's design: a mask over the map's grid whose edge is the region's outline in
    the plane; None for a sampled region or one that is not placed in the pose."""
    mech = section.mechanism
    if region in SAMPLED:
        return None
    where = mech.region(region)
    if not isinstance(where, PlacedRegion) or where.dimension != mech.n_out:
        return None
    centre, size = where.placement(mech.functions, section.design.vector())
    scale = np.asarray(where.scale(ca.DM(size)), dtype=float).ravel()
    names = list(mech.pose_names)
    U, V = np.meshgrid(section.u, section.v, indexing="ij")
    x = np.tile([section.held.get(n, math.nan) for n in names], (U.size, 1))
    x[:, names.index(section.axes[0])], x[:, names.index(section.axes[1])] = U.ravel(), V.ravel()
    return where.inside_reference((x - np.asarray(centre, dtype=float).ravel()) / scale).reshape(U.shape)
