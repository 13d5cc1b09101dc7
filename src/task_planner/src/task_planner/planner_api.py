"""The planner interface: the three kinds of planner the simulation runs (the executor: two).

A planner is reset with every new instruction set (`reset(problem)`, a `problem.Problem`) and is
then asked, at the robot's node `node` and time `clock` [s], about the `available` instructions
(an int array of indices into the problem: launched, pending, predecessor done, never empty):

- a node planner (`kind = NODE`) answers `decide(...) -> (action, value)`: ("serve", index) of an
  available instruction waiting on `node`, or ("move", neighbour) to drive one edge; it is asked
  again at every node (the seed's Algorithm 4-2 decided once per node, the rollout planner);
- a target planner (`kind = TARGET`) answers `choose(...) -> index`: the robot drives the shortest
  path to that instruction's node and serves it, then asks again (the §5.3 dispatch rules, the
  optima);
- a step planner (`kind = STEP`) is asked at every step of every edge, given the robot's state
  vector (`robot_state.RobotState` on its own `step_adj`, starting from `start_state()`) instead
  of a node: `decide(state, clock, available) -> ("serve", index)` on a node, or
  ("step", n) toward neighbouring node n, which may turn the robot back mid-edge (the seed's
  Algorithm 4-2 as written). The executor drives whole edges with move_base and refuses it.

A planner states its kind in the class attribute `kind` and its display name (tables, figures,
the benchmark JSON's keys) in `name`; `kind_of` reads the kind and refuses an object that states
none. The planners are registered in `planner_registry`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar, Final, Literal, Protocol

import numpy as np

if TYPE_CHECKING:
    from task_planner.problem import Problem
    from task_planner.robot_state import RobotState

NODE: Final = "node"  # decide(node, clock, available) -> ("serve", index) or ("move", neighbour)
TARGET: Final = "target"  # choose(node, clock, available) -> index
STEP: Final = "step"  # decide(state, clock, available) -> ("serve", index) or ("step", neighbour)
KINDS = (NODE, TARGET, STEP)


class NodePlanner(Protocol):
    """Decides one step at every node: serve an instruction here, or move to a neighbour."""

    kind: ClassVar[Literal["node"]]
    name: str

    def reset(self, problem: Problem) -> None: ...

    def decide(self, node: int, clock: float,
               available: np.ndarray) -> tuple[Literal["serve", "move"], int]: ...


class TargetPlanner(Protocol):
    """Chooses the next instruction; the robot drives the shortest path to it and serves it."""

    kind: ClassVar[Literal["target"]]
    name: str

    def reset(self, problem: Problem) -> None: ...

    def choose(self, node: int, clock: float, available: np.ndarray) -> int: ...


class StepPlanner(Protocol):
    """Decides every step along the edges, from the robot's state vector."""

    kind: ClassVar[Literal["step"]]
    name: str
    step_adj: np.ndarray  # (V, V) edge lengths in steps, set by reset
    step_s: float         # seconds per step

    def reset(self, problem: Problem) -> None: ...

    def start_state(self) -> RobotState: ...

    def decide(self, state: RobotState, clock: float,
               available: np.ndarray) -> tuple[Literal["serve", "step"], int]: ...


Planner = NodePlanner | TargetPlanner | StepPlanner


def kind_of(planner: Planner) -> str:
    """The planner's stated kind, NODE or TARGET; TypeError naming its class otherwise."""
    kind = getattr(type(planner), "kind", None)
    if kind not in KINDS:
        raise TypeError(f"{type(planner).__name__} states no planner kind: its class attribute "
                        f"`kind` must be one of {', '.join(map(repr, KINDS))}, got {kind!r} "
                        f"(see task_planner.planner_api)")
    return kind
