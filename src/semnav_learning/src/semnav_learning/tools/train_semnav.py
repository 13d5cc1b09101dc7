"""Command line of scripts/train_semnav: argparse -> TrainerConfig -> Trainer.run()."""
import argparse
import signal
import sys
from pathlib import Path

from semnav_learning.trainer import (INTERRUPTED_EXIT, SELECTIONS, Trainer, TrainerConfig,
                                     TrainingError)
from tamp_resources import resource, workspace


def argument_parser(description=None):
    """The options of train_semnav; outputs and inputs default under the workspace's build/."""
    build = workspace() / "build"
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dataset", type=Path, nargs="+",
                        default=[build / "semnav_dataset"],
                        help="dataset directories (scripts/build_semnav_dataset); their splits "
                             "are joined and their record rates must agree")
    parser.add_argument("--train-split", default="train")
    parser.add_argument("--validation-split", default="validation")
    parser.add_argument("--dagger-records", type=Path, nargs="*", default=[],
                        help="aggregated DAgger record files (control rate) added to training")
    parser.add_argument("--init", type=Path, help="continue from this .keras model")
    parser.add_argument("--epochs", type=int, help="default: TrainingConfig.epochs")
    parser.add_argument("--learning-rate", type=float)
    parser.add_argument("--stop-weight", type=float,
                        help="loss weight of zero-label steps (default: TrainingConfig)")
    parser.add_argument("--mirror", type=float, metavar="P",
                        help="beyond the seed: mirror this share of the training sequences "
                             "left-right each epoch (training.mirror_sequence; default 0)")
    parser.add_argument("--word-noise", type=float, metavar="SIGMA",
                        help="beyond the seed: Gaussian noise of this std on the word vectors of "
                             "training sentences (training.word_noise; default 0)")
    parser.add_argument("--retrain-classifier", type=int, metavar="BATCHES",
                        help="with --init: train only LSTM_w and Z_w for BATCHES phrase-set "
                             "batches (LSTM_fused and the heads untouched), save, and stop; "
                             "no dataset is read")
    parser.add_argument("--turn-weight", type=float,
                        help="beyond the seed: loss weight of steps where the expert turns "
                             "(|ω| ≥ TrainingConfig.turn_threshold; default 1)")
    parser.add_argument("--stop-head", action="store_true",
                        help="beyond the seed: add (or keep) the sigmoid stop output, trained "
                             "with binary cross-entropy on the zero-label steps")
    parser.add_argument("--stop-loss-weight", type=float,
                        help="weight of the stop output's cross-entropy (default: "
                             "NetworkConfig.stop_loss_weight)")
    parser.add_argument("--decision-head", action="store_true",
                        help="beyond the seed: add (or keep) the auxiliary output that predicts "
                             "the distance to the expert's turn or stop "
                             "(training.decision_distance)")
    parser.add_argument("--decision-horizon", type=float, metavar="METRES",
                        help="clip (and scale) the decision distances here (default: "
                             "TrainingConfig.decision_horizon)")
    parser.add_argument("--decision-loss-weight", type=float,
                        help="weight of the decision output's MSE (default: "
                             "NetworkConfig.decision_loss_weight)")
    parser.add_argument("--count-input", action="store_true",
                        help="beyond the seed: give LSTM_fused the corners counted so far over "
                             "both sides (corner_count.CornerCounter) as a third input; an "
                             "--init model without it gets it with zero weights")
    parser.add_argument("--balance-classes", type=int, default=1, metavar="MAX_REPEAT",
                        help="repeat the records of rare classes (third corner: few floors "
                             "have one) up to MAX_REPEAT times towards the commonest class")
    parser.add_argument("--batch-size", type=int, help="default: TrainingConfig.batch_size")
    parser.add_argument("--scan-units", type=int, help="default: NetworkConfig.scan_units")
    parser.add_argument("--fused-units", type=int, help="default: NetworkConfig.fused_units")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=1, help="torch CPU threads")
    parser.add_argument("--work-dir", type=Path, default=build / "semnav_train" / "run")
    parser.add_argument("--resume", action="store_true",
                        help="go on from WORK_DIR/checkpoint (written after every epoch) when it "
                             "is there: an interrupted run ends as the uninterrupted one would")
    parser.add_argument("--count-head", action="store_true",
                        help="beyond the seed, learned counting: no count input (an --init "
                             "model's is dropped); the counting mode as an input and a count "
                             "output trained on the corners the counter finds in each record's "
                             "scans in its mode")
    parser.add_argument("--follower-config", type=Path, metavar="YAML",
                        help="follower config of the closed-loop monitor's episodes (default: "
                             "config/semnav_follower.yaml), e.g. "
                             "config/semnav_follower_no_count.yaml for a network that counts")
    parser.add_argument("--closed-loop-plan", type=Path, nargs="+", metavar="PLAN",
                        help="eval_semnav plan(s) (JSON) on validation floors, their episodes "
                             "driven after each epoch; never a test floor or a training floor")
    parser.add_argument("--select", choices=SELECTIONS,
                        default="best_validation", help="model copied to --out at the end")
    parser.add_argument("--out", type=Path, help="copy the selected model here (.keras)")
    parser.add_argument("--cache", type=Path, default=build / "semnav_cache",
                        help="preprocessed-scan cache")
    parser.add_argument("--words", help="GloVe text file or cache directory (default cache)")
    parser.add_argument("--door-width", type=float, default=0.0, metavar="M",
                        help="close the doorways narrower than M m in every record scan, as the "
                             "follower does (semantic_nav.doorways; its default 1.4); 0: the "
                             "scans as recorded")
    return parser


def trainer_config(args, command=""):
    """Parsed options -> TrainerConfig, with tamp_resources' laser, phrase and world files."""
    config = resource("config")
    return TrainerConfig(**vars(args), laser_config=config / "semnav_laser.yaml",
                         phrases=config / "semnav_phrases.yaml",
                         world_template=config / "worlds" / "office_penguin.yaml",
                         command=command)


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def main(argv=None, description=None):
    """Parse, train, report on stdout -> exit status (0, 130 interrupted; bad settings exit
    with their message)."""
    args = argument_parser(description).parse_args(argv)
    config = trainer_config(args, " ".join(sys.argv if argv is None else argv))
    signal.signal(signal.SIGTERM, _interrupt)        # `kill` saves the model as Ctrl-C does
    signal.signal(signal.SIGINT, _interrupt)         # also when started in the background
    try:
        summary = Trainer(config, report=print).run()
    except TrainingError as error:
        sys.exit(str(error))
    return INTERRUPTED_EXIT if summary.get("interrupted") else 0
