"""The braking drive around the commutation core, designed from the spec.

* `current_loop`: the braking-current PI (gains from R, L and the bandwidth, its fixed
  point as IR, proven and error-analysed) and the current reference conversion;
* `sensing`: where in the PWM period and from which signal the braking current I of
  Eqs. 15-20 is sampled, per sector, and the proof that the sample is clear of every
  switching edge;
* `safe_state`: all-off or the active short circuit, by speed region, from the physics.

Target-independent: the STM32F103 port (codegen/port.py) prints the registers.
"""
