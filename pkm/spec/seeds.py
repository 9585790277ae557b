"""The configurations that seed a described machine's forward kinematics and the signature that names its
assembly modes (:class:`Seeds`)."""

from __future__ import annotations

import contextlib
import hashlib
import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np

from pkm.batch import evaluate
from pkm.io import atomic_write
from pkm.kinematics import FunctionTable
from pkm.spec.vocabulary import (
    kind_of,
    passive_angles,
)

SEED_SAMPLES = 16384  # random poses per round of the search for seeds (and per box size of the workspace box)
SEED_COUNT = 32768  # configurations that seed the forward kinematics, at least (unless SEED_ROUNDS run out)
SEED_ROUNDS = 32
SEED_STEP = 1 / 32  # after the first round, half the poses are found ones moved by this share of the box
SEEDS_KEPT = 8  # seed tables kept in a process (one per design)
SEEDS_STORED = 8  # seed tables kept in the cache per description (3-5 MB each), the oldest removed first
BOX_MARGIN = 0.05  # an estimated workspace box grows by this share of its width on each side
BOX_SCALES = 4  # sizes of the boxes about the home pose where the workspace box is looked for


@dataclass(frozen=True)
class Seeds:
    """The configurations that seed a description's forward kinematics (:class:`pkm.kinematics.NearestSeeds`)
    and the signature that names its assembly modes: the side of each leg whose passive joints have two
    branches (``branch_sides``: an RR leg's elbow, sin(phi - theta); a chain's det of its closure's Jacobian
    in its joints) and the sign of the type-II determinant det [H_p H_x]. The configurations are those of every
    branch of the legs where they assemble at random poses in the workspace box (:meth:`box`; a fixed
    seed), half of them, after the first round, found ones moved at random (so that a thin workspace fills
    too), until there are SEED_COUNT; one table per design, kept in this process for the last SEEDS_KEPT designs
    and, where ``store`` is given, in the user's cache beside the derived module for the last SEEDS_STORED designs
    (its name the digest of the design, the search's constants and this module's source), read back by a later
    process instead of searched again."""

    data: Mapping[str, Any]
    store: Path | None = None  # where the tables are kept between processes: <store>.seeds.<digest>.npz

    @property
    def periodic(self) -> tuple[bool, ...]:
        return tuple(kind_of(leg).unit == "rad" for leg in self.data["legs"])

    @property
    def angles(self) -> tuple[bool, ...]:
        passive = tuple(a for leg in self.data["legs"] for a in passive_angles(leg))
        return passive + tuple(unit == "rad" for unit in self.data["pose"]["units"])

    def signature(self, functions: FunctionTable, q: np.ndarray, x: np.ndarray, design: np.ndarray) -> np.ndarray:
        *_, det = evaluate(functions["first_order"], q, x, design)
        if "branch_sides" not in functions:
            return np.sign(det[:, 0, 0])[:, None]
        (sides,) = evaluate(functions["branch_sides"], q, x, design)
        return np.column_stack([np.sign(sides[:, :, 0]), np.sign(det[:, 0, 0])])

    def table(self, functions: FunctionTable, design: np.ndarray) -> dict[tuple[float, ...], tuple[np.ndarray, ...]]:
        return self._pooled(functions, np.asarray(design, dtype=float))

    def _pooled(self, functions: FunctionTable, design: np.ndarray) -> dict[tuple[float, ...], tuple[np.ndarray, ...]]:
        key = (id(functions), design.tobytes())
        if key not in _SEED_TABLES:
            if len(_SEED_TABLES) >= SEEDS_KEPT:
                _SEED_TABLES.pop(next(iter(_SEED_TABLES)))
            path = self._path(design)
            groups = _read(path)
            if groups is None:
                q, x, signatures = self._configurations(functions, design)
                n_act = len(self.data["legs"])
                groups = {}
                for signature in sorted(set(map(tuple, signatures.tolist()))):
                    mine = np.all(signatures == signature, axis=1)
                    groups[signature] = (q[mine, :n_act], np.hstack([q[mine, n_act:], x[mine]]))
                _write(path, groups)
            _SEED_TABLES[key] = (functions, groups)
        return _SEED_TABLES[key][1]

    def _path(self, design: np.ndarray) -> Path | None:
        if self.store is None:
            return None
        constants = repr((SEED_SAMPLES, SEED_COUNT, SEED_ROUNDS, SEED_STEP, BOX_MARGIN, BOX_SCALES)).encode()
        digest = hashlib.sha256(design.tobytes() + constants + _source()).hexdigest()[:16]
        return self.store.with_name(f"{self.store.name}.seeds.{digest}.npz")

    def _assembled(self, functions: FunctionTable, x: np.ndarray, design: np.ndarray) -> tuple[np.ndarray, ...]:
        """The configurations (q, x) of every branch of the legs at the poses x where they assemble."""
        branched = sum(kind_of(leg).branched for leg in self.data["legs"])
        qs, xs = [], []
        for signs in itertools.product((1.0, -1.0), repeat=branched) if branched else [(1.0,)]:
            with np.errstate(invalid="ignore"):
                q, reach = evaluate(functions["inverse_kinematics"], x, np.array(signs), design)
                ok = np.all(reach[:, :, 0] >= 0.0, axis=1) & np.all(np.isfinite(q[:, :, 0]), axis=1)
            qs.append(q[ok, :, 0])
            xs.append(x[ok])
        return np.concatenate(qs), np.concatenate(xs)

    def _sample(self, box: np.ndarray) -> np.ndarray:
        rng = np.random.default_rng(0)
        return rng.uniform(box[:, 0], box[:, 1], size=(SEED_SAMPLES, len(box)))

    def box(self, functions: FunctionTable, design: np.ndarray) -> np.ndarray:
        """The box of the poses where some branch of the legs assembles, estimated from random poses about
        the home pose (in boxes of BOX_SCALES sizes, halving, so that a small workspace is found in a large
        box), grown by BOX_MARGIN of its width on each side; kept for the last SEEDS_KEPT designs."""
        design = np.asarray(design, dtype=float)
        key = (id(functions), design.tobytes())
        if key not in _BOXES:
            if len(_BOXES) >= SEEDS_KEPT:
                _BOXES.pop(next(iter(_BOXES)))
            _BOXES[key] = (functions, self._box(functions, design))
        return _BOXES[key][1].copy()

    def _box(self, functions: FunctionTable, design: np.ndarray) -> np.ndarray:
        units = self.data["pose"]["units"]
        (home,) = evaluate(functions["home"], design)
        lengths = [abs(v) for p, v in zip(self.data["parameters"], design, strict=True) if p["unit"] == "m"]
        half = np.array([math.pi / 2 if unit == "rad" else (sum(lengths) or 1.0) for unit in units])
        centre = home[0, :, 0]
        around = np.column_stack([centre - half, centre + half])
        scales = 2.0 ** -np.arange(BOX_SCALES)
        x = np.concatenate([centre + scale * (self._sample(around) - centre) for scale in scales])
        _, inside = self._assembled(functions, x, design)
        if len(inside) == 0:
            return around
        lo, hi = inside.min(axis=0), inside.max(axis=0)
        grow = BOX_MARGIN * np.maximum(hi - lo, 1e-9)
        return np.column_stack([np.maximum(lo - grow, around[:, 0]), np.minimum(hi + grow, around[:, 1])])

    def _configurations(self, functions: FunctionTable, design: np.ndarray) -> tuple[np.ndarray, ...]:
        box = self.box(functions, design)
        rng = np.random.default_rng(1)
        qs, xs = [], []
        width = box[:, 1] - box[:, 0]
        for _ in range(SEED_ROUNDS):
            x = rng.uniform(box[:, 0], box[:, 1], size=(SEED_SAMPLES, len(box)))
            if xs:
                found = np.concatenate(xs)
                x[SEED_SAMPLES // 2 :] = found[rng.integers(len(found), size=SEED_SAMPLES - SEED_SAMPLES // 2)] \
                    + SEED_STEP * width * rng.standard_normal((SEED_SAMPLES - SEED_SAMPLES // 2, len(box)))
            q, x = self._assembled(functions, x, design)
            qs.append(q)
            xs.append(x)
            if sum(map(len, qs)) >= SEED_COUNT:
                break
        q, x = np.concatenate(qs), np.concatenate(xs)
        with np.errstate(invalid="ignore"):
            signature = self.signature(functions, q, x, design)
        regular = np.all(signature != 0.0, axis=1)
        return q[regular], x[regular], signature[regular]


@lru_cache(maxsize=1)
def _source() -> bytes:
    return Path(__file__).read_bytes()


def _read(path: Path | None) -> dict[tuple[float, ...], tuple[np.ndarray, ...]] | None:
    """A seed table kept by an earlier process, or None (none kept, or not readable)."""
    if path is None or not path.exists():
        return None
    try:
        with np.load(path) as stored:
            return {tuple(stored[f"signature{k}"].tolist()): (stored[f"actuated{k}"], stored[f"rest{k}"])
                    for k in range(int(stored["groups"]))}
    except (OSError, ValueError, KeyError):
        return None


def _write(path: Path | None, groups: dict[tuple[float, ...], tuple[np.ndarray, ...]]) -> None:
    """Keep a seed table for later processes, atomically; nothing where the cache cannot be written."""
    if path is None:
        return
    arrays = {"groups": np.array(len(groups))}
    for k, (signature, (actuated, rest)) in enumerate(groups.items()):
        arrays |= {f"signature{k}": np.array(signature), f"actuated{k}": actuated, f"rest{k}": rest}

    def save(tmp: Path) -> None:
        with open(tmp, "wb") as handle:
            np.savez(handle, **arrays)

    with contextlib.suppress(OSError):
        atomic_write(path, save)
        kept = sorted(path.parent.glob(f"{path.name.split('.seeds.')[0]}.seeds.*.npz"), key=lambda f: f.stat().st_mtime)
        for old in kept[: max(0, len(kept) - SEEDS_STORED)]:
            old.unlink(missing_ok=True)


_SEED_TABLES: dict[tuple, tuple[FunctionTable, dict[tuple[float, ...], tuple[np.ndarray, ...]]]] = {}
_BOXES: dict[tuple, tuple[FunctionTable, np.ndarray]] = {}


