"""Trainer on a tiny synthetic set (semnav_train_data: 9 + 3 records, a network of a few hundred
weights): the loss falls, every file of a run is written, a run repeats exactly from its seed,
--init continues from a saved model, an interrupt saves the current one, Z_w-only retraining
leaves the control layers alone, and bad settings are refused with their reason."""
import json
import math
from pathlib import Path

import numpy as np
import pytest

from semnav_learning.tools.train_semnav import argument_parser, main, trainer_config
from semnav_learning.trainer import (StageProgress, Trainer, TrainerConfig, TrainingError,
                                     format_duration, selected_entry)
from semnav_learning.training import TrainingConfig
from semnav_train_data import CONFIG, ROOT, write_dataset, write_words

EPOCHS = 4


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("semnav_train")
    return write_dataset(folder / "data"), write_words(folder / "words.txt"), folder


def tiny(inputs, name, **fields):
    """A TrainerConfig of a few seconds: small batches and network, few Z_w batches."""
    from semantic_nav.network import NetworkConfig
    data, words, folder = inputs
    training = TrainingConfig(epochs=EPOCHS, batch_size=4, hold_steps=10, class_batches=1,
                              class_batch_size=16, class_warmup_batches=5,
                              class_monitor_every=2, class_monitor_size=30)
    network = NetworkConfig(word_units=4, scan_units=8, fused_units=8, learning_rate=1e-2)
    return TrainerConfig(**{"dataset": [data], "work_dir": folder / name,
                            "laser_config": CONFIG / "semnav_laser.yaml",
                            "phrases": CONFIG / "semnav_phrases.yaml", "words": str(words),
                            "cache": folder / "cache", "training": training,
                            "network": network, **fields})


def without_seconds(history):
    return [{k: v for k, v in entry.items() if k != "seconds"} for entry in history]


@pytest.fixture(scope="module")
def first_run(inputs):
    lines = []
    config = tiny(inputs, "first", out=inputs[2] / "models" / "tiny.keras", command="train")
    summary = Trainer(config, report=lines.append).run()
    return config, summary, lines


def test_a_run_lowers_the_loss_and_writes_every_file(first_run):
    config, summary, _ = first_run
    history = summary["history"]
    assert [h["epoch"] for h in history] == list(range(1, EPOCHS + 1))
    assert not summary["interrupted"]
    assert history[-1]["velocity_loss"] < 0.8 * history[0]["velocity_loss"]
    assert history[-1]["loss_monitor"] == min(h["velocity_loss"] for h in history)
    work = config.work_dir
    for name in ("config.json", "history.json", "current.keras", "lowest_loss.keras",
                 "best_validation.keras", "training.png"):
        assert (work / name).stat().st_size > 0, name
    record = json.loads((work / "config.json").read_text())
    assert record["training"]["record_rate"] == 10.0          # from the dataset's summary.yaml
    assert (record["train_records"], record["validation_records"]) == (9, 3)
    assert record["network"]["fused_units"] == 8
    assert json.loads((work / "history.json").read_text())["history"] == history
    card = json.loads(config.out.with_suffix(".json").read_text())
    assert card["command"] == "train" and card["epochs_run"] == EPOCHS
    assert card["selected_epoch"] == selected_entry(history, "best_validation")
    assert config.out.read_bytes() == (work / "best_validation.keras").read_bytes()


def test_progress_lines_give_each_stage_its_eta(first_run):
    lines = first_run[2]
    stages = {line.split(":")[0] for line in lines if ", ETA " in line}
    assert stages == {"Z_w warm-up", *(f"Epoch {k}/{EPOCHS}" for k in range(1, EPOCHS + 1))}
    assert sum(line.startswith(f"Epoch {EPOCHS}/{EPOCHS} - ") and "training ETA 0.0 s" in line
               for line in lines) == 1


def test_the_same_seed_repeats_the_run_and_another_does_not(inputs, first_run):
    again = Trainer(tiny(inputs, "again"), report=lambda line: None).run()
    assert without_seconds(again["history"]) == without_seconds(first_run[1]["history"])
    other = Trainer(tiny(inputs, "other", seed=1, epochs=1), report=lambda line: None).run()
    assert other["history"][0]["velocity_loss"] != first_run[1]["history"][0]["velocity_loss"]


def test_init_continues_from_the_saved_model(inputs, first_run):
    lines = []
    init = first_run[0].work_dir / "current.keras"
    summary = Trainer(tiny(inputs, "continued", init=init, epochs=1), report=lines.append).run()
    assert not any(line.startswith("Z_w warm-up") for line in lines)   # Z_w already trained
    first = first_run[1]["history"]
    assert summary["history"][0]["velocity_loss"] < 0.8 * first[0]["velocity_loss"]


def test_learned_counting_drops_the_init_count_input_and_learns_the_count(inputs):
    """--count-head from a count-input model: the count input goes, the counting input and the
    count output come, and the count's cross-entropy falls over the epochs."""
    from semantic_nav.network import (has_count_input, has_counting_input, has_head,
                                      load_network)
    counted = tiny(inputs, "counted", count_input=True, epochs=1)
    Trainer(counted, report=lambda line: None).run()
    assert has_count_input(load_network(counted.work_dir / "current.keras"))
    learned = tiny(inputs, "learned", init=counted.work_dir / "current.keras", count_head=True,
                   epochs=3)
    history = Trainer(learned, report=lambda line: None).run()["history"]
    model = load_network(learned.work_dir / "current.keras")
    assert not has_count_input(model) and has_counting_input(model) and has_head(model, "count")
    assert history[-1]["count_loss"] < history[0]["count_loss"]


def test_an_interrupt_saves_the_current_model(inputs):
    from semantic_nav.network import load_network

    def report(line):
        if line.startswith("Epoch 2/"):
            raise KeyboardInterrupt                     # Ctrl-C during the second epoch

    config = tiny(inputs, "interrupted")
    summary = Trainer(config, report=report).run()
    assert summary["interrupted"] and [h["epoch"] for h in summary["history"]] == [1]
    assert json.loads((config.work_dir / "history.json").read_text())["interrupted"]
    assert load_network(str(config.work_dir / "current.keras")).get_layer("lstm_fused")


def test_an_interrupt_before_the_first_epoch_ends_writes_no_model(inputs):
    lines = []

    def report(line):
        lines.append(line)
        if line.startswith("Epoch 1/"):
            raise KeyboardInterrupt                     # before any model was selected

    out = inputs[2] / "models" / "early.keras"
    summary = Trainer(tiny(inputs, "early", out=out), report=report).run()
    assert summary["interrupted"] and summary["history"] == []
    assert not out.exists() and any(f"{out} not written" in line for line in lines)


def test_an_interrupted_run_resumes_to_the_uninterrupted_result(inputs, first_run):
    from semantic_nav.network import load_network

    def stop_in_epoch_3(line):
        if line.startswith("Epoch 3/"):
            raise KeyboardInterrupt

    config = tiny(inputs, "resumed", resume=True)
    stopped = Trainer(config, report=stop_in_epoch_3).run()
    assert stopped["interrupted"] and len(stopped["history"]) == 2
    assert json.loads((config.work_dir / "checkpoint" / "state.json").read_text())["epoch"] == 2
    lines = []
    summary = Trainer(config, report=lines.append).run()
    assert f"resuming after epoch 2/{EPOCHS} from {config.work_dir / 'checkpoint'}" in lines
    assert not any(line.startswith(("Z_w warm-up", "Epoch 1/", "Epoch 2/")) for line in lines)
    assert without_seconds(summary["history"]) == without_seconds(first_run[1]["history"])
    resumed = load_network(str(config.work_dir / "current.keras")).get_weights()
    straight = load_network(str(first_run[0].work_dir / "current.keras")).get_weights()
    assert all(np.array_equal(a, b) for a, b in zip(resumed, straight, strict=True))


def test_a_checkpoint_of_another_configuration_is_refused(inputs, first_run):
    import shutil
    config = tiny(inputs, "other_checkpoint", resume=True, seed=5)
    config.work_dir.mkdir(parents=True)
    shutil.copytree(first_run[0].work_dir / "checkpoint", config.work_dir / "checkpoint")
    with pytest.raises(TrainingError, match="made with another configuration"):
        Trainer(config, report=lambda line: None).run()


def test_retraining_the_classifier_leaves_the_control_layers_alone(inputs, first_run):
    from semantic_nav.network import load_network
    init = first_run[0].work_dir / "current.keras"
    out = inputs[2] / "models" / "retrained.keras"
    config = tiny(inputs, "retrained", init=init, retrain_classifier=4, out=out)
    summary = Trainer(config, report=lambda line: None).run()
    assert [c["batches"] for c in summary["phrasing_monitor"]] == [0, 2, 4]
    assert summary["kept_batch"] in (0, 2, 4)
    before, after = load_network(str(init)), load_network(str(out))
    for layer in ("fc_scan", "lstm_fused", "velocity"):
        for a, b in zip(before.get_layer(layer).get_weights(),
                        after.get_layer(layer).get_weights()):
            np.testing.assert_array_equal(a, b)
    assert json.loads(out.with_suffix(".json").read_text())["kept_batch"] == summary["kept_batch"]


def test_bad_settings_are_refused_with_their_reason(inputs, tmp_path):
    def refused(match, **fields):
        with pytest.raises(TrainingError, match=match):
            Trainer(tiny(inputs, "refused", **fields), report=lambda line: None).run()

    refused("needs --closed-loop-plan", select="best_closed_loop")
    refused("needs --init MODEL", retrain_classifier=3)
    refused("--mirror must be a share between 0 and 1, got 1.5", mirror=1.5)
    refused("--word-noise must be a standard deviation >= 0", word_noise=-0.1)
    refused("no records in train or validation", dataset=[tmp_path])
    (tmp_path / "summary.yaml").write_text("record_rate: 40\n")
    refused(r"recorded at different rates \[10.0, 40.0\] Hz", dataset=[inputs[0], tmp_path])


def test_every_command_line_option_is_a_trainer_field():
    args = argument_parser().parse_args(["--epochs", "7", "--mirror", "0.5", "--stop-head",
                                         "--dataset", "a", "b", "--seed", "4"])
    config = trainer_config(args, "train_semnav --epochs 7")
    assert (config.epochs, config.mirror, config.stop_head, config.seed) == (7, 0.5, True, 4)
    assert config.dataset == [Path("a"), Path("b")]
    assert config.laser_config == ROOT / "config" / "semnav_laser.yaml"
    assert config.select == "best_validation" and config.balance_classes == 1


def test_the_command_line_exits_with_the_reason():
    with pytest.raises(SystemExit, match="--select best_closed_loop needs --closed-loop-plan"):
        main(argv=["--select", "best_closed_loop"])


def test_stage_progress_reports_every_tenth_with_its_eta():
    lines, now = [], [0.0]
    progress = StageProgress("Epoch 1/2", 25, "batches", lines.append, clock=lambda: now[0])
    for _ in range(25):
        now[0] += 2.0                                   # 2 s per batch
        progress.step("loss 0.1")
    assert len(lines) == 13                             # every 2nd batch of 25, and the last
    assert lines[0] == "Epoch 1/2: 2/25 batches, 4.0 s elapsed, ETA 46.0 s, loss 0.1"
    assert lines[-1] == "Epoch 1/2: 25/25 batches, 50.0 s elapsed, ETA 0.0 s, loss 0.1"


def test_format_duration():
    assert [format_duration(s) for s in (12.34, 245.0, 7620.0)] == \
        ["12.3 s", "4 min 05 s", "2 h 07 min"]
    assert math.isclose(float(format_duration(59.94).split()[0]), 59.9)
