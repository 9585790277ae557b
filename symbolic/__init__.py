"""Symbolic derivations (sympy) of pkm's mechanisms. Never imported by the runtime package ``pkm``."""
