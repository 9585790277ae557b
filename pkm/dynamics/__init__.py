"""The dynamic model at runtime, by job.

* :mod:`pkm.dynamics.rigid`: inertia matrices and inverse dynamics with rigid transmissions;
* :mod:`pkm.dynamics.flexible`: the flexible-joint model (natural frequencies, the exact motor torques
  along a trajectory, energy);
* :mod:`pkm.dynamics.trajectories`: end-effector trajectories x(t);
* :mod:`pkm.dynamics.simulation`: forward dynamics of the flexible-joint model.
"""

from pkm.dynamics.flexible import (
    FlexibleMotion,
    NaturalFrequencies,
    energy,
    flexible_inverse_dynamics,
    natural_frequencies,
)
from pkm.dynamics.rigid import SPACES, inertia_matrix, inverse_dynamics
from pkm.dynamics.simulation import METHODS, Simulation, simulate
from pkm.dynamics.trajectories import Trajectory, rest_to_rest

__all__ = [
    "METHODS",
    "SPACES",
    "FlexibleMotion",
    "NaturalFrequencies",
    "Simulation",
    "Trajectory",
    "energy",
    "flexible_inverse_dynamics",
    "inertia_matrix",
    "inverse_dynamics",
    "natural_frequencies",
    "rest_to_rest",
    "simulate",
]
