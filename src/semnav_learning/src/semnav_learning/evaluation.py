"""Per-class evaluation on unseen floors (thesis 002 §4.2.1, Table 4.2-1).

`plan_episodes` draws, for every class, N legal simple instructions from starts on the test
floors (each start displaced at random), 80 % of the sentences from the training phrasings and
20 % from held-out phrasings (§4.2.1: 80 of 100 from the basic instruction sets, 20 new
sentences of similar meaning). `evaluate` runs them in sim2d (episodes.run_episode) with a
policy made in each worker process, on one or more cores. `success_table` gives the rows of
Table 4.2-1 (class, tests, successes, rate, and the total).
"""
import json
import math
import multiprocessing
import sys
import time
import zlib
from collections import Counter
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from semnav_learning.demonstrations import world_for_floor
from semnav_learning.episodes import (EpisodeConfig, EpisodeError, ExpertPolicy, chain_applies,
                                   chain_goals, run_episode)
from semnav_learning.floor_structure import floor_structure, sample_corridor_starts
from semantic_nav.instruction_classes import (CLASS_IDS, COUNT_CORNERS, COUNT_SIDE, COUNTING_IDS,
                                              COUNTINGS, END_TURN, STRAIGHT, TURN, get, ids)
from semnav_learning.phrase_sets import sample_sentence
from semnav_learning.route_oracle import (OracleError, RouteOracle, branches_on_side,
                                       counting_matters, goal_branch)


@dataclass
class EvaluationConfig:
    """How episodes are drawn."""

    candidates: int = 240            # at most this many corridor starts sampled per floor [-]
    batch: int = 40                  # starts sampled per floor and round [-]
    min_starts: int = 6              # stop sampling once every class has this many starts [-]
    held_out_fraction: float = 0.2   # §4.2.1: 20 of 100 sentences are new phrasings [-]
    start_offset: float = 0.2        # start displaced up to ± this in x and y [m]
    start_yaw_offset: float = 8.0    # and up to ± this in heading [deg]
    start_clearance: float = 0.4     # displaced start must have this clearance [m]
    max_redraws: int = 50            # displacements tried per episode before skipping [-]
    side_share: float = None         # classes 5-8: this share of each class's episodes counted
    #                                  on one side, the rest over both sides (None: as the
    #                                  phrase sets' sentences fall) [0, 1]


@dataclass
class EpisodeSpec:
    """One evaluation episode: where, which instruction, which phrasing."""

    floor: str               # map_server YAML path
    start: tuple             # (x, y, yaw) displaced start
    labels: tuple            # class per simple instruction
    sentence: str
    held_out: bool           # sentence uses a held-out phrasing
    countings: tuple = ()    # per part: instruction_classes.COUNT_CORNERS (also for parts left
    #                          out) or COUNT_SIDE ("take the second right"), as the oracle counts


@dataclass
class PolicySpec:
    """How a worker process makes its policy: the expert or the learned follower."""

    kind: str = "model"      # "model" | "expert"
    model_path: str = None   # None: the follower's default model
    word_vectors: str = None
    config: object = None     # FollowerConfig, a follower YAML path, or None (defaults)


@dataclass
class EpisodeOutcome:
    """What is kept of one episode (picklable, JSON-friendly)."""

    spec: EpisodeSpec
    success: bool
    reason: str
    duration: float          # [s]
    steps: int
    predicted: list
    path: list = field(default_factory=list)    # [[x, y, yaw], ...]
    step_seconds: float = 0.0                   # wall time per control step [s]


def _displaced(oracle, start, labels, rng, config, countings=()):
    """start moved at random (clear of walls, classes still applicable as `countings` count)
    -> (pose, parts)."""
    for _ in range(config.max_redraws):
        pose = (start[0] + rng.uniform(-config.start_offset, config.start_offset),
                start[1] + rng.uniform(-config.start_offset, config.start_offset),
                start[2] + math.radians(rng.uniform(-config.start_yaw_offset,
                                                    config.start_yaw_offset)))
        if oracle.field.at(pose[0], pose[1]) < config.start_clearance:
            continue
        try:
            return pose, chain_goals(oracle, pose, labels, countings)
        except (EpisodeError, OracleError):
            continue
    return None, None


def applicable_starts(oracles, rng, config, classes=CLASS_IDS):
    """{class: [(floor, start)]} over corridor starts sampled on the floors, in rounds of
    `batch` per floor until every class has `min_starts` (or `candidates` per floor)."""
    pool = {label: [] for label in CLASS_IDS}
    structures = {floor: floor_structure(oracle.field, oracle.config.robot_radius)
                  for floor, oracle in oracles.items()}
    for _ in range(max(1, config.candidates // config.batch)):
        for floor, oracle in oracles.items():
            for start in sample_corridor_starts(oracle, structures[floor], config.batch, rng):
                for label, goal in oracle.goals(start).items():
                    if goal is not None:
                        pool[label].append((floor, start))
        if min(len(pool[label]) for label in classes) >= config.min_starts:
            break
    return pool


def class_census(oracle, starts, same_place=1.5):
    """{class: (starts it applies from, of those: its goal within `same_place` [m] of the
    same side's end turn)} for a floor. Where every third corner is a corridor's end, "turn
    right at the third corner" is learnt as "turn right at the end"."""
    census = {label: [0, 0] for label in CLASS_IDS}
    for start in starts:
        goals = oracle.goals(start)
        for label, goal in goals.items():
            if goal is None:
                continue
            census[label][0] += 1
            end = goals.get(END_TURN.get(label))
            if end is not None and math.dist(goal.pose[:2], end.pose[:2]) < same_place:
                census[label][1] += 1
    return {label: tuple(counts) for label, counts in census.items()}


def plan_episodes(oracles, per_class, sets, rng, config=None, classes=CLASS_IDS):
    """`per_class` single-instruction episodes per class over the floors' starts -> [EpisodeSpec].

    Starts are used in turn (shuffled) so every applicable start is used about equally; a class
    applicable from none of the sampled starts gets no episodes."""
    config = config or EvaluationConfig()
    pool = applicable_starts(oracles, rng, config, classes)
    specs = []
    for label in classes:
        candidates = pool[label]
        if not candidates:      # the table then shows which classes these floors cannot test
            continue
        held = np.zeros(per_class, dtype=bool)
        held[:int(round(config.held_out_fraction * per_class))] = True
        rng.shuffle(held)
        modes = counting_shares(label, per_class, config.side_share, rng)
        starts = {mode: [c for c in candidates if mode != COUNT_SIDE
                         or chain_applies(oracles[c[0]], c[1], (label,), (COUNT_SIDE,))]
                  for mode in dict.fromkeys(modes)}    # in a seeded order
        orders = {mode: rng.permutation(len(pool)) for mode, pool in starts.items()}
        used = dict.fromkeys(starts, 0)
        for i, mode in enumerate(modes):
            if not starts[mode]:
                raise EpisodeError(f"class {label}: no start of the floors has enough branches "
                                   "on its side to count one side")
            floor, start = starts[mode][orders[mode][used[mode] % len(orders[mode])]]
            used[mode] += 1
            countings = () if mode is None else (mode,)
            pose, _ = _displaced(oracles[floor], start, (label,), rng, config, countings)
            if pose is None:
                pose = start
            split = "held_out" if held[i] else "train"
            sentence = applicable_sentence(sets, label, rng, split, oracles[floor], pose, mode)
            specs.append(EpisodeSpec(str(floor), tuple(float(v) for v in pose), (label,),
                                     sentence.text, bool(held[i]), (sentence.counting,)))
    return specs


def counting_shares(label, count, side_share, rng):
    """How each of `count` episodes of class `label` counts: None (as its sentence falls) for
    every class when `side_share` is None or the class counts nothing, else COUNT_SIDE for
    round(side_share * count) of them and COUNT_CORNERS for the rest, in random order."""
    if side_share is None or label not in COUNTING_IDS:
        return [None] * count
    if not 0.0 <= side_share <= 1.0:
        raise ValueError(f"side_share must lie in [0, 1], got {side_share}")
    side = int(round(side_share * count))
    return [COUNTINGS[k] for k in rng.permutation([1] * side + [0] * (count - side))]


def applicable_sentence(sets, label, rng, split, oracle, pose, counting=None, tries=200):
    """A sentence of class `label` (phrase_sets.sample_sentence) whose counting applies at
    `pose`: one that counts the branches on one side ("take the second right") is redrawn
    where that side has too few branches (counting corners applies: the start was drawn so);
    `counting` (COUNT_CORNERS / COUNT_SIDE): redrawn until the sentence counts so."""
    for _ in range(tries):
        sentence = sample_sentence(sets, label, rng, split)
        if counting is not None and sentence.counting != counting:
            continue
        if sentence.counting == COUNT_CORNERS or chain_applies(oracle, pose, (label,),
                                                                 (sentence.counting,)):
            return sentence
    raise EpisodeError(f"class {label}: no {split} sentence"
                       f"{'' if counting is None else ' counting ' + counting} applies at "
                       f"{pose} in {tries} draws")


def plan_chain_episodes(oracles, labels, sentence, count, rng, config=None, per_start=4):
    """Beyond the seed's table: `count` episodes of one chained instruction (e.g. labels (1, 3),
    "go straight to the end, then turn left"), shared evenly by the floors, `per_start`
    displaced starts at each sampled corridor start from which the whole chain is applicable
    -> [EpisodeSpec]."""
    config = config or EvaluationConfig()
    quota = -(-count // len(oracles))
    specs = []
    for floor, oracle in oracles.items():
        structure = floor_structure(oracle.field, oracle.config.robot_radius)
        mine = []
        for _ in range(max(1, config.candidates // config.batch)):
            starts = sample_corridor_starts(oracle, structure, config.batch, rng)
            for start in (s for s in starts if chain_applies(oracle, s, labels)):
                for _ in range(per_start):
                    pose, _ = _displaced(oracle, start, tuple(labels), rng, config)
                    if pose is not None and len(mine) < quota:
                        mine.append(EpisodeSpec(str(floor), tuple(float(v) for v in pose),
                                                tuple(labels), sentence, False))
            if len(mine) >= quota:
                break
        specs += mine
    return specs[:count]


# --- running (one process per core) ------------------------------------------------------
_WORKER = {}


def _init_worker(template, policy_spec, raycast, episode_config, laser_dir):
    # floors already loaded for the same robot and laser stay: a training run evaluates its
    # closed-loop plan in-process after every epoch
    same = _WORKER.get("world_key") == (template, raycast, laser_dir)
    _WORKER.update(template=template, policy_spec=policy_spec, raycast=raycast,
                   episode_config=episode_config, laser_dir=laser_dir, policy=None,
                   world_key=(template, raycast, laser_dir),
                   worlds=_WORKER["worlds"] if same else {})
    torch = sys.modules.get("torch")      # one core per worker: no thread oversubscription
    if torch is not None:                 # (the policy runs on numpy: a spawned worker does not
        torch.set_num_threads(1)          # import torch for it)


def _make_policy(spec):
    if spec.kind == "expert":
        return None
    from semantic_nav.follower import DirectionFollower
    return DirectionFollower.from_files(spec.model_path, spec.word_vectors, spec.config)


def _world(floor):
    if floor not in _WORKER["worlds"]:
        world = world_for_floor(_WORKER["template"], floor, _WORKER["laser_dir"],
                                raycast=_WORKER["raycast"])
        _WORKER["worlds"][floor] = (world, RouteOracle(world.grid))
    return _WORKER["worlds"][floor]


def load_plan(path):
    """Episode specs of a plan file (a JSON list of EpisodeSpec fields), or of the episodes of
    an earlier eval_semnav --json result. ValueError naming the file if it is neither."""
    try:
        data = json.loads(Path(path).read_text())
        entries = [e["spec"] for e in data["episodes"]] if isinstance(data, dict) else data
        return [EpisodeSpec(e["floor"], tuple(e["start"]), tuple(e["labels"]), e["sentence"],
                            bool(e["held_out"]), tuple(e.get("countings", ())))
                for e in entries]
    except (json.JSONDecodeError, KeyError, TypeError) as error:
        raise ValueError(f"{path}: not an evaluation plan ({type(error).__name__}: {error})") \
            from None


def episode_seed(spec):
    """Laser-noise seed of one episode, from what defines it (floor name, start, classes,
    sentence): the same episode sees the same noise in any worker and any order."""
    key = repr((Path(spec.floor).stem, [round(float(v), 6) for v in spec.start],
                list(spec.labels), spec.sentence))
    return zlib.crc32(key.encode())


def run_spec(spec):
    """One episode in this worker -> EpisodeOutcome."""
    world, oracle = _world(spec.floor)
    robot = world.robots[0]
    parts = chain_goals(oracle, spec.start, spec.labels, spec.countings)
    if _WORKER["policy_spec"].kind == "expert":
        policy = ExpertPolicy(parts, lambda: robot.state.pose)
    else:
        if _WORKER["policy"] is None:
            _WORKER["policy"] = _make_policy(_WORKER["policy_spec"])
        policy = _WORKER["policy"]
    began = time.perf_counter()
    result = run_episode(world, robot.name, policy, spec.start, spec.sentence, parts,
                         config=_WORKER["episode_config"], noise_seed=episode_seed(spec))
    seconds = (time.perf_counter() - began) / max(result.steps, 1)
    path = np.round(result.path, 3).tolist()
    return EpisodeOutcome(spec, result.success, result.reason, round(result.duration, 2),
                          result.steps, [int(c) for c in result.predicted], path, seconds)


def evaluate(specs, template, policy_spec, workers=1, raycast="table", episode_config=None,
             progress=None, laser_dir=None, start_method="fork"):
    """Run every spec -> [EpisodeOutcome] in spec order; `progress(n)` after each episode.
    `start_method` of the worker processes: "fork" shares the floors already loaded here;
    "spawn" starts clean processes, for a caller whose own threads (torch's) a fork would
    copy in a held state."""
    args = (str(template), policy_spec, raycast, episode_config or EpisodeConfig(), laser_dir)
    if workers <= 1:
        _init_worker(*args)
        outcomes = []
        for spec in specs:
            outcomes.append(run_spec(spec))
            if progress:
                progress(1)
        return outcomes
    context = multiprocessing.get_context(start_method)
    with context.Pool(workers, initializer=_init_worker, initargs=args) as pool:
        outcomes = []
        for outcome in pool.imap(run_spec, specs, chunksize=4):
            outcomes.append(outcome)
            if progress:
                progress(1)
    return outcomes


# --- results -------------------------------------------------------------------------------
def success_table(outcomes):
    """Table 4.2-1 rows: [(class, tests, successes, rate)] and the total row."""
    tests, wins = Counter(), Counter()
    for outcome in outcomes:
        label = outcome.spec.labels[-1]
        tests[label] += 1
        wins[label] += bool(outcome.success)
    rows = [(label, tests[label], wins[label], wins[label] / tests[label])
            for label in sorted(tests)]
    total = sum(tests.values())
    return rows, ("Total", total, sum(wins.values()), sum(wins.values()) / max(total, 1))


def format_table(rows, total, title=""):
    """Markdown table in the layout of Table 4.2-1."""
    lines = [title] if title else []
    lines += ["| Instruction Number | Testing Times | Success Times | Success Rate |",
              "|---:|---:|---:|---:|"]
    for label, tests, wins, rate in rows + [total]:
        lines.append(f"| {label} | {tests} | {wins} | {rate:.4f} |")
    return "\n".join(lines)


def mode_breakdown(outcomes):
    """Classes 5-8 (single-part episodes) per counting mode -> {class: {mode: {"tests",
    "successes"}}}, classes and modes in order (what "both counting modes" is judged on)."""
    table = {}
    for outcome in sorted(outcomes, key=lambda o: o.spec.labels):
        labels = outcome.spec.labels
        if len(labels) != 1 or labels[0] not in COUNTING_IDS:
            continue
        mode = (outcome.spec.countings or (COUNT_CORNERS,))[0]
        cell = table.setdefault(labels[0], {}).setdefault(mode, {"tests": 0, "successes": 0})
        cell["tests"] += 1
        cell["successes"] += bool(outcome.success)
    return {label: dict(sorted(modes.items())) for label, modes in table.items()}


def counting_breakdown(outcomes, oracles):
    """Classes 5-8 (single-part episodes) split by whether counting the corners over both sides
    matters from their start (route_oracle.counting_matters) -> {"matters" / "alike":
    {"tests", "successes"}}: a policy that counts one side only fails the first group.
    Episodes whose sentence counts one side ("take the second right") are left out."""
    groups = {}
    for outcome in outcomes:
        labels = outcome.spec.labels
        if len(labels) != 1 or labels[0] not in COUNTING_IDS:
            continue
        label = labels[0]
        if outcome.spec.countings[:1] == (COUNT_SIDE,):
            continue               # counted on one side: the other side does not count
        walk = oracles[outcome.spec.floor].walk(outcome.spec.start)
        group = groups.setdefault("matters" if counting_matters(walk, label) else "alike",
                                  {"tests": 0, "successes": 0})
        group["tests"] += 1
        group["successes"] += bool(outcome.success)
    return groups


def failure_place(walk, label, end, margin=0.3, counting=COUNT_CORNERS):
    """Where a failed single instruction of class 1, 2, 3 or 5-10 ended, against the oracle's
    walk from its start -> "through the wall ahead" when the final position `end` (x, y) lies
    beyond the wall that ends the walked corridor (the robot went through a door there); for
    class 1 "off to one side" or "short of the corridor's end"; for a turn "opening K of N on
    its side (goal: M)" when it lies in the K-th of the N openings on the turning side (the
    goal's is the M-th), "other side", "short of the goal's corner" or "past the goal's corner"
    (still in the walked corridor).

    Beyond the seed: tells a policy that counts the openings of one side only (it reaches
    opening M' != M) from one that misses or overshoots the turn, and both from one that takes
    a door at the corridor's end for more corridor. `counting`: the episode's (goal_branch)."""
    along, lateral = walk.frame(end)
    if along > walk.front + margin:
        return "through the wall ahead"
    cls = get(label)
    if cls.motion == STRAIGHT:
        return "off to one side" if abs(lateral) > walk.half_width + margin else \
            "short of the corridor's end"
    side = cls.side
    branches = branches_on_side(walk, side)
    goal = goal_branch(walk, label, counting)
    if abs(lateral) > walk.half_width + margin:
        if (lateral > 0) != (side == "left"):
            return "other side"
        inside = [k for k, b in enumerate(branches, 1)
                  if b.start - margin <= along <= b.end + margin]
        where = inside[0] if inside else "?"
        goal_index = next((k for k, b in enumerate(branches, 1) if b is goal), "?")
        return f"opening {where} of {len(branches)} on its side (goal: {goal_index})"
    if goal is None:
        return "in the corridor"
    return "short of the goal's corner" if along < goal.start else "past the goal's corner"


PLACED_IDS = ids(motion=STRAIGHT) + ids(motion=TURN)   # the classes failure_place places


def failure_places(outcomes, oracles):
    """failure_place of every failed single-part episode of class 1, 2, 3 or 5-10 ->
    {class: {place: count}}."""
    places = {}
    for outcome in outcomes:
        labels = outcome.spec.labels
        if outcome.success or len(labels) != 1 or labels[0] not in PLACED_IDS \
                or not outcome.path:
            continue
        walk = oracles[outcome.spec.floor].walk(outcome.spec.start)
        countings = outcome.spec.countings or (COUNT_CORNERS,)
        place = failure_place(walk, labels[0], outcome.path[-1][:2], counting=countings[0])
        counts = places.setdefault(labels[0], {})
        counts[place] = counts.get(place, 0) + 1
    return dict(sorted(places.items()))


def mcnemar_exact(only_first, only_second):
    """Exact two-sided McNemar test on paired episodes: the discordant counts (episodes only
    the first / only the second policy reached) -> p, twice the binomial(n, 1/2) tail of the
    smaller count, at most 1 (beyond the seed: two models on the same plan).

    The tail is `scipy.stats.binomtest` (Fagerland, Lydersen & Laake, "The McNemar test for
    binary matched-pairs data", BMC Med. Res. Methodol. 13:91, 2013), which stays finite for
    any number of discordant pairs."""
    # imported here: scipy.stats takes most of the import time of this module, which every
    # spawned worker process of `evaluate` pays before its first episode
    from scipy.stats import binomtest
    n = only_first + only_second
    if n == 0:
        return 1.0
    return float(binomtest(only_first, n, 0.5, alternative="two-sided").pvalue)


def paired_comparison(first, second):
    """Two result lists of the same plan (episode records with "spec" and "success", e.g. the
    "episodes" of two eval_semnav --json files) -> {"first", "second", "only_first",
    "only_second", "p"} overall and per class ("by_class"). ValueError naming the first
    episode whose spec differs."""
    if len(first) != len(second):
        raise ValueError(f"the results have {len(first)} and {len(second)} episodes: not the "
                         f"same plan")
    for index, (a, b) in enumerate(zip(first, second)):
        if a["spec"] != b["spec"]:
            raise ValueError(f"episode {index} differs: {a['spec']} vs {b['spec']}")

    def compare(pairs):
        only_first = sum(1 for a, b in pairs if a["success"] and not b["success"])
        only_second = sum(1 for a, b in pairs if b["success"] and not a["success"])
        return {"first": sum(bool(a["success"]) for a, _ in pairs),
                "second": sum(bool(b["success"]) for _, b in pairs), "only_first": only_first,
                "only_second": only_second, "p": mcnemar_exact(only_first, only_second)}
    pairs = list(zip(first, second))
    labels = sorted({a["spec"]["labels"][-1] for a in first})
    return {**compare(pairs), "by_class": {
        label: compare([(a, b) for a, b in pairs if a["spec"]["labels"][-1] == label])
        for label in labels}}


def breakdown(outcomes):
    """Success by phrasing (train / held-out), failure reasons, class predictions."""
    by_split = {}
    for held in (False, True):
        chosen = [o for o in outcomes if o.spec.held_out == held]
        if chosen:
            by_split["held_out" if held else "train"] = {
                "tests": len(chosen), "successes": sum(o.success for o in chosen)}
    reasons = Counter(o.reason.split(":")[0] for o in outcomes)
    predicted = [o for o in outcomes if o.predicted]
    correct = sum(list(o.predicted) == list(o.spec.labels) for o in predicted)
    held = [o for o in predicted if o.spec.held_out]
    return {"by_phrasing": by_split, "reasons": dict(reasons),
            "class_prediction_accuracy": correct / max(len(predicted), 1),
            "held_out_class_prediction_accuracy":
                sum(list(o.predicted) == list(o.spec.labels) for o in held) / max(len(held), 1)}


def outcome_record(outcome, keep_path=False):
    """JSON-friendly dict of one outcome."""
    record = asdict(outcome)
    if not keep_path:
        record.pop("path")
    return record
