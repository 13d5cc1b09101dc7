"""dagger_semnav's command line (dagger_cli): the train_semnav command of a round, the model card,
a --collect-only round of the default model on the L floor, and the required --init."""
import json
import os
import subprocess
import sys

import pytest

from penguin_base.record_format import read_records
from semnav_learning.dagger_cli import (TRAIN_ENVIRONMENT, argument_parser, main, train_command,
                                        write_model_card)
from semnav_l_floor import write_l_floor
from tamp_resources import resource, workspace

ROOT = resource()


def test_a_round_trains_on_every_aggregated_record_file(tmp_path):
    args = argument_parser().parse_args(
        ["--init", "bc.keras", "--seed", "5", "--epochs", "3", "--stop-loss-weight", "0.5",
         "--train-args", "--batch-size 32  --threads 2", "--work-dir", str(tmp_path),
         "--dataset", "data"])
    command = train_command(args, "round1.keras", [tmp_path / "a.records", "b.records"], 2,
                            tmp_path / "round2.keras")
    assert command == [sys.executable, "-m", "semnav_learning.train_cli", "--init", "round1.keras",
                       "--dagger-records", str(tmp_path / "a.records"), "b.records",
                       "--epochs", "3", "--seed", "7", "--dataset", "data",
                       "--work-dir", str(tmp_path / "train2"),
                       "--out", str(tmp_path / "round2.keras"), "--stop-loss-weight", "0.5",
                       "--batch-size", "32", "--threads", "2"]
    plain = argument_parser().parse_args(["--init", "bc.keras"])
    assert "--stop-loss-weight" not in train_command(plain, "bc.keras", [], 1, "o")
    assert plain.dataset == workspace() / "build" / "semnav_dataset"


def test_a_round_trains_in_a_process_of_train_cli():
    """The module a round runs parses train_semnav's options and exits with their reason."""
    plain = argument_parser().parse_args(["--init", "bc.keras"])
    module = train_command(plain, "bc.keras", [], 1, "o")[:3]
    done = subprocess.run([*module, "--select", "best_closed_loop"], capture_output=True,
                          text=True, env=TRAIN_ENVIRONMENT | os.environ, timeout=300)
    assert done.returncode == 1
    assert "--select best_closed_loop needs --closed-loop-plan" in done.stderr


def test_init_is_required(capsys):
    with pytest.raises(SystemExit) as stop:
        argument_parser().parse_args(["--rounds", "1"])
    assert stop.value.code == 2
    assert "--init" in capsys.readouterr().err


def test_the_model_card_joins_the_dagger_and_training_summaries(tmp_path):
    (tmp_path / "round2.keras").write_bytes(b"model")
    (tmp_path / "round2.json").write_text('{"epochs": 3}')
    (tmp_path / "summary.json").write_text('{"rounds": [1, 2]}')
    write_model_card(tmp_path / "round2.keras", tmp_path / "out" / "dagger.keras", tmp_path)
    assert (tmp_path / "out" / "dagger.keras").read_bytes() == b"model"
    card = json.loads((tmp_path / "out" / "dagger.json").read_text())
    assert card == {"dagger": {"rounds": [1, 2]}, "last_training": {"epochs": 3}}


def test_collect_only_writes_the_states_of_one_round(tmp_path, capsys):
    write_l_floor(tmp_path)
    assert main(argv=[        # class 4, turn around: the shortest episode
        "--init", str(ROOT / "models" / "semantic_nav" / "default.keras"), "--collect-only",
        "--floors", str(tmp_path / "l_floor.yaml"), "--classes", "4", "--per-class", "1",
        "--world", str(ROOT / "config" / "worlds" / "office_penguin_urg.yaml"),
        "--work-dir", str(tmp_path / "dagger")]) == 0
    records = read_records(tmp_path / "dagger" / "round1.records")
    assert [r.instruction_class for r in records] == [4] and len(records[0].samples) > 10
    assert not (tmp_path / "dagger" / "summary.json").exists()     # no training round
    printed = capsys.readouterr().out
    assert f"round 1: 1/1 episodes reached the goal on the training floors; " \
           f"{len(records[0].samples)} states labelled" in printed
