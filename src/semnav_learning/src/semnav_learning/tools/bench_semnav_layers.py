"""Cost of semantic_nav's data layers (scripts/bench_semnav_layers): laser preprocessing per
scan, GloVe cache loading, instruction conversion per sentence, phrase-set enumeration per split."""
import argparse
import time

import numpy as np

from semantic_nav.instruction_classes import CLASS_IDS
from semantic_nav.instruction_layer import convert_instruction
from semantic_nav.laser_layer import load_laser_config, preprocess_scan
from semantic_nav.word_vectors import load_word_vectors
from semnav_learning.phrase_sets import SPLITS, enumerate_sentences, load_phrase_sets
from tamp_resources import resource

SENTENCE = "Go straight to the end of this aisle, and then turn left at the second corner."


def per_call(function, repeats):
    """Wall time of each of `repeats` calls of `function` [s] (an array)."""
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        function()
        times.append(time.perf_counter() - began)
    return np.array(times)


def spread_us(seconds):
    """"p50 X µs, p99 Y µs" of call times [s]."""
    return (f"p50 {1e6 * np.percentile(seconds, 50):.0f} µs, "
            f"p99 {1e6 * np.percentile(seconds, 99):.0f} µs")


def dropout_scan(beams, rng):
    """Ranges of `beams` beams, uniform in 0.2-8 m, every 50th a dropout (0)."""
    ranges = rng.uniform(0.2, 8.0, beams)
    ranges[::50] = 0.0
    return ranges


def sentence_counts(sets, split):
    """{class: number of sentences the phrase sets of `split` make}."""
    return {label: sum(1 for _ in enumerate_sentences(sets, label, split)) for label in CLASS_IDS}


def main(argv=None, description=None):
    """Measure and print each layer's cost (config of tamp_resources) -> exit status 0."""
    argparse.ArgumentParser(description=description).parse_args(argv)
    config_dir = resource("config")
    models, canonical, config = load_laser_config(config_dir / "semnav_laser.yaml")
    rng = np.random.default_rng(0)
    for name, model in models.items():
        ranges = dropout_scan(model.beams, rng)
        seconds = per_call(lambda: preprocess_scan(ranges, model, canonical, config), 2000)
        print(f"laser layer {name} -> canonical {canonical.steps} beams: "
              f"{spread_us(seconds)} per scan")
    began = time.perf_counter()
    vectors = load_word_vectors()
    print(f"GloVe compact cache ({len(vectors.index)} words, {vectors.dim}-d): "
          f"loaded in {time.perf_counter() - began:.2f} s")
    seconds = per_call(lambda: convert_instruction(SENTENCE, vectors), 2000)
    print(f"instruction layer (2 simple instructions, 14 words): {spread_us(seconds)}")
    sets = load_phrase_sets(config_dir / "semnav_phrases.yaml")
    for split in SPLITS:
        began = time.perf_counter()
        counts = sentence_counts(sets, split)
        print(f"phrase sets, {split}: {sum(counts.values())} sentences in "
              f"{time.perf_counter() - began:.1f} s, per class {counts}")
    return 0
