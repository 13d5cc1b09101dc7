"""Kinematics against closed-form motion; collisions stall the robot."""
import math

import pytest

from sim2d.kinematics import (DIFFERENTIAL, HOLONOMIC, DriveLimits, RobotState, WheelConfig,
                              step_robot, twist_to_wheels, wheels_to_twist)

FREE_SPACE = lambda x, y: 100.0  # noqa: E731
NO_RAMP = DriveLimits(max_linear=1.0, max_angular=2.0, max_linear_accel=1e9,
                      max_angular_accel=1e9)


def test_differential_drive_follows_the_closed_form_arc():
    wheels = WheelConfig(radius=0.075, separation=0.45)
    v, w, duration = 0.3, 0.5, 4.0
    # wheel speeds computed independently: v_{l,r} = v -/+ w * L / 2, divided by the radius
    left, right = (v - w * 0.225) / 0.075, (v + w * 0.225) / 0.075
    assert twist_to_wheels(v, w, wheels) == pytest.approx((left, right))
    state = RobotState(pose=(1.0, 2.0, 0.0))
    state.command = (*wheels_to_twist(left, right, wheels)[:1], 0.0,
                     wheels_to_twist(left, right, wheels)[1])
    for _ in range(400):
        step_robot(state, DIFFERENTIAL, NO_RAMP, 0.3, FREE_SPACE, duration / 400, wheels)
    radius = v / w                                   # circle of radius 0.6 m about (1.0, 2.6)
    assert state.pose[0] == pytest.approx(1.0 + radius * math.sin(w * duration), abs=1e-9)
    assert state.pose[1] == pytest.approx(2.0 + radius * (1 - math.cos(w * duration)), abs=1e-9)
    assert state.pose[2] == pytest.approx(w * duration, abs=1e-9)
    assert state.wheel_angles == pytest.approx([left * duration, right * duration])


def test_holonomic_lateral_motion_in_a_rotated_frame():
    state = RobotState(pose=(0.0, 0.0, math.pi / 2))
    state.command = (0.0, 0.2, 0.0)                  # body +y = map -x when facing +y
    for _ in range(50):
        step_robot(state, HOLONOMIC, NO_RAMP, 0.3, FREE_SPACE, 0.1)
    assert state.pose[0] == pytest.approx(-1.0)
    assert state.pose[1] == pytest.approx(0.0, abs=1e-12)


def test_acceleration_limit_ramps_the_speed():
    limits = DriveLimits(max_linear=0.5, max_linear_accel=1.0)
    state = RobotState()
    state.command = (0.5, 0.0, 0.0)
    step_robot(state, DIFFERENTIAL, limits, 0.3, FREE_SPACE, 0.1)
    assert state.twist[0] == pytest.approx(0.1)
    assert state.pose[0] == pytest.approx(0.01)


def test_speed_limit_clamps_the_command():
    state = RobotState()
    state.command = (5.0, 0.0, -9.0)
    step_robot(state, DIFFERENTIAL, NO_RAMP, 0.3, FREE_SPACE, 1.0)
    assert state.twist == pytest.approx((1.0, 0.0, -2.0))


def test_robot_driving_into_a_wall_stalls_and_reports_bumps():
    wall_x = 2.0
    clearance = lambda x, y: wall_x - x  # noqa: E731  (free distance to a wall at x = 2 m)
    state = RobotState(pose=(0.0, 0.0, 0.0))
    state.command = (0.4, 0.0, 0.0)                  # 0.04 m per step
    for _ in range(100):
        step_robot(state, DIFFERENTIAL, NO_RAMP, 0.3, clearance, 0.1)
        assert clearance(*state.pose[:2]) >= 0.3
    assert state.stalled and state.bumps == 100 - 42
    assert state.pose[0] == pytest.approx(1.68)      # 1.72 would leave only 0.28 m clearance
    assert state.twist[0] == 0.0
