"""Evaluation: episode plans (classes, 80/20 phrasings), running them, Table 4.2-1."""
import json
import math
from dataclasses import asdict, astuple
from fractions import Fraction

import numpy as np
import pytest

import semnav_learning.evaluation as evaluation
from semnav_learning.evaluation import (EpisodeOutcome, EpisodeSpec, EvaluationConfig, PolicySpec,
                                     breakdown, class_census, counting_breakdown, episode_seed,
                                     mode_breakdown,
                                     evaluate, failure_place, failure_places, format_table,
                                     load_plan, mcnemar_exact, paired_comparison,
                                     plan_chain_episodes,
                                     plan_episodes, success_table)
from floorplan.occupancy_map import load_map
from semnav_learning.episodes import chain_goals
from semnav_learning.phrase_sets import load_phrase_sets
from semnav_learning.route_oracle import RouteOracle, branches_on_side
from semnav_l_floor import write_l_floor
from tamp_resources import resource

ROOT = resource()


@pytest.fixture(scope="module")
def l_floor(tmp_path_factory):
    """A 1.8 m corridor running east 10 m into an L corner that turns north for 6 m."""
    folder = tmp_path_factory.mktemp("eval")
    grid = write_l_floor(folder)
    return folder, {str(folder / "l_floor.yaml"): RouteOracle(grid)}


@pytest.fixture(scope="module")
def sets():
    return load_phrase_sets(ROOT / "config" / "semnav_phrases.yaml")


@pytest.fixture(scope="module")
def plan(l_floor, sets):
    """10 episodes per applicable class of the L floor."""
    _, oracles = l_floor
    config = EvaluationConfig(candidates=40, batch=20, min_starts=2)
    return plan_episodes(oracles, 10, sets, np.random.default_rng(0), config)


def test_plan_has_n_per_applicable_class_and_a_fifth_held_out(l_floor, plan):
    _, oracles = l_floor
    specs = plan
    per_class = {}
    for spec in specs:
        per_class.setdefault(spec.labels[0], []).append(spec)
    # an L corridor: straight on (1), the corner's branch turning one way (2 or 3), back (4),
    # and the end turn of the same side (9 or 10); never a second or third corner
    assert set(per_class) <= {1, 2, 3, 4, 9, 10} and {1, 4} <= set(per_class)
    assert not set(per_class) & {5, 6, 7, 8}
    for specs_of_class in per_class.values():
        assert len(specs_of_class) == 10
        assert sum(s.held_out for s in specs_of_class) == 2     # §4.2.1: 20 of 100
    oracle = next(iter(oracles.values()))
    assert all(oracle.field.at(*s.start[:2]) >= 0.4 for s in specs)


def test_plan_of_chosen_classes_only(l_floor, sets):
    """DAgger rounds on the classes a model gets wrong (dagger_semnav --classes)."""
    _, oracles = l_floor
    config = EvaluationConfig(candidates=40, batch=20, min_starts=2)
    specs = plan_episodes(oracles, 5, sets, np.random.default_rng(1), config, classes=(4, 1))
    assert sorted(s.labels[0] for s in specs) == [1] * 5 + [4] * 5


def test_a_side_share_splits_the_counting_classes_between_both_counts(sets):
    """--side-share 0.5 on office_comb: classes 5 and 7 get 4 episodes counted on their side
    ("take the second right", from starts where that side has the branches) and 4 over both
    sides; a class that counts nothing is drawn as before."""
    from semantic_nav.instruction_classes import COUNT_SIDE
    floor = str(ROOT / "maps" / "office_comb.yaml")
    oracles = {floor: RouteOracle(load_map(floor))}
    config = EvaluationConfig(candidates=80, batch=40, side_share=0.5)
    specs = plan_episodes(oracles, 8, sets, np.random.default_rng(2), config, classes=(1, 5, 7))
    for label in (5, 7):
        modes = [s.countings for s in specs if s.labels == (label,)]
        assert sorted(modes) == [("corners",)] * 4 + [("side",)] * 4
    for spec in specs:
        if spec.countings == (COUNT_SIDE,):
            chain_goals(oracles[floor], spec.start, spec.labels, spec.countings)  # applies
    assert len([s for s in specs if s.labels == (1,)]) == 8
    with pytest.raises(ValueError, match="side_share must lie in"):
        plan_episodes(oracles, 2, sets, np.random.default_rng(2),
                      EvaluationConfig(candidates=40, batch=40, side_share=1.5), classes=(5,))


def test_census_finds_the_l_corner_is_the_corridors_end(l_floor):
    """The L floor's only corner is its east end: from starts heading east, "turn left" (3)
    goes where "go straight to the end and turn left" (10) does; nothing has a second corner."""
    _, oracles = l_floor
    oracle = next(iter(oracles.values()))
    starts = [(1.0, 1.0, 0.0), (3.0, 0.9, 0.0), (1.0, 1.0, math.pi)]
    census = class_census(oracle, starts)
    assert census[3] == (2, 2) and census[10][0] == 2
    assert census[1][0] == 2 and census[4][0] == 3
    assert all(census[label] == (0, 0) for label in (5, 6, 7, 8))


def test_chain_plan_takes_starts_where_the_whole_chain_applies(l_floor):
    """The L corridor turns left (north) at its east end: "go straight to the end, then turn
    left" (1, 3) applies from starts facing east, "... then turn right" (1, 2) from starts in
    the north leg facing south (right of south is west, back into the east-west leg)."""
    _, oracles = l_floor
    config = EvaluationConfig(candidates=40, batch=20)
    rng = np.random.default_rng(0)
    sentence = "go straight to the end, then turn left"
    specs = plan_chain_episodes(oracles, (1, 3), sentence, 12, rng, config)
    assert len(specs) == 12
    assert all(s.labels == (1, 3) and s.sentence == sentence and not s.held_out for s in specs)
    assert all(abs(np.cos(s.start[2]) - 1.0) < 0.1 for s in specs)          # heading east
    oracle = next(iter(oracles.values()))
    for spec in specs:
        assert chain_goals(oracle, spec.start, spec.labels)[-1].goal.pose[1] > 2.0  # in the branch
    right = plan_chain_episodes(oracles, (1, 2), "then turn right", 12, rng, config)
    assert len(right) == 12
    assert all(abs(np.sin(s.start[2]) + 1.0) < 0.1 for s in right)         # heading south
    for spec in right:
        assert chain_goals(oracle, spec.start, spec.labels)[-1].goal.pose[1] < 2.0


def test_expert_episodes_in_a_worker_process(l_floor):
    folder, oracles = l_floor
    floor = next(iter(oracles))
    specs = [EpisodeSpec(floor, (5.0, 1.0, 0.0), (1,), "go straight to the end", False),
             EpisodeSpec(floor, (1.2, 0.9, 0.05), (4,), "turn around", True)]
    outcomes = evaluate(specs, folder / "world.yaml", PolicySpec(kind="expert"), workers=2,
                        raycast="march", laser_dir=ROOT / "config" / "lasers")
    assert [o.success for o in outcomes] == [True, True]
    assert [o.spec.labels for o in outcomes] == [(1,), (4,)]
    assert outcomes[0].path[-1][0] == pytest.approx(8.9, abs=0.2)
    rows, total = success_table(outcomes)
    assert rows == [(1, 1, 1, 1.0), (4, 1, 1, 1.0)] and total == ("Total", 2, 2, 1.0)


MODEL_RUN = dict(raycast="march", laser_dir=ROOT / "config" / "lasers")


@pytest.fixture(scope="module")
def model_episodes(l_floor):
    """The default model's episodes a, b, a in this process: "go straight to the end" from
    3.4 m before the corridor's end wall, "turn around" (a held-out phrasing), then a again."""
    folder, oracles = l_floor
    floor = next(iter(oracles))
    a = EpisodeSpec(floor, (6.5, 1.0, 0.0), (1,), "go straight to the end", False)
    b = EpisodeSpec(floor, (1.5, 0.8, 0.1), (4,), "turn around", True)
    specs = [a, b, a]
    return specs, evaluate(specs, folder / "world.yaml", PolicySpec(), workers=1, **MODEL_RUN)


def test_an_episode_sees_the_same_laser_noise_whatever_ran_before(model_episodes):
    """Each episode reseeds the laser from its own spec (episode_seed), so a model's episode
    drives the same path first in a worker or after another episode."""
    (a, b, _), outcomes = model_episodes
    assert episode_seed(a) == episode_seed(EpisodeSpec(*astuple(a))) != episode_seed(b)
    assert outcomes[0].steps > 10 and outcomes[1].steps > 10
    assert outcomes[0].path == outcomes[2].path and outcomes[0].reason == outcomes[2].reason
    assert outcomes[0].path != outcomes[1].path


def test_spawned_workers_drive_what_this_process_drives(l_floor, model_episodes):
    """The trainer's closed-loop monitor runs its episodes in spawned workers: the same
    outcomes, in spec order, as in-process."""
    folder, _ = l_floor
    specs, here = model_episodes
    spawned = evaluate(specs, folder / "world.yaml", PolicySpec(), workers=2,
                       start_method="spawn", **MODEL_RUN)
    assert [o.spec for o in spawned] == specs
    assert [(o.success, o.reason, o.path) for o in spawned] == \
        [(o.success, o.reason, o.path) for o in here]


def test_floors_load_once_for_every_evaluate_call_in_a_process(l_floor, monkeypatch):
    """A training run drives the closed-loop plan after every epoch: the floor's world (and its
    range table) is built once, not once per call."""
    folder, oracles = l_floor
    floor = next(iter(oracles))
    built = []

    def counting(*args, **kwargs):
        built.append(args[1])
        return world_for_floor(*args, **kwargs)

    world_for_floor = evaluation.world_for_floor
    monkeypatch.setattr(evaluation, "world_for_floor", counting)
    monkeypatch.setattr(evaluation, "_WORKER", {})
    lasers = ROOT / "config" / "lasers"
    spec = EpisodeSpec(floor, (1.2, 0.9, 0.05), (4,), "turn around", False)
    for _ in range(2):
        outcome, = evaluate([spec], folder / "world.yaml", PolicySpec(kind="expert"), workers=1,
                            raycast="march", laser_dir=lasers)
        assert outcome.success
    assert built == [floor]
    evaluate([spec], folder / "world.yaml", PolicySpec(kind="expert"), workers=1,
             raycast="table", laser_dir=lasers)          # another laser model: a new world
    assert built == [floor, floor]


def test_plan_file_round_trip_and_a_bad_plan_is_named(plan, tmp_path):
    specs = plan
    assert any(s.held_out for s in specs) and not all(s.held_out for s in specs)
    path = tmp_path / "plan.json"
    path.write_text(json.dumps([asdict(s) for s in specs]))
    assert load_plan(path) == specs
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps([{"floor": "x.yaml"}]))
    with pytest.raises(ValueError, match="bad.json: not an evaluation plan"):
        load_plan(bad)


def test_table_in_the_layout_of_table_4_2_1():
    # the seed's own rows for classes 7 and 8 (Table 4.2-1)
    outcomes = []
    for label, tests, wins in ((7, 76, 17), (8, 62, 14)):
        spec = EpisodeSpec("f", (0, 0, 0), (label,), "s", False)
        outcomes += [EpisodeOutcome(spec, k < wins, "reached" if k < wins else "collision", 1.0,
                                    10, [label]) for k in range(tests)]
    rows, total = success_table(outcomes)
    text = format_table(rows, total)
    assert "| 7 | 76 | 17 | 0.2237 |" in text and "| 8 | 62 | 14 | 0.2258 |" in text
    assert "| Total | 138 | 31 | 0.2246 |" in text
    extra = breakdown(outcomes)
    assert extra["reasons"] == {"reached": 31, "collision": 107}
    assert extra["class_prediction_accuracy"] == 1.0


def test_counting_breakdown_splits_classes_5_to_8_by_the_other_side():
    from floorplan.occupancy_map import load_map
    floor = str(ROOT / "maps" / "office_comb.yaml")
    oracles = {floor: RouteOracle(load_map(floor))}
    # from the spine's south end corners on the other side count for 5, 7, 8; from the west
    # corridor (4, 11) northwards class 5 counts alike; classes 1-4 and chains are left out
    spine, west = (18.0, 5.0, math.pi / 2), (4.0, 11.0, math.pi / 2)
    cases = [(spine, (7,), True), (spine, (8,), False), (spine, (5,), False),
             (west, (5,), True), (west, (5,), True), (spine, (1,), True), (spine, (1, 3), True)]
    outcomes = [EpisodeOutcome(EpisodeSpec(floor, start, labels, "s", False), ok, "r", 1.0, 1,
                               list(labels)) for start, labels, ok in cases]
    assert counting_breakdown(outcomes, oracles) == {
        "matters": {"tests": 3, "successes": 1}, "alike": {"tests": 2, "successes": 2}}


def test_mode_breakdown_counts_each_counting_class_per_mode():
    start = (0.0, 0.0, 0.0)
    cases = [((5,), ("side",), True), ((5,), ("side",), False), ((5,), (), True),
             ((8,), ("corners",), False), ((1,), (), True), ((5, 3), ("side",), True)]
    outcomes = [EpisodeOutcome(EpisodeSpec("f", start, labels, "s", False, countings), ok, "r",
                               1.0, 1, list(labels)) for labels, countings, ok in cases]
    assert mode_breakdown(outcomes) == {      # no counting given: corners; chains left out
        5: {"corners": {"tests": 1, "successes": 1}, "side": {"tests": 2, "successes": 1}},
        8: {"corners": {"tests": 1, "successes": 0}}}


def test_failure_places_tell_one_side_counting_from_overshooting():
    from floorplan.occupancy_map import load_map
    floor = str(ROOT / "maps" / "office_comb.yaml")
    oracles = {floor: RouteOracle(load_map(floor))}
    # office_comb's spine from its south end, facing north: west openings at y = 10, 18, 24,
    # east ones at y = 14, 18, 27. The third corner is the crossroad y = 18: the second opening
    # on either side; counting one side only reaches y = 27 (east) or y = 24 (west).
    spine = (18.0, 4.0, math.pi / 2)
    walk = oracles[floor].walk(spine)
    assert failure_place(walk, 7, (20.5, 27.0)) == "opening 3 of 3 on its side (goal: 2)"
    assert failure_place(walk, 8, (15.5, 24.0)) == "opening 3 of 3 on its side (goal: 2)"
    assert failure_place(walk, 7, (15.5, 18.0)) == "other side"
    assert failure_place(walk, 7, (18.0, 12.0)) == "short of the goal's corner"
    assert failure_place(walk, 7, (18.2, 22.0)) == "past the goal's corner"
    assert failure_place(walk, 2, (20.5, 18.0)) == "opening 2 of 3 on its side (goal: 1)"
    ends = [((20.5, 27.0), 7, False), ((20.5, 27.2), 7, False), ((18.0, 22.0), 7, False),
            ((20.5, 18.0), 7, True), ((18.0, 25.0), 1, False), ((15.5, 24.0), 8, False)]
    outcomes = [EpisodeOutcome(EpisodeSpec(floor, spine, (label,), "s", False), ok, "r", 1.0, 1,
                               [label], [[18.0, 4.0, 1.57], [x, y, 0.0]])
                for (x, y), label, ok in ends]
    assert failure_places(outcomes, oracles) == {
        1: {"short of the corridor's end": 1},
        7: {"opening 3 of 3 on its side (goal: 2)": 2, "past the goal's corner": 1},
        8: {"opening 3 of 3 on its side (goal: 2)": 1}}


def test_failure_place_tells_a_door_at_the_corridor_end_from_a_short_stop():
    from floorplan.occupancy_map import load_map
    ring = RouteOracle(load_map(ROOT / "maps" / "office_ring.yaml"))
    # heading south down office_ring's x = 15 corridor: the walk ends at the T's far wall
    # (y = 4.1), which has a 1.0 m door (x 14.5-15.5) into the office below
    walk = ring.walk((14.8, 9.5, -1.5))
    assert walk.front == pytest.approx(9.5 - 4.1, abs=0.1)
    assert failure_place(walk, 1, (15.1, 2.9)) == "through the wall ahead"
    assert failure_place(walk, 9, (13.5, 2.5)) == "through the wall ahead"
    assert failure_place(walk, 1, (15.0, 6.5)) == "short of the corridor's end"
    assert failure_place(walk, 1, (17.0, 5.0)) == "off to one side"
    assert failure_place(walk, 10, (15.0, 4.8)) == "past the goal's corner"


def test_mcnemar_exact_against_the_binomial_tail_by_hand():
    assert mcnemar_exact(0, 5) == pytest.approx(2 / 32)             # 2 · (1/2)^5
    assert mcnemar_exact(9, 1) == pytest.approx(2 * (1 + 10) / 1024)  # 2 (C(10,0) + C(10,1)) / 2^10
    assert mcnemar_exact(3, 3) == 1.0                               # 2 · 42/64 > 1: capped
    assert mcnemar_exact(0, 0) == 1.0


def _mcnemar_by_fractions(only_first, only_second):
    """Independent exact reference: 2 · sum_{i<=k} C(n, i) / 2^n in rationals, capped at 1
    (C(n, i) by the exact recurrence C(n, i) = C(n, i - 1) (n - i + 1) / i)."""
    n, k = only_first + only_second, min(only_first, only_second)
    term = tail = 1
    for i in range(1, k + 1):
        term = term * (n - i + 1) // i
        tail += term
    return float(min(Fraction(1), 2 * Fraction(tail, 2 ** n)))


@pytest.mark.parametrize("only_first, only_second", [
    (0, 1), (1, 0), (2, 7), (7, 2), (4, 6), (5, 5), (13, 30), (100, 140), (0, 200), (499, 524),
    (300, 723)])
def test_mcnemar_exact_matches_exact_fractions_below_1024_pairs(only_first, only_second):
    assert mcnemar_exact(only_first, only_second) == \
        pytest.approx(_mcnemar_by_fractions(only_first, only_second), rel=1e-12, abs=1e-300)


@pytest.mark.parametrize("only_first, only_second", [(500, 524), (0, 1024), (2400, 2600),
                                                     (2500, 2500), (5000, 0)])
def test_mcnemar_exact_gives_a_p_value_from_1024_pairs_on(only_first, only_second):
    p = mcnemar_exact(only_first, only_second)   # 2.0 ** 1024 overflows a float
    assert isinstance(p, float) and 0.0 <= p <= 1.0
    assert p == pytest.approx(_mcnemar_by_fractions(only_first, only_second), rel=1e-9,
                              abs=1e-300)


def test_mcnemar_exact_at_5000_pairs_matches_the_normal_approximation():
    # 2400 vs 2600 of 5000: z = (2400 + 0.5 - 2500) / sqrt(5000/4) = -2.814; 2·Φ(z) = 0.00489
    z = (2400 + 0.5 - 2500) / math.sqrt(5000 / 4)
    assert mcnemar_exact(2400, 2600) == pytest.approx(math.erfc(-z / math.sqrt(2)), rel=0.02)


def test_paired_comparison_counts_discordant_episodes_per_class():
    def episode(label, index, success):
        return {"spec": {"labels": [label], "start": [index, 0, 0]}, "success": success}
    first = [episode(7, 0, True), episode(7, 1, False), episode(7, 2, False), episode(2, 3, True)]
    second = [episode(7, 0, True), episode(7, 1, True), episode(7, 2, True), episode(2, 3, False)]
    result = paired_comparison(first, second)
    assert (result["first"], result["second"], result["only_first"], result["only_second"]) == \
        (2, 3, 1, 2)
    assert result["p"] == pytest.approx(1.0)
    assert result["by_class"][7] == {"first": 1, "second": 3, "only_first": 0, "only_second": 2,
                                     "p": pytest.approx(0.5)}
    with pytest.raises(ValueError, match="episode 1 differs"):
        paired_comparison(first, [first[0], episode(7, 9, True), *first[2:]])
    with pytest.raises(ValueError, match="4 and 3 episodes"):
        paired_comparison(first, first[:3])


def test_a_plan_counts_one_side_where_its_sentence_says_so(tmp_path, sets):
    """On the alternating floor the class 5 episodes whose sentence counts the right-hand
    branches ("take the second right") are judged by that count; the others by the corners."""
    from semnav_alternating_floor import alternating_floor_world
    _, oracle = alternating_floor_world(tmp_path)
    floor = str(tmp_path / "alternating.yaml")
    specs = plan_episodes({floor: oracle}, 40, sets, np.random.default_rng(4),
                          EvaluationConfig(), classes=(5,))
    side = [s for s in specs if s.countings == ("side",)]
    corners = [s for s in specs if s.countings == ("corners",)]
    assert side and corners and len(side) + len(corners) == len(specs)
    counted = [p.text.format(dir="right") for p in sets["class_turn_counted"]]
    assert all(any(text in s.sentence for text in counted) for s in side)
    differ = 0
    for spec in side:      # judged at the second right-hand branch of the start's corridor
        goal = chain_goals(oracle, spec.start, spec.labels, spec.countings)[-1].goal
        walk = oracle.walk(spec.start)
        branch = branches_on_side(walk, "right")[1]
        assert math.dist(goal.pose[:2], walk.point(branch.centre)) < walk.half_width + 1.5
        corner_goal = oracle.goal(spec.start, 5, walk)
        differ += corner_goal is None or math.dist(goal.pose[:2], corner_goal.pose[:2]) > 1.0
    assert differ > 0                      # somewhere the two countings part
    old = tmp_path / "old_plan.json"       # a plan written before countings: corners
    old.write_text(json.dumps([{k: v for k, v in asdict(side[0]).items() if k != "countings"}]))
    assert load_plan(old)[0].countings == ()


def test_failure_place_counts_as_the_episode_does(tmp_path):
    """On the alternating floor a robot that ends in the first right-hand branch, asked for
    "the second right", stopped at opening 1 of 2 (goal: 2); asked for "the second corner"
    (the first right-hand branch) it would have been at its goal's opening."""
    from semnav_alternating_floor import START, alternating_floor_world
    _, oracle = alternating_floor_world(tmp_path)
    walk = oracle.walk(START)
    end = (12.0, 3.0)                                   # in the branch at x 11-13 m, south
    assert failure_place(walk, 5, end, counting="side") == "opening 1 of 2 on its side (goal: 2)"
    assert failure_place(walk, 5, end) == "opening 1 of 2 on its side (goal: 1)"
