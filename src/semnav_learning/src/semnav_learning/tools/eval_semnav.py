"""Command line of scripts/eval_semnav: the options of an evaluation_run.EvaluationRun, run by
evaluation_run.evaluate_run."""
import argparse
import sys
from pathlib import Path

from semantic_nav.instruction_classes import CLASS_IDS
from semnav_learning.evaluation_run import (EvaluationRun, EvaluationRunError, evaluate_run,
                                            laser_templates)
from semnav_learning.spoken import DEFAULT_VOICES

COMMAND = "scripts/eval_semnav"


def counted(least):
    """An argparse type: an integer of at least `least`, else a message naming what was given
    ("--first 0" ran every episode)."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value < least:
            raise argparse.ArgumentTypeError(f"must be an integer of at least {least}; got "
                                             f"{text!r}")
        return value
    return parse


def argument_parser(description=None):
    """The options of eval_semnav: the fields of EvaluationRun, with its defaults."""
    defaults = EvaluationRun()
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--map", dest="maps", nargs="+", type=Path, default=defaults.maps,
                        help="map_server YAML floor(s) (default: the test floors)")
    parser.add_argument("--laser", choices=sorted(laser_templates()), default=defaults.laser)
    parser.add_argument("--episodes-per-class", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--candidates", type=int, default=defaults.candidates,
                        help="corridor starts a new plan samples per floor at most (fewer: a "
                             "floor where some classes never apply is sampled sooner)")
    parser.add_argument("--side-share", type=float, metavar="SHARE",
                        help="a new plan's classes 5-8: this share of each class's episodes "
                             "counted on one side (\"take the second right\"), the rest over "
                             "both sides, e.g. 0.5 for equal shares (default: as the phrase "
                             "sets' sentences fall)")
    parser.add_argument("--json", type=Path, help="write every episode and the table here")
    parser.add_argument("--model", help="model file of the follower (default: its default)")
    parser.add_argument("--follower-config", type=Path,
                        help="follower YAML (config/semnav_follower.yaml keys), e.g. the guard off")
    parser.add_argument("--policy", choices=("model", "expert"), default="model")
    parser.add_argument("--expert-reference", action="store_true",
                        help="also run the expert on the same episodes (reference, plots)")
    parser.add_argument("--workers", type=int, default=defaults.workers)
    parser.add_argument("--classes", type=int, nargs="+", choices=CLASS_IDS,
                        default=list(CLASS_IDS))
    parser.add_argument("--name", default=None, help="name of the docs outputs (table, plot)")
    parser.add_argument("--docs", type=Path, default=defaults.docs)
    parser.add_argument("--first", type=counted(1), help="run only the first N (at least 1) "
                        "episodes of each class of the plan")
    parser.add_argument("--skip", type=counted(0), default=0, metavar="K",
                        help="leave out the first K episodes of each class of the plan (before "
                             "--first): another subset of the same plan")
    parser.add_argument("--chain", type=int, nargs="+", metavar="CLASS",
                        help="instead of the per-class table: --episodes-per-class episodes of "
                             "one chained instruction of these classes, e.g. --chain 1 3 "
                             "--sentence \"go straight to the end, then turn left\"")
    parser.add_argument("--sentence", help="the sentence of --chain")
    parser.add_argument("--spoken", nargs="*", metavar="VOICE",
                        help="speak each sentence with espeak-ng (these voice:words-per-minute "
                             f"in turn; none given: {' '.join(DEFAULT_VOICES)}), transcribe it "
                             "with Whisper tiny.en and follow the transcript as the node "
                             "reads /voice_message; lists the misheard words")
    parser.add_argument("--stt-config", type=Path,
                        default=defaults.stt_config,
                        help="Whisper's settings for --spoken (perception.stt.SttConfig as YAML; "
                             "default config/semnav_stt.yaml, as semantic_nav.launch starts the "
                             "STT node)")
    parser.add_argument("--plan", type=Path, help="episode plan (JSON, or an earlier --json "
                        "result): reused when it exists (same episodes for every model and "
                        "laser), else written")
    parser.add_argument("--phrases", type=Path,
                        default=defaults.phrases,
                        help="phrase sets a new plan's sentences are drawn from (default: "
                             "config/semnav_phrases.yaml)")
    return parser


def main(argv=None, description=None):
    """Parse, evaluate, report on stdout and write the outputs -> exit status 0 (bad input
    exits with its message)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    run = EvaluationRun(**vars(argument_parser(description).parse_args(argv)))
    try:
        evaluate_run(run, " ".join([COMMAND] + argv))
    except EvaluationRunError as error:
        sys.exit(f"eval_semnav: {error}")
    return 0
