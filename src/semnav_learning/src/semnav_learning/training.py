"""Training data, the validation function and the monitors of thesis 002 §4.1 (no Keras here).

Episodes: one recording sequence (penguin_base record format, Fig. 3.3.1) as preprocessed
canonical scans (N, beams) float32 and clean expert labels (N, 2) = (v [m/s], ω [rad/s]) at the
record rate. Training subsamples them to the control rate with a random phase, appends the robot
standing still at the goal (zero labels) for `hold_steps`, and pairs each with a random sentence of
its class (§3.4), so every epoch sees new (phase, sentence) pairings.
"""
import hashlib
import json
import zipfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from semantic_nav.corner_count import (CornerCountConfig, count_inputs, one_hot_counting,
                                       one_hot_counts, side_ranges)
from semantic_nav.doorways import close_doorways
from semantic_nav.instruction_classes import (CLASS_IDS, COUNT_CORNERS, COUNT_SIDE, COUNTINGS,
                                              MIRRORED_CLASS, SIDE)
from semantic_nav.instruction_layer import sentence_vector
from semantic_nav.laser_layer import preprocess_scan
from semnav_learning.phrase_sets import sample_sentence
from semnav_learning.route_oracle import true_runs


@dataclass
class TrainingConfig:
    """How records become training sequences and how long training runs."""

    control_rate: float = 10.0   # network steps per second (§2.2.5.2: 50 steps ≈ 5 s) [Hz]
    record_rate: float = 40.0    # laser rate of the demonstration records (UTM-30LX) [Hz]
    hold_steps: int = 60         # zero-label steps appended at the goal (> the 50 of halting) [1]
    batch_size: int = 8          # sequences per batch [1]
    epochs: int = 160            # [1]
    class_batches: int = 4       # extra Z_w-only batches of phrase-set sentences per epoch [1]
    class_batch_size: int = 256  # sentences per Z_w batch [1]
    class_warmup_batches: int = 200  # Z_w-only batches before the first epoch (new model) [1]
    class_monitor_every: int = 50    # retrain_classifier: batches between validation checks [1]
    class_monitor_size: int = 1000   # validation-phrasing sentences of each check [1]
    class_monitor_seed: int = 0      # draws them: the same sentences for every run [1]
    stop_weight: float = 1.0     # loss weight of zero-label steps (standing at the goal) [1]
    turn_weight: float = 1.0     # loss weight of turning steps (beyond the seed, step_weights) [1]
    turn_threshold: float = 0.15  # |ω| of the expert from which a step counts as turning [rad/s]
    mirror_probability: float = 0.0  # share of training sequences mirrored left-right [1]
    word_noise: float = 0.0      # std of Gaussian noise on training word vectors (word_noise) [1]
    stop_targets: bool = False   # add the "stop" target (network with a stop head) [bool]
    decision_targets: bool = False  # add the "decision" target (network with a decision head)
    decision_horizon: float = 15.0  # decision distances are clipped here and scaled by it [m]
    decision_turn_seconds: float = 2.0  # a turn lasts this long; shorter ones are steering [s]
    count_inputs: bool = False      # add the "counts" input (network with the count input)
    counting_inputs: bool = False   # add the "counting" input (counting mode, learned counting)
    count_targets: bool = False     # add the "count" target (network with a count head)
    corners: CornerCountConfig = field(default_factory=CornerCountConfig)  # their side beams


@dataclass
class ValidationThresholds:
    """§4.1.2: tolerable error per step and accumulated (the seed does not give its values)."""

    step_linear: float = 0.1     # |d_i| below this is a correct v [m/s]
    step_angular: float = 0.25   # |e_i| below this is a correct ω [rad/s]
    distance: float = 1.0        # |D_i| above this ends the sequence [m]
    angle: float = 0.6           # |E_i| above this ends the sequence [rad] (34°)


@dataclass
class Episode:
    """One recording sequence, preprocessed."""

    label: int              # basic instruction class 1..10
    scans: np.ndarray       # (N, beams) float32, canonical normalised scans at the record rate
    commands: np.ndarray    # (N, 2) float32 clean expert (v, ω) at the record rate
    source: str = ""        # file the sequence came from
    rate: float = 40.0      # record rate [Hz] (demonstrations: laser rate; DAgger: control rate)
    sides: np.ndarray = None  # (N, 2) float32 raw side ranges, left / right (corner_count)
    counting: str = COUNT_CORNERS   # how a class 5-8 demonstration counted (COUNTINGS)


def split_record_files(datasets, split):
    """Record files of `split` (a sub-directory) in the dataset directories, sorted."""
    return sorted(f for d in datasets for f in (Path(d) / split).glob("*.records"))


def dataset_record_rate(directory, default):
    """[Hz] the rate a dataset's summary.yaml records (datasets at the control rate say so)."""
    summary = Path(directory) / "summary.yaml"
    if not summary.is_file():
        return default
    return float(yaml.safe_load(summary.read_text()).get("record_rate", default))


def iter_record_arrays(path):
    """Stream a record file (Fig. 3.3.1) -> (class, commands (N, 2), ranges (N, beams)) per
    sequence, without building a Python float per range."""
    label, rows = None, []
    with open(path, encoding="ascii") as stream:
        for number, line in enumerate(stream, 1):
            line = line.strip().rstrip(";")
            if not line:
                continue
            if line.startswith("R;"):
                label, rows = int(line[2:]), []
            elif line == "STOP":
                if label is None:
                    raise ValueError(f"{path}:{number}: STOP without a start indicator")
                data = np.asarray(rows, dtype=np.float64)
                yield label, data[:, :2], data[:, 2:]
                label = None
            else:
                rows.append(np.array(line.split(";"), dtype=np.float64))


def preprocess_matrix(ranges, laser, canonical, preprocess):
    """laser_layer.preprocess_scan for every row -> (N, canonical.steps) float32."""
    return np.stack([preprocess_scan(row, laser, canonical, preprocess)[0] for row in ranges])


def load_episodes(paths, laser, canonical, preprocess, cache_dir=None, rate=40.0,
                  window_deg=CornerCountConfig.window_deg, doors=None):
    """Episodes of record files (recorded at `rate` [Hz]) with their side ranges
    (corner_count.side_ranges over ±window_deg); preprocessed scans and side ranges cached as
    .npz keyed by file size/mtime (a cache without side ranges for this window gets them
    added). `doors` (doorways.DoorConfig with width > 0): every scan with its doorways closed
    first, as the follower sees it (a cache of its own)."""
    closing = doors is not None and doors.width > 0
    suffix = f":doors:{doors.width}:{doors.max_range}:{doors.depth}" if closing else ""
    episodes = []
    for path in map(Path, paths):
        stat = path.stat()
        key = hashlib.sha1(f"{path.resolve()}:{stat.st_size}:{stat.st_mtime_ns}:"
                           f"{canonical.start}:{canonical.steps}{suffix}".encode()
                           ).hexdigest()[:16]
        cache = Path(cache_dir) / f"{path.stem}-{key}.npz" if cache_dir else None
        arrays = _read_cache(cache)
        if arrays is None or float(arrays.get("side_window", np.nan)) != window_deg:
            arrays = _parse_records(path, laser, canonical, preprocess, window_deg, arrays,
                                    doors if closing else None)
            if cache and len(arrays["labels"]):
                cache.parent.mkdir(parents=True, exist_ok=True)
                partial = cache.with_suffix(".partial.npz")
                np.savez(partial, **arrays)
                partial.replace(cache)     # an interrupted write never leaves a cache behind
        bounds = np.cumsum(np.concatenate([[0], arrays["lengths"]])).astype(int)
        countings = record_countings(path, len(arrays["labels"]))
        episodes.extend(
            Episode(int(label), arrays["scans"][a:b], arrays["commands"][a:b], str(path), rate,
                    arrays["sides"][a:b], counting)
            for label, a, b, counting in zip(arrays["labels"], bounds[:-1], bounds[1:],
                                             countings))
    return episodes


def countings_path(path):
    """Where the counting modes of a record file's records lie: beside it, <name>.json (the
    record format has no field for them)."""
    return Path(path).with_suffix(".json")


def record_countings(path, records):
    """Each record's counting mode: the `countings` list a dataset build (<floor>.json) or a
    DAgger round (dagger.write_round) writes beside a record file (countings_path),
    COUNT_CORNERS for records without one (datasets built before side counting)."""
    entry = countings_path(path)
    countings = json.loads(entry.read_text()).get("countings") if entry.is_file() else None
    if countings is None:
        return [COUNT_CORNERS] * records
    if len(countings) != records or not set(countings) <= set(COUNTINGS):
        raise ValueError(f"{entry}: {len(countings)} counting modes for {records} records, or "
                         f"one not in {COUNTINGS}")
    return countings


def _read_cache(cache):
    """The arrays of a cache file, or None when there is none or it cannot be read (a cache of
    an older, interrupted write: rebuilt from the records)."""
    if not cache or not cache.is_file():
        return None
    try:
        with np.load(cache) as data:   # each data[key] reads the whole array: once only
            return {name: data[name] for name in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile):
        return None


def _parse_records(path, laser, canonical, preprocess, window_deg, cached=None, doors=None):
    """One record file -> the cache arrays; with `cached` (a cache without side ranges) only
    the side ranges are computed, the preprocessed scans are kept; with `doors` the doorways
    of every scan are closed first."""
    labels, lengths, scans, commands, sides = [], [], [], [], []
    for label, command, ranges in iter_record_arrays(path):
        if doors is not None:
            ranges = np.stack([close_doorways(row, laser, doors) for row in ranges])
        labels.append(label)
        lengths.append(len(command))
        commands.append(command.astype(np.float32))
        sides.append(side_ranges(ranges, laser.angle_min, laser.angle_increment, window_deg))
        if cached is None:
            scans.append(preprocess_matrix(ranges, laser, canonical, preprocess))
    if not labels:
        return {"labels": np.zeros(0, int), "lengths": np.zeros(0, int),
                "scans": np.zeros((0, canonical.steps), np.float32),
                "commands": np.zeros((0, 2), np.float32), "sides": np.zeros((0, 2), np.float32),
                "side_window": np.float64(window_deg)}
    return {"labels": np.array(labels), "lengths": np.array(lengths),
            "scans": cached["scans"] if cached is not None else np.concatenate(scans),
            "commands": np.concatenate(commands), "sides": np.concatenate(sides),
            "side_window": np.float64(window_deg)}


def episode_stride(episode, config):
    """Records per control step: 4 for 40 Hz demonstrations, 1 for 10 Hz DAgger records."""
    return max(1, int(round(episode.rate / config.control_rate)))


def control_rate_sequence(episode, phase, config):
    """Subsample an episode to the control rate from `phase`; if it ends standing at the goal
    (zero labels), make sure it stands there for `hold_steps` control steps: records with a
    shorter standing tail (e.g. made before the expert recorded 6 s of standing, expert.py
    `stop_duration`) get the trailing zero-label scans repeated with zero labels."""
    stride = episode_stride(episode, config)
    scans, commands = episode.scans[phase::stride], episode.commands[phase::stride]
    moving = np.flatnonzero(np.any(episode.commands != 0.0, axis=1))
    if moving.size and moving[-1] == len(episode.commands) - 1:
        return scans, commands            # ended elsewhere (e.g. a DAgger episode that hit a wall)
    last = moving[-1] if moving.size else -1
    standing = int(np.count_nonzero(np.arange(phase, len(episode.commands), stride) > last))
    missing = config.hold_steps - standing
    if missing <= 0:
        return scans, commands
    tail = episode.scans[last + 1:]
    hold = tail[np.arange(missing) % len(tail)]
    return (np.concatenate([scans, hold]),
            np.concatenate([commands, np.zeros((missing, 2), np.float32)]))


def control_rate_sides(episode, phase, steps, config):
    """The episode's side ranges at the control rate from `phase`, the last row repeated over
    the hold steps control_rate_sequence appends -> (steps, 2), or None without side ranges."""
    if episode.sides is None:
        return None
    sides = episode.sides[phase::episode_stride(episode, config)][:steps]
    return np.concatenate([sides, np.repeat(sides[-1:], steps - len(sides), axis=0)])


def pad_words(vector_list, dim):
    """Word vectors of several sentences -> (batch, n_max, dim), zero-padded (masked)."""
    longest = max(len(v) for v in vector_list)
    out = np.zeros((len(vector_list), longest, dim), np.float32)
    for row, vectors in enumerate(vector_list):
        out[row, :len(vectors)] = vectors
    return out


def sentence_vectors(label, sets, word_vectors, rng, split="train", noise=0.0):
    """§3.4: word vectors of a random sentence of class `label` (with word_noise if noise > 0)."""
    vectors = sentence_vector(sample_sentence(sets, label, rng, split).text, word_vectors).vectors
    return word_noise(vectors, noise, rng)


def word_noise(vectors, sigma, rng):
    """Word vectors + N(0, sigma²) per component; unchanged (no draw) when sigma is 0.

    Beyond the seed: a phrasing Z_w never saw differs from the training phrasings by words whose
    GloVe vectors lie near, not on, the training words' vectors ("halt" / "stop"). Noise on the
    training vectors makes LSTM_w answer alike in a neighbourhood of each training sentence.
    Chosen on training phrasings alone: with a third of them held back, sigma 0.2-0.4 classified
    the held-back ones about 91 % right against 86 % without noise (EVALUATION.md)."""
    if sigma <= 0:
        return vectors
    return (vectors + rng.normal(0.0, sigma, vectors.shape)).astype(np.float32)


def step_weights(commands, config):
    """MSE weight per control step: stop_weight where the expert stands, turn_weight where it
    turns (|ω| ≥ turn_threshold), 1 elsewhere.

    Beyond the seed (§4.1.1 weights every step alike): a corner-counting instruction is decided
    in the few steps where the expert turns; the hundreds of straight steps before it dominate
    an unweighted MSE, so a model that drives past the corner loses little."""
    standing = np.all(commands == 0.0, axis=1)
    turning = np.abs(commands[:, 1]) >= config.turn_threshold
    return np.where(standing, config.stop_weight,
                    np.where(turning, config.turn_weight, 1.0)).astype(np.float32)


def decision_step(commands, rate, config):
    """The step where the expert decides: the first step of its first turn that lasts
    `decision_turn_seconds` (at least |ω| ≥ turn_threshold all along; shorter runs are steering
    back onto the corridor axis), else its first standing step, else None."""
    turning = np.abs(commands[:, 1]) >= config.turn_threshold
    least = max(1, int(round(config.decision_turn_seconds * rate)))
    for first, last in true_runs(turning):
        if last - first + 1 >= least:
            return int(first)
    standing = np.flatnonzero(np.all(commands == 0.0, axis=1))
    return int(standing[0]) if standing.size else None


def decision_distance(commands, rate, config):
    """Beyond the seed, the auxiliary target of the decision head: per step, the distance
    [m] the expert still drives before its decision step (sum of v / rate), 0 from there on,
    clipped at decision_horizon and divided by it -> (N,) float32 in [0, 1]. Without a decision
    (a sequence that ends elsewhere) the distance counts to the sequence's end plus the
    horizon, i.e. "far"."""
    decision = decision_step(commands, rate, config)
    travel = np.abs(commands[:, 0]) / rate
    end = len(commands) if decision is None else decision
    remaining = np.zeros(len(commands))
    # distance from step t to `end`: the travel of steps t … end-1
    remaining[:end] = np.cumsum(travel[:end][::-1])[::-1]
    if decision is None:
        remaining += config.decision_horizon
    return (np.minimum(remaining, config.decision_horizon)
            / config.decision_horizon).astype(np.float32)


def mirror_sequence(scans, commands, label):
    """The sequence a mirrored building gives: beams reversed (the canonical scan is symmetric,
    -110° … +110°), ω negated, right and left swapped in the class.

    Beyond the seed: a floor's left turns are another floor's right turns, so every
    demonstration also teaches its mirror image, and the network cannot prefer one side."""
    return scans[:, ::-1], commands * np.array([1.0, -1.0], np.float32), MIRRORED_CLASS[label]


def make_batches(episodes, sets, word_vectors, rng, config, phases=None, sentences=None):
    """One epoch: episodes -> [(inputs, targets, sample weights)] of similar lengths (all
    built at once: validation, reports; training builds each batch when it needs it,
    batch_chunks + batch_arrays, so an epoch's padded copy of the data never sits in memory).

    phases / sentences: fixed per episode (validation); random per epoch when None. Mirroring
    and word noise apply to training batches (phases None) only."""
    return [batch_arrays(chunk, word_vectors.dim, config)
            for chunk in batch_chunks(episodes, sets, word_vectors, rng, config, phases,
                                      sentences)]


def batch_chunks(episodes, sets, word_vectors, rng, config, phases=None, sentences=None):
    """The random part of make_batches: per episode its control-rate sequence (views of the
    episode's arrays where possible), mirroring and sentence -> the epoch's batches as lists of
    (scans, commands, word vectors, class, side ranges or None, counting), sorted by length."""
    noise = config.word_noise if phases is None else 0.0
    items = []
    for index, episode in enumerate(episodes):
        stride = episode_stride(episode, config)
        phase = int(rng.integers(stride)) if phases is None else min(phases[index], stride - 1)
        scans, commands = control_rate_sequence(episode, phase, config)
        sides = control_rate_sides(episode, phase, len(scans), config)
        label = episode.label
        if phases is None and config.mirror_probability > 0 and \
                rng.random() < config.mirror_probability:
            scans, commands, label = mirror_sequence(scans, commands, label)
            sides = None if sides is None else sides[:, ::-1]
        words = (sentence_vectors(label, sets, word_vectors, rng, noise=noise)
                 if sentences is None else sentences[index])
        items.append((scans, commands, words, label, sides, episode.counting))
    items.sort(key=lambda item: len(item[0]))
    return [items[start:start + config.batch_size]
            for start in range(0, len(items), config.batch_size)]


def batch_arrays(chunk, word_dim, config):
    """One chunk of batch_chunks -> (inputs, targets, sample weights), zero-padded to its
    longest sequence."""
    steps = max(len(item[0]) for item in chunk)
    scans = np.zeros((len(chunk), steps, chunk[0][0].shape[1]), np.float32)
    commands = np.zeros((len(chunk), steps, 2), np.float32)
    weights = np.zeros((len(chunk), steps), np.float32)
    stop = np.zeros((len(chunk), steps, 1), np.float32)
    decision = np.zeros((len(chunk), steps, 1), np.float32)
    counts = np.zeros((len(chunk), steps), np.int64)
    counting = np.zeros((len(chunk), steps, len(COUNTINGS)), np.float32)
    for row, (s, c, _, label, sides, mode) in enumerate(chunk):
        scans[row, :len(s)], commands[row, :len(c)] = s, c
        standing = np.all(c == 0.0, axis=1)
        weights[row, :len(s)] = step_weights(c, config)
        stop[row, :len(s), 0] = standing
        if config.decision_targets:
            decision[row, :len(s), 0] = decision_distance(c, config.control_rate, config)
        counting[row, :len(s)] = one_hot_counting(mode)
        if config.count_inputs or config.count_targets:  # beyond the seed: corners so far
            if sides is None:
                raise ValueError("count inputs and targets need the side ranges of the "
                                 "records (training.load_episodes)")
            side = SIDE[label] if mode == COUNT_SIDE else None
            counts[row, :len(s)] = count_inputs(sides, c, config.control_rate, config.corners,
                                                side)
    words = pad_words([item[2] for item in chunk], word_dim)
    labels = np.array([item[3] - 1 for item in chunk])
    targets = {"velocity": commands, "instruction_class": labels}
    sample_weights = {"velocity": weights, "instruction_class": np.ones(len(chunk), np.float32)}
    if config.stop_targets:      # beyond the seed: 1 where the expert stands still
        targets["stop"] = stop
        sample_weights["stop"] = (weights > 0).astype(np.float32)
    if config.decision_targets:  # beyond the seed: distance to the expert's decision
        targets["decision"] = decision
        sample_weights["decision"] = (weights > 0).astype(np.float32)
    if config.count_targets:     # beyond the seed: corners passed so far (learned counting)
        targets["count"] = counts
        sample_weights["count"] = (weights > 0).astype(np.float32)
    inputs = {"words": words, "scans": scans}
    if config.count_inputs:
        inputs["counts"] = one_hot_counts(counts, config.corners.max_count)
    if config.counting_inputs:
        inputs["counting"] = counting
    return inputs, targets, sample_weights


def class_batch(sets, word_vectors, rng, size, split="train", noise=0.0):
    """A batch of random sentences, classes drawn uniformly -> (padded words, labels 0..9);
    `noise`: word_noise's sigma."""
    labels = rng.integers(CLASS_IDS[0], CLASS_IDS[-1] + 1, size)
    vectors = [sentence_vectors(int(label), sets, word_vectors, rng, split, noise)
               for label in labels]
    return pad_words(vectors, word_vectors.dim), labels - 1


def class_hits_and_loss(probabilities, labels):
    """Z_w (batch, 10) softmax outputs and labels 0..9 -> (argmax hits, mean cross-entropy)."""
    probabilities = np.asarray(probabilities, dtype=np.float64)
    picked = probabilities[np.arange(len(labels)), labels]
    hits = int((np.argmax(probabilities, axis=1) == labels).sum())
    return hits, float(-np.mean(np.log(np.maximum(picked, 1e-12))))


def step_errors(reference, output):
    """Eq. 4.2-1 and 4.2-2: d_i = v_ref - v_out, e_i = ω_ref - ω_out -> (d, e)."""
    reference, output = np.asarray(reference), np.asarray(output)
    return reference[:, 0] - output[:, 0], reference[:, 1] - output[:, 1]


def accumulated_errors(d, e, rate):
    """Eq. 4.2-3 and 4.2-4: D_i = sum_k d_k / f, E_i = sum_k e_k / f (distance, angle)."""
    return np.cumsum(d) / rate, np.cumsum(e) / rate


def validate_sequence(reference, output, thresholds, rate):
    """§4.1.2 for one sequence -> (correct outputs, destination reached).

    A step is correct when |d_i| and |e_i| are below their thresholds; counting stops at the
    first step where |D_i| or |E_i| exceeds its threshold, and then the destination is not
    counted as reached. Otherwise it is reached when every output was correct."""
    d, e = step_errors(reference, output)
    dist, angle = accumulated_errors(d, e, rate)
    broken = (np.abs(dist) > thresholds.distance) | (np.abs(angle) > thresholds.angle)
    end = int(np.argmax(broken)) if broken.any() else len(d)
    correct = (np.abs(d[:end]) < thresholds.step_linear) & \
        (np.abs(e[:end]) < thresholds.step_angular)
    return int(correct.sum()), bool(not broken.any() and correct.all())


def validation_value(sequences, thresholds, rate):
    """§4.1.2: [correct, destination] summed over the (reference, output) sequences."""
    results = [validate_sequence(ref, out, thresholds, rate) for ref, out in sequences]
    return [sum(r[0] for r in results), sum(r[1] for r in results)]


def batch_rows(targets, outputs, weights):
    """Per row of a make_batches batch and the network's outputs on it: (class 1..10, expert
    (v, ω), network (v, ω)) over the steps that count in the loss (weight > 0; padding is 0).
    Counting steps, not summing weights: --turn-weight / --stop-weight change the sums."""
    lengths = np.count_nonzero(weights["velocity"] > 0, axis=1)
    velocity = np.asarray(outputs["velocity"])
    for row, steps in enumerate(lengths):
        yield (int(targets["instruction_class"][row]) + 1, targets["velocity"][row, :steps],
               velocity[row, :steps])


def turn_onset(reference, output, threshold):
    """Open-loop turn onset on a recorded sequence (beyond the seed: where §4.1.2 counts steps,
    this asks whether the network turns where the expert did) -> (expert step, model step) or
    None when the expert never turns. The expert's onset is its first step with |ω| ≥ threshold;
    the model's is its first step with ω ≥ threshold in the expert's turn direction (None if it
    never turns that way)."""
    reference, output = np.asarray(reference), np.asarray(output)
    turning = np.flatnonzero(np.abs(reference[:, 1]) >= threshold)
    if not turning.size:
        return None
    expert = int(turning[0])
    side = np.sign(reference[expert, 1])
    model = np.flatnonzero(side * output[:, 1] >= threshold)
    return expert, (int(model[0]) if model.size else None)


def onset_verdict(onset, tolerance):
    """turn_onset -> "on time" (within `tolerance` steps), "early", "late" or "never"."""
    expert, model = onset
    if model is None:
        return "never"
    if abs(model - expert) <= tolerance:
        return "on time"
    return "early" if model < expert else "late"


def turn_fit_by_class(rows, threshold, tolerance):
    """Open-loop fit where the expert turns, per class, over (class, expert, network) rows
    (batch_rows) -> {class: (records with a turn, mean turning-step MSE(ω),
    Counter of onset_verdict)}. Rows where the expert never turns are left out."""
    errors, verdicts = {}, {}
    for label, reference, output in rows:
        onset = turn_onset(reference, output, threshold)
        if onset is None:
            continue
        turning = np.abs(reference[:, 1]) >= threshold
        errors.setdefault(label, []).append(
            float(np.mean((reference[turning, 1] - output[turning, 1]) ** 2)))
        verdicts.setdefault(label, Counter())[onset_verdict(onset, tolerance)] += 1
    return {label: (len(errors[label]), float(np.mean(errors[label])), verdicts[label])
            for label in sorted(verdicts)}


class Monitor:
    """§4.1.3: remembers the best value seen; update() says whether a new model must be saved.

    Loss monitor: lower is better. Validation monitor: [correct, destination] with more
    destinations better, ties broken by more correct outputs. Beyond the seed, the closed-loop
    monitor: episodes that reached their goal on validation floors, more is better (a tie keeps
    the earlier model). The phrasing monitor (Z_w alone): (validation-phrasing sentences
    classified right, their mean cross-entropy), more right better, ties by lower entropy."""

    KINDS = ("loss", "validation", "closed_loop", "phrasing")

    def __init__(self, kind):
        if kind not in self.KINDS:
            raise ValueError(f"monitor kind must be one of {', '.join(self.KINDS)}, got {kind!r}")
        self.kind, self.best = kind, None

    def better(self, value):
        if self.best is None:
            return True
        if self.kind == "loss":
            return value < self.best
        if self.kind == "closed_loop":
            return value > self.best
        if self.kind == "phrasing":
            return (value[0], -value[1]) > (self.best[0], -self.best[1])
        return (value[1], value[0]) > (self.best[1], self.best[0])

    def update(self, value):
        if self.better(value):
            self.best = value
            return True
        return False
