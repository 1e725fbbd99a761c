"""Symbolic derivation of the paper's Eqs. 1-20 from the circuit model (Eq. 1).

`derive()` returns a frozen `Derivation`; every downstream consumer (audit, fixed-point
design, generated models, verifier) reads its expressions instead of re-typing them.
"""

from codegen.derivation.paper import Derivation, DerivedResult, derive

__all__ = ["Derivation", "DerivedResult", "derive"]
