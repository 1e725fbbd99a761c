"""The resistance-aware rule in the form the firmware runs: one constant duty pair and
one commutation time per Hall edge, integer arithmetic, a small table for the
exponential parts. See `codegen.derivation.constant_pair` for the equations."""
