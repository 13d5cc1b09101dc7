"""The semnav benchmarks as modules (tools.bench_semnav_control, bench_semnav_expert,
bench_semnav_layers): what they measure on, what they print and their errors; timings themselves
are not asserted."""
import re
from collections import Counter

import numpy as np
import pytest

from semnav_learning.tools import bench_semnav_control, bench_semnav_expert, bench_semnav_layers
from semnav_learning.evaluation_run import laser_templates
from semnav_l_floor import write_l_floor
from tamp_resources import resource

ROOT = resource()
RING = ROOT / "maps" / "office_ring.yaml"


def test_expert_bench_on_the_l_floor_is_reproducible(tmp_path):
    write_l_floor(tmp_path)
    first = bench_semnav_expert.bench_floor(tmp_path / "l_floor.yaml", 3, seed=4)
    again = bench_semnav_expert.bench_floor(tmp_path / "l_floor.yaml", 3, seed=4)
    # one corner: straight on and turning round apply from every start; no counted corners
    assert first.per_class[1] == 3 and first.per_class[4] == 3
    assert not set(first.per_class) & {5, 6, 7, 8}
    assert first.ok + len(first.failures) == first.total == len(first.steps)
    assert (again.ok, again.per_class, again.steps) == (first.ok, first.per_class, first.steps)


def test_expert_bench_reports_share_and_failures():
    bench = bench_semnav_expert.FloorBench(ok=3, per_class=Counter({2: 1, 1: 3}),
                                           steps=[100, 300, 200, 400],
                                           failures=[((1.0, 2.0, 0.5), 2, False, 0.21)],
                                           seconds=1.25, demo_ms=[10.0, 20.0, 30.0, 40.0])
    assert bench_semnav_expert.report_lines("f", bench) == [
        "f: 3/4 = 75.0 % reach the goal without touching a wall; 250 commands per demo; "
        "1.2 s; a demo p50 25.0 ms, p99 39.7 ms; per class {1: 3, 2: 1}",
        "  failed: start (1.0, 2.0, 0.5) class 2 reached=False min clearance 0.21 m"]


def test_expert_bench_takes_the_office_floors_not_their_graphs(tmp_path):
    for name in ("office_b.yaml", "office_a.yaml", "office_a.graph.yaml", "household.yaml"):
        (tmp_path / name).write_text("")
    assert [p.name for p in bench_semnav_expert.office_floors(tmp_path)] == ["office_a.yaml",
                                                                             "office_b.yaml"]


def test_layers_bench_scan_and_timing_helpers():
    ranges = bench_semnav_layers.dropout_scan(1081, np.random.default_rng(0))
    assert ranges.shape == (1081,) and np.all(ranges[::50] == 0.0)
    kept = np.delete(ranges, np.arange(0, 1081, 50))
    assert kept.min() >= 0.2 and kept.max() < 8.0
    calls = []
    times = bench_semnav_layers.per_call(lambda: calls.append(1), 7)
    assert len(times) == len(calls) == 7 and np.all(times >= 0.0)
    assert re.fullmatch(r"p50 \d+ µs, p99 \d+ µs", bench_semnav_layers.spread_us(times))
    with pytest.raises(SystemExit):
        bench_semnav_layers.main(argv=["--steps", "3"])        # it has no options


def test_control_bench_scans_repeat_the_corridor():
    templates = laser_templates()
    scans, laser = bench_semnav_control.scans(templates["urg04lx"], RING, 8, "march", places=5)
    assert len(scans) == 8 and laser.beams == 683
    assert scans[5] is scans[0] and scans[7] is scans[2] and scans[4] is not scans[0]


def test_control_bench_worst_case_faces_a_wall_just_ahead():
    wall = bench_semnav_control.blocked_scan(laser_templates(), RING, "urg04lx")
    front = wall[len(wall) // 2 - 2:len(wall) // 2 + 3]
    assert np.median(front) == pytest.approx(bench_semnav_control.WALL_GAP, abs=0.05)


def test_control_bench_untrained_prints_both_lasers(capsys):
    assert bench_semnav_control.main(argv=["--untrained", "--steps", "4"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "model: untrained network (same shape)"
    laser_lines = [line for line in lines if not line.startswith(" ")][1:3]
    assert [line.split(" (")[0] for line in laser_lines] == ["utm30lx", "urg04lx"]
    assert all(re.search(r"beams\): control step p50 [\d.]+ ms, p99 [\d.]+ ms, .* over 4 "
                         r"steps \(budget \d+ ms\)", line) for line in laser_lines)
    assert lines[-2].startswith("Keras model, one step") and lines[-1].startswith("start(")


def test_control_bench_without_a_model_names_untrained(tmp_path):
    with pytest.raises(SystemExit, match=r"bench_semnav_control: .*none.keras not found.*, or "
                                         r"pass --untrained"):
        bench_semnav_control.main(argv=["--model", str(tmp_path / "none.keras")])
