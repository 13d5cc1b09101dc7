"""Expert demonstrator driven with unicycle kinematics on the office floors."""
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from semnav_learning.expert import (ExpertConfig, ExpertDriver, recorded_stop_steps, rehearse,
                                 unicycle_step)
from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.route_oracle import RouteOracle
from floorplan.occupancy_map import load_map
import rospkg
from tamp_resources import resource

ROOT = resource()
FIXTURES = Path(rospkg.RosPack().get_path("semnav_learning")) / "fixtures"
STARTS = yaml.safe_load((FIXTURES /
                         "oracle_expected_goals.yaml").read_text())


@pytest.fixture(scope="module")
def crossroads():
    return RouteOracle(load_map(ROOT / "maps" / "office_crossroads.yaml"))


def test_unicycle_step_on_a_circle():
    # v = 0.5 m/s, ω = 0.5 rad/s: radius 1 m; after 2π s half a circle -> (0, 2), heading π
    pose = (0.0, 0.0, 0.0)
    for _ in range(100):
        pose = unicycle_step(pose, 0.5, 0.5, 2 * math.pi / 100)
    assert pose[0] == pytest.approx(0.0, abs=1e-3)
    assert pose[1] == pytest.approx(2.0, abs=1e-3)
    assert abs(pose[2]) == pytest.approx(math.pi, abs=1e-6)


def test_turn_right_is_smooth_and_does_not_stop(crossroads):
    config = ExpertConfig()
    demo = rehearse(crossroads, (2.0, 10.0, 0.0), 2, config)
    assert demo.reached and demo.min_clearance > 0.6
    v, w = demo.labels[:, 0], demo.labels[:, 1]
    dt = 1.0 / config.rate
    assert np.all(np.abs(np.diff(v)) <= config.max_linear_accel * dt + 1e-9)
    assert np.all(np.abs(np.diff(w)) <= config.max_angular_accel * dt + 1e-9)
    assert v.max() == pytest.approx(config.max_linear_speed, abs=0.01)
    assert np.all(np.abs(w) <= config.max_angular_speed + 1e-9)
    moving = np.flatnonzero(v > 0.05)
    # between first and last moving command the robot never stops, also through the turn
    assert np.all(v[moving[0]:moving[-1]] > 0.05)
    turning = np.flatnonzero(np.abs(w) > 0.3)
    assert turning.size and np.all(v[turning[turning < moving[-1]]] > 0.05)
    # ends facing along the new corridor (south) and records zero commands at the end
    assert math.remainder(demo.poses[-1, 2] + math.pi / 2, 2 * math.pi) == pytest.approx(
        0.0, abs=math.radians(config.align_tolerance))
    # §2.2.5.2: the demonstration ends standing still for 6 s = 60 steps at 10 Hz (> 50 of halting)
    assert recorded_stop_steps(config) == 60
    assert np.all(demo.labels[-60:] == 0.0) and np.any(demo.labels[-61] != 0.0)
    assert recorded_stop_steps(ExpertConfig(rate=40.0)) == 240     # the sim2d scan rate


def test_turn_around_turns_on_the_spot(crossroads):
    demo = rehearse(crossroads, (2.0, 10.0, 0.0), 4)
    assert demo.reached
    assert np.all(demo.labels[:, 0] == 0.0)
    assert np.hypot(*(demo.poses[-1, :2] - [2.0, 10.0])) < 0.01


def test_not_applicable_class_gives_no_demonstration(crossroads):
    assert rehearse(crossroads, (2.0, 10.0, 0.0), 9) is None


def test_driver_corrects_an_offset_start():
    driver = ExpertDriver([[0.0, 0.0], [6.0, 0.0]], (6.0, 0.0, 0.0))
    pose = (0.0, 0.4, math.radians(15))
    for _ in range(400):
        _, executed, done = driver.command(pose)
        if done:
            break
        pose = unicycle_step(pose, *executed, 0.1)
    assert done and abs(pose[1]) < 0.05 and abs(pose[0] - 6.0) < 0.15


@pytest.mark.parametrize("floor", sorted(STARTS))
def test_noisy_demonstrations_reach_the_goal_without_touching_walls(floor):
    oracle = RouteOracle(load_map(ROOT / "maps" / f"{floor}.yaml"))
    rng = np.random.default_rng(7)
    results = []
    for entry in STARTS[floor]:
        x, y, yaw = entry["start"]
        start = (x, y, math.radians(yaw))
        walk = oracle.walk(start)           # the same for every class from this start
        for label in CLASS_IDS:
            offset = (rng.uniform(-0.25, 0.25), rng.uniform(-0.25, 0.25),
                      math.radians(rng.uniform(-10, 10)))
            demo = rehearse(oracle, start, label, rng=rng, start_offset=offset, walk=walk)
            if demo is not None:
                results.append(demo.reached and demo.min_clearance >= oracle.config.robot_radius)
    assert len(results) >= 9 and np.mean(results) >= 0.99


def test_long_corridor_at_the_utm30lx_rate(crossroads):
    # 26.9 m at <= 0.4 m/s is more than 67 s: 2700 commands at 40 Hz must not run out of time
    demo = rehearse(crossroads, (2.0, 10.0, 0.0), 1, ExpertConfig(rate=40.0))
    assert demo.reached and len(demo.poses) > 2700
