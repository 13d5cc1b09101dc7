"""Odometry drift models (Probabilistic Robotics Table 5.6 and its body-frame form for holonomic
bases), against hand calculations."""
import math

import numpy as np
import pytest

from sim2d import odometry as odometry_module
from sim2d.odometry import Odometry, OdometryConfig

NOISE_FREE = dict(alpha_rot_rot=0.0, alpha_rot_trans=0.0, alpha_trans_trans=0.0,
                  alpha_trans_rot=0.0)
HOUSEHOLD = dict(alpha_rot_rot=0.03, alpha_rot_trans=0.02, alpha_trans_trans=0.03,
                 alpha_trans_rot=0.01)   # config/worlds/household.yaml's Pepper


def drive(odometry, start, velocity, steps, dt=0.01):
    """Feed `steps` true poses of a constant world-frame velocity (vx, vy, w) from `start`."""
    for k in range(1, steps + 1):
        odometry.update(tuple(s + v * k * dt for s, v in zip(start, velocity)))
    return odometry.pose


def test_odometry_scale_error_drifts_by_the_configured_factor():
    config = OdometryConfig(**NOISE_FREE, scale_linear=1.05)
    odometry = Odometry(config, (1.0, 1.0, 0.0))
    for k in range(1, 101):                          # 2 m straight along +x in 2 cm steps
        odometry.update((1.0 + 0.02 * k, 1.0, 0.0))
    assert odometry.pose == pytest.approx((2.1, 0.0, 0.0))


def test_noise_free_holonomic_odometry_follows_a_sideways_arc():
    """Translating while turning: the odom pose is the true motion seen from the start pose."""
    start = (2.0, 3.0, math.pi / 2)
    odometry = Odometry(OdometryConfig(**NOISE_FREE), start, holonomic=True)
    truth = start
    for k in range(1, 101):
        t = 0.01 * k
        truth = (2.0 - 0.2 * t, 3.0 + 0.1 * t, math.pi / 2 + 0.8 * t)
        odometry.update(truth)
    # odom frame = start pose: world (dx, dy) = (-0.2, 0.1) is body (0.1, 0.2) at yaw pi/2
    assert odometry.pose == pytest.approx((0.1, 0.2, 0.8), abs=1e-9)


def test_sideways_steps_do_not_turn_the_holonomic_estimate():
    """A 0.1 m sideways move in 100 steps: the heading error is alpha2 per metre driven,
    std = alpha2 * 1 mm * sqrt(100) = 0.2 mrad, as for a forward move; Table 5.6 instead reads
    each step as turn +-pi/2, drive, turn back, and its heading wanders by
    alpha1 * pi/2 * sqrt(2 * 100) = 0.67 rad."""
    sideways, forward, table = [], [], []
    for seed in range(300):
        config = OdometryConfig(**HOUSEHOLD, seed=seed)
        sideways.append(drive(Odometry(config, (0, 0, 0), holonomic=True), (0, 0, 0),
                              (0.0, 0.1, 0.0), 100)[2])
        forward.append(drive(Odometry(config, (0, 0, 0), holonomic=True), (0, 0, 0),
                             (0.1, 0.0, 0.0), 100)[2])
        table.append(drive(Odometry(config, (0, 0, 0)), (0, 0, 0), (0.0, 0.1, 0.0), 100)[2])
    expected = 0.02 * 0.001 * math.sqrt(100)
    assert np.std(sideways) == pytest.approx(expected, rel=0.15)
    assert np.std(forward) == pytest.approx(expected, rel=0.15)
    assert np.std(table) == pytest.approx(0.03 * math.pi / 2 * math.sqrt(200), rel=0.15)


def test_holonomic_turn_in_place_drifts_by_alpha1():
    """1 rad turned in 100 steps: heading std alpha1 * 0.01 * sqrt(100) = 3 mrad, position
    std per axis alpha4 * 0.01 rad * sqrt(100) = 1 mm."""
    yaws, xs = [], []
    for seed in range(300):
        pose = drive(Odometry(OdometryConfig(**HOUSEHOLD, seed=seed), (0, 0, 0), holonomic=True),
                     (0, 0, 0), (0.0, 0.0, 1.0), 100)
        yaws.append(pose[2] - 1.0)
        xs.append(pose[0])
    assert np.std(yaws) == pytest.approx(0.03 * 0.01 * 10, rel=0.15)
    assert np.std(xs) == pytest.approx(0.01 * 0.01 * 10, rel=0.15)


def test_the_noise_stream_does_not_depend_on_the_pool_size(monkeypatch):
    """Refilling the pool continues the generator's stream: the poses past two refills equal
    those of one large draw."""
    config = OdometryConfig(**HOUSEHOLD, seed=7)
    steps = 2 * odometry_module.NOISE_POOL + 5
    pooled = drive(Odometry(config, (0, 0, 0)), (0, 0, 0), (0.3, 0.0, 0.2), steps)
    monkeypatch.setattr(odometry_module, "NOISE_POOL", 4 * odometry_module.NOISE_POOL)
    at_once = drive(Odometry(config, (0, 0, 0)), (0, 0, 0), (0.3, 0.0, 0.2), steps)
    assert pooled == at_once
