"""DAgger data aggregation (Ross, Gordon & Bagnell 2011) for the direction follower — beyond the
seed, against the compounding error of §4.2 ("the network's output changes its next input").

One round: the learned policy (DirectionFollower) drives single-instruction episodes closed-loop in
sim2d on the TRAINING floors (semantic_nav.episodes.run_episode); at every visited state the
expert's clean command (episodes.ExpertLabeller) is recorded as the label next to the scan the
policy saw. The visited states are written in penguin_base's record format at the control rate
and added to the training set for the next training round.
"""
import numpy as np

from penguin_base.record_format import RecordSequence, Sample, write_records
from semantic_nav.episodes import ExpertLabeller, chain_goals, run_episode
from semantic_nav.demonstrations import world_for_floor
from semantic_nav.evaluation import plan_episodes
from semantic_nav.phrase_sets import CLASSES
from semantic_nav.route_oracle import RouteOracle

RANGE_DECIMALS = 3   # as the demonstrations: ranges to the millimetre


def visited_states(world, oracle, policy, spec):
    """Run one episode with the expert labelling every visited state -> (RecordSequence,
    EpisodeResult). The sequence holds (expert v, expert ω, ranges seen) per control step."""
    robot = world.robots[0]
    parts = chain_goals(oracle, spec.start, spec.labels)
    result = run_episode(world, robot.name, policy, spec.start, spec.sentence, parts,
                         labeller=ExpertLabeller(parts), record_scans=True)
    samples = [Sample(float(v), float(w), tuple(np.round(ranges.astype(np.float64),
                                                         RANGE_DECIMALS)))
               for (v, w), ranges in zip(result.expert_commands, result.scans)]
    return RecordSequence(spec.labels[-1], samples), result


def collect_round(floors, template, policy, sets, per_class, rng, progress=None,
                  classes=CLASSES):
    """One DAgger round on `floors` (map YAML paths) over `classes` -> ([RecordSequence],
    [EpisodeResult])."""
    worlds = {str(f): world_for_floor(template, f) for f in floors}
    oracles = {floor: RouteOracle(world.grid) for floor, world in worlds.items()}
    specs = plan_episodes(oracles, per_class, sets, rng, classes=classes)
    sequences, results = [], []
    for spec in specs:
        sequence, result = visited_states(worlds[spec.floor], oracles[spec.floor], policy, spec)
        if sequence.samples:
            sequences.append(sequence)
        results.append(result)
        if progress:
            progress(result)
    return sequences, results


def write_round(path, sequences):
    """The aggregated states of one round as a record file (read back at the control rate)."""
    write_records(path, sequences)
