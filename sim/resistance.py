"""Re-export: the resistance-aware rule is derived in `codegen.derivation.resistance`.

The generator needs the same expressions for the firmware form of the rule, so the
derivation lives in codegen (the pipeline never reaches back into sim/).
"""

from codegen.derivation.resistance import (
    NumericRule,
    ResistanceRule,
    alpha,
    beta,
    decay,
    derive_resistance_rule,
    i0,
    numeric_rule,
)

__all__ = [
    "NumericRule",
    "ResistanceRule",
    "alpha",
    "beta",
    "decay",
    "derive_resistance_rule",
    "i0",
    "numeric_rule",
]
