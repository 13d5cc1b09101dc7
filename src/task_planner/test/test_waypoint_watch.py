"""task_planner.waypoint_watch: a waypoint goal counts as passed once, within its radius."""
from task_planner.waypoint_watch import WaypointWatch


def test_a_waypoint_is_passed_once_within_the_radius_of_its_own_goal():
    watch = WaypointWatch(0.6)
    assert watch.passing(1.57) and not watch.passing(None)
    watch.sent(3, 2.0, 1.0, waypoint=True)
    assert watch.passed(3, 2.0, 1.7) is None             # 0.7 m off
    assert watch.passed(2, 2.0, 1.2) is None             # feedback on a goal replaced since
    assert watch.passed(3, 2.0, 1.5) == 0.5
    assert watch.passed(3, 2.0, 1.2) is None             # once


def test_a_goal_that_is_no_waypoint_or_a_radius_of_zero_is_never_passed_early():
    watch = WaypointWatch(0.6)
    watch.sent(1, 0.0, 0.0, waypoint=True)
    watch.sent(2, 0.0, 0.0, waypoint=False)              # replaces the waypoint
    assert watch.passed(1, 0.0, 0.0) is None and watch.passed(2, 0.0, 0.0) is None
    assert not WaypointWatch(0.0).passing(1.57)
