"""One symbolic module per mechanism; each exposes ``module() -> codegen.ModuleSpec``."""

from symbolic.mechanisms import five_bar

MECHANISMS = {"five_bar": five_bar}
