"""Closed-loop episodes in sim2d judged by the route oracle."""
import math

import numpy as np
import pytest

from semnav_learning.episodes import (COLLISION, NOT_UNDERSTOOD, REACHED, STOPPED_OUTSIDE, TIMEOUT,
                                   EpisodeError, ExpertLabeller, ExpertPolicy, PolicyCommand,
                                   chain_goals, run_episode, run_expert_episode, time_limit)
from semnav_l_floor import l_floor_world

START = (1.0, 1.0, 0.0)


@pytest.fixture(scope="module")
def l_corridor(tmp_path_factory):
    """A 1.8 m corridor running east 10 m into an L corner that turns north for 6 m."""
    return l_floor_world(tmp_path_factory.mktemp("world"))


class ConstantPolicy:
    """Sends one command for ever (or reports done at once)."""

    def __init__(self, v, w, done=False, labels=(1,)):
        self.v, self.w, self.done, self.labels = v, w, done, list(labels)
        self.beams = []

    def start(self, sentence):
        if "flibber" in sentence:
            raise ValueError("no known word in 'flibber'")
        return self.labels

    def step(self, ranges, laser):
        self.beams.append((len(ranges), laser.beams))
        return PolicyCommand(self.v, self.w, 0, self.labels[0], self.done)


def test_chain_goals_follow_the_parts(l_corridor):
    _, oracle = l_corridor
    parts = chain_goals(oracle, START, (1, 3))
    # class 1: 1.0 m before the end wall's face at x = 9.9 (corridor centre y = 1.0); then "turn
    # left" there: the L corner (branch x = 8.1 ... 9.9), 0.9 + 1.0 m into it, facing north
    assert parts[0].goal.pose[:2] == pytest.approx((8.9, 1.0), abs=0.25)
    assert parts[1].goal.pose[:2] == pytest.approx((9.0, 2.9), abs=0.25)
    assert parts[1].goal.pose[2] == pytest.approx(math.pi / 2, abs=0.1)
    assert parts[0].length == pytest.approx(7.9, abs=0.25)
    assert parts[1].length == pytest.approx(0.1 + 1.9, abs=0.25)
    assert time_limit(parts) == pytest.approx(5.0 * (parts[0].length + parts[1].length) + 30.0)
    with pytest.raises(EpisodeError, match="class 2 is not applicable"):
        chain_goals(oracle, START, (2,))


def test_expert_reaches_two_part_goal(l_corridor):
    world, oracle = l_corridor
    parts = chain_goals(oracle, START, (1, 3))
    result = run_expert_episode(world, "penguin", START, parts)
    assert result.success and result.reason == REACHED
    assert result.predicted == [1, 3]
    assert len(result.part_ends) == 2
    assert parts[0].goal.contains(*result.part_ends[0])
    assert parts[1].goal.contains(*result.path[-1])
    # ~6 m + ~2 m at <= 0.4 m/s, plus turning and two halts of 1 s: 25-60 s
    assert 25.0 < result.duration < 60.0
    assert result.steps == len(result.commands) == len(result.path) - 1
    assert result.commands[:, 0].max() == pytest.approx(0.4, abs=0.01)
    assert result.min_clearance > 0.3


def test_collision_timeout_stop_and_unknown_words(l_corridor):
    world, oracle = l_corridor
    parts = chain_goals(oracle, START, (1,))
    crash = run_episode(world, "penguin", ConstantPolicy(0.4, 0.0), START, "go", parts)
    assert crash.reason == COLLISION and not crash.success
    # 9.9 - 0.3 - 1.0 = 8.6 m to the end wall: ~22 s at 0.4 m/s (with the ramp)
    assert crash.path[-1][0] == pytest.approx(9.6, abs=0.1)
    assert 20.0 < crash.duration < 24.0
    idle = run_episode(world, "penguin", ConstantPolicy(0.0, 0.0), START, "go", parts,
                       limit=3.0)
    assert idle.reason == TIMEOUT and idle.steps == 30
    early = run_episode(world, "penguin", ConstantPolicy(0.0, 0.0, done=True), START, "go",
                        parts)
    assert early.reason == STOPPED_OUTSIDE and early.steps == 1
    unknown = run_episode(world, "penguin", ConstantPolicy(0.0, 0.0), START, "flibber", parts)
    assert unknown.reason.startswith(NOT_UNDERSTOOD) and "flibber" in unknown.reason
    assert unknown.steps == 0


def test_policy_gets_the_sim_laser_and_labels_are_recorded(l_corridor):
    world, oracle = l_corridor
    parts = chain_goals(oracle, START, (1,))
    policy = ConstantPolicy(0.2, 0.0)
    result = run_episode(world, "penguin", policy, START, "go", parts, limit=2.0,
                         labeller=ExpertLabeller(parts), record_scans=True)
    assert set(policy.beams) == {(683, 683)}          # URG-04LX
    assert len(result.scans) == result.steps == len(result.expert_commands) == 20
    # the expert, asked at each visited state, accelerates along the corridor at 0.5 m/s^2
    assert result.expert_commands[0] == pytest.approx((0.05, 0.0), abs=1e-6)
    assert result.expert_commands[-1][0] == pytest.approx(0.4, abs=1e-6)


def test_expert_policy_interface(l_corridor):
    world, oracle = l_corridor
    robot = world.robot("penguin")
    parts = chain_goals(oracle, START, (4,))
    policy = ExpertPolicy(parts, lambda: robot.state.pose)
    assert policy.start("go back") == [4]
    result = run_episode(world, "penguin", policy, START, "go back", parts)
    assert result.success
    assert abs(math.remainder(result.path[-1][2] - math.pi, 2 * math.pi)) < 0.1
    assert np.hypot(*(result.path[-1][:2] - np.array(START[:2]))) < 0.1
