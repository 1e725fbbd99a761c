"""Fixed-point design: scaling from physical units, formats, overflow proof, error bounds."""
