"""The symmetric planar 5R (Gao 1998; Lara-Molina 2016): the mechanism, its normalised design spaces
and its synthesis problems (:mod:`pkm.models.five_bar.problems`)."""

from pkm.models.five_bar.mechanism import FiveBar

MECHANISMS = (FiveBar,)

__all__ = ["MECHANISMS", "FiveBar"]
