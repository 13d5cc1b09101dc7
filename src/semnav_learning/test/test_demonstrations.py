"""Expert demonstrations driven in the sim2d world and recorded in penguin_base's format."""
import math

import numpy as np
import pytest

from penguin_base.record_format import format_records, parse_records
from semnav_learning.demonstrations import demonstrate, world_for_floor
from semantic_nav.laser_layer import model_from_scan, preprocess_scan, load_laser_config
from semnav_learning.route_oracle import RouteOracle
from semnav_l_floor import l_floor_world, write_l_floor
from tamp_resources import resource

ROOT = resource()


@pytest.fixture(scope="module")
def l_corridor(tmp_path_factory):
    """A 1.8 m corridor running east 10 m into an L corner that turns north for 6 m."""
    return l_floor_world(tmp_path_factory.mktemp("world"))


@pytest.fixture(scope="module")
def turn_left(l_corridor):
    """The expert's "turn left" from the corridor's start: to the L corner, 1 m into the branch
    (driven once for the two tests that look at it)."""
    world, oracle = l_corridor
    return demonstrate(world, "penguin", oracle, (1.0, 1.0, 0.0), 3,
                       rng=np.random.default_rng(0))


def test_turn_left_at_the_corner_in_the_simulator(turn_left):
    demo = turn_left
    assert demo.ok, demo
    x, y, yaw = demo.final_pose
    assert (x, y) == pytest.approx((9.0, 2.9), abs=0.75)      # 1.0 m into the branch
    assert math.remainder(yaw - math.pi / 2, 2 * math.pi) == pytest.approx(0.0, abs=0.1)
    sequence = demo.sequence
    assert sequence.instruction_class == 3
    # URG-04LX: 683 beams at 10 Hz; ~8 m of path at <= 0.4 m/s is more than 20 s of samples
    assert all(len(s.ranges) == 683 for s in sequence.samples)
    assert len(sequence.samples) > 200
    assert max(s.v for s in sequence.samples) == pytest.approx(0.4, abs=0.01)
    # §2.2.5.2: ends standing for 6 s = 60 samples of the 10 Hz URG-04LX (expert stop_duration)
    assert all(s.v == 0.0 and s.omega == 0.0 for s in sequence.samples[-60:])
    assert (sequence.samples[-61].v, sequence.samples[-61].omega) != (0.0, 0.0)
    again = parse_records(format_records([sequence]))[0].samples[5]
    assert (again.v, again.omega) == (sequence.samples[5].v, sequence.samples[5].omega)
    np.testing.assert_array_equal(again.ranges, sequence.samples[5].ranges)   # NaN == NaN


def test_turn_after_the_end_starts_where_go_to_the_end_stops(l_corridor, turn_left):
    """after=(1,): "turn left" standing at the corner that "go straight to the end" reached
    (the oracle's class-1 goal, episodes.chain_goals), not from the corridor's start."""
    world, oracle = l_corridor
    whole = turn_left
    end = oracle.goal((1.0, 1.0, 0.0), 1, oracle.walk((1.0, 1.0, 0.0))).pose
    demo = demonstrate(world, "penguin", oracle, (1.0, 1.0, 0.0), 3,
                       rng=np.random.default_rng(0), after=(1,))
    assert demo.ok, demo
    assert demo.sequence.instruction_class == 3
    assert demo.final_pose[:2] == pytest.approx(whole.final_pose[:2], abs=0.3)
    # the drive from `end` is shorter than the whole one by at least the corridor from x = 1
    # to `end` at 0.4 m/s (10 Hz samples), less a margin for the turn's own speed profile
    skipped = (end[0] - 1.0) / 0.4 * 10
    assert len(demo.sequence.samples) < len(whole.sequence.samples) - 0.8 * skipped
    assert demonstrate(world, "penguin", oracle, (1.0, 1.0, 0.0), 2, after=(1,)) is None


def test_recorded_scans_go_through_the_laser_layer(l_corridor):
    world, oracle = l_corridor
    demo = demonstrate(world, "penguin", oracle, (1.0, 1.0, 0.0), 4)
    _, canonical, config = load_laser_config(ROOT / "config" / "semnav_laser.yaml")
    model = world.robot("penguin").lasers[0].model
    source = model_from_scan("urg_04lx", model.angle_min, model.angle_increment,
                             model.num_beams, model.range_min, model.range_max)
    vector, _ = preprocess_scan(demo.sequence.samples[0].ranges, source, canonical, config)
    assert vector.shape == (881,) and np.linalg.norm(vector) == pytest.approx(1.0, abs=1e-5)


def test_record_rate_records_one_scan_per_period(l_corridor):
    """record_rate 5 Hz on the 10 Hz URG-04LX: half the samples of the same drive, still
    ending with the 6 s of standing (30 samples at 5 Hz)."""
    world, oracle = l_corridor
    full = demonstrate(world, "penguin", oracle, (5.0, 1.0, 0.0), 1)
    half = demonstrate(world, "penguin", oracle, (5.0, 1.0, 0.0), 1, record_rate=5.0)
    assert full.ok and half.ok
    assert len(half.sequence.samples) == pytest.approx(len(full.sequence.samples) / 2, abs=3)
    assert all(s.v == 0.0 and s.omega == 0.0 for s in half.sequence.samples[-30:])
    assert half.sequence.samples[-31].v > 0.0


def test_world_for_floor_starts_the_robot_on_this_floor(tmp_path):
    """The template's pose (2, 10) lies outside the 10 m x 8 m L floor (World would refuse
    it); the robot is put where this floor is most open instead: the 8 m x 6 m free area north
    of the corridor wall, whose centre is 3 m from its walls."""
    write_l_floor(tmp_path)
    world = world_for_floor(ROOT / "config" / "worlds" / "office_penguin.yaml",
                            tmp_path / "l_floor.yaml", cache_dir=None, raycast="march")
    x, y, _ = world.robot("penguin").state.pose
    clearance = world.geometry.clearance(np.array([x]), np.array([y]))[0]
    assert clearance == pytest.approx(2.9, abs=0.1)     # 3 m minus half the 0.2 m walls


def test_not_applicable_class_is_not_driven(l_corridor):
    world, oracle = l_corridor
    assert demonstrate(world, "penguin", oracle, (1.0, 1.0, 0.0), 2) is None


def test_plan_balances_classes_over_starts():
    from semnav_learning.demonstrations import plan_demonstrations
    from semantic_nav.instruction_classes import CLASS_IDS
    from floorplan.occupancy_map import load_map
    oracle = RouteOracle(load_map(ROOT / "maps" / "office_longhall.yaml"))
    starts = [(2.0, 8.0, 0.0), (11.0, 14.0, -math.pi / 2), (21.0, 2.0, math.pi / 2)]
    plan = plan_demonstrations(oracle, starts, 2, np.random.default_rng(0))
    per_class = {label: [s for s, c in plan if c == label] for label in CLASS_IDS}
    # fixture: class 5 and 8 only from the hall start, 9 from the two side corridors, 6/7 never
    assert per_class[5] == [starts[0]] and per_class[8] == [starts[0]]
    assert per_class[6] == [] and per_class[7] == []
    assert sorted(per_class[9]) == sorted(starts[1:])
    assert len(per_class[1]) == 2 and len(per_class[4]) == 2


# office_comb's spine from its south end, the side corridors and the west branch
SPINE = (18.0, 5.0, math.pi / 2)
COMB_STARTS = [SPINE, (4.0, 11.0, math.pi / 2), (32.0, 16.0, math.pi / 2), (6.0, 18.0, 0.0)]


@pytest.mark.parametrize("planner", ["plan_counting_demonstrations", "plan_side_demonstrations"])
def test_counting_plans_take_only_starts_where_the_other_side_counts(planner):
    """From the spine the crossroad is the 3rd corner but the 2nd on either side, so counting
    over both sides and counting one side differ for classes 5, 7 and 8 (the side plan
    drives the one-side counts there); from the side corridors and the west branch classes 5
    and 6 apply, but one side counts alike."""
    import semnav_learning.demonstrations as demonstrations
    from floorplan.occupancy_map import load_map
    oracle = RouteOracle(load_map(ROOT / "maps" / "office_comb.yaml"))
    plan = getattr(demonstrations, planner)
    assert plan(oracle, COMB_STARTS, 3, np.random.default_rng(0)) == [
        (SPINE, 5), (SPINE, 7), (SPINE, 8)]
    assert plan(oracle, COMB_STARTS, 0, np.random.default_rng(0)) == []


def test_a_demonstration_counted_on_one_side_ends_at_that_sides_branch():
    """Counting the right-hand branches from the spine, the second right (class 5) is the
    crossroad at 13 m; counting every corner gives the branch at 9 m."""
    from semnav_learning.episodes import chain_goals
    from semantic_nav.instruction_classes import COUNT_SIDE
    from floorplan.occupancy_map import load_map
    oracle = RouteOracle(load_map(ROOT / "maps" / "office_comb.yaml"))
    world = world_for_floor(ROOT / "config" / "worlds" / "office_penguin.yaml",
                            ROOT / "maps" / "office_comb.yaml", cache_dir=None)
    demo = demonstrate(world, "penguin", oracle, SPINE, 5, record_rate=10.0,
                       counting=COUNT_SIDE)
    side_goal = chain_goals(oracle, SPINE, (5,), (COUNT_SIDE,))[-1].goal
    corner_goal = chain_goals(oracle, SPINE, (5,))[-1].goal
    assert demo.ok and side_goal.contains(*demo.final_pose)
    assert not corner_goal.contains(*demo.final_pose)
