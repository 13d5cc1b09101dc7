"""Neural network model (thesis 002 §2.2.4, Fig. 2.2.4) in Keras 3 and its single-step numpy twin.

Stage 1: LSTM_w reads the word vectors (w_1 … w_n) of one simple instruction; a softmax over the
basic instruction classes (instruction_classes.CLASSES, ten) gives the instruction vector Z_w
(Eq. 2.2-11, softmax).
Stage 2: a fully connected ReLU layer turns each preprocessed scan (l_i1 … l_iN) into Z_si
(Eq. 2.2-11, ReLU); [Z_w, Z_si] goes into LSTM_fused, whose linear output is (v, ω).

Array layouts: words (batch, n_words, word_dim), padded with all-zero vectors (masked);
scans (batch, T, beams) at the control rate; velocity (batch, T, 2) = (v [m/s], ω [rad/s]);
instruction_class (batch, 10) = Z_w, class c (1..10) at index c - 1.

Beyond the seed (optional, `NetworkConfig.stop_head`): a sigmoid output `stop` (batch, T, 1) on
LSTM_fused, trained with binary cross-entropy on "the expert stands still here" (zero labels). A
linear (v, ω) regression is never within the 1e-3 of Eq. 2.2-12 near the goal (its error is a few
cm/s), so the halting counter never starts; the stop output turns "stop now" into a
classification the post-processing can act on (postprocess.apply_stop).

Beyond the seed (optional, `NetworkConfig.decision_head`): a linear output `decision`
(batch, T, 1) on LSTM_fused, trained with MSE on the distance the expert still drives before
its decision (its turn, or its stop), over `TrainingConfig.decision_horizon`
(training.decision_distance).
An auxiliary task: "turn left at the third corner" is decided in a few steps, but this target
asks at every step how far that corner still is, so LSTM_fused must keep count of the corners
passed. Control does not use it.

Beyond the seed (optional, `NetworkConfig.count_input`): a third input `counts` (batch, T,
CORNER_CLASSES), the one-hot number of corners counted so far over both sides from the side
beams (corner_count.CornerCounter, the same counter in training and control), joins [Z_w, Z_s]
at LSTM_fused. Counting is then done outside the network: it only has to tie the count to the
instruction's corner number.

Beyond the seed, learned counting (optional, `NetworkConfig.counting_input` and `count_head`):
the network counts the corners itself. A third input `counting` (batch, T, COUNTING_MODES)
says how "the second right" counts (instruction_classes.COUNTINGS: the corners over both sides
or the branches on the turning side only), and a softmax output `count` (batch, T,
CORNER_CLASSES), trained on the corners the counter finds in the demonstrations' scans in that
mode (supervision at training time only; control ignores it), makes LSTM_fused keep the count.

`step_policy.StepPolicy` (re-exported here) re-implements the trained network in numpy for
control: classify a simple instruction once, then one scan in, one command out, with the
LSTM_fused state kept between steps; `step_policy.load_step_policy` reads a saved model without
Keras.
"""
import functools
import os
import threading
from collections.abc import Sequence
from dataclasses import asdict
from typing import TYPE_CHECKING, Any

import numpy as np

os.environ.setdefault("KERAS_BACKEND", "torch")
import keras  # noqa: E402  (the backend must be chosen before the import)

from semantic_nav.instruction_classes import NUM_CLASSES  # noqa: E402  (Table 3.1-1: ten)
from semantic_nav.step_policy import (CORNER_CLASSES, COUNTING_MODES,  # noqa: E402,F401
                                      ModelFileError, NetworkConfig, StepPolicy,
                                      check_model_file, lstm_step, relu, sigmoid, softmax)

if TYPE_CHECKING:
    import torch


@keras.saving.register_keras_serializable(package="semantic_nav")
class ConcatOverTime(keras.layers.Layer):
    """[Z_w (batch, k), Z_s (batch, T, m)] -> (batch, T, k + m): Z_w repeated at every step."""

    def call(self, inputs: Sequence["torch.Tensor"]) -> "torch.Tensor":
        z_w, z_s = inputs
        steps = keras.ops.shape(z_s)[1]
        tiled = keras.ops.repeat(keras.ops.expand_dims(z_w, 1), steps, axis=1)
        return keras.ops.concatenate([tiled, z_s], axis=-1)

    def compute_output_shape(
            self, input_shapes: tuple[tuple[int | None, int], tuple[int | None, int | None, int]]
    ) -> tuple[int | None, int | None, int]:
        (batch, k), (_, steps, m) = input_shapes
        return (batch, steps, k + m)


@functools.cache
def _lstm_shell(input_size: int, units: int, thread: int) -> "torch.nn.LSTM":
    """A one-layer, batch-first torch.nn.LSTM without weights of its own (meta device), one per
    thread (torch.func.functional_call swaps parameters in and out of the module it runs)."""
    import torch
    return torch.nn.LSTM(input_size, units, batch_first=True, device="meta")


@keras.saving.register_keras_serializable(package="semantic_nav")
class SequenceLSTM(keras.layers.Layer):
    """An LSTM returning the whole output sequence, with Keras' weights and gate order (i, f, c, o)
    but run by `torch.nn.LSTM` (whose gate order i, f, g, o is the same) through
    `torch.func.functional_call` on the layer's own variables, so gradients reach them and the
    weights stay Keras' (kernel, recurrent_kernel, bias). keras.layers.LSTM on the torch backend
    steps a Python loop on the CPU, about ten times slower for the hundreds of steps of a
    demonstration. (Hochreiter & Schmidhuber, "Long short-term memory", Neural Comput. 9(8),
    1997; https://pytorch.org/docs/stable/generated/torch.nn.LSTM.html)"""

    def __init__(self, units: int, **kwargs: Any) -> None:   # kwargs: keras.layers.Layer's own
        super().__init__(**kwargs)
        self.units = units

    def build(self, input_shape: tuple[int | None, ...]) -> None:
        units = self.units
        self.kernel = self.add_weight(shape=(input_shape[-1], 4 * units), name="kernel",
                                      initializer="glorot_uniform")
        self.recurrent_kernel = self.add_weight(shape=(units, 4 * units), name="recurrent_kernel",
                                                initializer="orthogonal")
        # unit forget bias, as keras.layers.LSTM
        forget = np.concatenate([np.zeros(units), np.ones(units), np.zeros(2 * units)])
        self.bias = self.add_weight(shape=(4 * units,), name="bias",
                                    initializer=keras.initializers.Constant(forget))

    def call(self, inputs: "torch.Tensor") -> "torch.Tensor":
        import torch
        from torch.func import functional_call
        batch = inputs.shape[0]
        zeros = torch.zeros(1, batch, self.units, dtype=inputs.dtype, device=inputs.device)
        bias = self.bias.value
        weights = {"weight_ih_l0": self.kernel.value.t().contiguous(),
                   "weight_hh_l0": self.recurrent_kernel.value.t().contiguous(),
                   "bias_ih_l0": bias, "bias_hh_l0": torch.zeros_like(bias)}
        shell = _lstm_shell(inputs.shape[-1], self.units, threading.get_ident())
        output, _ = functional_call(shell, weights, (inputs, (zeros, zeros)))
        return output

    def compute_output_shape(self, input_shape: tuple[int | None, ...]) -> tuple[int | None, ...]:
        return (*input_shape[:-1], self.units)

    def get_config(self) -> dict[str, Any]:   # Keras' layer config: JSON-like values
        return {**super().get_config(), "units": self.units}


def build_network(config: NetworkConfig | None = None) -> keras.Model:
    """Fig. 2.2.4 as a Keras model: {words, scans} -> {velocity, instruction_class}, compiled
    with the MSE of §4.1.1 on (v, ω) plus the cross-entropy on Z_w."""
    config = config or NetworkConfig()
    words = keras.Input((None, config.word_dim), name="words")
    scans = keras.Input((None, config.beams), name="scans")
    masked = keras.layers.Masking(0.0, name="word_mask")(words)
    h_w = keras.layers.LSTM(config.word_units, name="lstm_w")(masked)
    z_w = keras.layers.Dense(NUM_CLASSES, activation="softmax", name="instruction_class")(h_w)
    z_s = keras.layers.Dense(config.scan_units, activation="relu", name="fc_scan")(scans)
    fused = ConcatOverTime(name="concat")([z_w, z_s])
    inputs = {"words": words, "scans": scans}
    for name, size, layer in FUSED_EXTRAS:
        if getattr(config, f"{name}_input"):
            inputs[INPUT_NAMES[name]] = keras.Input((None, size), name=INPUT_NAMES[name])
            fused = keras.layers.Concatenate(name=layer)([fused, inputs[INPUT_NAMES[name]]])
    h_f = SequenceLSTM(config.fused_units, name="lstm_fused")(fused)
    velocity = keras.layers.Dense(2, name="velocity")(h_f)
    outputs = {"velocity": velocity, "instruction_class": z_w}
    for name in wanted_heads(config):
        outputs[name] = _head_layer(name)(h_f)
    model = keras.Model(inputs, outputs, name="semnav")
    compile_network(model, config)
    return model


# Inputs joined to [Z_w, Z_s] at LSTM_fused, in order: (NetworkConfig field prefix, width,
# Concatenate layer); INPUT_NAMES: the model's input names.
FUSED_EXTRAS = (("count", CORNER_CLASSES, "concat_counts"),
                ("counting", COUNTING_MODES, "concat_counting"))
INPUT_NAMES = {"count": "counts", "counting": "counting"}


def has_count_input(model: keras.Model) -> bool:
    return isinstance(model.input, dict) and "counts" in model.input


def has_counting_input(model: keras.Model) -> bool:
    return isinstance(model.input, dict) and "counting" in model.input


def rebuild_fused_inputs(model: keras.Model, config: NetworkConfig) -> keras.Model:
    """A model of build_network -> the network of `config` with the inputs beside [Z_w, Z_s]
    that `config` asks for (count_input, counting_input), compiled: every weight copied,
    LSTM_fused's kernel rows of an input kept, dropped or added as zeros, so a grown network
    drives exactly as `model` until training gives the new input a weight. The model's sizes
    and heads are kept (`config` is updated with them); a model with the asked inputs is only
    recompiled."""
    config.stop_head = config.stop_head or has_head(model, "stop")
    config.decision_head = config.decision_head or has_head(model, "decision")
    config.count_head = config.count_head or has_head(model, "count")
    has = {"count": has_count_input(model), "counting": has_counting_input(model)}
    if all(has[name] == getattr(config, f"{name}_input") for name in has):
        return add_heads(model, config)
    config.word_dim, config.beams = (model.get_layer(name).input.shape[-1]
                                     for name in ("word_mask", "fc_scan"))
    config.word_units = model.get_layer("lstm_w").units
    config.scan_units = model.get_layer("fc_scan").units
    config.fused_units = model.get_layer("lstm_fused").units
    rebuilt = build_network(config)
    for layer in model.layers:
        weights = layer.get_weights()
        if not weights:
            continue
        if layer.name == "lstm_fused":
            weights[0] = _fused_kernel_rows(weights[0], has, config)
        rebuilt.get_layer(layer.name).set_weights(weights)
    return rebuilt


def _fused_kernel_rows(kernel: np.ndarray, has: dict[str, bool],
                       config: NetworkConfig) -> np.ndarray:
    """LSTM_fused's kernel of a model with the inputs `has` -> the rows of `config`'s inputs."""
    start = NUM_CLASSES + config.scan_units
    blocks = [kernel[:start]]
    for name, size, _ in FUSED_EXTRAS:
        old = kernel[start:start + size] if has[name] else None
        start += size if has[name] else 0
        if getattr(config, f"{name}_input"):
            blocks.append(old if old is not None else np.zeros((size, kernel.shape[1]),
                                                                kernel.dtype))
    return np.concatenate(blocks)


def interpolate_weights(base: keras.Model, tuned: keras.Model,
                        alpha: float) -> dict[str, list[np.ndarray]]:
    """Weight-space ensemble of a model and its fine-tune (beyond the seed; WiSE-FT, Wortsman
    et al., "Robust fine-tuning of zero-shot models", CVPR 2022, Eq. 1):
    θ_α = (1 − α) θ_base + α θ_tuned, layer by layer. A fine-tune that learns a new kind of floor
    can lose some of what its starting model did well; models on one fine-tuning path sit in
    one basin, so the mixture keeps part of both. Returns {layer name: mixed arrays} for every
    layer with weights (set them into a copy of `tuned`); both models must have the same layers
    and weight shapes."""
    if not 0.0 <= alpha <= 1.0:
        raise ValueError(f"interpolation weight alpha must lie in [0, 1], got {alpha}")
    mixed: dict[str, list[np.ndarray]] = {}
    for layer in tuned.layers:
        tuned_weights = layer.get_weights()
        if not tuned_weights:
            continue
        try:
            base_weights = base.get_layer(layer.name).get_weights()
        except ValueError:
            raise ValueError(f"layer {layer.name!r} of the fine-tuned model is not in the base "
                             "model") from None
        shapes = [w.shape for w in base_weights], [w.shape for w in tuned_weights]
        if shapes[0] != shapes[1]:
            raise ValueError(f"layer {layer.name!r}: weight shapes {shapes[0]} in the base "
                             f"model, {shapes[1]} in the fine-tuned one")
        mixed[layer.name] = [((1.0 - alpha) * b + alpha * t).astype(t.dtype)
                             for b, t in zip(base_weights, tuned_weights)]
    return mixed


# Optional outputs on LSTM_fused (beyond the seed): name -> (width, activation, loss)
HEADS = {"stop": (1, "sigmoid", "binary_crossentropy"), "decision": (1, None, "mse"),
         "count": (CORNER_CLASSES, "softmax", "sparse_categorical_crossentropy")}


def _head_layer(name: str) -> keras.layers.Dense:
    width, activation, _ = HEADS[name]
    return keras.layers.Dense(width, activation=activation, name=name)


def wanted_heads(config: NetworkConfig) -> list[str]:
    """The optional outputs `config` asks for, in HEADS order."""
    return [name for name in HEADS if getattr(config, f"{name}_head")]


def has_head(model: keras.Model, name: str) -> bool:
    return any(layer.name == name for layer in model.layers)


def has_stop_head(model: keras.Model) -> bool:
    return has_head(model, "stop")


def add_heads(model: keras.Model, config: NetworkConfig) -> keras.Model:
    """A model of build_network -> the same layers (shared weights) plus the optional outputs
    `config` asks for that it lacks, compiled (fine-tuning a model with a new head). Heads the
    model has are kept."""
    missing = [name for name in wanted_heads(config) if not has_head(model, name)]
    if missing:
        inputs = {"words": model.get_layer("word_mask").input,
                  "scans": model.get_layer("fc_scan").input}
        for name in INPUT_NAMES.values():
            if isinstance(model.input, dict) and name in model.input:
                inputs[name] = model.input[name]
        fused = model.get_layer("lstm_fused").output
        outputs = {name: model.get_layer(name).output for name in
                   ("velocity", "instruction_class", *HEADS) if has_head(model, name)}
        outputs.update({name: _head_layer(name)(fused) for name in missing})
        model = keras.Model(inputs, outputs, name="semnav")
    compile_network(model, config)
    return model


def compile_network(model: keras.Model, config: NetworkConfig) -> None:
    """§4.1.1: MSE on (v, ω); cross-entropy on Z_w; Adam (+ the losses of the optional heads the
    model has: binary cross-entropy on stop, MSE on decision, cross-entropy on count)."""
    loss = {"velocity": "mse", "instruction_class": "sparse_categorical_crossentropy"}
    weights = {"velocity": 1.0, "instruction_class": config.class_loss_weight}
    for name, (_, _, head_loss) in HEADS.items():
        if has_head(model, name):
            loss[name] = head_loss
            weights[name] = getattr(config, f"{name}_loss_weight")
    model.compile(optimizer=keras.optimizers.Adam(config.learning_rate), loss=loss,
                  loss_weights=weights)


def build_classifier(model: keras.Model) -> keras.Model:
    """The first stage alone (words -> Z_w), sharing the layers (and weights) of `model`; compiled
    for extra instruction batches (the phrase sets are far larger than the record set)."""
    words = model.get_layer("word_mask").input
    classifier = keras.Model(words, model.get_layer("instruction_class").output,
                             name="semnav_classifier")
    classifier.compile(optimizer=keras.optimizers.Adam(float(model.optimizer.learning_rate)),
                       loss="sparse_categorical_crossentropy")
    return classifier


def network_config_dict(config: NetworkConfig) -> dict[str, Any]:
    return asdict(config)


def load_network(path: str | os.PathLike[str]) -> keras.Model:
    """Load a saved .keras model (custom layers registered above).

    A missing file is a FileNotFoundError naming it and `make train`; a file that is there but
    cannot be loaded is a ModelFileError naming it as corrupt or unreadable, with the underlying
    error (Keras itself says "File not found" for any file that is not a zip archive)."""
    path = str(path)
    fix = check_model_file(path)
    try:
        return keras.saving.load_model(path, compile=False)
    except Exception as error:  # noqa: BLE001 - Keras raises many kinds; each is named
        raise ModelFileError(f"semantic_nav model {path} is corrupt or unreadable (Keras: "
                             f"{type(error).__name__}: {error}); {fix}") from error
