"""The executor node's parameters are checked before anything starts."""
import math

import pytest

from task_planner.ros_executor import NodeParams


def test_defaults_pass():
    NodeParams().check()


@pytest.mark.parametrize("name, value, bound", [
    ("tick_period", 0.0, "> 0"), ("goal_silence", -1.0, "> 0"), ("event_hold", math.nan, "> 0"),
    ("look_dwell", -0.1, ">= 0"), ("max_preemptions", -1, ">= 0"),
    ("pass_wait", math.inf, ">= 0"), ("max_open_instructions", -1, ">= 0"),
    ("pass_radius", -0.5, ">= 0"), ("search_miss", -1.0, ">= 0"), ("stay", 0.0, "> 0")])
def test_a_number_that_cannot_work_is_named(name, value, bound):
    params = NodeParams(**{name: value})
    with pytest.raises(ValueError, match=rf"parameter ~{name} must be a finite number {bound}; "
                                         rf"got {value}"):
        params.check()


def test_an_unknown_fleet_allocator_is_named_with_the_choices():
    with pytest.raises(ValueError, match=r"parameter ~fleet_allocator: unknown fleet allocator "
                                         r"'auktion' \(choose one of seed, rollout, auction, "
                                         r"auction_waiting\)"):
        NodeParams(fleet_allocator="auktion").check()
