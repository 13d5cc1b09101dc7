"""The planner interface: the two kinds of planner the executor and the simulation run.

A planner is reset with every new instruction set (`reset(problem)`, a `problem.Problem`) and is
then asked, at the robot's node `node` and time `clock` [s], about the `available` instructions
(an int array of indices into the problem: launched, pending, predecessor done, never empty):

- a node planner (`kind = NODE`) answers `decide(...) -> (action, value)`: ("serve", index) of an
  available instruction waiting on `node`, or ("move", neighbour) to drive one edge; it is asked
  again at every node (the seed's Algorithm 4-2, the rollout planner);
- a target planner (`kind = TARGET`) answers `choose(...) -> index`: the robot drives the shortest
  path to that instruction's node and serves it, then asks again (the §5.3 dispatch rules, the
  optima).

A planner states its kind in the class attribute `kind` and its display name (tables, figures,
the benchmark JSON's keys) in `name`; `kind_of` reads the kind and refuses an object that states
none. The planners are registered in `planner_registry`.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar, Literal, Protocol

import numpy as np

if TYPE_CHECKING:
    from task_planner.problem import Problem

NODE = "node"      # decide(node, clock, available) -> ("serve", index) or ("move", neighbour)
TARGET = "target"  # choose(node, clock, available) -> index
KINDS = (NODE, TARGET)


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


Planner = NodePlanner | TargetPlanner


def kind_of(planner: Planner) -> str:
    """The planner's stated kind, NODE or TARGET; TypeError naming its class otherwise."""
    kind = getattr(type(planner), "kind", None)
    if kind not in KINDS:
        raise TypeError(f"{type(planner).__name__} states no planner kind: its class attribute "
                        f"`kind` must be one of {', '.join(map(repr, KINDS))}, got {kind!r} "
                        f"(see task_planner.planner_api)")
    return kind
