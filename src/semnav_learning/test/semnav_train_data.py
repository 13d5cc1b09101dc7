"""Test helper: a tiny synthetic training set for the Trainer (seconds, not minutes).

Record files of a UTM-30LX (1081 beams) in train/ and validation/ splits at 10 Hz, where class 1
drives straight at 0.3 m/s towards a wall that comes closer, class 2 turns right and class 3 turns
left at a side opening; and a GloVe text file with a random 50-d vector for every phrase-set word.
"""

import numpy as np

from penguin_base.record_format import RecordSequence, Sample, write_records
from semantic_nav.instruction_layer import tokenise
from semnav_learning.phrase_sets import load_phrase_sets
from tamp_resources import resource

ROOT = resource()
CONFIG = ROOT / "config"
BEAMS = 1081                     # UTM-30LX: -135° … 135° every 0.25°
RATE = 10.0                      # [Hz] record rate of the synthetic records
TURN = {1: 0.0, 2: -0.5, 3: 0.5}  # ω of the turning half of each class [rad/s]


def corridor_scan(ahead, opening_side, rng):
    """Ranges [m] of a 1.8 m corridor with a wall `ahead` m away; opening_side -1 / +1 opens
    the right / left wall (a branch), 0 none; a little range noise."""
    angles = np.radians(np.linspace(-135.0, 135.0, BEAMS))
    sin, cos = np.abs(np.sin(angles)), np.cos(angles)
    with np.errstate(divide="ignore"):
        side = np.where(sin > 1e-6, 0.9 / sin, 30.0)
        front = np.where(cos > 1e-6, ahead / cos, 30.0)
    ranges = np.minimum(side, front)
    if opening_side:
        ranges[np.sign(angles) == opening_side] = np.minimum(front, 30.0)[
            np.sign(angles) == opening_side]
    return np.clip(ranges + rng.normal(0.0, 0.01, BEAMS), 0.05, 30.0)


def sequence(label, rng, steps=30):
    """One demonstration of class `label` (1 straight, 2 right, 3 left)."""
    samples = []
    for step in range(steps):
        turning = label != 1 and step >= steps // 2
        v = 0.3 if step < steps - 5 else 0.0
        omega = TURN[label] if turning and v else 0.0
        opening = int(np.sign(TURN[label])) if turning else 0
        ahead = max(0.5, 6.0 - 0.03 * step)
        samples.append(Sample(v, omega, tuple(corridor_scan(ahead, opening, rng))))
    return RecordSequence(label, samples)


def write_dataset(folder, seed=0, per_class=(3, 1)):
    """train/ and validation/ record files and summary.yaml (record rate) in `folder`."""
    rng = np.random.default_rng(seed)
    for split, count in zip(("train", "validation"), per_class):
        (folder / split).mkdir(parents=True, exist_ok=True)
        sequences = [sequence(label, rng) for label in (1, 2, 3) for _ in range(count)]
        write_records(folder / split / f"synthetic_{split}.records", sequences)
    (folder / "summary.yaml").write_text(f"record_rate: {RATE}\n")
    return folder


def write_words(path, dim=50, seed=0):
    """A GloVe text file with a random vector for every word of the phrase sets."""
    sets = load_phrase_sets(CONFIG / "semnav_phrases.yaml")
    vocabulary = sorted({t for phrases in sets.values() for p in phrases
                         for t in tokenise(p.text)})
    vectors = np.random.default_rng(seed).normal(size=(len(vocabulary), dim))
    path.write_text("".join(f"{word} {' '.join(f'{x:.5f}' for x in row)}\n"
                            for word, row in zip(vocabulary, vectors)))
    return path
