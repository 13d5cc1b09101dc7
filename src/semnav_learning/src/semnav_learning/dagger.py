"""DAgger data aggregation (Ross, Gordon & Bagnell 2011) for the direction follower — beyond the
seed, against the compounding error of §4.2 ("the network's output changes its next input").

One round: the learned policy (DirectionFollower) drives single-instruction episodes closed-loop in
sim2d on the TRAINING floors (semnav_learning.episodes.run_episode); at every visited state the
expert's clean command (episodes.ExpertLabeller) is recorded as the label next to the scan the
policy saw. The visited states are written in penguin_base's record format at the control rate
and added to the training set for the next training round.
"""
import json

import numpy as np

from penguin_base.record_format import RecordSequence, Sample, write_records
from semnav_learning.episodes import ExpertLabeller, chain_goals, run_episode
from semnav_learning.demonstrations import world_for_floor
from semnav_learning.evaluation import EvaluationConfig, plan_episodes
from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.route_oracle import RouteOracle
from semnav_learning.training import countings_path

RANGE_DECIMALS = 3   # as the demonstrations: ranges to the millimetre


def route_distances(points, route):
    """Distance [m] of each point (N, 2) to the polyline `route` (M, 2)."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    route = np.asarray(route, dtype=float).reshape(-1, 2)
    if len(route) == 1:
        return np.hypot(*(points - route[0]).T)
    a, b = route[:-1], route[1:]
    ab = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12)
    t = np.clip(np.einsum("nij,ij->ni", points[:, None, :] - a[None], ab) / length2, 0.0, 1.0)
    nearest = a[None] + t[..., None] * ab[None]
    return np.min(np.hypot(*(points[:, None, :] - nearest).transpose(2, 0, 1)), axis=1)


def on_route_steps(path, routes, max_offset):
    """Leading control steps whose pose lies within `max_offset` [m] of one of the expert's
    part routes: the states before the policy left the expert's way (e.g. drove past its corner).
    """
    distance = np.min([route_distances(np.asarray(path)[:, :2], r) for r in routes], axis=0)
    off = np.flatnonzero(distance > max_offset)
    return int(off[0]) if off.size else len(distance)


def visited_states(world, oracle, policy, spec, max_route_offset=None):
    """Run one episode with the expert labelling every visited state -> (RecordSequence,
    EpisodeResult). The sequence holds (expert v, expert ω, ranges seen) per control step.

    max_route_offset [m]: keep only the states before the robot first strays that far from the
    expert's route. Beyond the seed's DAgger: once a recurrent policy has driven past its
    corner, the expert's label (turn back) depends on where the robot is, but the policy's
    memory says it has not reached the corner yet; those labels contradict the instruction
    and teach the network to turn around instead of to count."""
    robot = world.robots[0]
    parts = chain_goals(oracle, spec.start, spec.labels, spec.countings)
    result = run_episode(world, robot.name, policy, spec.start, spec.sentence, parts,
                         labeller=ExpertLabeller(parts), record_scans=True)
    samples = [Sample(float(v), float(w), tuple(np.round(ranges.astype(np.float64),
                                                         RANGE_DECIMALS)))
               for (v, w), ranges in zip(result.expert_commands, result.scans)]
    if max_route_offset is not None and samples:
        keep = on_route_steps(result.path[:len(samples)], [p.route for p in parts],
                              max_route_offset)
        samples = samples[:keep]
    return RecordSequence(spec.labels[-1], samples), result


def collect_round(floors, template, policy, sets, per_class, rng, progress=None,
                  classes=CLASS_IDS, max_route_offset=None, side_share=None):
    """One DAgger round on `floors` (map YAML paths) over `classes` -> ([RecordSequence],
    [EpisodeResult], [counting mode of each sequence]); max_route_offset as in visited_states;
    side_share: the share of each of classes 5-8's episodes counted on one side
    (evaluation.counting_shares; None: as the sentences fall)."""
    worlds = {str(f): world_for_floor(template, f) for f in floors}
    oracles = {floor: RouteOracle(world.grid) for floor, world in worlds.items()}
    specs = plan_episodes(oracles, per_class, sets, rng, EvaluationConfig(side_share=side_share),
                          classes=classes)
    sequences, results, countings = [], [], []
    for spec in specs:
        sequence, result = visited_states(worlds[spec.floor], oracles[spec.floor], policy, spec,
                                          max_route_offset)
        if sequence.samples:
            sequences.append(sequence)
            countings.append(spec.countings[-1])
        results.append(result)
        if progress:
            progress(result)
    return sequences, results, countings


def write_round(path, sequences, countings):
    """The aggregated states of one round as a record file (read back at the control rate), and
    each sequence's counting mode beside it (training.countings_path, where
    training.record_countings reads them)."""
    write_records(path, sequences)
    countings_path(path).write_text(json.dumps({"countings": list(countings)}))
