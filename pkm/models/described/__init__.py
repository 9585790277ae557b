"""Machines described as data (:mod:`pkm.spec`), one TOML file each beside this module: the symmetric planar
3-RRR, the Delta robot and the 6-UPS Stewart-Gough platform. ``pkm.load(path)`` derives one on first use."""

from pathlib import Path

HERE = Path(__file__).resolve().parent
DESCRIPTIONS = {name: HERE / f"{name}.toml" for name in ("rrr3", "delta", "stewart")}
