"""Command line of scripts/train_recipe (`make train`): run a training recipe
(recipe.RecipeRun) or list its units, and with --install install its models."""
import argparse
import multiprocessing
import os
import signal
import sys
from pathlib import Path

from semnav_learning.recipe import RecipeError, RecipeRun, load_recipe
from semnav_learning.trainer import format_duration
from tamp_resources import resource, workspace


def argument_parser(description=None):
    """The options of scripts/train_recipe."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--recipe", type=Path,
                        default=resource("config", "semnav_recipe.yaml"))
    parser.add_argument("--install", action="store_true",
                        help="after the run, copy the recipe's `install` models (and their "
                             "cards) over the committed ones in models/semantic_nav/")
    parser.add_argument("--only", nargs="+", metavar="NAME",
                        help="run only these stages or units (their inputs must be done)")
    parser.add_argument("--list", action="store_true",
                        help="print the units, their estimates and what is done, then stop")
    return parser


def _interrupt(signum, frame):
    """SIGTERM stops the run as Ctrl-C does; a pool worker (a dataset build's, inheriting this
    handler) that its pool terminates just ends."""
    if multiprocessing.parent_process() is not None:
        os._exit(128 + signum)
    raise KeyboardInterrupt


def list_units(run, report):
    """The units with their estimates and, where done, their measured durations."""
    done = run.done()
    for unit in run.recipe.units:
        state = (f"done in {format_duration(done[unit.name]['seconds'])}"
                 if unit.name in done else "to run")
        report(f"{unit.stage}/{unit.name} ({unit.kind}): estimate "
               f"{format_duration(60 * unit.minutes)}, {state}")
    left = sum(60 * u.minutes for u in run.recipe.units if u.name not in done)
    report(f"estimate of what is left: {format_duration(left)}")


def main(argv=None, description=None, report=None):
    """Parse, run (and with --install, install) -> exit status (0; 130 interrupted, the unit
    running then not marked done; a bad recipe exits with its message). The recipe's relative
    paths are under the workspace (tamp_resources.workspace())."""
    args = argument_parser(description).parse_args(argv)
    report = report or (lambda line: print(line, flush=True))
    signal.signal(signal.SIGTERM, _interrupt)        # `kill` stops as Ctrl-C does
    try:
        run = RecipeRun(load_recipe(args.recipe, workspace()), report=report)
        if args.list:
            list_units(run, report)
            return 0
        run.run(args.only)
        if args.install:
            run.install()
    except RecipeError as error:
        sys.exit(f"train_recipe: {error}")
    except KeyboardInterrupt:
        report("interrupted: the running unit is not marked done (rerun to resume)")
        return 130
    return 0
