"""The planar manipulator with a passive constraining leg (Nam 2006): the mechanism, its design space,
the paper's indices and the composed-index synthesis."""

from pkm.models.passive_leg.mechanism import ForwardSolutions, PassiveLeg

MECHANISMS = (PassiveLeg,)

__all__ = ["MECHANISMS", "ForwardSolutions", "PassiveLeg"]
