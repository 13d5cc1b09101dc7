"""When a waypoint counts as passed (ROS-free): the executor node sends a waypoint goal (a graph
node on the way to the place a move is for, `Navigate.through`) and takes it as reached once
navigation's feedback puts the robot within `radius_m` of it, so the next goal replaces it while
the robot is moving instead of stopping and turning on the node."""
import math


class WaypointWatch:
    """The one waypoint goal not yet passed, if any (a goal sent later replaces it)."""

    def __init__(self, radius_m: float) -> None:
        self.radius_m = radius_m   # [m]; 0: no goal is a waypoint (the seed's stop at each node)
        self._waiting: tuple[int, float, float] | None = None  # (goal seq, x, y [m])

    def passing(self, through: float | None) -> bool:
        """Whether a goal with heading-on `through` is sent as a waypoint."""
        return through is not None and self.radius_m > 0

    def sent(self, goal_seq: int, x: float, y: float, waypoint: bool) -> None:
        """Goal `goal_seq` to (x, y) went out; only a waypoint is watched."""
        self._waiting = (goal_seq, x, y) if waypoint else None

    def passed(self, goal_seq: int, x: float, y: float) -> float | None:
        """Feedback on goal `goal_seq` with the robot at (x, y): its distance [m] from the
        waypoint the first time it is within `radius_m`, else None."""
        waiting = self._waiting
        if waiting is None or waiting[0] != goal_seq:
            return None
        distance = math.hypot(x - waiting[1], y - waiting[2])
        if distance > self.radius_m:
            return None
        self._waiting = None
        return distance
