"""What the executor (task_planner.executor) asks of the robot, and its modes (ROS-free): the
node carries the commands out with move_base and /robot/say, the in-process model
(executor_sim) with its timing rule."""
from dataclasses import dataclass

IDLE, MOVING, EXECUTING, VERIFYING, LOOKING = "idle", "moving", "executing", "verifying", "looking"


@dataclass(frozen=True)
class Navigate:
    """Send the robot to graph node `node` (a neighbour of where it is, or the node just left),
    or, with `yaw`, turn in place on its own node to that heading [rad] (a look around). With
    `through`, `node` is a waypoint on the way to another place: the robot may pass it without
    stopping, heading `through` [rad] (towards the node after it)."""

    node: int
    instruction_id: int  # the instruction this move is for (0 when none)
    yaw: float | None = None
    through: float | None = None


@dataclass(frozen=True)
class StopMotion:
    """Cancel the current navigation goal (a look ended early)."""


@dataclass(frozen=True)
class Wait:
    """Nothing to do before `until_s` [s] (asked to pass; the retry follows)."""

    until_s: float


@dataclass(frozen=True)
class Execute:
    """Run robot function `function` for `instruction_id` for `duration_s` seconds."""

    instruction_id: int
    function: str
    duration_s: float


@dataclass(frozen=True)
class Verify:
    """Look for person `target` at the robot's place until `until_s` [s], then decide again."""

    instruction_id: int
    target: str
    until_s: float


@dataclass(frozen=True)
class Search:
    """A finished search for an instruction's person (journalled in the task buffer)."""

    instruction_id: int
    target: str
    start_s: float       # first miss [s]
    end_s: float         # found or given up [s]
    found: bool
    places: tuple[str, ...]  # place names looked at, in order (the last one found them if found)


@dataclass(frozen=True)
class Say:
    text: str


@dataclass(frozen=True)
class Ask:
    """Ask the person perception saw at `place` but could not tell whether they are `name`,
    or with `call` call `name` there (the introduction node says the question; a yes reaches
    the belief through human_db)."""

    instruction_id: int
    name: str
    place: str
    call: bool = False


# what the executor's events return, for the node or executor_sim to carry out
Command = Navigate | StopMotion | Wait | Execute | Verify | Say | Ask
