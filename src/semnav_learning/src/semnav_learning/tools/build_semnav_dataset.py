"""Command line of scripts/build_semnav_dataset: argparse -> DatasetConfig -> build_dataset()."""
import argparse
import sys
from pathlib import Path

from semantic_nav.instruction_classes import CLASS_IDS, COUNTING_IDS
from semnav_learning.dataset_build import (DEFAULT_SPLIT, DatasetConfig, build_dataset,
                                           parse_split, summary_lines)
from semnav_learning.episodes import TURN_AT_END
from semnav_learning.floor_generator import FloorGeneratorConfig
from tamp_resources import resource, workspace


def split_option(text):
    """--split's value -> {split: [floor, ...]}; a bad value exits naming the option."""
    try:
        return parse_split(text)
    except ValueError as error:
        raise SystemExit(f"--split: {error}") from None


def _listed(labels):
    """(5, 6, 7, 8) -> "5, 6, 7, 8"."""
    return ", ".join(str(label) for label in labels)


def _add_generator_options(parser):
    """The options of the generated floors (floor_generator.FloorGeneratorConfig)."""
    parser.add_argument("--generated", type=int, default=0,
                        help="random office floors added to the training split")
    parser.add_argument("--corridors", type=int, nargs=2, metavar=("MIN", "MAX"),
                        default=FloorGeneratorConfig.corridors,
                        help="corridors per direction of a generated floor")
    parser.add_argument("--width", type=float, nargs=2, metavar=("MIN", "MAX"),
                        default=FloorGeneratorConfig.width, help="generated floor size along x [m]")
    parser.add_argument("--depth", type=float, nargs=2, metavar=("MIN", "MAX"),
                        default=FloorGeneratorConfig.depth, help="generated floor size along y [m]")
    parser.add_argument("--spacing", type=float, default=FloorGeneratorConfig.spacing,
                        help="least distance of parallel corridors of a generated floor [m] "
                             "(4: corners 4 m apart along a corridor, a ladder of small rooms)")
    parser.add_argument("--side-branches", type=float, default=0.0, metavar="RATE",
                        help="one-sided branches per metre of corridor of a generated floor, "
                             "between the crossings (staggered corners)")
    parser.add_argument("--side-branch-length", type=float, nargs=2, metavar=("MIN", "MAX"),
                        default=FloorGeneratorConfig.side_branch_length,
                        help="length of those branches [m] (3 to 5: short dead-end stubs)")
    parser.add_argument("--end-doors", type=float, default=0.0, metavar="P",
                        help="probability that a corridor end of a generated floor with an "
                             "office behind it has a door straight ahead (dead end, L corner, "
                             "far wall of a T)")


def argument_parser(description=None):
    """The options of build_semnav_dataset; the world defaults to tamp_resources', the output
    to the workspace's build/."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--world", type=Path,
                        default=resource("config", "worlds", "office_penguin.yaml"),
                        help="robot and laser template (sim2d world)")
    parser.add_argument("--split", type=split_option, default=DEFAULT_SPLIT,
                        help='floors per split, e.g. "train=office_crossroads,office_loop,'
                             'office_grid validation=office_longhall test=office_ring,office_comb"')
    parser.add_argument("--per-class", type=int, default=4,
                        help="demonstrations per class and floor (fewer where a class is rare)")
    parser.add_argument("--classes", type=int, nargs="+", choices=CLASS_IDS,
                        default=list(CLASS_IDS),
                        help="demonstrate only these classes (e.g. 5 6 7 8 on long floors)")
    parser.add_argument("--after-end", type=int, default=0,
                        help=f"per floor, demonstrations of classes {_listed(TURN_AT_END)} "
                             "standing at the end of a corridor (the second part of \"go "
                             "straight to the end, then turn ...\")")
    parser.add_argument("--counting", type=int, default=0,
                        help="per floor, demonstrations of each of classes "
                             f"{_listed(COUNTING_IDS)} from starts where counting the corners "
                             "over both sides reaches another branch than counting the turning "
                             "side only (route_oracle.counting_matters)")
    parser.add_argument("--candidates", type=int, default=80,
                        help="candidate start poses sampled per floor")
    _add_generator_options(parser)
    parser.add_argument("--record-rate", type=float, default=None,
                        help="record one scan per 1/RATE s [Hz] (default: every laser scan)")
    parser.add_argument("--workers", type=int, default=2, help="floors built in parallel")
    parser.add_argument("--resume", action="store_true",
                        help="keep the floors an earlier or interrupted build of --out "
                             "finished (several --seed runs add their generated floors)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=workspace() / "build" / "semnav_dataset")
    return parser


def main(argv=None, description=None, progress=True):
    """Parse, build, print the summary -> exit status 0; the named floors are
    maps/<floor>.yaml of tamp_resources."""
    args = argument_parser(description).parse_args(sys.argv[1:] if argv is None else argv)
    config = DatasetConfig(**vars(args), maps_dir=resource("maps"))
    summary = build_dataset(config, progress)
    for line in summary_lines(summary, config.out):
        print(line)
    return 0
