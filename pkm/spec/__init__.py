"""Machines as data (DESIGN.md section 6b): a description, checked, derived on first use, loaded as a
:class:`pkm.mechanism.Mechanism`, in five modules around one vocabulary:

* :mod:`pkm.spec.vocabulary`: what a description, a leg of each kind and a joint of each type hold (each field
  with what it holds and means), the frames of a pose, and each named leg kind as the chain of joints it is;
* :mod:`pkm.spec.schema`: the checks (:func:`~pkm.spec.schema.describe`: a description normalised, or a
  :class:`~pkm.spec.schema.DescriptionError` naming the field and the violated condition);
* :mod:`pkm.spec.compose`: what the runtime composes in CasADi from the derived module (the first order leg
  by leg, the continuation of chain legs, inertia and dynamics);
* :mod:`pkm.spec.seeds`: the configurations that seed the forward kinematics and name the assembly modes;
* :mod:`pkm.spec.machine`: the derivation into the user's cache and the mechanism class.

The package imports none of them, so that a module may read the vocabulary without loading the machine.
"""
