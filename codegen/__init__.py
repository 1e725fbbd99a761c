"""Spec-driven toolchain for BLDC braking commutation (Cai, Shen, Xu, Wang).

Pipeline: spec/*.yaml -> spec_loader -> derivation -> audit / fixed-point design ->
templates -> generated/<spec name>/.
"""

__all__ = ["__version__"]
__version__ = "0.1.0"
