"""Differential-drive kinematics and odometry against closed form (r = 0.075 m, b = 0.45 m)."""
import math

import pytest

from penguin_base.config import BaseConfig, ConfigError, wheel_speed_limit
from penguin_base.kinematics import (integrate_pose, rate_limit, saturate_wheel_speeds,
                                     twist_from_wheel_speeds, wheel_speeds_from_twist, wrap_angle)
from penguin_base.odometry import EncoderError, OdometryIntegrator
from tamp_resources import resource

R, B = 0.075, 0.45


@pytest.mark.parametrize("v, omega, left, right", [
    (0.3, 0.0, 4.0, 4.0),                      # straight: v / r
    (0.0, 1.0, -3.0, 3.0),                     # spin in place: omega b / 2r
    (0.2, 0.5, 0.0875 / R, 0.3125 / R),        # arc: (v -+ omega b/2) / r
    (-0.1, -0.4, (-0.1 + 0.09) / R, (-0.1 - 0.09) / R),
])
def test_inverse_and_forward_kinematics_match_closed_form(v, omega, left, right):
    assert wheel_speeds_from_twist(v, omega, R, B) == pytest.approx((left, right), abs=1e-12)
    assert twist_from_wheel_speeds(left, right, R, B) == pytest.approx((v, omega), abs=1e-12)


def test_seed_wheel_speed_limit_gives_about_0_4_m_per_s():
    # §2.1.1: 10000 rpm / 200 = 50 rpm at the wheel = 5.236 rad/s; times 0.075 m = 0.393 m/s
    limit = wheel_speed_limit(10000.0, 200.0)
    assert limit == pytest.approx(50.0 * 2.0 * math.pi / 60.0)
    assert limit * R == pytest.approx(0.3927, abs=1e-4)
    assert BaseConfig().max_wheel_speed == pytest.approx(limit)


def test_saturation_scales_both_wheels_and_keeps_curvature():
    left, right = saturate_wheel_speeds(2.0, 8.0, 5.0)
    assert (left, right) == pytest.approx((1.25, 5.0))
    assert saturate_wheel_speeds(-3.0, 4.0, 5.0) == (-3.0, 4.0)


def test_rate_limit_moves_at_most_rate_times_dt():
    assert rate_limit(0.0, 0.4, 0.5, 0.1) == pytest.approx(0.05)
    assert rate_limit(0.3, 0.0, 0.5, 0.1) == pytest.approx(0.25)
    assert rate_limit(0.1, 0.12, 0.5, 0.1) == pytest.approx(0.12)


def test_integrate_pose_follows_the_circle():
    # v = 0.2 m/s, omega = 0.5 rad/s for 1 s: radius 0.4 m, heading 0.5 rad
    x, y, theta = integrate_pose(0.0, 0.0, 0.0, 0.0875, 0.3125, B)
    assert (x, y, theta) == pytest.approx((0.4 * math.sin(0.5), 0.4 * (1 - math.cos(0.5)), 0.5))


def test_integrate_pose_straight_line_at_heading():
    x, y, theta = integrate_pose(1.0, 2.0, math.pi / 2, 0.3, 0.3, B)
    assert (x, y, theta) == pytest.approx((1.0, 2.3, math.pi / 2))


def test_wrap_angle():
    assert wrap_angle(3 * math.pi / 2) == pytest.approx(-math.pi / 2)
    assert wrap_angle(-math.pi) == pytest.approx(math.pi)


def test_odometry_from_encoder_angles_matches_closed_form_arc():
    odometry = OdometryIntegrator(R, B)
    left_speed, right_speed = wheel_speeds_from_twist(0.2, 0.5, R, B)
    for k in range(0, 41):  # 4 s at 10 Hz, starting from arbitrary encoder angles
        t = 0.1 * k
        state = odometry.update(100.0 + t, 7.0 + left_speed * t, -3.0 + right_speed * t)
    # closed form after 4 s: theta = 2 rad, x = R sin(theta), y = R (1 - cos(theta)), R = 0.4 m
    assert (state.x, state.y) == pytest.approx((0.4 * math.sin(2.0), 0.4 * (1 - math.cos(2.0))))
    assert state.theta == pytest.approx(2.0)
    assert (state.v, state.omega) == pytest.approx((0.2, 0.5))


def test_odometry_rejects_bad_encoder_readings():
    odometry = OdometryIntegrator(R, B)
    odometry.update(1.0, 0.0, 0.0)
    with pytest.raises(EncoderError, match="left wheel position is nan"):
        odometry.update(1.1, float("nan"), 0.0)
    with pytest.raises(EncoderError, match="older"):
        odometry.update(0.5, 0.0, 0.0)
    assert odometry.update(1.0, 5.0, 5.0).x == 0.0  # same stamp: ignored


def test_config_rejects_unknown_and_non_positive_values():
    assert BaseConfig.from_dict({"wheel_radius": 0.1}).wheel_radius == 0.1
    with pytest.raises(ConfigError, match="unknown parameter.*wheel_radus"):
        BaseConfig.from_dict({"wheel_radus": 0.1})
    with pytest.raises(ConfigError, match="base.wheel_separation must be a positive"):
        BaseConfig.from_dict({"wheel_separation": 0.0})
    with pytest.raises(ConfigError, match="must be a number"):
        BaseConfig.from_dict({"watchdog_timeout": "soon"})


def test_deployment_config_file_loads():

    import yaml
    path = resource("config") / "penguin.yaml"
    values = yaml.safe_load(path.read_text())
    config = BaseConfig.from_dict(values["base"])
    assert (config.wheel_radius, config.watchdog_timeout) == (0.075, 0.5)
    assert values["laser_mount"]["z"] == 0.45
