"""The two-slider gantry of Wu 2008 and its symmetric variant: the mechanisms, Wu's workspace-based
synthesis (:mod:`pkm.models.slider_gantry.wu2008`) and pkm's synthesis problems
(:mod:`pkm.models.slider_gantry.problems`)."""

from pkm.models.slider_gantry.mechanism import SliderGantry, SliderGantrySymmetric, TaskRectangle

MECHANISMS = (SliderGantry, SliderGantrySymmetric)

__all__ = ["MECHANISMS", "SliderGantry", "SliderGantrySymmetric", "TaskRectangle"]
