"""Machines described as data (:mod:`pkm.spec`), one TOML file each beside this module, registered by name: the
symmetric planar 3-RRR, the Delta robot and the 6-UPS Stewart-Gough platform. Each derives on first use."""

from pathlib import Path

from pkm.spec.machine import mechanism_class
from pkm.spec.schema import read

HERE = Path(__file__).resolve().parent
DESCRIPTIONS = {name: HERE / f"{name}.toml" for name in ("rrr3", "delta", "stewart")}
MECHANISMS = [mechanism_class(read(path)) for path in DESCRIPTIONS.values()]
