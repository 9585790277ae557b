"""The spatial 2-UPS-PU platform (Zhao 2008): the mechanism, its statics and workspace."""

from pkm.models.ups_pu.mechanism import Statics, UpsPu

MECHANISMS = (UpsPu,)

__all__ = ["MECHANISMS", "Statics", "UpsPu"]
