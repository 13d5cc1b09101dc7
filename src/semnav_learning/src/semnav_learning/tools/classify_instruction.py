"""Command line of scripts/classify_instruction: Z_w of LSTM_w (thesis 002 §2.2.4) on sentences
from stdin, or its accuracy on sentences of held-out (or validation) phrasings."""
import argparse
import os
import sys
from pathlib import Path

import numpy as np
import yaml

from tamp_resources import resource


def argument_parser(description=None):
    """The options of classify_instruction; the phrase sets default to tamp_resources'."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--model", type=Path, help="default: models/semantic_nav/default.keras")
    parser.add_argument("--words", help="GloVe text file or cache directory (default cache)")
    parser.add_argument("--held-out", type=int, metavar="N",
                        help="instead of stdin: accuracy on N held-out-phrasing sentences")
    parser.add_argument("--split", choices=("held_out", "validation"), default="held_out",
                        help="the phrasings of --held-out: the held-out test (default) or the "
                             "validation phrasings that choose between classifiers")
    parser.add_argument("--phrases", type=Path,
                        default=resource("config", "semnav_phrases.yaml"),
                        help="phrase sets of --held-out (default: config/semnav_phrases.yaml)")
    parser.add_argument("--blind", type=Path, metavar="FILE",
                        help="instead of stdin: how many directions of a blind set (e.g. "
                             "config/semnav_blind_directions.yaml) are read as meant, and which "
                             "are not")
    parser.add_argument("--seed", type=int, default=0)
    return parser


def read_phrase_sets(path):
    """The phrase sets of --phrases; a bad file ends the program with a message naming it."""
    from semnav_learning.phrase_sets import PhraseSetError, load_phrase_sets
    try:
        return load_phrase_sets(path)
    except (OSError, yaml.YAMLError, PhraseSetError) as error:
        sys.exit(f"classify_instruction: --phrases {path}: {error}")


def phrasing_accuracy(follower, sets, split, count, seed):
    """Z_w accuracy on `count` sentences of one split's phrasings, classes drawn in turn, and
    the phrases of that split it misses (printed) -> the accuracy."""
    from semnav_learning.phrase_sets import score_phrasings
    score = score_phrasings(sets, follower.start, count, np.random.default_rng(seed), split)
    print(f"{split} phrasings: {score.hits}/{count} = {score.accuracy:.2%} classified correctly")
    print("per class: " + ", ".join(f"{label}: {h}/{n}"
                                    for label, (h, n) in score.per_class.items()))
    for text, missed, used in score.missed_phrases():
        print(f"  missed {missed:4d} of {used:4d} sentences with {text!r}")
    return score.accuracy


def blind_accuracy(follower, path):
    """Print the blind set's score (semnav_learning.blind_set) -> the accuracy."""
    from semantic_nav.follow_session import FollowSession, InstructionRefused
    from semnav_learning.blind_set import (BlindSetError, format_blind_score, load_blind_set,
                                           score_blind_set)
    try:
        entries = load_blind_set(path)
    except BlindSetError as error:
        sys.exit(f"classify_instruction: --blind: {error}")
    # as the node reads a sentence: its refusals, its splitting, Z_w
    score = score_blind_set(entries, lambda text: FollowSession(follower, text, 0.0, 0.0).classes,
                            (InstructionRefused,))
    print("\n".join(format_blind_score(score)))
    return score.accuracy


def classify_lines(follower, lines):
    """Print the classes of each non-blank line (`unknown: <reason>` for unknown words) ->
    exit status: 1 if a line had unknown words, else 0. A counted class (5-8) shows how it
    counts: "5:corners" (over both sides) or "5:side" ("take the second right")."""
    from semantic_nav.follower import UnknownInstructionError
    from semantic_nav.instruction_classes import COUNTING_IDS
    status = 0
    for line in lines:
        if not line.strip():
            continue
        try:
            classes = follower.start(line.strip())
            countings = getattr(follower, "countings", None) or [None] * len(classes)
            print(" ".join(f"{c}:{how}" if c in COUNTING_IDS and how else str(c)
                           for c, how in zip(classes, countings)), flush=True)
        except UnknownInstructionError as error:
            print(f"unknown: {error}", flush=True)
            status = 1
    return status


def main(argv=None, description=None, lines=None):
    """Parse, load the model, classify `lines` (default stdin) or score --held-out -> exit
    status. A reader that stops early (`| head -1`) ends the run quietly."""
    try:
        return run(argument_parser(description).parse_args(argv), lines)
    except BrokenPipeError:
        # the reader has gone: nothing more can be printed, and Python's flush at exit must not
        # write to the closed pipe either
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


def run(args, lines=None):
    """classify_instruction with parsed `args` -> exit status."""
    sets = read_phrase_sets(args.phrases) if args.held_out else None   # before the model loads
    from semantic_nav.follower import DirectionFollower, ModelMissingError
    try:
        follower = DirectionFollower.from_files(args.model, args.words)
    except ModelMissingError as error:
        sys.exit(str(error))
    if args.held_out:
        phrasing_accuracy(follower, sets, args.split, args.held_out, args.seed)
        return 0
    if args.blind:
        blind_accuracy(follower, args.blind)
        return 0
    return classify_lines(follower, sys.stdin if lines is None else lines)
