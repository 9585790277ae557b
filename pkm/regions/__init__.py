"""Regions over which global indices are taken (DESIGN.md section 5).

* :mod:`pkm.regions.region`: what a region offers (:class:`Region`) and a global index over one region in one
  working mode of one mechanism (:class:`RegionIndex`), what the quadratures take;
* :mod:`pkm.regions.shapes`: parametrised regions, small shape classes with one protocol (disc,
  rectangle, box, cylinder, a domain between curves, a shape mapped from other coordinates, shapes side
  by side), each
  with a fixed quadrature mapped into the region that the design places, and given poses (a path, a cloud);
* :mod:`pkm.regions.trajectory`: a trajectory, a region in time whose nodes know the pose's motion;
* :mod:`pkm.regions.sampled`: the sampled reachable workspace, an n-D grid with a mask;
* :mod:`pkm.regions.pipeline`: the one fused graph pose -> IK -> first order (and inertia) -> local index;
* :mod:`pkm.regions.quadrature`: global indices over parametrised regions with exact design gradients.

To add a shape, subclass :class:`PlacedRegion` (a reference rule, the inside test, boundary points)
or follow the :class:`Region` protocol as :class:`MappedSquare` does.
"""

from importlib import import_module
from typing import Any

from pkm.regions.pipeline import MOTION, Evaluation, evaluate_at, first_order_outputs, index_values, pipeline
from pkm.regions.region import (
    ASSEMBLED_WORKSPACE,
    Piece,
    Region,
    RegionIndex,
    RegionLike,
    SampledWorkspace,
    region_name,
)
from pkm.regions.shapes import (
    Box,
    Cylinder,
    Disc,
    Mapped,
    MappedSquare,
    PlacedRegion,
    Poses,
    Rectangle,
    Union,
    grid,
)
from pkm.regions.value import GlobalValue

_LAZY = {
    "quadrature": ("INDEX_ACCURACY", "QUADRATURE_RESOLUTION", "adaptive_value", "admissible", "admits",
                   "epigraph_margins", "epigraph_point_margins", "epigraph_values", "global_value", "global_values",
                   "node_quadrature", "node_values", "parametrised_global", "quadrature_function", "quadrature_value",
                   "refined_extremes", "sampled_check", "sampled_value", "value_and_gradient", "value_at"),
    "trajectory": ("TimeSegment", "TrajectoryRegion", "trajectory_region"),
    "sampled": ("SAMPLED_RESOLUTION", "SINGULARITY_MARGIN", "check_margin", "sampled_global"),
}


def __getattr__(name: str) -> Any:
    """The names of the quadratures and the sampled regions, imported at first use: loading a mechanism
    needs only its shapes."""
    for module, names in _LAZY.items():
        if name in names:
            value = getattr(import_module(f"pkm.regions.{module}"), name)
            globals()[name] = value
            return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "ASSEMBLED_WORKSPACE",
    "INDEX_ACCURACY",
    "MOTION",
    "QUADRATURE_RESOLUTION",
    "SAMPLED_RESOLUTION",
    "SINGULARITY_MARGIN",
    "Box",
    "Cylinder",
    "Disc",
    "Evaluation",
    "GlobalValue",
    "Mapped",
    "MappedSquare",
    "Piece",
    "PlacedRegion",
    "Poses",
    "Rectangle",
    "Region",
    "RegionIndex",
    "RegionLike",
    "SampledWorkspace",
    "TimeSegment",
    "TrajectoryRegion",
    "Union",
    "adaptive_value",
    "admissible",
    "admits",
    "check_margin",
    "epigraph_margins",
    "epigraph_point_margins",
    "epigraph_values",
    "evaluate_at",
    "first_order_outputs",
    "global_value",
    "global_values",
    "grid",
    "index_values",
    "node_quadrature",
    "node_values",
    "parametrised_global",
    "pipeline",
    "quadrature_function",
    "quadrature_value",
    "refined_extremes",
    "region_name",
    "sampled_check",
    "sampled_global",
    "sampled_value",
    "trajectory_region",
    "value_and_gradient",
    "value_at",
]
