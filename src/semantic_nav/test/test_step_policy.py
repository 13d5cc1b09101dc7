"""The numpy control network read without Keras: the same weights and commands as through Keras,
clear errors for bad files, and no Keras or torch in the control path."""
import subprocess
import sys
import zipfile

import numpy as np
import pytest

from semantic_nav.step_policy import (ModelFileError, StepPolicy, load_step_policy,
                                      read_keras_weights, weight_groups)
from tamp_resources import resource

MODELS = sorted(resource("models", "semantic_nav").glob("*.keras"))


def test_weight_groups_follow_keras_naming():
    layers = [("LSTM", "lstm_w"), ("Dense", "instruction_class"), ("Dense", "fc_scan"),
              ("ConcatOverTime", "concat"), ("SequenceLSTM", "lstm_fused"),
              ("Dense", "velocity")]
    assert weight_groups(layers) == {
        "lstm_w": "layers/lstm/cell", "instruction_class": "layers/dense",
        "fc_scan": "layers/dense_1", "concat": "layers/concat_over_time",
        "lstm_fused": "layers/sequence_lstm", "velocity": "layers/dense_2"}


def _learned_counting_model(directory):
    """A small network that counts itself (counting input, count head), saved."""
    import keras
    from semantic_nav.network import NetworkConfig, build_network
    keras.utils.set_random_seed(4)
    path = directory / "learned_counting.keras"
    build_network(NetworkConfig(word_units=4, scan_units=8, fused_units=6, stop_head=True,
                                counting_input=True, count_head=True)).save(path)
    return path


@pytest.mark.skipif(not MODELS, reason="no committed models")
@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_weights_and_commands_equal_those_read_through_keras(path):
    _same_through_keras(path)


def test_a_network_that_counts_itself_reads_the_same_without_keras(tmp_path):
    policy = _same_through_keras(_learned_counting_model(tmp_path))
    assert policy.config.counting_input and not policy.config.count_input
    assert "count/kernel" in policy.w and policy.counted in range(4)


def _same_through_keras(path):
    from semantic_nav.network import load_network
    through_keras = StepPolicy.from_keras(load_network(path))
    without = load_step_policy(path)
    assert without.config == through_keras.config
    assert sorted(without.w) == sorted(through_keras.w)
    for name, value in through_keras.w.items():
        assert np.array_equal(without.w[name], value), name
    rng = np.random.default_rng(0)
    words = rng.normal(size=(6, through_keras.config.word_dim))
    z_a, z_b = through_keras.classify(words), without.classify(words)
    assert np.array_equal(z_a, z_b)
    counts = np.eye(4)[1] if without.config.count_input else None
    counting = np.eye(2)[1] if without.config.counting_input else None
    for _ in range(5):
        scan = rng.random(through_keras.config.beams)
        assert through_keras.step(z_a, scan, counts, counting) == \
            without.step(z_b, scan, counts, counting)
        assert through_keras.counted == without.counted
    return without


def test_bad_files_are_named(tmp_path):
    with pytest.raises(FileNotFoundError, match="make train"):
        read_keras_weights(tmp_path / "none.keras")
    garbage = tmp_path / "garbage.keras"
    garbage.write_bytes(b"garbage\n")
    with pytest.raises(ModelFileError, match=r"not a \.keras zip archive"):
        read_keras_weights(garbage)
    other = tmp_path / "other.keras"
    with zipfile.ZipFile(other, "w") as archive:
        archive.writestr("notes.txt", "not a model")
    with pytest.raises(ModelFileError, match=rf"^semantic_nav model {other} is corrupt or "
                                             r"unreadable \(not one of our networks: KeyError"):
        read_keras_weights(other)


@pytest.mark.skipif(not MODELS, reason="no committed models")
def test_the_follower_loads_without_keras_or_torch():
    code = ("import sys\n"
            "from semantic_nav.follower import DirectionFollower\n"
            "from semantic_nav.step_policy import load_step_policy\n"
            f"load_step_policy({str(MODELS[0])!r})\n"
            "import semantic_nav.ros_follower\n"
            "print(sorted(m for m in ('keras', 'torch') if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"

