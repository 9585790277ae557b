"""A description loaded as a :class:`pkm.mechanism.Mechanism`: derived once into the user's cache (``descriptions/``
of the kernel cache, content-addressed by the normalised description and the deriving modules: ``python -m
symbolic.described`` in a process of its own, :mod:`pkm.spec.derivation`, for pkm never imports sympy), its
working modes the named sign combinations of the legs with two branches or, unnamed, every combination, those in
which the home pose is regular first (:func:`working_modes`), its assembly modes, regions and stated limits, and
its mobility checked at the home pose (:func:`check_mobility`)."""

from __future__ import annotations

import importlib.util
import itertools
import json
import os
import reprlib
import tempfile
import warnings
from collections.abc import Mapping, Sequence
from functools import cached_property
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions, io, registry
from pkm.batch import evaluate
from pkm.compiled.cache import location
from pkm.design import Condition, Parameter
from pkm.errors import ComputationError, SingularityWarning
from pkm.indices.local import SINGULAR, SINGULARITY_TYPE1, SINGULARITY_TYPE2
from pkm.kinematics import Branch, FunctionTable, NearestSeeds, within_limits
from pkm.mechanism import Mechanism
from pkm.progress import Progress
from pkm.regions import Box, Cylinder, Disc, Mapped, Rectangle, index_values
from pkm.spec import derivation
from pkm.spec.collisions import composed_collisions
from pkm.spec.compose import (
    composed_energy,
    composed_first_order,
    composed_inertia,
    composed_inverse_dynamics,
    composed_inverse_kinematics,
    legs_layout,
)
from pkm.spec.schema import SUFFIX, Description, DescriptionError, describe, read
from pkm.spec.seeds import Seeds
from pkm.spec.stiffness import elastic_functions
from pkm.spec.vocabulary import (
    FRAMES,
    RANKS,
    kind_of,
)

CLOSURE_TOLERANCE = 1e-9  # [m] the home pose closes every leg to this, relative to the largest length
DERIVATION_SECONDS = 120.0  # the time limit of a description's derivation
UNDEFINED = 3  # the derivation's exit status where an expression has no finite value (symbolic.described)
RANK_TOLERANCE = 1e-9  # relative singular value below which the closure's Jacobian loses rank


def _stem(description: Description) -> Path:
    """Where a description's derived module and its seed tables are kept in the user's cache, less suffixes."""
    return location() / "descriptions" / f"{description.name}_{description.key[:16]}"


def module_path(description: Description) -> Path:
    """The derived module of a description in the user's cache, derived now where it is not there yet (a
    progress bar on a terminal meanwhile)."""
    target = _stem(description).with_suffix(".py")
    folder = target.parent
    if target.exists():
        return target
    folder.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        source = Path(tmp) / "description.json"
        source.write_text(json.dumps({**description.data, "key": description.key}, sort_keys=True))
        out = Path(tmp) / "module.py"
        with Progress(1, f"deriving {description.name} (first use, into {folder})") as bar:
            done = derivation.derive(source, out, DERIVATION_SECONDS)
            bar.advance()
        if done is None:
            raise ComputationError(f"deriving {description.name} took longer than its limit of "
                                   f"{DERIVATION_SECONDS:g} s")
        code, last = done
        if code == UNDEFINED:
            raise DescriptionError(f"description {description.name}: {last.removeprefix('undefined: ')} (a zero "
                                   "length or axis, or a function outside its domain, in the description?)")
        if code != 0:
            raise ComputationError(f"deriving {description.name} failed: {reprlib.repr(last)}")
        io.atomic_write(target, lambda path: path.write_bytes(out.read_bytes()))
    return target



class DescribedFunctions(FunctionTable):
    """The functions of a description's derived module and those composed from them."""

    def __init__(self, description: Description) -> None:
        super().__init__({}, f"the description {description.name}")
        self.description = description

    @cached_property
    def _functions(self) -> dict[str, ca.Function]:
        path = module_path(self.description)
        spec = importlib.util.spec_from_file_location(f"pkm_description_{self.description.name}", path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        functions = module.build()
        n_act = len(module.ACTUATORS)
        functions["first_order"] = composed_first_order(functions["constraint"], n_act, legs_layout(self.description))
        if "continuation_start" in functions:
            functions["inverse_kinematics"] = composed_inverse_kinematics(self.description, functions)
        if limited(self.description.data):
            functions.update(within_limits(functions, LIMITS))
        self._limit_names = tuple(getattr(module, "LIMITS", ()))
        if "capsules" in functions:
            functions["collision"] = composed_collisions(self.description, functions)
        if "mass_matrix" in functions:
            functions["inertia"] = composed_inertia(functions["mass_matrix"], functions["first_order"])
            functions["energy"] = composed_energy(functions["mass_matrix"], functions["first_order"],
                                                  functions.get("gravity"))
            functions["inverse_dynamics"] = composed_inverse_dynamics(
                functions["constraint"], functions["mass_matrix"], functions["first_order"], functions.get("gravity"))
        functions.update(elastic_functions(self.description, functions))
        return functions

    def _load(self) -> dict[str, ca.Function]:
        return self._functions

    @property
    def limit_names(self) -> tuple[str, ...]:
        """The names of the margins of ``workspace_margins``, leg by leg (``leg 1 reach``, ``leg 1 range
        upper``, ...)."""
        self._load()
        return self._limit_names

    @property
    def source_hash(self) -> str:
        """The description's key: the hash of its normalised form and of the tools that derive it."""
        return self.description.key[:16]


LIMITS = "workspace_margins"  # a description's stated limits: its legs' ranges and cones, beside their reach


def limited(data: Mapping[str, Any]) -> bool:
    """Whether a normalised description states limits beyond its legs' reach (a range, a cone)."""
    return any("range" in leg or "cone" in leg for leg in data["legs"])


def _mode_name(signs: Sequence[int]) -> str:
    return "".join("p" if s > 0 else "n" for s in signs)


def _modes(data: Mapping[str, Any]) -> tuple[Branch, ...]:
    """The working modes: the named sign combinations of the branched legs where the description names
    some, else every combination (the first leg's sign the slowest, +1 before -1), named by the words of each
    leg's branch in order (``left_left_right``)."""
    kinds = [kind_of(leg) for leg in data["legs"] if kind_of(leg).branched]
    named = {tuple(float(s) for s in v): k for k, v in data["modes"].items()}
    combos = list(named) or (list(itertools.product((1.0, -1.0), repeat=len(kinds))) if kinds else [(1.0,)])
    meanings = "; ".join(dict.fromkeys(f"{'/'.join(k.branches)}: {k.meaning}" for k in kinds))

    def words(combo: tuple[float, ...]) -> list[str]:
        return [k.branches[0 if s > 0 else 1] for k, s in zip(kinds, combo, strict=True)]

    if not kinds:
        return tuple(Branch(named.get(c, "single"), tuple(c), "every leg has one branch") for c in combos)
    return tuple(Branch(named.get(c, "_".join(words(c))), tuple(c),
                        f"legs {', '.join(words(c))} ({meanings}); branch signs {', '.join(f'{s:+.0f}' for s in c)}")
                 for c in combos)


def working_modes(mech: Mechanism) -> tuple[Branch, ...]:
    """A described mechanism's working modes (:func:`_modes`): those its description names, in its order, else
    every combination, those in which the home pose is regular at the default design (reached, both
    singularity margins at least :data:`pkm.indices.local.SINGULAR`) first, each part in the combinations' order:
    the default mode is not a degenerate one where another is regular (a 2-PRR's with both sliders at one
    point, where the platform turns about them with the sliders held)."""
    modes = _modes(mech.description.data)
    if mech.description.data["modes"] or len(modes) == 1:
        return modes
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)

    def singular(mode: Branch) -> bool:
        margins = [index_values(mech, (index,), home[:, :, 0], np.array(mode.signs), design)[0][0]
                   for index in (SINGULARITY_TYPE1, SINGULARITY_TYPE2)]
        return not np.all(np.concatenate(margins) >= SINGULAR)

    return tuple(sorted(modes, key=singular))




def _assemblies(data: Mapping[str, Any]) -> tuple[Branch, ...]:
    """The assembly modes: the side of each two-branched leg, the sign of the type-II determinant (the
    signature of :class:`Seeds`) and the rank among the signature's solutions by the last pose coordinate
    (:class:`pkm.kinematics.NearestSeeds`; ``_2`` names the second) where a frame has several (RANKS)."""
    elbows = sum(kind_of(leg).sided for leg in data["legs"])
    last = FRAMES[data["pose"]["frame"]][0][-1]
    out = []
    for combo in itertools.product((1.0, -1.0), repeat=elbows):
        for det, label in ((1.0, "positive"), (-1.0, "negative")):
            for rank in range(1, RANKS[data["pose"]["frame"]] + 1):
                name = "_".join(filter(None, [_mode_name(combo), label, "" if rank == 1 else str(rank)]))
                sides = f"elbow sides {', '.join(f'{s:+.0f}' for s in combo)}, " if combo else ""
                out.append(Branch(name, (*combo, det, float(rank)),
                                  f"{sides}type-II determinant {label}, solution {rank} by {last}"))
    return tuple(out)


def mechanism_class(description: Description) -> type[Mechanism]:
    """The :class:`Mechanism` subclass of a description."""
    data = description.data
    pose_names, _ = FRAMES[data["pose"]["frame"]]
    seeds = Seeds(data, _stem(description))
    parameters = tuple(Parameter(p["name"], p["default"], p["lower"], p["upper"], p["unit"], p["doc"],
                                 closed_lower=True) for p in data["parameters"])
    conditions = tuple(Condition(f"{c['doc']} ({expressions.text(c['margin'])} > 0)", expressions.function(c["margin"]))
                       for c in data.get("conditions", []))
    length = data["characteristic_length"]
    attributes = {
        "name": data["name"],
        "doc": data["doc"],
        "parameters": parameters,
        "conditions": conditions,
        "working_modes": cached_property(working_modes),
        "assembly_modes": _assemblies(data),
        "pose_names": pose_names,
        "pose_units": tuple(data["pose"]["units"]),
        "actuator_names": tuple(f"q{k + 1}" for k in range(len(data["legs"]))),
        "actuator_units": tuple(kind_of(leg).unit for leg in data["legs"]),
        "skeleton_legs": tuple(kind_of(leg).points for leg in data["legs"]),
        "forward": NearestSeeds(seeds),
        "description": description,
        "functions": cached_property(lambda self: DescribedFunctions(self.description)),
        "workspace_box": _workspace_box,
        "regions": {r["name"]: _region(r, len(pose_names)) for r in data["regions"]},
        "limits": LIMITS if limited(data) else None,
        "limit_names": property(lambda self: self.functions.limit_names),
        "variant": staticmethod(variant),
    }
    if length is not None:
        attributes["characteristic_length"] = staticmethod(expressions.function(length))
    cls = type(f"Described_{data['name']}", (Mechanism,), attributes)
    cls.functions.__set_name__(cls, "functions")
    return cls


def variant(data: Mapping[str, Any]) -> Mechanism:
    """The mechanism of a normalised description changed from a described machine's (its legs expanded with
    errors of their own, :mod:`pkm.accuracy`), derived and checked like any description."""
    return load(Description(dict(data)))


SHAPE_CLASSES = {"disc": Disc, "rectangle": Rectangle, "box": Box, "cylinder": Cylinder}


def _region(region: Mapping[str, Any], n_out: int) -> Any:
    """The parametrised region of a description's region: placed by the derived ``region_<name>(design) ->
    (centre, size)``, and mapped into the pose by ``region_<name>_pose(y, design) -> x`` where it spans
    other coordinates than the pose's own, in order."""
    name, doc = region["name"], region["doc"]
    extra = {"axis": region["axis"]} if region["shape"] == "cylinder" else {}
    shape = SHAPE_CLASSES[region["shape"]](name, doc, function=f"region_{name}", **extra)
    if region["coordinates"] == list(range(n_out)):
        return shape
    return Mapped(name, doc, shape, to_pose=f"region_{name}_pose")



def _workspace_box(self: Mechanism, design: np.ndarray) -> np.ndarray:
    """The box the sampled workspace grids: that of the poses where some branch of the legs assembles
    (:meth:`Seeds.box`)."""
    return self.forward.seeds.box(self.functions, np.asarray(design, dtype=float))


_INSTANCES: dict[str, Mechanism] = {}


def _instance(description: Description) -> Mechanism:
    """One mechanism per description (by its key), checked once."""
    if description.key not in _INSTANCES:
        mech = mechanism_class(description)()
        check_mobility(mech)
        warn_singular_home(mech)
        _INSTANCES[description.key] = mech
    return _INSTANCES[description.key]


def load(source: Mapping[str, Any] | Description | str | os.PathLike) -> Mechanism:
    """The mechanism of a description (a mapping, a :class:`Description` or a TOML file's path), derived on
    first use and checked (:func:`check_mobility`)."""
    description = read(source) if isinstance(source, str | os.PathLike) else describe(source)
    return _instance(description)


def resolve(text: str) -> Mechanism:
    """The mechanism a :func:`pkm.registry.reference` names: a described machine derived (once) into this
    process's cache, or the registered one."""
    if text.startswith(registry.DESCRIBED):
        return load(Description(json.loads(text[len(registry.DESCRIBED) :])))
    return registry.mechanism(text)


def resolve_name(name: str) -> Mechanism:
    """The mechanism of a name: a description file (``.toml``) derived on first use, or a registered one."""
    return load(name) if name.endswith(SUFFIX) else registry.mechanism(name)


def warn_singular_home(mech: Mechanism) -> None:
    """A :class:`pkm.errors.SingularityWarning` for each working mode in which the home pose is singular at the
    default design, naming the singularity and its margin (an index there is its limit, not the machine's)."""
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)
    for mode in mech.modes:
        note = mech.singularity_note(home[0, :, 0], design, mode=mode)
        if note:
            warnings.warn(SingularityWarning(f"description {mech.name}: its home {note}"), stacklevel=3)


def _unreached(mech: Mechanism, x: np.ndarray, design: np.ndarray) -> list[str]:
    """Why a pose is out of reach in the first working mode: each margin of ``workspace_margins`` below 0 at
    the joints without the stated limits (a range by its leg's actuated joint, its value and the range; a reach
    or a cone by its margin), and each leg whose joints do not close there otherwise; else a chain leg's reach
    (the sign of its Jacobian's determinant, which ``workspace_margins`` does not hold)."""
    data = mech.description.data
    q = mech.inverse_kinematics(x, design, passive=True, limits=False)
    (margins,) = evaluate(mech.functions["workspace_margins"], q, x, design)
    values = dict(zip(mech.parameter_names(), design, strict=True))
    reasons, named = [], set()
    for name, margin in zip(mech.limit_names, margins[0, :, 0], strict=True):
        if not margin < 0:
            continue
        leg, what = name.removeprefix("leg ").split(" ", 1)
        k = int(leg) - 1
        named.add(k)
        if what.startswith("range"):
            unit = mech.actuator_units[k]
            low, high = (expressions.evaluate(b, values) for b in data["legs"][k]["range"])
            reasons.append(f"leg {leg}'s actuated joint {mech.actuator_names[k]} = {q[k]:.6g} {unit} lies outside "
                           f"its range [{low:.6g}, {high:.6g}] {unit} ({name} = {margin:.3g})")
        else:
            reasons.append(f"{name} = {margin:.3g} < 0")
    for k, (_, passive, _) in enumerate(legs_layout(mech.description)):
        joints = q[[k, *(len(data["legs"]) + p for p in passive)]]
        if k not in named and not np.all(np.isfinite(joints)):
            reasons.append(f"leg {k + 1}'s joints do not close at the pose")
    return reasons or ["a chain leg crosses its own singularity on the way from its seed"]


def check_mobility(mech: Mechanism) -> None:
    """The home pose assembles at the default design in the first mode, closing every leg, and the closure's
    Jacobian [H_q H_x] has full row rank there with as many degrees of freedom as actuated joints:
    :class:`DescriptionError` otherwise."""
    design = mech.design().vector()
    (home,) = evaluate(mech.functions["home"], design)
    x = home[0, :, 0]
    q = mech.inverse_kinematics(x, design, passive=True)
    if not np.all(np.isfinite(q)):
        raise DescriptionError(f"description {mech.name}: the home pose {x.tolist()} does not assemble at the "
                               f"default design in its first working mode {mech.working_modes[0].name}: "
                               f"{'; '.join(_unreached(mech, x, design))}")
    h, H_q, H_x = (v[0] for v in evaluate(mech.functions["constraint"], q, x, design))
    scale = max(1.0, float(np.abs(design).max()))
    if np.abs(h).max() > CLOSURE_TOLERANCE * scale**2:
        raise DescriptionError(f"description {mech.name}: the legs do not close at the home pose (residual "
                               f"{np.abs(h).max():.1e})")
    full = np.hstack([H_q, H_x])
    singular = np.linalg.svd(full, compute_uv=False)
    rank = int(np.sum(singular > RANK_TOLERANCE * singular.max()))
    freedom = full.shape[1] - rank
    if rank < full.shape[0] or freedom != mech.n_out:
        raise DescriptionError(f"description {mech.name}: mobility {freedom} at the home pose, not the {mech.n_out} "
                               f"of its pose ({full.shape[0]} closure equations of rank {rank} in {full.shape[1]} "
                               "coordinates)")
