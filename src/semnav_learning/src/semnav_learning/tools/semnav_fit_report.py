"""Command line of scripts/semnav_fit_report: the open-loop fit of a model on recorded sequences,
per instruction class: the turning-step MSE of ω and whether the turn onset is on time, early,
late or never (training.turn_fit_by_class)."""
import argparse
from pathlib import Path

import numpy as np

from semantic_nav.instruction_classes import CLASS_IDS
from tamp_resources import resource, workspace

VERDICTS = ("on time", "early", "late", "never")


def argument_parser(description=None):
    """The options of semnav_fit_report; the scan cache defaults under the workspace's build/."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--model", type=Path, help="default: the follower's default model")
    parser.add_argument("--dataset", type=Path, nargs="+", required=True,
                        help="dataset directories (scripts/build_semnav_dataset)")
    parser.add_argument("--split", default="train")
    parser.add_argument("--classes", type=int, nargs="+", choices=CLASS_IDS,
                        default=list(CLASS_IDS))
    parser.add_argument("--threshold", type=float, default=0.15,
                        help="|ω| from which a step is a turn [rad/s]")
    parser.add_argument("--tolerance", type=int, default=10,
                        help="onset difference still on time [control steps]")
    parser.add_argument("--seed", type=int, default=0, help="sentences drawn per record")
    parser.add_argument("--cache", type=Path, default=workspace() / "build" / "semnav_cache")
    parser.add_argument("--words", help="GloVe text file or cache directory (default cache)")
    return parser


def load_records(args, record_rate, laser_config):
    """The --split records of --dataset of the --classes -> [training episodes]; no records
    exits naming the split and datasets."""
    from semantic_nav.laser_layer import load_laser_config
    from semnav_learning.training import load_episodes, split_record_files
    files = split_record_files(args.dataset, args.split)
    if not files:
        raise SystemExit(f"no records in the {args.split!r} split of "
                         f"{', '.join(map(str, args.dataset))}: run scripts/build_semnav_dataset")
    models, canonical, preprocess = load_laser_config(laser_config)
    episodes = load_episodes(files, models["utm30lx"], canonical, preprocess, args.cache,
                             record_rate)
    return [e for e in episodes if e.label in args.classes]


def fit_table(fit):
    """turn_fit_by_class's result -> Markdown lines (verdicts as shares of the records)."""
    lines = ["| class | records with a turn | turning-step MSE(ω) | " + " | ".join(VERDICTS)
             + " |", "|---:|---:|---:|" + "---:|" * len(VERDICTS)]
    for label, (n, mse, verdicts) in fit.items():
        shares = " | ".join(f"{verdicts[v] / n:.0%}" for v in VERDICTS)
        lines.append(f"| {label} | {n} | {mse:.4f} | {shares} |")
    return lines


def main(argv=None, description=None):
    """Parse, run the model over the records, print the table -> exit status 0."""
    config_dir = resource("config")
    args = argument_parser(description).parse_args(argv)
    from semantic_nav.follower import model_file
    from semantic_nav.network import has_count_input, load_network
    from semantic_nav.word_vectors import load_word_vectors
    from semnav_learning.phrase_sets import load_phrase_sets
    from semnav_learning.training import (TrainingConfig, batch_rows, dataset_record_rate,
                                          make_batches, turn_fit_by_class)
    config = TrainingConfig(batch_size=16)
    rates = {dataset_record_rate(d, config.record_rate) for d in args.dataset}
    if len(rates) != 1:
        raise SystemExit(f"datasets record at different rates {sorted(rates)} [Hz]")
    episodes = load_records(args, rates.pop(), config_dir / "semnav_laser.yaml")
    model = load_network(model_file(args.model))
    config.count_inputs = has_count_input(model)    # the corner count as the network's input
    sets = load_phrase_sets(config_dir / "semnav_phrases.yaml")
    batches = make_batches(episodes, sets, load_word_vectors(args.words),
                           np.random.default_rng(args.seed), config, phases=[0] * len(episodes))
    rows = [row for inputs, targets, weights in batches
            for row in batch_rows(targets, model.predict_on_batch(inputs), weights)]
    fit = turn_fit_by_class(rows, args.threshold, args.tolerance)
    print(f"model {model_file(args.model)}; {args.split} records of "
          f"{', '.join(map(str, args.dataset))}; onset on time within {args.tolerance} steps")
    for line in fit_table(fit):
        print(line)
    return 0
