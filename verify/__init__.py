"""The verifier: compiles the generated C and cross-checks it against the symbolic model.

It arrives with the fixed-point C generator (issues "Fixed-point C for STM32F103" and
"Verifier"); until then this package is intentionally empty.
"""
