"""Tables 5-7 / 5-9 of the thesis, and the settings sweep that scores runs against them."""
import pytest

from task_planner.tools import settings_fit as fit
from task_planner.tools import thesis_comparison as thesis
from task_planner.tools.benchmark import BenchConfig
from task_planner.graph import load_graph
from task_planner.reward import load_priorities
from tamp_resources import resource


def thesis_shape():
    """The thesis's own figures as a shape: every check must find them exact."""
    return {n: {"ratio": thesis.thesis_ratio(n), "similarity": thesis.TABLE_5_9_SIMILARITY[n],
                "completion_s": thesis.TABLE_5_7_TIME_S[n]} for n in thesis.REWARD_ORDER}


def test_the_thesis_figures_satisfy_their_own_orders_with_zero_gaps():
    shape = thesis_shape()
    assert thesis.thesis_ratio("Ours") == pytest.approx(11.87 / 13.18)   # 0.901
    assert thesis.thesis_ratio("SF") == pytest.approx(0.7428, abs=1e-4)
    assert thesis.reward_order_holds(shape) and thesis.similarity_order_holds(shape)
    assert thesis.reward_gap(shape) == thesis.similarity_gap(shape) == thesis.time_gap(shape) == 0


def test_orders_ignore_fcfs_against_rand_but_not_ours_against_sf():
    shape = thesis_shape()
    shape["FCFS"], shape["Rand"] = shape["Rand"], shape["FCFS"]
    assert thesis.reward_order_holds(shape) and thesis.similarity_order_holds(shape)
    shape["Ours"], shape["SF"] = shape["SF"], shape["Ours"]
    assert not thesis.reward_order_holds(shape)
    assert not thesis.similarity_order_holds(shape)
    shape = thesis_shape()
    shape["PF"] = dict(shape["PF"], ratio=0.3, similarity=40.0)  # below FCFS and Rand
    assert not thesis.reward_order_holds(shape) and not thesis.similarity_order_holds(shape)


def test_static_shape_is_a_ratio_of_means_and_skips_planners_run_on_a_few_sets():
    rows = [{"Exact": {"reward": 10.0, "similarity": 0, "completion_s": 100.0},
             "SF": {"reward": 9.0, "similarity": 4, "completion_s": 80.0},
             "Opt": {"reward": 10.0, "similarity": 0, "completion_s": 100.0}},
            {"Exact": {"reward": 30.0, "similarity": 0, "completion_s": 50.0},
             "SF": {"reward": 15.0, "similarity": 8, "completion_s": 60.0}}]
    shape = thesis.static_shape(rows, "Exact")
    assert shape["SF"] == {"ratio": 24.0 / 40.0, "similarity": 6.0, "completion_s": 70.0}
    assert "Opt" not in shape   # a mean ratio of 0.9 / 0.5 would have been 0.7


def test_time_gap_is_relative():
    shape = thesis_shape()
    for name in thesis.TIMED:
        shape[name] = dict(shape[name], completion_s=2 * thesis.TABLE_5_7_TIME_S[name])
    assert thesis.time_gap(shape) == pytest.approx(1.0)


def test_sweep_scores_both_readings_per_graph_and_plots(tmp_path):
    graph = load_graph(resource("maps", "household.graph.yaml"), cache_dir=tmp_path)
    priorities = list(load_priorities(resource("config", "priorities.yaml")).values())
    lines = []
    results = fit.sweep({"household": graph}, priorities, BenchConfig(static_trials=3),
                        speeds=(0.5, 0.25), durations=((1, 10),), report=lines.append)
    assert [(r.speed_mps, r.durations_s) for r in results] == [(0.5, (1, 10)), (0.25, (1, 10))]
    assert len(lines) == 2 and "ETA" in lines[-1]
    for r in results:
        assert set(r.shapes) == set(fit.readings())
        for shape in r.shapes.values():
            assert set(shape) == set(thesis.REWARD_ORDER)
            assert all(0 < shape[n]["ratio"] <= 1 + 1e-12 for n in shape)
    # a slower robot travels longer: every planner finishes later
    slow, fast = results[1].shapes[fit.readings()[0]], results[0].shapes[fit.readings()[0]]
    assert all(slow[n]["completion_s"] > fast[n]["completion_s"] for n in thesis.TIMED)
    summary = fit.summary_rows(results, fit.readings()[1])
    assert summary[0][:2] == ["household", 2] and len(summary[0]) == len(fit.summary_header())
    assert len(fit.fit_rows(results, fit.readings()[0])[0]) == len(fit.fit_header())
    fit.plot(results, tmp_path / "fit.png")
    assert (tmp_path / "fit.png").stat().st_size > 10_000
