"""A controller's decision at a Hall edge, whatever computed it (the C core, or the
per-period Python ideal `improved_r_pp`)."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Command:
    """What the bridge does from the Hall edge on.

    During the commutation (0 <= t < commutation_time_s) the turn-on and turn-off
    transistors run at their duties; the duties are given per carrier period counted
    from the edge, and the last one holds. Afterwards the turn-off transistor is off
    and the turn-on transistor runs at the main duty (PWM-OFF-PWM).
    """

    method: str
    turn_on_switch: int | None  # 0..5 = T1..T6, None: every switch off
    turn_off_switch: int | None
    on_duties: tuple[float, ...]
    off_duties: tuple[float, ...]
    commutation_time_s: float
    main_duty: float
    flags: int = 0
    #: The C core's inputs ("in." keys) and outputs (empty for the Python ideal).
    core_outputs: dict[str, int] = field(default_factory=dict)

    def on_duty(self, period: int) -> float:
        return self.on_duties[min(max(period, 0), len(self.on_duties) - 1)]

    def off_duty(self, period: int) -> float:
        return self.off_duties[min(max(period, 0), len(self.off_duties) - 1)]

    @property
    def constant_duties(self) -> bool:
        return len(set(self.on_duties)) == 1 and len(set(self.off_duties)) == 1
