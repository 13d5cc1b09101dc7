"""Command line of scripts/compare_semnav: two eval_semnav --json results of one plan -> each
one's successes, the episodes only one reached and the exact McNemar p, per class and overall."""
import argparse
import json
import sys
from pathlib import Path

from semnav_learning.evaluation import paired_comparison


def argument_parser(description=None):
    """The options of compare_semnav: two result files."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("first", type=Path)
    parser.add_argument("second", type=Path)
    return parser


def read_episodes(path):
    """The episodes of an eval_semnav --json result; anything else exits naming the file."""
    try:
        return json.loads(path.read_text())["episodes"]
    except (OSError, ValueError, KeyError, TypeError) as error:
        sys.exit(f"compare_semnav: {path}: not an eval_semnav --json result "
                 f"({type(error).__name__}: {error})")


def comparison_table(names, comparison):
    """paired_comparison's result -> Markdown lines, one row per class and one for all."""
    lines = [f"| class | {names[0]} | {names[1]} | only {names[0]} | only {names[1]} | p |",
             "|---|---:|---:|---:|---:|---:|"]
    for label, row in [*comparison["by_class"].items(), ("all", comparison)]:
        lines.append(f"| {label} | {row['first']} | {row['second']} | {row['only_first']} | "
                     f"{row['only_second']} | {row['p']:.3g} |")
    return lines


def main(argv=None, description=None):
    """Parse, compare, print the table -> exit status 0 (unusable files exit with a message)."""
    args = argument_parser(description).parse_args(argv)
    results = [read_episodes(path) for path in (args.first, args.second)]
    try:
        comparison = paired_comparison(*results)
    except ValueError as error:
        sys.exit(f"compare_semnav: {args.first} vs {args.second}: {error}")
    for line in comparison_table((args.first.stem, args.second.stem), comparison):
        print(line)
    return 0
