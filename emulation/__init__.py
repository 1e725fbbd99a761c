"""Cortex-M3 emulation of the generated firmware and `make bench`.

The linked STM32F103 image runs in unicorn (`armsim`); `cycles` prices the executed
trace by the Cortex-M3 TRM with the STM32F103's flash wait states and prefetch buffer;
`isr_bench` plays the timers and the NVIC around the port's interrupt handlers;
`rule_bench`, `reciprocal_bench` and `peers` measure alternatives; `bench` is the
`make bench` driver (`python -m emulation`).

This package sits below `codegen`, `verify` and `sim`: it may import them, and nothing
in `codegen` imports it.
"""
