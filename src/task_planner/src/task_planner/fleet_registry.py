"""FLEET_ALLOCATORS, the one registry of fleet allocators (name -> factory from the planner
settings, role, description); `make_allocator(name, settings)` builds one by name."""
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from task_planner.fleet import Allocator, PerRobotPlanners
from task_planner.fleet_auction import AuctionConfig, SequentialAuction
from task_planner.planner_registry import (IMPROVED, SEED_FAITHFUL, PlannerSettings,
                                           make_planner)


@dataclass(frozen=True)
class AllocatorEntry:
    name: str
    role: str           # planner_registry's SEED_FAITHFUL (the seed extended) or IMPROVED
    description: str
    factory: Callable[[PlannerSettings], Allocator]


def _per_robot(planner: str) -> Callable[[PlannerSettings], PerRobotPlanners]:
    return lambda settings: PerRobotPlanners(lambda: make_planner(planner, settings),
                                             f"per-robot {planner}")


FLEET_ALLOCATORS = {entry.name: entry for entry in (
    AllocatorEntry("seed", SEED_FAITHFUL,
                   "each robot runs the seed's Algorithm 4-2 (planner `seed`) on the "
                   "instructions nobody has claimed", _per_robot("seed")),
    AllocatorEntry("rollout", IMPROVED,
                   "each robot runs the rollout planner on the instructions nobody has claimed",
                   _per_robot("rollout")),
    AllocatorEntry("auction", IMPROVED,
                   "sequential single-item auction of the open instructions over all robots "
                   "(best insertion), re-run at every decision", lambda settings:
                   SequentialAuction()),
    AllocatorEntry("auction_waiting", IMPROVED,
                   "the auction; a robot free with nothing planned waits at one of the graph's "
                   "k-median places (fleet_waiting)", lambda settings:
                   SequentialAuction(AuctionConfig(wait_at_medians=True))),
)}


def make_allocator(name: str,
                   settings: PlannerSettings | Mapping[str, Any] | None = None) -> Allocator:
    """A fresh allocator by registry name; ValueError names the choices."""
    if name not in FLEET_ALLOCATORS:
        raise ValueError(f"unknown fleet allocator '{name}' (choose one of "
                         f"{', '.join(FLEET_ALLOCATORS)})")
    return FLEET_ALLOCATORS[name].factory(PlannerSettings.of(settings))
