"""Every planner of the package, registered once: its name, how it is made, its kind, what it is.

`PLANNERS` maps a name (the executor node's `~planner`, `scripts/bench_executor --planner`) to a
`PlannerEntry`: a factory from the planner settings (`config/task_planner.yaml`) and a seed, the
planner's kind (`planner_api.NODE`, `TARGET` or `STEP`), its display name, a one-line
description, its role (a §5.3 baseline, the seed's own planner, or improved beyond the seed) and
where it runs.
The executor node, the scenario report's model figures and the planner benchmark take their
planners from here, in registration order; adding a planner is one `PlannerEntry` below.
`python3 -m task_planner.planner_registry` prints the registry.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from task_planner.baselines import (FirstComeFirstServe, PlannedOrder, PriorityFirst,
                                    RandomOrder, ShortestTimeFirst, exhaustive_optimum)
from task_planner.exact import ExactReplanner, warm_exact_optimum
from task_planner.planner_api import KINDS, NODE, STEP, TARGET, Planner, kind_of
from task_planner.ripple_planner import RipplePlanner
from task_planner.rollout_planner import RolloutConfig, RolloutPlanner
from task_planner.step_planner import StepRipplePlanner

# role: what a planner is, relative to thesis 000
BASELINE = "baseline"            # a comparison planner of the seed (§5.3)
SEED_FAITHFUL = "seed-faithful"  # the seed's own planner as the thesis gives it (Algorithm 4-2)
IMPROVED = "improved"            # ours, beyond the seed
ROLES = (BASELINE, SEED_FAITHFUL, IMPROVED)

# uses: where a planner runs
EXECUTOR = "executor"              # the executor node's ~planner, scripts/bench_executor --planner
SCENARIO_MODEL = "scenario-model"  # a model figure of scripts/scenario_report (the run's arrivals)
BENCH_STATIC = "bench-static"      # benchmark: every static set and the Table 5-6 set
BENCH_STATIC_FEW = "bench-static-few"  # benchmark: the first `opt_trials` static sets and the
#                                        Table 5-6 set only (too slow for all of them)
BENCH_SCALING = "bench-scaling"    # benchmark: scaling to 200 instructions (Fig. 5-8, 5-9)
BENCH_DYNAMIC = "bench-dynamic"    # benchmark: Poisson arrivals
USES = (EXECUTOR, SCENARIO_MODEL, BENCH_STATIC, BENCH_STATIC_FEW, BENCH_SCALING, BENCH_DYNAMIC)
_BENCH_ONLINE = (BENCH_STATIC, BENCH_SCALING, BENCH_DYNAMIC)
_EXACT, _OPT = "Exact", "Opt"  # display names of the offline optima (PlannedOrder)


@dataclass(frozen=True)
class PlannerSettings:
    """What the factories read: keys of config/task_planner.yaml (defaults: the file's values)."""

    step_s: float = 1.0                # ripple planner time step [s]
    opt_max_instructions: int = 10     # exhaustive Opt refuses larger sets
    exact_max_instructions: int = 40   # the exact optimiser refuses larger sets
    rollout: RolloutConfig = field(default_factory=RolloutConfig)  # rollout_* keys

    @classmethod
    def of(cls, settings: PlannerSettings | Mapping[str, Any] | None = None) -> PlannerSettings:
        """PlannerSettings from a settings mapping (missing keys keep the defaults); None gives
        the defaults and a PlannerSettings is returned as it is."""
        if isinstance(settings, PlannerSettings):
            return settings
        given, default = dict(settings or {}), cls()
        rollout = default.rollout
        return cls(
            step_s=float(given.get("step_s", default.step_s)),
            opt_max_instructions=int(given.get("opt_max_instructions",
                                               default.opt_max_instructions)),
            exact_max_instructions=int(given.get("exact_max_instructions",
                                                 default.exact_max_instructions)),
            rollout=RolloutConfig(
                candidates=int(given.get("rollout_candidates", rollout.candidates)),
                horizon=int(given.get("rollout_horizon", rollout.horizon)),
                tail_weight=float(given.get("rollout_tail_weight", rollout.tail_weight)),
                priority_first_at_node=bool(given.get("rollout_priority_first_at_node",
                                                      rollout.priority_first_at_node))))


@dataclass(frozen=True)
class PlannerEntry:
    name: str          # registry name: ~planner, --planner, the scenario report
    label: str         # the planner's display name (`planner.name`): tables, figures, JSON keys
    kind: str          # planner_api.NODE, TARGET or STEP
    role: str          # BASELINE, SEED_FAITHFUL or IMPROVED
    description: str   # one line
    factory: Callable[[PlannerSettings, int], Planner]  # (settings, seed of a random planner)
    uses: frozenset[str]  # where it runs (USES)
    offline: bool = False  # solves the whole set at its first decision: a reference optimum

    def make(self, settings: PlannerSettings | Mapping[str, Any] | None = None,
             seed: int = 0) -> Planner:
        """A fresh planner; `settings`: a mapping of config/task_planner.yaml, PlannerSettings or
        None (defaults); `seed`: the generator seed of a randomised planner."""
        planner = self.factory(PlannerSettings.of(settings), seed)
        if kind_of(planner) != self.kind or planner.name != self.label:
            raise TypeError(f"planner '{self.name}' is registered as a {self.kind} planner "
                            f"named {self.label!r} but its factory made a {kind_of(planner)} "
                            f"planner named {planner.name!r}")
        return planner


def _registry(*entries: PlannerEntry) -> dict[str, PlannerEntry]:
    for entry in entries:
        if entry.kind not in KINDS or entry.role not in ROLES \
                or not entry.uses <= set(USES):
            raise ValueError(f"planner '{entry.name}': bad kind, role or uses")
    for what in ("name", "label"):
        values = [getattr(entry, what) for entry in entries]
        if len(set(values)) != len(values):
            raise ValueError(f"planner {what}s registered twice: {values}")
    return {entry.name: entry for entry in entries}


# Registration order is the order in which the benchmark runs the planners and the executor
# offers them (the benchmark's JSON and figures depend on it). Rand's seed comes from the caller.
PLANNERS = _registry(
    PlannerEntry("fcfs", FirstComeFirstServe.name, TARGET, BASELINE,
                 "first come, first served: the earliest launched instruction",
                 lambda s, seed: FirstComeFirstServe(),
                 frozenset((EXECUTOR, SCENARIO_MODEL) + _BENCH_ONLINE)),
    PlannerEntry("random", RandomOrder.name, TARGET, BASELINE,
                 "a uniformly random available instruction, from a seeded generator",
                 lambda s, seed: RandomOrder(seed=seed), frozenset(_BENCH_ONLINE)),
    PlannerEntry("pf", PriorityFirst.name, TARGET, BASELINE,
                 "priority first: the highest initial reward gamma",
                 lambda s, seed: PriorityFirst(), frozenset((EXECUTOR,) + _BENCH_ONLINE)),
    PlannerEntry("sf", ShortestTimeFirst.name, TARGET, BASELINE,
                 "shortest first: the least travel plus service time from the robot's node",
                 lambda s, seed: ShortestTimeFirst(), frozenset((EXECUTOR,) + _BENCH_ONLINE)),
    PlannerEntry("seed", RipplePlanner.name, NODE, SEED_FAITHFUL,
                 "the seed's ripple expected reward and value iteration (Algorithm 4-2) decided "
                 "once per node: one edge per decision",
                 lambda s, seed: RipplePlanner(step_s=s.step_s),
                 frozenset((EXECUTOR, SCENARIO_MODEL) + _BENCH_ONLINE)),
    PlannerEntry("seed_step", StepRipplePlanner.name, STEP, SEED_FAITHFUL,
                 "Algorithm 4-2 line by line: decided at every step along the edges from the "
                 "robot's state vector, turning back mid-edge when that is worth more",
                 lambda s, seed: StepRipplePlanner(step_s=s.step_s),
                 frozenset((SCENARIO_MODEL,) + _BENCH_ONLINE)),
    PlannerEntry("rollout", RolloutPlanner.name, NODE, IMPROVED,
                 "rollouts of the reward-rate rule from the most promising first instructions, "
                 "one edge per decision",
                 lambda s, seed: RolloutPlanner(s.rollout),
                 frozenset((EXECUTOR, SCENARIO_MODEL) + _BENCH_ONLINE)),
    PlannerEntry("exact", ExactReplanner.name, TARGET, IMPROVED,
                 "the exact optimum re-solved over the known instructions whenever new ones "
                 "arrive",
                 lambda s, seed: ExactReplanner(s.exact_max_instructions),
                 frozenset((EXECUTOR, BENCH_DYNAMIC))),
    PlannerEntry("exact_offline", _EXACT, TARGET, IMPROVED,
                 "the exact optimum of the whole set (label-setting DP warm-started by the "
                 "rollout planner), solved at the first decision",
                 lambda s, seed: PlannedOrder(_EXACT, lambda problem: warm_exact_optimum(
                     problem, s.exact_max_instructions, s.rollout)),
                 frozenset((BENCH_STATIC,)), offline=True),
    PlannerEntry("opt", _OPT, TARGET, BASELINE,
                 "the best of all orders, enumerated (refuses sets above opt_max_instructions)",
                 lambda s, seed: PlannedOrder(_OPT, lambda problem: exhaustive_optimum(
                     problem, s.opt_max_instructions)),
                 frozenset((BENCH_STATIC_FEW,)), offline=True),
)


def entries(*uses: str) -> tuple[PlannerEntry, ...]:
    """The registered entries (registration order) that run in any of `uses`; all without."""
    return tuple(e for e in PLANNERS.values() if not uses or e.uses & set(uses))


def planner_names(*uses: str) -> tuple[str, ...]:
    """Registry names of `entries(*uses)`."""
    return tuple(e.name for e in entries(*uses))


def make_planner(name: str, settings: PlannerSettings | Mapping[str, Any] | None = None,
                 seed: int = 0, use: str | None = None) -> Planner:
    """A fresh planner by registry name (see PlannerEntry.make); with `use`, only a planner that
    runs there (EXECUTOR: the executor node's choices). ValueError names the choices."""
    choices = planner_names(*(() if use is None else (use,)))
    if name not in choices:
        where = "" if use is None else f" for the {use}"
        raise ValueError(f"unknown planner '{name}'{where} (choose one of {', '.join(choices)})")
    return PLANNERS[name].make(settings, seed)


def make_planners(uses: Iterable[str], settings: PlannerSettings | Mapping[str, Any] | None = None,
                  seed: int = 0) -> list[Planner]:
    """Fresh planners of every entry that runs in any of `uses`, in registration order."""
    return [entry.make(settings, seed) for entry in entries(*uses)]


def display_order() -> list[str]:
    """Display names in table order: the offline optima first, then baselines, the seed's
    planner and ours (registration order within each)."""
    ranked = sorted(PLANNERS.values(), key=lambda e: (not e.offline, ROLES.index(e.role)))
    return [entry.label for entry in ranked]


def label(name: str) -> str:
    """The display name of the planner registered as `name`."""
    return PLANNERS[name].label


def registry_table() -> str:
    """The registry as a Markdown table."""
    rows = ["| name | label | kind | role | runs in | description |", "|---|---|---|---|---|---|"]
    rows += [f"| `{e.name}` | {e.label} | {e.kind} | {e.role} | "
             f"{', '.join(u for u in USES if u in e.uses)} | {e.description} |"
             for e in PLANNERS.values()]
    return "\n".join(rows)


if __name__ == "__main__":
    print(registry_table())
