"""fkSGP's forward kinematics of a general 6-6 Stewart-Gough platform, the reference the spatial homotopy
(:mod:`pkm.homotopy`) is checked and timed against.

Vendored from https://github.com/martyushev/fkSGP at commit 8bd29e5 (``python/solver66.py`` and
``python/cayley.py``, copied verbatim; ``LICENSE`` beside them), MIT licence, copyright 2025 Evgeniy Martyushev.
The method: E. Martyushev, "Forward kinematics of a general Stewart-Gough platform by elimination templates",
Mechanism and Machine Theory 215 (2025) 106170.

``solver66(X, x, L, realOnly)`` takes the base points X (6, 3) and the platform points x (6, 3), each with its
first row zero, and the squared leg lengths L (6,); it returns the poses Rt (k, 3, 4) = [R | t] with
R x_i + t - X_i of length sqrt(L_i), the real ones only where ``realOnly`` is 1, and each one's error (k,). It
draws two random rotations from numpy's global generator at each call.
"""

from .solver66 import solver66

__all__ = ["solver66"]
