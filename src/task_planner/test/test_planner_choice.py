"""The executor's ~planner parameter maps to the planners of the package."""
from pathlib import Path

import pytest
import yaml

from task_planner.baselines import FirstComeFirstServe, PriorityFirst, ShortestTimeFirst
from task_planner.exact import ExactReplanner
from task_planner.planner_choice import PLANNER_NAMES, make_planner
from task_planner.ripple_planner import RipplePlanner
from task_planner.rollout_planner import RolloutPlanner

SETTINGS = yaml.safe_load(
    (Path(__file__).resolve().parents[3] / "config" / "task_planner.yaml").read_text())


def test_each_name_gives_its_planner_with_the_configured_settings():
    planners = {name: make_planner(name, SETTINGS) for name in PLANNER_NAMES}
    expected = {"seed": RipplePlanner, "rollout": RolloutPlanner, "exact": ExactReplanner,
                "fcfs": FirstComeFirstServe, "pf": PriorityFirst, "sf": ShortestTimeFirst}
    assert {n: type(p) for n, p in planners.items()} == expected
    assert planners["seed"].step_s == SETTINGS["step_s"]
    assert planners["rollout"].config.horizon == SETTINGS["rollout_horizon"]
    assert planners["exact"].max_instructions == SETTINGS["exact_max_instructions"]


def test_unknown_name_is_named():
    with pytest.raises(ValueError, match="unknown planner 'greedy'"):
        make_planner("greedy", SETTINGS)
