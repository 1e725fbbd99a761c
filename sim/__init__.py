"""Commutation simulation of the paper's PWM-OFF-PWM braking drive.

The plant is Eq. 1 with R kept: a star-connected winding behind a bridge of ideal
switches and freewheeling diodes, with trapezoidal (or the paper's flat) back-EMF at
constant speed. Two resolutions of the same circuit:

* `sim.switched`: every PWM edge and diode-blocking event, integrated exactly;
* `sim.averaged`: the PWM-averaged terminal voltages, integrated with casadi (CVODES).

`sim.sil` drives either plant with the generated C core (software in the loop) for
every firmware method, the paper's three and the resistance-aware `improved_r`;
`sim.improved_r_pp` is that rule's per-period ideal in Python (a comparison line, no
firmware); `sim.clamp` finds where the cores clamp the commutation time;
`sim.optimise` asks Ipopt for the best constant duty pair; `sim.sweep`, `sim.figures`
and `sim.report` turn it into the simulation report (`python -m sim SPEC`).
"""
