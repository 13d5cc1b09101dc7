"""The executor's planner, chosen by name (node parameter ~planner)."""
from task_planner.baselines import FirstComeFirstServe, PriorityFirst, ShortestTimeFirst
from task_planner.exact import ExactReplanner
from task_planner.ripple_planner import RipplePlanner
from task_planner.rollout_planner import RolloutConfig, RolloutPlanner

PLANNER_NAMES = ("seed", "rollout", "exact", "fcfs", "pf", "sf")


def make_planner(name, settings):
    """A fresh planner: `seed` (Algorithm 4-2), `rollout` (ours), `exact`, or a §5.3 baseline.

    Args:
        name: one of PLANNER_NAMES.
        settings: the mapping of config/task_planner.yaml (step_s, rollout_*, exact_*).
    """
    if name == "seed":
        return RipplePlanner(step_s=float(settings.get("step_s", 1.0)))
    if name == "rollout":
        return RolloutPlanner(RolloutConfig(
            candidates=int(settings.get("rollout_candidates", 6)),
            horizon=int(settings.get("rollout_horizon", 10)),
            tail_weight=float(settings.get("rollout_tail_weight", 0.5)),
            priority_first_at_node=bool(settings.get("rollout_priority_first_at_node", True))))
    if name == "exact":
        return ExactReplanner(int(settings.get("exact_max_instructions", 40)))
    baselines = {"fcfs": FirstComeFirstServe, "pf": PriorityFirst, "sf": ShortestTimeFirst}
    if name in baselines:
        return baselines[name]()
    raise ValueError(f"unknown planner '{name}' (choose one of {', '.join(PLANNER_NAMES)})")
