"""The base controller core: commands and safety inputs in, limited wheel speeds out.

Plays the part of the Penguin's ros_control (thesis 002 §2.1.3): command velocity -> the
rotational speeds of the two differential wheels. Stops (watchdog, e-stop, bumper, stall, invalid
command) set the wheels to zero at once; the acceleration limits shape commanded motion only.
A fault of the node's control step (`halt`) stops the base too: a robot stops when its controller
stops.
"""
from dataclasses import dataclass

from penguin_base.kinematics import (rate_limit, saturate_wheel_speeds, twist_from_wheel_speeds,
                                     wheel_speeds_from_twist)
from penguin_base.safety import (BumperStop, CommandWatchdog, EStopLatch, InvalidCommand,
                                 StallDetector, sanitize_twist)

OK, WARN, ERROR = 0, 1, 2  # diagnostic levels (same values as diagnostic_msgs/DiagnosticStatus)


@dataclass(frozen=True)
class WheelCommand:
    """One control step's output."""

    left: float         # [rad/s]
    right: float        # [rad/s]
    v: float            # [m/s] twist the wheels realise
    omega: float        # [rad/s]
    stop_reason: str    # "" when driving, else why the base is held at zero


class BaseController:
    """Feed it commands and safety inputs; call `update(now)` at the control rate."""

    def __init__(self, config):
        self.config = config
        self.watchdog = CommandWatchdog(config.watchdog_timeout)
        self.estop = EStopLatch()
        self.bumper = BumperStop()
        self.stall = StallDetector(config.stall_min_command, config.stall_speed_ratio,
                                   config.stall_time)
        self._target = (0.0, 0.0)
        self._output = (0.0, 0.0)  # (v, omega) after acceleration limits
        self._last_update = None
        self.invalid_count = 0
        self.clamped_count = 0
        self.halt_count = 0
        self.last_problem = ""
        self._last_problem_time = None
        self._rejected = False
        self.last_command = WheelCommand(0.0, 0.0, 0.0, 0.0, "no command yet")

    def command(self, v, omega, now):
        """A /cmd_vel arrived. Non-finite: stop and raise InvalidCommand. Absurd: clamped."""
        c = self.config
        try:
            v, omega, clamped = sanitize_twist(v, omega, c.max_linear_speed, c.max_angular_speed)
        except InvalidCommand as error:
            self.invalid_count += 1
            self._note_problem(str(error), now)
            self._target = (0.0, 0.0)
            self._rejected = True  # stay stopped until a valid command arrives
            raise
        if clamped:
            self.clamped_count += 1
            self._note_problem(f"command clamped to ({v:.3f} m/s, {omega:.3f} rad/s)", now)
        self._rejected = False
        self._target = (v, omega)
        self.watchdog.feed(now)
        self.bumper.on_command(v, omega)
        if v == 0.0 and omega == 0.0:
            self.stall.reset()
        return v, omega

    def halt(self, reason, now):
        """Stop at once from outside the control step (the step itself failed): zero wheels, and
        the output restarts from rest under the acceleration limits. Returns the zero command."""
        self._output = (0.0, 0.0)
        self.halt_count += 1
        self._note_problem(reason, now)
        self.last_command = WheelCommand(0.0, 0.0, 0.0, 0.0, reason)
        return self.last_command

    def _note_problem(self, text, now):
        self.last_problem, self._last_problem_time = text, now

    def set_estop(self, engaged):
        self.estop.set(engaged)

    def set_bumper(self, pressed):
        self.bumper.set_pressed(pressed)

    def stop_reason(self, now):
        """Why the base must stand still now, or ""."""
        if self.estop.engaged:
            return "e-stop engaged"
        if self.bumper.stopping:
            return "bumper pressed" if self.bumper.pressed else "bumped: waiting for a zero command"
        if self.stall.stalled:
            return "wheel stall: waiting for a zero command"
        if self._rejected:
            return "last /cmd_vel rejected (not finite)"
        if self.watchdog.expired(now):
            return "no /cmd_vel" if self.watchdog.age(now) is None else "command watchdog expired"
        return ""

    def update(self, now, measured=None):
        """One control step at time `now` [s]; measured = (left, right) wheel speeds or None."""
        c = self.config
        dt = 0.0 if self._last_update is None else max(0.0, now - self._last_update)
        self._last_update = now
        if measured is not None and self._output != (0.0, 0.0):
            self.stall.update(now, (self.last_command.left, self.last_command.right), measured)
        reason = self.stop_reason(now)
        if reason:
            self._output = (0.0, 0.0)
        else:
            self._output = (rate_limit(self._output[0], self._target[0], c.max_linear_accel, dt),
                            rate_limit(self._output[1], self._target[1], c.max_angular_accel, dt))
        left, right = wheel_speeds_from_twist(*self._output, c.wheel_radius, c.wheel_separation)
        left, right = saturate_wheel_speeds(left, right, c.max_wheel_speed)
        v, omega = twist_from_wheel_speeds(left, right, c.wheel_radius, c.wheel_separation)
        self.last_command = WheelCommand(left, right, v, omega, reason)
        return self.last_command

    def diagnostics(self, now):
        """(level, message, key/value dict) describing the controller's health."""
        reason = self.stop_reason(now)
        if self.estop.engaged or self.bumper.stopping or self.stall.stalled:
            level = ERROR
        elif (self._last_problem_time is not None
              and now - self._last_problem_time <= self.config.problem_report_window):
            level = WARN
        else:
            level = OK
        age = self.watchdog.age(now)
        values = {
            "stop reason": reason or "none (driving)",
            "left wheel [rad/s]": f"{self.last_command.left:.3f}",
            "right wheel [rad/s]": f"{self.last_command.right:.3f}",
            "seconds since last command": "never" if age is None else f"{age:.2f}",
            "e-stop engagements": str(self.estop.engage_count),
            "invalid commands rejected": str(self.invalid_count),
            "commands clamped": str(self.clamped_count),
            "control steps failed": str(self.halt_count),
            "last problem": self.last_problem or "none",
        }
        return level, reason or "driving", values
