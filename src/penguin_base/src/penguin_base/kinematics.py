"""Differential-drive kinematics and the velocity/acceleration limits of the base.

Wheel speeds are angular [rad/s], positive forward; twists are (v [m/s], omega [rad/s]) with
omega positive counter-clockwise (REP-103).
"""
import math


def wheel_speeds_from_twist(v, omega, wheel_radius, wheel_separation):
    """§2.1.3 (ros_control): inverse kinematics, twist -> (left, right) wheel speeds [rad/s]."""
    half_track = 0.5 * wheel_separation * omega
    return (v - half_track) / wheel_radius, (v + half_track) / wheel_radius


def twist_from_wheel_speeds(left, right, wheel_radius, wheel_separation):
    """Forward kinematics: (left, right) wheel speeds [rad/s] -> body twist (v, omega)."""
    v = 0.5 * wheel_radius * (right + left)
    omega = wheel_radius * (right - left) / wheel_separation
    return v, omega


def clamp(value, limit):
    """Clamp value into [-limit, limit]."""
    return max(-limit, min(limit, value))


def clamp_twist(v, omega, max_linear, max_angular):
    """Clamp a twist to the speed limits; returns (v, omega, was_clamped)."""
    v_out, omega_out = clamp(v, max_linear), clamp(omega, max_angular)
    return v_out, omega_out, (v_out != v or omega_out != omega)


def rate_limit(previous, target, max_rate, dt):
    """Move from previous toward target by at most max_rate * dt (acceleration limit)."""
    step = max_rate * dt
    return previous + clamp(target - previous, step)


def saturate_wheel_speeds(left, right, max_wheel_speed):
    """Scale both wheel speeds by one factor so neither exceeds the limit (keeps the curvature)."""
    peak = max(abs(left), abs(right))
    if peak <= max_wheel_speed:
        return left, right
    scale = max_wheel_speed / peak
    return left * scale, right * scale


def integrate_pose(x, y, theta, left_distance, right_distance, wheel_separation):
    """Dead reckoning: move a pose by the distances rolled by each wheel [m], along the exact arc.

    Returns the new (x, y, theta), theta wrapped to (-pi, pi].
    """
    distance = 0.5 * (right_distance + left_distance)
    dtheta = (right_distance - left_distance) / wheel_separation
    if abs(dtheta) < 1e-9:  # straight line: the arc formula divides by dtheta
        x += distance * math.cos(theta + 0.5 * dtheta)
        y += distance * math.sin(theta + 0.5 * dtheta)
    else:
        radius = distance / dtheta
        x += radius * (math.sin(theta + dtheta) - math.sin(theta))
        y -= radius * (math.cos(theta + dtheta) - math.cos(theta))
    return x, y, wrap_angle(theta + dtheta)


def wrap_angle(angle):
    """Wrap an angle [rad] to (-pi, pi]."""
    wrapped = math.remainder(angle, 2.0 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped
