"""Wheel odometry: encoder positions (wheel angles) -> pose and twist in the odom frame."""
import math
from dataclasses import dataclass

from penguin_base.kinematics import integrate_pose, twist_from_wheel_speeds


class EncoderError(ValueError):
    """An encoder reading that cannot be used (non-finite, time going backwards)."""


@dataclass(frozen=True)
class OdometryState:
    """Pose of base_link in odom and its body twist."""

    stamp: float      # [s]
    x: float          # [m]
    y: float          # [m]
    theta: float      # [rad] in (-pi, pi]
    v: float          # [m/s] forward speed
    omega: float      # [rad/s] yaw rate
    left_speed: float   # [rad/s] measured left wheel speed
    right_speed: float  # [rad/s] measured right wheel speed


class OdometryIntegrator:
    """Integrates successive encoder readings (wheel angles [rad]) into a pose."""

    def __init__(self, wheel_radius, wheel_separation):
        self.wheel_radius = wheel_radius
        self.wheel_separation = wheel_separation
        self._last = None  # (stamp, left angle, right angle)
        self.state = OdometryState(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)

    @property
    def started(self):
        """True once a first encoder reading set the reference angles."""
        return self._last is not None

    def update(self, stamp, left_angle, right_angle):
        """Add one encoder reading; returns the new OdometryState.

        The first reading only sets the reference angles. A reading at the same stamp as the
        previous one is ignored; an older stamp or a non-finite value raises EncoderError.
        """
        for name, value in (("stamp", stamp), ("left wheel position", left_angle),
                            ("right wheel position", right_angle)):
            if not math.isfinite(value):
                raise EncoderError(f"{name} is {value}")
        if self._last is None:
            self._last = (stamp, left_angle, right_angle)
            self.state = OdometryState(stamp, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            return self.state
        last_stamp, last_left, last_right = self._last
        dt = stamp - last_stamp
        if dt < 0.0:
            raise EncoderError(f"encoder stamp {stamp:.3f} s is older than the previous "
                               f"{last_stamp:.3f} s")
        if dt == 0.0:
            return self.state
        d_left, d_right = left_angle - last_left, right_angle - last_right
        s = self.state
        x, y, theta = integrate_pose(s.x, s.y, s.theta, d_left * self.wheel_radius,
                                     d_right * self.wheel_radius, self.wheel_separation)
        left_speed, right_speed = d_left / dt, d_right / dt
        v, omega = twist_from_wheel_speeds(left_speed, right_speed, self.wheel_radius,
                                           self.wheel_separation)
        self._last = (stamp, left_angle, right_angle)
        self.state = OdometryState(stamp, x, y, theta, v, omega, left_speed, right_speed)
        return self.state
