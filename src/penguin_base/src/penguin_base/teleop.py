"""The five-key teleoperation scheme of thesis 002 §3.3.2 (Fig. 3.3.3) as a pure state machine.

- Up: speed up by one step; the robot keeps moving without holding the key.
- Down: slow down by one step.
- Left/Right: a single press turns slightly (a short rotation); held (key repeat), the rotating
  speed grows step by step; released (no repeat within `hold_timeout`), rotation returns to 0.
- Stop: linear and angular speed to 0.

A terminal reports no key releases, only presses and auto-repeats, so "held" means "pressed again
within hold_timeout" and "released" means "not pressed again within hold_timeout".
"""
from penguin_base.kinematics import clamp

UP, DOWN, LEFT, RIGHT, STOP = "up", "down", "left", "right", "stop"
KEYS = (UP, DOWN, LEFT, RIGHT, STOP)


class TeleopState:
    """Feed it key presses with their time; ask it for the command (v, omega) at any time."""

    def __init__(self, config):
        self.config = config
        self.linear = 0.0          # [m/s] persists until changed by Up/Down/Stop
        self._turn_direction = 0   # +1 left (counter-clockwise), -1 right, 0 none
        self._turn_speed = 0.0     # [rad/s] magnitude
        self._last_turn_press = None

    def press(self, key, now):
        """§3.3.2: apply one key press (or key repeat) at time `now` [s]."""
        c = self.config
        if key == UP:
            self.linear = min(self.linear + c.linear_step, c.max_linear_speed)
        elif key == DOWN:
            self.linear = max(self.linear - c.linear_step, c.min_linear_speed)
        elif key in (LEFT, RIGHT):
            self._press_turn(1 if key == LEFT else -1, now)
        elif key == STOP:
            self.linear = 0.0
            self._turn_direction, self._turn_speed, self._last_turn_press = 0, 0.0, None
        else:
            raise ValueError(f"unknown teleop key {key!r}; expected one of {KEYS}")
        self.linear = round(self.linear, 9)  # keep repeated steps from drifting off the grid

    def _press_turn(self, direction, now):
        c = self.config
        if self._turning(now) and direction == self._turn_direction:
            self._turn_speed = min(self._turn_speed + c.angular_step, c.max_angular_speed)
        else:
            self._turn_speed = min(c.tap_angular_speed, c.max_angular_speed)
        self._turn_direction = direction
        self._last_turn_press = now

    def _turning(self, now):
        return (self._last_turn_press is not None
                and now - self._last_turn_press <= self.config.hold_timeout)

    def command(self, now):
        """The (v [m/s], omega [rad/s]) to publish at time `now`."""
        if not self._turning(now):
            self._turn_direction, self._turn_speed = 0, 0.0
        omega = self._turn_direction * self._turn_speed
        return self.linear, clamp(omega, self.config.max_angular_speed)
