"""The numpy single-step path reproduces the Keras sequence model (Fig. 2.2.4) to 1e-5; model
files that are missing or damaged are told apart by name."""
import zipfile

import numpy as np
import pytest

keras = pytest.importorskip("keras")

from semantic_nav.network import (CORNER_CLASSES, COUNTING_MODES, NetworkConfig,  # noqa: E402
                                  SequenceLSTM, StepPolicy, add_heads, build_network,
                                  has_count_input, has_counting_input, has_head, has_stop_head,
                                  interpolate_weights, load_network, ModelFileError,
                                  rebuild_fused_inputs, relu, softmax)
from semantic_nav.follower import DEFAULT_MODEL  # noqa: E402


def test_softmax_and_relu_eq_2_2_11():
    z = np.array([1.0, 2.0, 3.0])
    e = np.exp([1.0, 2.0, 3.0])
    np.testing.assert_allclose(softmax(z), e / e.sum())
    np.testing.assert_array_equal(relu(np.array([-1.0, 0.0, 2.5])), [0.0, 0.0, 2.5])


def _compare(model, config, rng):
    words = rng.normal(size=(3, 9, config.word_dim)).astype(np.float32)
    lengths = [9, 4, 6]
    for row, n in enumerate(lengths):
        words[row, n:] = 0.0                       # padding is masked
    scans = rng.random((3, 120, config.beams)).astype(np.float32)
    scans /= np.linalg.norm(scans, axis=2, keepdims=True)
    inputs = {"words": words, "scans": scans}
    counts = [[None] * 120] * 3
    if has_count_input(model):      # a count that rises as corners would, 0 … 3
        counts = np.eye(CORNER_CLASSES, dtype=np.float32)[np.minimum(
            np.cumsum(rng.random((3, 120)) < 0.03, axis=1), CORNER_CLASSES - 1)]
        inputs["counts"] = counts
    counting = [[None] * 120] * 3
    if has_counting_input(model):   # one counting mode per sequence
        counting = np.repeat(np.eye(COUNTING_MODES, dtype=np.float32)[
            rng.integers(0, COUNTING_MODES, 3)][:, None], 120, axis=1)
        inputs["counting"] = counting
    out = model.predict_on_batch(inputs)
    policy = StepPolicy.from_keras(model)
    worst = 0.0
    for row, n in enumerate(lengths):
        z_w = policy.classify(words[row, :n])
        worst = max(worst, np.abs(z_w - np.asarray(out["instruction_class"][row])).max())
        policy.reset()
        steps = np.array([policy.step(z_w, scan, count, mode)
                          for scan, count, mode in zip(scans[row], counts[row], counting[row])])
        worst = max(worst, np.abs(steps - np.asarray(out["velocity"][row])).max())
    return worst


def test_single_step_path_matches_sequence_model():
    keras.utils.set_random_seed(3)
    config = NetworkConfig(word_units=8, scan_units=16, fused_units=12)
    model = build_network(config)
    # larger weights than the initialiser's so the gates leave their linear range
    for layer in model.layers:
        layer.set_weights([w * 3.0 for w in layer.get_weights()])
    assert _compare(model, config, np.random.default_rng(0)) < 1e-5


@pytest.mark.skipif(not DEFAULT_MODEL.is_file(), reason="no committed default model")
def test_single_step_path_matches_the_default_model():
    model = load_network(str(DEFAULT_MODEL))
    config = StepPolicy.from_keras(model).config
    assert _compare(model, config, np.random.default_rng(1)) < 1e-5


def test_reset_clears_the_memory():
    keras.utils.set_random_seed(4)
    config = NetworkConfig(word_units=4, scan_units=8, fused_units=6)
    policy = StepPolicy.from_keras(build_network(config))
    z_w = policy.classify(np.ones((2, config.word_dim)))
    scan = np.full(config.beams, 1 / np.sqrt(config.beams))
    first = policy.step(z_w, scan)
    second = policy.step(z_w, scan)
    policy.reset()
    assert policy.step(z_w, scan) == first
    assert second != first


def test_stop_head_single_step_matches_sequence_model():
    """Beyond the seed: the stop output of StepPolicy reproduces the Keras model to 1e-5."""
    keras.utils.set_random_seed(5)
    config = NetworkConfig(word_units=8, scan_units=16, fused_units=12, stop_head=True)
    model = build_network(config)
    for layer in model.layers:
        layer.set_weights([w * 3.0 for w in layer.get_weights()])
    rng = np.random.default_rng(2)
    words = rng.normal(size=(1, 5, config.word_dim)).astype(np.float32)
    scans = rng.random((1, 60, config.beams)).astype(np.float32)
    out = model.predict_on_batch({"words": words, "scans": scans})
    policy = StepPolicy.from_keras(model)
    assert policy.config.stop_head
    z_w = policy.classify(words[0])
    stops = []
    for scan in scans[0]:
        policy.step(z_w, scan)
        stops.append(policy.stop_probability)
    np.testing.assert_allclose(stops, np.asarray(out["stop"])[0, :, 0], atol=1e-5)
    assert _compare(model, config, rng) < 1e-5


def test_add_heads_keeps_the_velocity_outputs():
    keras.utils.set_random_seed(6)
    config = NetworkConfig(word_units=4, scan_units=8, fused_units=6)
    plain = build_network(config)
    config.stop_head = True
    with_stop = add_heads(plain, config)
    assert has_stop_head(with_stop) and not has_stop_head(plain)
    config.decision_head = True
    both = add_heads(with_stop, config)
    assert has_head(both, "decision") and not has_head(with_stop, "decision")
    rng = np.random.default_rng(3)
    inputs = {"words": rng.normal(size=(2, 4, config.word_dim)).astype(np.float32),
              "scans": rng.random((2, 7, config.beams)).astype(np.float32)}
    a, b, c = (m.predict_on_batch(inputs) for m in (plain, with_stop, both))
    np.testing.assert_allclose(np.asarray(a["velocity"]), np.asarray(b["velocity"]), atol=1e-6)
    np.testing.assert_allclose(np.asarray(a["velocity"]), np.asarray(c["velocity"]), atol=1e-6)
    np.testing.assert_allclose(np.asarray(b["stop"]), np.asarray(c["stop"]), atol=1e-6)
    assert np.asarray(c["decision"]).shape == (2, 7, 1)
    assert StepPolicy.from_keras(plain).stop_probability is None
    # control does not use the decision output: the single-step path still matches
    assert _compare(both, config, rng) < 1e-5


def test_count_input_grows_the_network_without_changing_it_and_steps_match():
    """rebuild_fused_inputs: zero weights for the count, so the grown network drives as before;
    once the count has weights, the single-step path (with counts) still matches the sequence
    model."""
    keras.utils.set_random_seed(8)
    config = NetworkConfig(word_units=4, scan_units=8, fused_units=6, decision_head=True)
    plain = build_network(config)
    config.count_input = True
    grown = rebuild_fused_inputs(plain, config)
    assert has_count_input(grown) and not has_count_input(plain) and has_head(grown, "decision")
    rng = np.random.default_rng(5)
    words = rng.normal(size=(2, 4, config.word_dim)).astype(np.float32)
    scans = rng.random((2, 30, config.beams)).astype(np.float32)
    counts = np.eye(CORNER_CLASSES, dtype=np.float32)[rng.integers(0, CORNER_CLASSES, (2, 30))]
    before = plain.predict_on_batch({"words": words, "scans": scans})
    after = grown.predict_on_batch({"words": words, "scans": scans, "counts": counts})
    np.testing.assert_allclose(np.asarray(after["velocity"]), np.asarray(before["velocity"]),
                               atol=1e-6)
    kernel, recurrent, bias = grown.get_layer("lstm_fused").get_weights()
    kernel[-CORNER_CLASSES:] = rng.normal(0.0, 0.5, (CORNER_CLASSES, kernel.shape[1]))
    grown.get_layer("lstm_fused").set_weights([kernel, recurrent, bias])
    out = grown.predict_on_batch({"words": words, "scans": scans, "counts": counts})
    assert np.abs(np.asarray(out["velocity"]) - np.asarray(before["velocity"])).max() > 1e-3
    policy = StepPolicy.from_keras(grown)
    assert policy.config.count_input
    z_w = policy.classify(words[0])
    steps = np.array([policy.step(z_w, scans[0, i], counts[0, i]) for i in range(30)])
    np.testing.assert_allclose(steps, np.asarray(out["velocity"])[0], atol=1e-5)
    with pytest.raises(ValueError, match="needs counts"):
        policy.step(z_w, scans[0, 0])


def test_learned_counting_drops_the_count_input_and_adds_the_counting_input_and_head():
    """From a count-input network to one that counts itself: the count's kernel rows dropped
    (it drives as the old one given a count of all zeros), zero rows for the counting mode, a
    softmax count output; the single-step path matches, reports what it counts and asks for
    the mode."""
    keras.utils.set_random_seed(9)
    config = NetworkConfig(word_units=4, scan_units=8, fused_units=6, stop_head=True,
                           count_input=True)
    counted = build_network(config)
    learned = NetworkConfig(counting_input=True, count_head=True)
    model = rebuild_fused_inputs(counted, learned)
    assert not has_count_input(model) and has_counting_input(model)
    assert has_head(model, "count") and has_head(model, "stop")
    assert (learned.word_units, learned.scan_units, learned.fused_units) == (4, 8, 6)
    rng = np.random.default_rng(6)
    words = rng.normal(size=(2, 4, config.word_dim)).astype(np.float32)
    scans = rng.random((2, 25, config.beams)).astype(np.float32)
    zeros = np.zeros((2, 25, CORNER_CLASSES), np.float32)
    mode = np.zeros((2, 25, COUNTING_MODES), np.float32)
    mode[:, :, 1] = 1.0
    before = counted.predict_on_batch({"words": words, "scans": scans, "counts": zeros})
    after = model.predict_on_batch({"words": words, "scans": scans, "counting": mode})
    np.testing.assert_allclose(np.asarray(after["velocity"]), np.asarray(before["velocity"]),
                               atol=1e-6)
    assert np.asarray(after["count"]).shape == (2, 25, CORNER_CLASSES)
    np.testing.assert_allclose(np.asarray(after["count"]).sum(axis=2), 1.0, atol=1e-5)
    kernel, recurrent, bias = model.get_layer("lstm_fused").get_weights()
    kernel[-COUNTING_MODES:] = rng.normal(0.0, 0.5, (COUNTING_MODES, kernel.shape[1]))
    model.get_layer("lstm_fused").set_weights([kernel, recurrent, bias])
    assert _compare(model, learned, rng) < 1e-5
    policy = StepPolicy.from_keras(model)
    assert policy.config.counting_input and not policy.config.count_input
    z_w = policy.classify(words[0])
    policy.step(z_w, scans[0, 0], counting=mode[0, 0])
    out = model.predict_on_batch({"words": words, "scans": scans[:, :1], "counting": mode[:, :1]})
    assert policy.counted == int(np.argmax(np.asarray(out["count"])[0, 0]))
    with pytest.raises(ValueError, match="needs counting"):
        policy.step(z_w, scans[0, 0])


def test_interpolate_weights_mixes_every_layer_and_keeps_the_ends():
    """WiSE-FT (Eq. 1): α = 0 gives the base model's outputs, α = 1 the fine-tune's, and every
    array in between is (1 − α) base + α tuned; models of different shape are refused by name."""
    config = NetworkConfig(word_units=4, scan_units=8, fused_units=6, stop_head=True)
    keras.utils.set_random_seed(3)
    base = build_network(config)
    keras.utils.set_random_seed(4)
    tuned = build_network(config)
    rng = np.random.default_rng(2)
    inputs = {"words": rng.normal(size=(2, 3, config.word_dim)).astype(np.float32),
              "scans": rng.random((2, 12, config.beams)).astype(np.float32)}

    def outputs_with(mixed):
        model = build_network(config)
        for name, weights in mixed.items():
            model.get_layer(name).set_weights(weights)
        return np.asarray(model.predict_on_batch(inputs)["velocity"])

    for alpha, model in ((0.0, base), (1.0, tuned)):
        np.testing.assert_allclose(outputs_with(interpolate_weights(base, tuned, alpha)),
                                   np.asarray(model.predict_on_batch(inputs)["velocity"]),
                                   atol=1e-6)
    mixed = interpolate_weights(base, tuned, 0.25)
    assert set(mixed) == {layer.name for layer in tuned.layers if layer.get_weights()}
    kernel_b, kernel_t = (m.get_layer("lstm_fused").get_weights()[0] for m in (base, tuned))
    assert not np.allclose(kernel_b, kernel_t)
    np.testing.assert_allclose(mixed["lstm_fused"][0], 0.75 * kernel_b + 0.25 * kernel_t,
                               rtol=1e-6)
    wider = build_network(NetworkConfig(word_units=4, scan_units=9, fused_units=6,
                                        stop_head=True))
    with pytest.raises(ValueError, match="'fc_scan'"):
        interpolate_weights(base, wider, 0.5)
    headless = build_network(NetworkConfig(word_units=4, scan_units=8, fused_units=6))
    with pytest.raises(ValueError, match="'stop' of the fine-tuned model is not in the base"):
        interpolate_weights(headless, tuned, 0.5)
    with pytest.raises(ValueError, match="alpha"):
        interpolate_weights(base, tuned, 1.5)


def test_a_missing_model_names_make_train(tmp_path):
    with pytest.raises(FileNotFoundError,
                       match=r"model .*none\.keras not found: run `make train ARGS=--install`"):
        load_network(tmp_path / "none.keras")


@pytest.mark.parametrize("content", [b"garbage\n", b"PK\x03\x04" + b"\x00" * 100])
def test_a_file_that_is_not_a_keras_archive_is_named_corrupt_not_missing(tmp_path, content):
    path = tmp_path / "broken.keras"
    path.write_bytes(content)
    with pytest.raises(ModelFileError) as caught:
        load_network(path)
    message = str(caught.value)
    assert message.startswith(f"semantic_nav model {path} is corrupt or unreadable (not a "
                              ".keras zip archive: BadZipFile: ")
    assert "not found" not in message and "make train" in message


def test_a_zip_that_is_not_a_network_names_the_keras_error(tmp_path):
    path = tmp_path / "other.keras"
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("notes.txt", "not a model")
    with pytest.raises(ModelFileError, match=r"is corrupt or unreadable \(Keras: KeyError: "):
        load_network(path)


@pytest.mark.skipif(not DEFAULT_MODEL.is_file(), reason="no committed default model")
@pytest.mark.parametrize("damage", ["truncate", "flip"])
def test_a_damaged_default_model_is_named_corrupt(tmp_path, damage):
    data = bytearray(DEFAULT_MODEL.read_bytes())
    if damage == "truncate":
        data = data[:len(data) // 2]
    else:
        data[len(data) // 2] ^= 0xFF                     # inside the weights member
    path = tmp_path / "default.keras"
    path.write_bytes(bytes(data))
    with pytest.raises(ModelFileError, match=rf"^semantic_nav model {path} is corrupt"):
        load_network(path)


def _numpy_lstm(x, kernel, recurrent, bias):
    """Independent reference: the LSTM equations (Hochreiter & Schmidhuber 1997; gates i, f, c, o
    in Keras' column order) stepped in float64 over x (batch, T, d) from zero state."""
    batch, steps, _ = x.shape
    units = recurrent.shape[0]
    h, c = np.zeros((batch, units)), np.zeros((batch, units))
    out = np.empty((batch, steps, units))
    gate = lambda z: 1.0 / (1.0 + np.exp(-z))  # noqa: E731
    for t in range(steps):
        z = x[:, t] @ kernel + h @ recurrent + bias
        i, f, g, o = np.split(z, 4, axis=1)
        c = gate(f) * c + gate(i) * np.tanh(g)
        h = gate(o) * np.tanh(c)
        out[:, t] = h
    return out


@pytest.mark.parametrize("model_file", ["default.keras", "bc.keras"])
def test_lstm_fused_of_the_committed_models_matches_the_lstm_equations(model_file):
    path = DEFAULT_MODEL.parent / model_file
    if not path.is_file():
        pytest.skip(f"no committed model {model_file}")
    layer = load_network(str(path)).get_layer("lstm_fused")
    assert isinstance(layer, SequenceLSTM)
    kernel, recurrent, bias = (w.astype(np.float64) for w in layer.get_weights())
    x = np.random.default_rng(4).normal(size=(2, 60, kernel.shape[0])).astype(np.float32)
    out = keras.ops.convert_to_numpy(layer(x))
    np.testing.assert_allclose(out, _numpy_lstm(x.astype(np.float64), kernel, recurrent, bias),
                               atol=2e-5)


def test_sequence_lstm_gradients_reach_its_keras_weights():
    import torch
    keras.utils.set_random_seed(5)
    layer = SequenceLSTM(6)
    x = torch.tensor(np.random.default_rng(6).normal(size=(2, 7, 3)), dtype=torch.float32)
    layer.build(x.shape)
    loss = (layer(x) ** 2).sum()
    grads = torch.autograd.grad(loss, [w.value for w in (layer.kernel, layer.recurrent_kernel,
                                                         layer.bias)])
    assert all(float(g.abs().sum()) > 0.0 for g in grads)
    # the bias gradient by central differences on the independent equations, in float64
    kernel, recurrent, bias = (w.astype(np.float64) for w in layer.get_weights())
    x64, eps = x.numpy().astype(np.float64), 1e-6
    for index in (0, 7, 13, 20):            # one entry of each gate (units = 6)
        step = np.zeros_like(bias)
        step[index] = eps
        numeric = ((_numpy_lstm(x64, kernel, recurrent, bias + step) ** 2).sum()
                   - (_numpy_lstm(x64, kernel, recurrent, bias - step) ** 2).sum()) / (2 * eps)
        assert float(grads[2][index]) == pytest.approx(numeric, rel=1e-3, abs=1e-4)
