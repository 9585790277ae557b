"""Performance indices: local indices of a posture (:mod:`pkm.indices.local`) and their global
reductions over regions (:mod:`pkm.indices.global_indices`). Names become indices in
:mod:`pkm.registry`; to add an index, add a :class:`LocalIndex` or :class:`GlobalIndex` to the
catalogues here."""

from pkm.indices.global_indices import GLOBAL_INDICES, GlobalIndex, reduce_samples
from pkm.indices.local import LOCAL_INDICES, LocalIndex, epigraph_function, local_function

__all__ = [
    "GLOBAL_INDICES",
    "LOCAL_INDICES",
    "GlobalIndex",
    "LocalIndex",
    "epigraph_function",
    "local_function",
    "reduce_samples",
]
