"""Typed configuration of the base and the teleoperation program (deployment values:
config/penguin.yaml)."""
import math
from dataclasses import dataclass, fields


class ConfigError(ValueError):
    """A configuration value is missing, unknown or out of range."""


def wheel_speed_limit(motor_max_rpm, gear_ratio):
    """§2.1.1: wheel speed limit [rad/s] from the motor limit [rpm] and overall gear ratio."""
    return motor_max_rpm / gear_ratio * 2.0 * math.pi / 60.0


@dataclass(frozen=True)
class BaseConfig:
    """The Penguin's differential-drive base (thesis 002 §2.1.1)."""

    wheel_radius: float = 0.075        # [m] §2.1.1
    wheel_separation: float = 0.45     # [m] distance between the drive wheels (not in the seed)
    motor_max_rpm: float = 10000.0     # [rpm] motor limit set in the motion controllers, §2.1.1
    gear_ratio: float = 200.0          # [-] overall motor-to-wheel reduction, §2.1.1
    max_linear_speed: float = 0.4      # [m/s] §2.1.1: theoretical maximum about 0.4 m/s
    max_angular_speed: float = 1.0     # [rad/s]
    max_linear_accel: float = 0.5      # [m/s^2]
    max_angular_accel: float = 2.0     # [rad/s^2]
    watchdog_timeout: float = 0.5      # [s] no /cmd_vel for this long -> stop
    control_rate: float = 50.0         # [Hz] wheel command / odometry update rate
    stall_min_command: float = 0.5     # [rad/s] wheel command above which a stall can be detected
    stall_speed_ratio: float = 0.1     # [-] measured/commanded wheel speed below this = stalling
    stall_time: float = 1.0            # [s] stalling this long -> stop
    problem_report_window: float = 5.0  # [s] diagnostics stay WARN this long after a bad command

    @property
    def max_wheel_speed(self):
        """Wheel angular speed limit [rad/s]."""
        return wheel_speed_limit(self.motor_max_rpm, self.gear_ratio)

    @classmethod
    def from_dict(cls, values):
        """Build from a parameter dictionary; unknown keys and non-positive values are errors."""
        return _from_dict(cls, values, "base")

    def __post_init__(self):
        _require_positive(self, "base")
        if self.stall_speed_ratio >= 1.0:
            raise ConfigError(f"base.stall_speed_ratio must be < 1, got {self.stall_speed_ratio}")


@dataclass(frozen=True)
class TeleopConfig:
    """The five-key teleoperation program (thesis 002 §3.3.2, Fig. 3.3.3)."""

    linear_step: float = 0.02          # [m/s] speed change per Up/Down press (or key repeat)
    max_linear_speed: float = 0.4      # [m/s]
    min_linear_speed: float = 0.0      # [m/s] Down never goes below this (0: no reversing)
    tap_angular_speed: float = 0.2     # [rad/s] rotation of a single Left/Right press
    angular_step: float = 0.1          # [rad/s] rotation increase per key repeat while held
    max_angular_speed: float = 1.0     # [rad/s]
    hold_timeout: float = 0.55         # [s] no repeat of Left/Right for this long = released
    publish_rate: float = 20.0         # [Hz] /cmd_vel rate (keeps the base watchdog fed)

    @classmethod
    def from_dict(cls, values):
        """Build from a parameter dictionary; unknown keys and bad values are errors."""
        return _from_dict(cls, values, "teleop")

    def __post_init__(self):
        for name in ("linear_step", "max_linear_speed", "tap_angular_speed", "angular_step",
                     "max_angular_speed", "hold_timeout", "publish_rate"):
            _check_positive(name, getattr(self, name), "teleop")
        if not -self.max_linear_speed <= self.min_linear_speed <= 0.0:
            raise ConfigError("teleop.min_linear_speed must lie in [-max_linear_speed, 0], "
                              f"got {self.min_linear_speed}")


def _from_dict(cls, values, section):
    names = {f.name for f in fields(cls)}
    unknown = sorted(set(values) - names)
    if unknown:
        raise ConfigError(f"{section}: unknown parameter(s) {unknown}; known: {sorted(names)}")
    try:
        return cls(**{k: float(v) for k, v in values.items()})
    except (TypeError, ValueError) as error:
        if isinstance(error, ConfigError):
            raise
        raise ConfigError(f"{section}: every parameter must be a number ({error})") from None


def _require_positive(config, section):
    for f in fields(config):
        _check_positive(f.name, getattr(config, f.name), section)


def _check_positive(name, value, section):
    if not (math.isfinite(value) and value > 0.0):
        raise ConfigError(f"{section}.{name} must be a positive finite number, got {value}")
