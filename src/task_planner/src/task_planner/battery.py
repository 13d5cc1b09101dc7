"""Low-battery model of the companion robot: drains by activity, asks for a charge when low.

The seed lists `charge` among the robot functions (Table 4-1) but gives no battery figures; the
values in BatteryConfig are deployment estimates (config/task_planner.yaml `battery_*`). The
level falls at a constant power per activity; below `low_fraction` the robot generates itself a
"go charge" instruction (Table 4-1 type ROBOT, priority `self_generated` of Table 5-5) at the
charging place, lasting as long as a full charge takes from the current level.
"""
from dataclasses import dataclass

from task_planner.instruction import ROBOT, Instruction
from task_planner.reward import Priority


@dataclass(frozen=True)
class BatteryConfig:
    capacity_wh: float = 300.0      # usable energy [Wh]
    idle_w: float = 40.0            # power while idle [W]
    moving_w: float = 90.0          # power while driving [W]
    executing_w: float = 60.0       # power while executing a robot function [W]
    charge_w: float = 150.0         # charging power [W]
    low_fraction: float = 0.2       # ask for a charge below this share of capacity


class BatteryModel:
    """Energy bookkeeping per executor mode; `level_wh` in watt-hours."""

    def __init__(self, config: BatteryConfig | None = None, level_wh: float | None = None,
                 now: float = 0.0) -> None:
        self.config = config or BatteryConfig()
        self.level_wh = self.config.capacity_wh if level_wh is None else float(level_wh)
        self._last = float(now)

    def drain(self, mode: str, now: float) -> None:
        """Spend the energy of `mode` (idle, moving, executing, charging) since the last call.

        While charging nothing is drained; the gain is added by `charge` when the function ends.
        """
        power_w = {"idle": self.config.idle_w, "moving": self.config.moving_w,
                   "executing": self.config.executing_w, "charging": 0.0}[mode]
        self.level_wh = max(0.0, self.level_wh - power_w * (now - self._last) / 3600.0)
        self._last = float(now)

    def charge(self, duration_s: float) -> None:
        """Add `duration_s` of charging (the charge function ran this long)."""
        self.level_wh = min(self.config.capacity_wh,
                            self.level_wh + self.config.charge_w * duration_s / 3600.0)

    @property
    def fraction(self) -> float:
        return self.level_wh / self.config.capacity_wh

    def is_low(self) -> bool:
        return self.fraction < self.config.low_fraction

    def seconds_to_full(self) -> float:
        return (self.config.capacity_wh - self.level_wh) * 3600.0 / self.config.charge_w


def charge_instruction(instruction_id: int, now: float, place: int, place_name: str,
                       priority: Priority, battery: BatteryModel,
                       function_code: int) -> Instruction:
    """The self-generated 'go charge' instruction (Table 4-1, type ROBOT); the executor gives it
    the task buffer's next id."""
    return Instruction(id=instruction_id, gamma=priority.gamma, beta=priority.beta,
                       destination=place, type=ROBOT, start_time=float(now),
                       duration=int(round(battery.seconds_to_full())), source="robot",
                       function=function_code, destination_name=place_name,
                       text=f"battery at {100 * battery.fraction:.0f} %")
