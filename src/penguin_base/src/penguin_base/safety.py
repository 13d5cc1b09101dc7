"""Safety layers of the base: command validation, watchdog, e-stop latch, bumper and stall stop.

Every class takes the current time as an argument (an injected clock), so the timing is testable
without sleeping.
"""
import math

from penguin_base.kinematics import clamp_twist


class InvalidCommand(ValueError):
    """A velocity command that cannot be executed (NaN or infinite component)."""


def sanitize_twist(v, omega, max_linear, max_angular):
    """Reject non-finite commands, clamp absurd speeds to the limits.

    Returns (v, omega, was_clamped); raises InvalidCommand naming the bad component.
    """
    for name, value in (("linear.x", v), ("angular.z", omega)):
        if not math.isfinite(value):
            raise InvalidCommand(f"/cmd_vel {name} is {value}")
    return clamp_twist(v, omega, max_linear, max_angular)


class CommandWatchdog:
    """Expires when no command was fed for longer than the timeout (or none ever was)."""

    def __init__(self, timeout):
        self.timeout = timeout  # [s]
        self._last_feed = None

    def feed(self, now):
        self._last_feed = now

    def expired(self, now):
        return self._last_feed is None or now - self._last_feed > self.timeout

    def age(self, now):
        """Seconds since the last command, or None if none arrived yet."""
        return None if self._last_feed is None else now - self._last_feed


class EStopLatch:
    """/e_stop: True engages a stop that holds until an explicit False releases it."""

    def __init__(self):
        self.engaged = False
        self.engage_count = 0

    def set(self, engaged):
        if engaged and not self.engaged:
            self.engage_count += 1
        self.engaged = bool(engaged)


class BumperStop:
    """Stops on a bump; re-arms only after the bumper is clear and a zero command was received.

    Requiring a zero command keeps an old forward command from driving back into the obstacle the
    moment the contact opens.
    """

    def __init__(self):
        self.pressed = False
        self.latched = False

    def set_pressed(self, pressed):
        self.pressed = bool(pressed)
        if self.pressed:
            self.latched = True

    def on_command(self, v, omega):
        if self.latched and not self.pressed and v == 0.0 and omega == 0.0:
            self.latched = False

    @property
    def stopping(self):
        return self.pressed or self.latched


class StallDetector:
    """Latches a stall when a wheel is commanded but barely turns for `stall_time` seconds."""

    def __init__(self, min_command, speed_ratio, stall_time):
        self.min_command = min_command  # [rad/s]
        self.speed_ratio = speed_ratio  # [-]
        self.stall_time = stall_time    # [s]
        self._since = None
        self.stalled = False

    def update(self, now, commanded, measured):
        """commanded/measured: (left, right) wheel speeds [rad/s]. Returns True when stalled."""
        stalling = any(abs(c) >= self.min_command and abs(m) < self.speed_ratio * abs(c)
                       for c, m in zip(commanded, measured))
        if not stalling:
            self._since = None
        elif self._since is None:
            self._since = now
        elif now - self._since >= self.stall_time:
            self.stalled = True
        return self.stalled

    def reset(self):
        self._since = None
        self.stalled = False
