"""The planner interface and the one registry the executor, the reports and the benchmark use."""

import pytest
import yaml
from planner_factories import make_instruction

from task_planner.tools import benchmark, benchmark_report
from task_planner.baselines import RandomOrder
from task_planner.executor import Executor
from task_planner.planner_api import NODE, STEP, TARGET, kind_of
from task_planner.planner_registry import (BENCH_DYNAMIC, BENCH_SCALING, BENCH_STATIC,
                                           BENCH_STATIC_FEW, EXECUTOR, PLANNERS, PlannerEntry,
                                           PlannerSettings, display_order, entries, make_planner,
                                           planner_names)
from task_planner.problem import Problem
from task_planner.simulate import run_planner
from tamp_resources import resource

SETTINGS = yaml.safe_load(
    (resource("config") / "task_planner.yaml").read_text())


@pytest.fixture
def problem(line_graph):
    instructions = (make_instruction(1, 3, 3.0, 0.94, 2), make_instruction(2, 0, 1.0, 0.90, 1),
                    make_instruction(3, 2, 8.0, 0.98, 5, previous_id=2))
    return Problem(line_graph, instructions, speed_mps=1.0, start_node=1)


@pytest.mark.parametrize("name", list(PLANNERS))
def test_every_planner_is_what_its_entry_says_and_serves_every_instruction(name, problem):
    entry = PLANNERS[name]
    planner = entry.make(SETTINGS)
    assert kind_of(planner) == entry.kind and planner.name == entry.label
    assert callable(getattr(planner, "choose" if entry.kind == TARGET else "decide"))
    schedule = run_planner(problem, planner)
    assert sorted(int(problem.ids[i]) for i, _ in schedule.served) == [1, 2, 3]
    assert entry.description and "\n" not in entry.description


def test_the_executor_names_give_their_planners_with_the_configured_settings():
    assert set(planner_names(EXECUTOR)) == {"seed", "rollout", "exact", "fcfs", "pf", "sf"}
    planners = {name: make_planner(name, SETTINGS, use=EXECUTOR)
                for name in planner_names(EXECUTOR)}
    assert planners["seed"].step_s == SETTINGS["step_s"]
    assert planners["rollout"].config.horizon == SETTINGS["rollout_horizon"]
    assert planners["rollout"].config.priority_first_at_node is \
        SETTINGS["rollout_priority_first_at_node"]
    assert planners["exact"].max_instructions == SETTINGS["exact_max_instructions"]
    assert {kind_of(planners[n]) for n in ("seed", "rollout")} == {NODE}
    assert {kind_of(planners[n]) for n in ("exact", "fcfs", "pf", "sf")} == {TARGET}


def test_unknown_names_and_planners_not_offered_to_the_executor_are_named():
    with pytest.raises(ValueError, match="unknown planner 'greedy' \\(choose one of fcfs, "):
        make_planner("greedy", SETTINGS)
    with pytest.raises(ValueError, match="unknown planner 'opt' for the executor"):
        make_planner("opt", SETTINGS, use=EXECUTOR)
    assert make_planner("opt", SETTINGS).name == "Opt"


def test_a_planner_must_state_its_kind(line_graph, problem):
    class Kindless:
        name = "kindless"

        def reset(self, problem):
            pass

        def decide(self, node, clock, available):
            return "serve", int(available[0])

    with pytest.raises(TypeError, match="Kindless states no planner kind"):
        run_planner(problem, Kindless())
    with pytest.raises(TypeError, match="Kindless states no planner kind"):
        Executor(None, line_graph, Kindless(), None, {})


def test_an_entry_whose_factory_makes_another_kind_is_refused():
    wrong = PlannerEntry("wrong", "Rand", NODE, "baseline", "a target planner registered as node",
                         lambda settings, seed: RandomOrder(seed), frozenset())
    with pytest.raises(TypeError, match="registered as a node planner"):
        wrong.make()


def test_settings_from_a_mapping_keep_defaults_for_missing_keys():
    settings = PlannerSettings.of({"step_s": 2.0, "rollout_horizon": 4})
    assert settings.step_s == 2.0 and settings.rollout.horizon == 4
    assert settings.rollout.candidates == PlannerSettings().rollout.candidates
    assert PlannerSettings.of(settings) is settings


def test_the_benchmark_runs_the_registered_planners_in_registration_order():
    config = benchmark.BenchConfig(seed=2)
    static = benchmark.static_planners(config, trial=5, with_opt=False)
    assert [p.name for p in static] == [e.label for e in entries(BENCH_STATIC)]
    with_opt = benchmark.static_planners(config, trial=5, with_opt=True)
    assert [p.name for p in with_opt] == [e.label for e in entries(BENCH_STATIC,
                                                                    BENCH_STATIC_FEW)]
    assert with_opt[-1].name == "Opt"
    rand = next(p for p in static if isinstance(p, RandomOrder))
    assert rand.seed == 2 * 100003 + 5
    assert {e.name for e in entries(BENCH_SCALING)} < {e.name for e in entries(BENCH_DYNAMIC)}


def test_tables_put_the_offline_optima_first_and_take_their_planners_from_the_registry():
    order = display_order()
    assert sorted(order) == sorted(e.label for e in PLANNERS.values())
    offline = [e.label for e in PLANNERS.values() if e.offline]
    assert order[:len(offline)] == ["Opt", "Exact"]
    assert benchmark_report.LATENCY_NAMES == tuple(
        e.label for e in entries(BENCH_SCALING) if e.kind in (NODE, STEP))
