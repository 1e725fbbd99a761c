# Generated from template templates/python/bldc_current_loop.py.j2 with spec spec/paper_motor_improved_r.yaml (sha256 9f5d9c8963649549b4e129e1bd9cd35baa3c8e343f67f4b67f06c6141ed1f434). Do not edit: regenerate with `bldc-codegen generate spec/paper_motor_improved_r.yaml`.
"""Bit-exact integer model of bldc_current_loop.h/.c (the braking-current PI).

Printed from the same IR as the C (codegen/ir/py_printer.py): the same operations,
rounding and saturation, on Python integers (the IR proof rules out every overflow, so
they give the C's results). Standalone: the standard library only.
"""

from __future__ import annotations

BLDC_LOOP_CODE_MAX = 4095  # ADC full scale: inputs saturate here
BLDC_LOOP_STATE_MAX = 56164352  # D_max = 3428 counts in Q14
BLDC_LOOP_KP = 278672  # k_p = 17.0088 counts per code, Q14
BLDC_LOOP_KI = 5225  # k_i = 0.318915 counts per code per PWM period, Q14
BLDC_LOOP_MA_MAX = 10000  # braking_current_max, mA
BLDC_LOOP_REF_SCALE = 8329634  # codes per mA, Q27, rounded up
BLDC_LOOP_REF_OFFSET = 274877906944  # zero-current code, Q27, rounded up
BLDC_LOOP_FRAC_BITS = 14  # fraction bits of x and v
BLDC_LOOP_DUTY_MAX = 3428  # D_max, TIM1 counts: the OFF time holds the current sample


def current_loop_duty(integrator: int, reference_code: int, measured_code: int) -> int:
    """main duty in TIM1 counts, 0..D_max, for this period's sample (bldc_current_loop_duty)."""
    reference = BLDC_LOOP_CODE_MAX if reference_code > BLDC_LOOP_CODE_MAX else reference_code
    measured = BLDC_LOOP_CODE_MAX if measured_code > BLDC_LOOP_CODE_MAX else measured_code
    error = reference - measured  # codes: reference - measured
    state = 0 if integrator < 0 else BLDC_LOOP_STATE_MAX if integrator > BLDC_LOOP_STATE_MAX else integrator  # Q14 counts
    demand = BLDC_LOOP_KP * error + state  # k_p e + x
    limited = 0 if demand < 0 else BLDC_LOOP_STATE_MAX if demand > BLDC_LOOP_STATE_MAX else demand
    return (limited + 8192) >> 14


def current_loop_integrate(integrator: int, reference_code: int, measured_code: int) -> int:
    """the integrator for the next period (clamping anti-windup) (bldc_current_loop_integrate)."""
    reference = BLDC_LOOP_CODE_MAX if reference_code > BLDC_LOOP_CODE_MAX else reference_code
    measured = BLDC_LOOP_CODE_MAX if measured_code > BLDC_LOOP_CODE_MAX else measured_code
    error = reference - measured  # codes: reference - measured
    state = 0 if integrator < 0 else BLDC_LOOP_STATE_MAX if integrator > BLDC_LOOP_STATE_MAX else integrator  # Q14 counts
    demand = BLDC_LOOP_KP * error + state  # k_p e + x
    total = state + BLDC_LOOP_KI * error  # x + k_i e
    return state if demand > BLDC_LOOP_STATE_MAX or demand < 0 else total


def current_reference(milliamps: int) -> int:
    """the nearest ADC code of a braking current in mA, clamped to the spec's braking range (bldc_current_reference)."""
    held = BLDC_LOOP_MA_MAX if milliamps > BLDC_LOOP_MA_MAX else milliamps  # the spec's braking range
    scaled = held * BLDC_LOOP_REF_SCALE + BLDC_LOOP_REF_OFFSET
    return (scaled + 67108864) >> 27
