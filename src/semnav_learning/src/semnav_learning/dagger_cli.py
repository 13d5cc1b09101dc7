"""Command line of scripts/dagger_semnav: rounds of closed-loop collection (dagger.collect_round)
on the training floors, each followed by retraining with train_semnav (train_cli) in a
subprocess."""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np
from tqdm import tqdm

from semantic_nav.instruction_classes import CLASS_IDS
from tamp_resources import resource, workspace

TRAIN_FLOORS = ["office_crossroads", "office_loop", "office_grid"]
# as scripts/train_semnav sets them: one numpy BLAS thread, Keras on torch (unless set already)
TRAIN_ENVIRONMENT = {"OPENBLAS_NUM_THREADS": "1", "KERAS_BACKEND": "torch"}


def argument_parser(description=None):
    """The options of dagger_semnav; the world defaults to tamp_resources', the dataset and work
    directory to the workspace's build/."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--init", type=Path, required=True, help="behaviour-cloning model")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--per-class", type=int, default=4, help="episodes per class and round")
    parser.add_argument("--classes", type=int, nargs="+", choices=CLASS_IDS,
                        default=list(CLASS_IDS),
                        help="instruction classes to run (e.g. 5 6 7 8: the corners the model "
                             "miscounts)")
    parser.add_argument("--max-route-offset", type=float,
                        help="keep only the states before the robot first strays this far [m] "
                             "from the expert's route (default: every visited state)")
    parser.add_argument("--epochs", type=int, default=30, help="training epochs per round")
    parser.add_argument("--floors", nargs="+", default=TRAIN_FLOORS,
                        help="training floors: names under maps/ or map YAML paths (e.g. the "
                             "generated floors of build_semnav_dataset)")
    parser.add_argument("--world", type=Path,
                        default=resource("config", "worlds", "office_penguin.yaml"))
    parser.add_argument("--dataset", type=Path, default=workspace() / "build" / "semnav_dataset")
    parser.add_argument("--stop-loss-weight", type=float,
                        help="passed to train_semnav (models with the stop head)")
    parser.add_argument("--collect-only", action="store_true",
                        help="write round1.records with the --init model and stop (retrain "
                             "with scripts/train_semnav --dagger-records yourself)")
    parser.add_argument("--earlier-records", type=Path, nargs="*", default=[],
                        help="visited states of earlier DAgger runs, aggregated as well")
    parser.add_argument("--train-args", default="",
                        help='more train_semnav options, e.g. "--batch-size 32 --threads 2"')
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--work-dir", type=Path, default=workspace() / "build" / "semnav_dagger")
    parser.add_argument("--out", type=Path, help="copy the final model here")
    return parser


def collect(args, model, round_index, sets, maps_dir):
    """Run one round with `model` on --floors (names under `maps_dir` or YAML paths) ->
    (record file, success figures)."""
    import torch
    from semantic_nav.follower import DirectionFollower
    from semnav_learning.dagger import collect_round, write_round
    from semnav_learning.demonstrations import floor_map_path
    torch.set_num_threads(1)
    policy = DirectionFollower.from_files(model)
    rng = np.random.default_rng(args.seed * 1000 + round_index)
    floors = [floor_map_path(name, maps_dir) for name in args.floors]
    with tqdm(total=len(args.classes) * args.per_class, desc=f"DAgger round {round_index}",
              unit="episode") as bar:
        sequences, results = collect_round(floors, args.world, policy, sets, args.per_class,
                                           rng, progress=lambda result: bar.update(1),
                                           classes=args.classes,
                                           max_route_offset=args.max_route_offset)
    path = args.work_dir / f"round{round_index}.records"
    write_round(path, sequences)
    reasons = Counter(r.reason.split(":")[0] for r in results)
    figures = {"round": round_index, "model": str(model), "episodes": len(results),
               "successes": sum(r.success for r in results), "reasons": dict(reasons),
               "states": sum(len(s.samples) for s in sequences)}
    print(f"round {round_index}: {figures['successes']}/{figures['episodes']} episodes "
          f"reached the goal on the training floors; {figures['states']} states labelled; "
          f"{dict(reasons)}")
    return path, figures


def train_command(args, model, records, round_index, out):
    """The train_semnav command of one round (train_cli run as a module): continue from `model`
    on the dataset and every aggregated record file, seeded --seed + round, the model saved to
    `out`."""
    command = [sys.executable, "-m", "semnav_learning.train_cli", "--init", str(model),
               "--dagger-records", *map(str, records), "--epochs", str(args.epochs),
               "--seed", str(args.seed + round_index), "--dataset", str(args.dataset),
               "--work-dir", str(args.work_dir / f"train{round_index}"),
               "--out", str(out)]
    if args.stop_loss_weight is not None:
        command += ["--stop-loss-weight", str(args.stop_loss_weight)]
    return command + args.train_args.split()


def write_model_card(model, out, work_dir):
    """Copy the final model to `out` with a card: the DAgger summary and the last training's."""
    out.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(model, out)
    card = {"dagger": json.loads((work_dir / "summary.json").read_text()),
            "last_training": json.loads(Path(model).with_suffix(".json").read_text())}
    out.with_suffix(".json").write_text(json.dumps(card, indent=1))


def main(description=None, argv=None):
    """Parse, run the rounds -> exit status 0 (a failed training round exits with a message)."""
    args = argument_parser(description).parse_args(argv)
    from semnav_learning.phrase_sets import load_phrase_sets
    sets = load_phrase_sets(resource("config", "semnav_phrases.yaml"))
    args.work_dir.mkdir(parents=True, exist_ok=True)
    model, records, summary, began = args.init, list(args.earlier_records), [], \
        time.perf_counter()
    for round_index in range(1, args.rounds + 1):
        path, figures = collect(args, model, round_index, sets, resource("maps"))
        records.append(path)
        if args.collect_only:
            return 0
        out = args.work_dir / f"round{round_index}.keras"
        command = train_command(args, model, records, round_index, out)
        try:
            subprocess.run(command, check=True, env=TRAIN_ENVIRONMENT | os.environ)
        except subprocess.CalledProcessError as error:
            sys.exit(f"dagger_semnav: round {round_index}: train_semnav exited with status "
                     f"{error.returncode}")
        figures["trained"] = str(out)
        summary.append(figures)
        model = out
        (args.work_dir / "summary.json").write_text(json.dumps(
            {"args": {k: str(v) for k, v in vars(args).items()}, "rounds": summary,
             "seconds": round(time.perf_counter() - began, 1)}, indent=1))
    if args.out:
        write_model_card(model, args.out, args.work_dir)
        print(f"DAgger model -> {args.out}")
    return 0
