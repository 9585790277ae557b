"""A hand-derived mechanism whose legs are legs of the description vocabulary (:mod:`pkm.spec.vocabulary`) gives
them as a description (:meth:`GivenLegs.legs_description`), and its generated model emits ``skeleton``,
``elastic`` and ``leg_ends`` in a described machine's conventions (:func:`symbolic.described.elastic.add_hand_derived`):
its stiffness and elastic vibration are then composed as a described machine's
(:func:`pkm.spec.stiffness.elastic_functions`), and its error model (:mod:`pkm.accuracy`) expands those legs and
builds them with :func:`pkm.spec.machine.variant`. The tests load the same legs as a description to derive the
machine a second time."""

from __future__ import annotations

from collections.abc import Mapping
from functools import cache
from typing import Any

import casadi as ca

from pkm.spec.machine import variant
from pkm.spec.schema import Description, describe
from pkm.spec.stiffness import elastic_functions


class GivenLegs:
    """The mixin of such a mechanism (before :class:`pkm.Mechanism` among its bases)."""

    variant = staticmethod(variant)

    @classmethod
    def legs_description(cls) -> dict[str, Any]:
        """The mechanism's legs as a description, its parameters the mechanism's that the legs read."""
        raise NotImplementedError

    def described_legs(self) -> Description:
        return _described(type(self))

    def composed(self, generated: Mapping[str, ca.Function]) -> dict[str, ca.Function]:
        """The stiffness and the elastic vibration, composed from the legs' elastic elements as a described
        machine's of the same legs."""
        return elastic_functions(self.described_legs(), generated)


@cache
def _described(cls: type) -> Description:
    return describe(cls.legs_description())
