import math

import numpy as np
import pytest

from nav_mocks.amcl_model import (AmclConfig, AmclModel, gauss_markov_step, latest_pair,
                                  map_to_odom)
from nav_mocks.pose2d import compose, inverse, wrap_angle

TRUTH = (2.0, 3.0, 0.5)


def test_pose2d_inverse_and_wrap():
    a = (1.0, -2.0, 2.5)
    assert compose(a, inverse(a)) == pytest.approx((0.0, 0.0, 0.0))
    assert wrap_angle(3 * math.pi) == pytest.approx(-math.pi)


def test_map_to_odom_composes_to_the_estimate():
    odom_pose = (0.7, -0.2, 1.1)
    estimate = (2.0, 3.0, 0.5)
    assert compose(map_to_odom(estimate, odom_pose), odom_pose) == pytest.approx(estimate)


def test_latest_pair_takes_truth_and_odometry_of_one_instant():
    """The truth callback ran one sample ahead of the odometry one: pairing the two latest
    would give map -> odom the robot's turn between them (here 0.03 rad)."""
    truths = [(1.00, (1.0, 0.0, 0.00)), (1.02, (1.0, 0.0, 0.03)), (1.04, (1.0, 0.0, 0.06))]
    odoms = [(1.00, (0.0, 0.0, 0.00)), (1.02, (0.0, 0.0, 0.03))]
    assert latest_pair(truths, odoms, max_gap=0.011) == ((1.0, 0.0, 0.03), (0.0, 0.0, 0.03))
    # a base's own odometry, stamped between two truth samples: the nearer one
    assert latest_pair(truths, [(1.035, (0.0, 0.0, 0.05))], max_gap=0.011) == (
        (1.0, 0.0, 0.06), (0.0, 0.0, 0.05))


def test_latest_pair_without_a_common_instant_is_none():
    truths = [(1.00, (1.0, 0.0, 0.0))]
    assert latest_pair(truths, [(1.10, (0.0, 0.0, 0.0))], max_gap=0.011) is None
    assert latest_pair([], [(1.00, (0.0, 0.0, 0.0))], max_gap=0.011) is None
    # the newest odometry has no truth yet: the one before it pairs
    odoms = [(1.00, (0.0, 0.0, 0.0)), (1.10, (0.5, 0.0, 0.0))]
    assert latest_pair(truths, odoms, max_gap=0.011) == ((1.0, 0.0, 0.0), (0.0, 0.0, 0.0))


def test_not_localised_until_initial_pose():
    model = AmclModel(AmclConfig(require_initial_pose=True))
    assert model.estimate(0.0, TRUTH) is None
    model.set_initial_pose(1.0, (2.5, 3.0, 0.5), TRUTH)
    pose, cov = model.estimate(1.0, TRUTH)
    assert pose[0] == pytest.approx(2.5, abs=0.001)
    assert cov[0] == pytest.approx(0.02 ** 2 + 0.5 ** 2)


def test_initial_pose_error_decays_with_convergence_time():
    cfg = AmclConfig(noise_xy_std=0.0, noise_yaw_std=0.0, convergence_time=1.5)
    model = AmclModel(cfg)
    model.set_initial_pose(0.0, (2.6, 3.0, 0.5), TRUTH)
    pose, _ = model.estimate(3.0, TRUTH)
    assert pose[0] - TRUTH[0] == pytest.approx(0.6 * math.exp(-2.0))


def test_far_initial_pose_does_not_converge():
    cfg = AmclConfig(noise_xy_std=0.0, noise_yaw_std=0.0, convergence_radius=1.0)
    model = AmclModel(cfg)
    model.set_initial_pose(0.0, (4.0, 3.0, 0.5), TRUTH)
    pose, _ = model.estimate(100.0, TRUTH)
    assert pose[0] == pytest.approx(4.0)


def test_noise_has_the_configured_std_and_covariance():
    cfg = AmclConfig(noise_xy_std=0.05, noise_yaw_std=0.03, noise_correlation_time=0.5)
    model = AmclModel(cfg, seed=3)
    errors = []
    for k in range(20000):
        pose, cov = model.estimate(0.5 * k, TRUTH)   # dt = tau: samples nearly independent
        errors.append([pose[0] - TRUTH[0], wrap_angle(pose[2] - TRUTH[2])])
    std = np.std(errors, axis=0)
    assert std == pytest.approx([0.05, 0.03], rel=0.05)
    assert cov[0] == pytest.approx(0.0025) and cov[35] == pytest.approx(0.0009)


def test_gauss_markov_zero_dt_keeps_the_error():
    rng = np.random.default_rng(0)
    error = np.array([0.1, -0.2, 0.05])
    assert gauss_markov_step(error, 0.0, 2.0, 1.0, rng) == pytest.approx(error)
