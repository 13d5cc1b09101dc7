"""The planner settings file (config/task_planner.yaml): read and checked at start, ROS-free.

`load_settings(path)` returns the mapping with every value checked against SETTINGS: an
unreadable or malformed file, a missing required key, an unknown key (with the nearest known
one) or a value out of its range is a SettingsError naming the file, the key and the value, e.g.
`config/task_planner.yaml: speed_mps must be a finite number > 0 [m/s], got 0`. A speed of 0 used
to pass and make the executor's first tick divide by zero.
"""
import math
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypedDict

from supervision import config_file


class SettingsError(config_file.ConfigError):
    """The settings file cannot be used; the message names the file, the key and the value."""


@dataclass(frozen=True)
class Rule:
    kind: str                   # "number", "integer" or "flag"
    low: float = -math.inf      # smallest value allowed
    low_open: bool = False      # the value must be > low (else >= low)
    high: float = math.inf      # largest value allowed (inclusive)
    unit: str = ""

    def describe(self) -> str:
        what = {"number": "a finite number", "integer": "an integer",
                "flag": "true or false"}[self.kind]
        if self.low > -math.inf:
            what += f" {'>' if self.low_open else '>='} {self.low:g}"
        if self.high < math.inf:
            what += f" and <= {self.high:g}"
        return what + (f" [{self.unit}]" if self.unit else "")

    def accepts(self, value: object) -> bool:
        if self.kind == "flag":
            return isinstance(value, bool)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            return False
        if self.kind == "integer" and not isinstance(value, int):
            return False
        if not math.isfinite(value) or value > self.high:
            return False
        return value > self.low if self.low_open else value >= self.low


class _Bound(TypedDict):
    low: float
    low_open: bool


POSITIVE = _Bound(low=0.0, low_open=True)
SETTINGS = {
    "speed_mps": Rule("number", unit="m/s", **POSITIVE),
    "step_s": Rule("number", unit="s", **POSITIVE),
    "robot_radius_m": Rule("number", low=0.0, unit="m"),
    "opt_max_instructions": Rule("integer", low=1),
    "exact_max_instructions": Rule("integer", low=1),
    "rollout_candidates": Rule("integer", low=1),
    "rollout_horizon": Rule("integer", low=1),
    "rollout_tail_weight": Rule("number", low=0.0),
    "rollout_priority_first_at_node": Rule("flag"),
    "battery_capacity_wh": Rule("number", unit="Wh", **POSITIVE),
    "battery_idle_w": Rule("number", low=0.0, unit="W"),
    "battery_moving_w": Rule("number", low=0.0, unit="W"),
    "battery_executing_w": Rule("number", low=0.0, unit="W"),
    "battery_charge_w": Rule("number", unit="W", **POSITIVE),
    "battery_low_fraction": Rule("number", low=0.0, high=1.0),
}
REQUIRED = ("speed_mps", "robot_radius_m")
BATTERY = tuple(key for key in SETTINGS if key.startswith("battery_"))


def check_settings(settings: object, where: str,
                   required: Iterable[str] = REQUIRED) -> dict[str, Any]:
    """`settings` (a mapping) checked against SETTINGS; SettingsError "<where>: ..." names the
    first bad key. `required`: keys that must be present (the battery's too when it is used)."""
    if not isinstance(settings, dict):
        raise SettingsError(f"{where}: expected a mapping of settings, got {settings!r}")
    for key, value in settings.items():
        rule = SETTINGS.get(key)
        if rule is None:
            raise SettingsError(f"{where}: {config_file.unknown_key_message(key, SETTINGS)}")
        if not rule.accepts(value):
            raise SettingsError(f"{where}: {key} must be {rule.describe()}, got {value!r}")
    missing = [key for key in required if key not in settings]
    if missing:
        raise SettingsError(f"{where}: missing key(s) {', '.join(missing)}")
    return settings


def load_settings(path: str | Path, required: Iterable[str] = REQUIRED) -> dict[str, Any]:
    """The checked mapping of the YAML settings file at `path` (see check_settings)."""
    settings = config_file.read_yaml(path, SettingsError, "settings file")
    return check_settings(settings, str(path), required)
