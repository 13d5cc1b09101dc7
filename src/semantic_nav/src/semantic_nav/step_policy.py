"""The trained network in numpy for control (thesis 002 §2.2.4, Fig. 2.2.4), without Keras.

`StepPolicy` re-implements the network of `network.build_network` in numpy (float64): classify a
simple instruction once (LSTM_w, softmax Z_w), then one scan in, one command out (FC ReLU Z_s,
LSTM_fused with its state kept between steps, linear (v, ω)). `load_step_policy` reads a saved
.keras file's weights with h5py alone, so the control node imports neither Keras nor torch
(`network` needs them to build, train and save models; it re-exports what is here).
"""
import io
import json
import os
import re
import zipfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from semantic_nav.instruction_classes import COUNTINGS, NUM_CLASSES

if TYPE_CHECKING:
    import keras

CORNER_CLASSES = 4  # count input: 0, 1, 2, 3 or more (corner_count.CornerCountConfig.max_count)
COUNTING_MODES = len(COUNTINGS)   # counting input: corners over both sides, one side's branches


@dataclass
class NetworkConfig:
    """Layer sizes of Fig. 2.2.4 (kept small: CPU training, a model file of a few hundred kB)."""

    word_dim: int = 50        # GloVe dimension (6B-50d cache; the seed used 100)
    beams: int = 881          # canonical scan length (laser_layer: UTM-30LX steps 100 … 980)
    word_units: int = 32      # LSTM_w state size
    scan_units: int = 64      # width of the FC ReLU layer (Z_s)
    fused_units: int = 64     # LSTM_fused state size
    class_loss_weight: float = 0.2   # weight of the Z_w cross-entropy next to the (v, ω) MSE
    learning_rate: float = 2e-3      # Adam
    stop_head: bool = False          # beyond the seed: sigmoid "standing at the goal" output
    stop_loss_weight: float = 1.0    # weight of its binary cross-entropy
    decision_head: bool = False      # beyond the seed: "distance to the decision" output
    decision_loss_weight: float = 0.05  # weight of its MSE (targets in [0, 1])
    count_input: bool = False        # beyond the seed: corners counted so far as an input
    counting_input: bool = False     # beyond the seed: the counting mode as an input (one-hot)
    count_head: bool = False         # beyond the seed: softmax "corners passed so far" output
    count_loss_weight: float = 0.005  # weight of its cross-entropy: about 1.4 at first next
    #                                   to a velocity MSE of about 0.002; at 0.1 it rewired
    #                                   LSTM_fused (the closed loop fell from 439 to 227 of 490
    #                                   validation goals in one epoch, every class alike)


def sigmoid(x: NDArray[np.float64]) -> NDArray[np.float64]:
    return 1.0 / (1.0 + np.exp(-x))


def softmax(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Eq. 2.2-11 (first): sigma(Z)_i = e^{z_i} / sum_k e^{z_k}."""
    e = np.exp(z - np.max(z, axis=-1, keepdims=True))
    return e / np.sum(e, axis=-1, keepdims=True)


def relu(z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Eq. 2.2-11 (second): sigma(Z)_i = max(0, z_i)."""
    return np.maximum(z, 0.0)


def lstm_step(x: NDArray[np.float64], h: NDArray[np.float64], c: NDArray[np.float64],
              kernel: NDArray[np.float64], recurrent: NDArray[np.float64],
              bias: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """One LSTM step (Keras gate order i, f, c, o; tanh / sigmoid) -> (h, c)."""
    gates = x @ kernel + h @ recurrent + bias
    i, f, g, o = np.split(gates, 4, axis=-1)
    c = sigmoid(f) * c + sigmoid(i) * np.tanh(g)
    return sigmoid(o) * np.tanh(c), c


class StepPolicy:
    """The trained network in numpy (float64): classify once, then one command per scan."""

    def __init__(self, weights: Mapping[str, ArrayLike], config: NetworkConfig) -> None:
        self.config = config
        self.w = {name: np.asarray(value, dtype=np.float64) for name, value in weights.items()}
        self.reset()

    @classmethod
    def from_keras(cls, model: "keras.Model", config: NetworkConfig | None = None) -> "StepPolicy":
        """Copy the weights of a Keras model built by build_network."""
        weights: dict[str, np.ndarray] = {}
        for layer in ("lstm_w", "lstm_fused"):
            kernel, recurrent, bias = model.get_layer(layer).get_weights()
            weights.update({f"{layer}/kernel": kernel, f"{layer}/recurrent": recurrent,
                            f"{layer}/bias": bias})
        names = {layer.name for layer in model.layers}
        heads = ("instruction_class", "fc_scan", "velocity") + tuple(
            head for head in ("stop", "count") if head in names)
        for layer in heads:
            kernel, bias = model.get_layer(layer).get_weights()
            weights.update({f"{layer}/kernel": kernel, f"{layer}/bias": bias})
        return cls.from_weights(weights, config)

    @classmethod
    def from_weights(cls, weights: Mapping[str, np.ndarray],
                     config: NetworkConfig | None = None) -> "StepPolicy":
        """From {"<layer>/kernel" | "/recurrent" | "/bias": array}; the layer sizes (config)
        follow from the arrays' shapes unless given."""
        if config is None:
            config = NetworkConfig(
                word_dim=weights["lstm_w/kernel"].shape[0],
                beams=weights["fc_scan/kernel"].shape[0],
                word_units=weights["lstm_w/recurrent"].shape[0],
                scan_units=weights["fc_scan/kernel"].shape[1],
                fused_units=weights["lstm_fused/recurrent"].shape[0],
                stop_head="stop/kernel" in weights,
                **fused_extras(weights["lstm_fused/kernel"].shape[0]
                               - NUM_CLASSES - weights["fc_scan/kernel"].shape[1]))
        return cls(weights, config)

    def reset(self) -> None:
        """Clear the LSTM_fused memory (§2.2.5.2: a new simple instruction starts)."""
        units = self.config.fused_units
        self.h, self.c = np.zeros(units), np.zeros(units)
        self.stop_probability: float | None = None
        self.counted: int | None = None      # the count head's corners passed (None: no head)

    def classify(self, word_vectors: ArrayLike) -> NDArray[np.float64]:
        """LSTM_w over the word vectors (n, word_dim) of one simple instruction -> Z_w (10,)."""
        w = self.w
        h = c = np.zeros(self.config.word_units)
        for x in np.asarray(word_vectors, dtype=np.float64):
            h, c = lstm_step(x, h, c, w["lstm_w/kernel"], w["lstm_w/recurrent"], w["lstm_w/bias"])
        return softmax(h @ w["instruction_class/kernel"] + w["instruction_class/bias"])

    def step(self, z_w: NDArray[np.float64], scan: ArrayLike,
             counts: ArrayLike | None = None,
             counting: ArrayLike | None = None) -> tuple[float, float]:
        """One control step: Z_w and one preprocessed scan (beams,) -> (v, ω); state kept.
        With a stop head, `stop_probability` holds its output for this step (else None), with
        a count head `counted` the corners it has passed. A network with the count input needs
        `counts` (one-hot, CORNER_CLASSES), one with the counting input `counting` (one-hot,
        COUNTING_MODES: instruction_classes.COUNTINGS)."""
        w = self.w
        z_s = relu(np.asarray(scan, dtype=np.float64) @ w["fc_scan/kernel"] + w["fc_scan/bias"])
        parts = [z_w, z_s]
        if self.config.count_input:
            if counts is None:
                raise ValueError("this network has the corner-count input: step() needs counts")
            parts.append(np.asarray(counts, dtype=np.float64))
        if self.config.counting_input:
            if counting is None:
                raise ValueError("this network has the counting-mode input: step() needs "
                                 "counting")
            parts.append(np.asarray(counting, dtype=np.float64))
        x = np.concatenate(parts)
        self.h, self.c = lstm_step(x, self.h, self.c, w["lstm_fused/kernel"],
                                   w["lstm_fused/recurrent"], w["lstm_fused/bias"])
        out = self.h @ w["velocity/kernel"] + w["velocity/bias"]
        if "stop/kernel" in w:
            self.stop_probability = float(sigmoid(self.h @ w["stop/kernel"] + w["stop/bias"])[0])
        if "count/kernel" in w:      # what the network counts (diagnostics; control ignores it)
            self.counted = int(np.argmax(self.h @ w["count/kernel"] + w["count/bias"]))
        return float(out[0]), float(out[1])


def fused_extras(rows: int) -> dict[str, bool]:
    """The inputs beside [Z_w, Z_s] that `rows` extra rows of LSTM_fused's kernel hold ->
    NetworkConfig fields (count_input, counting_input); ValueError for another number."""
    for count in (False, True):
        for counting in (False, True):
            if rows == CORNER_CLASSES * count + COUNTING_MODES * counting:
                return {"count_input": count, "counting_input": counting}
    raise ValueError(f"LSTM_fused has {rows} input rows beyond Z_w and Z_s: not one of our "
                     "networks")


class ModelFileError(ValueError):
    """A model file that exists but cannot be loaded (corrupt, truncated, not a .keras archive,
    or not one of our networks); the message names the file and the underlying error."""


FIX = ("restore it (`git checkout -- models/semantic_nav/` for the committed models) or "
       "rebuild it with `make train ARGS=--install`")


def check_model_file(path: str | os.PathLike[str]) -> str:
    """A .keras file that is there and a whole zip archive -> the advice for a file that then
    fails to load; FileNotFoundError naming `make train` if missing, ModelFileError if not a
    zip archive or a member fails its CRC check."""
    path = str(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"semantic_nav model {path} not found: run "
                                "`make train ARGS=--install` (or pass a model path)")
    try:
        with zipfile.ZipFile(path) as archive:
            damaged = archive.testzip()      # the first member whose CRC does not match
    except (zipfile.BadZipFile, OSError, EOFError) as error:
        raise ModelFileError(f"semantic_nav model {path} is corrupt or unreadable (not a "
                             f".keras zip archive: {type(error).__name__}: {error}); "
                             f"{FIX}") from error
    if damaged is not None:
        raise ModelFileError(f"semantic_nav model {path} is corrupt (member {damaged!r} fails "
                             f"its CRC check); {FIX}")
    return FIX


# the layers the node runs (the count head for what it reports: control ignores it)
CONTROL_LAYERS = ("lstm_w", "lstm_fused", "instruction_class", "fc_scan", "velocity", "stop",
                  "count")
RECURRENT = ("lstm_w", "lstm_fused")


def _snake_case(name: str) -> str:
    """Keras' to_snake_case: "SequenceLSTM" -> "sequence_lstm", "LSTM" -> "lstm"."""
    name = re.sub(r"(.)([A-Z][a-z]+)", r"\1_\2", name)
    return re.sub(r"([a-z])([A-Z])", r"\1_\2", name).lower()


def weight_groups(layers: Iterable[tuple[str, str]]) -> dict[str, str]:
    """Where Keras 3 stores each layer's variables in model.weights.h5: the layers of config.json
    in order, named by their class in snake case with _1, _2, ... for repeats (an LSTM's under
    its cell). [(class name, layer name)] -> {layer name: group path}."""
    seen: dict[str, int] = {}
    groups: dict[str, str] = {}
    for class_name, name in layers:
        base = _snake_case(class_name)
        count = seen.get(base, 0)
        seen[base] = count + 1
        path = f"layers/{base}" + (f"_{count}" if count else "")
        groups[name] = path + ("/cell" if class_name == "LSTM" else "")
    return groups


def read_keras_weights(path: str | os.PathLike[str]) -> dict[str, np.ndarray]:
    """The control layers' weights of a saved .keras model, read with h5py (no Keras):
    {"<layer>/kernel" | "/recurrent" | "/bias": array}."""
    import h5py
    check_model_file(path)
    try:
        with zipfile.ZipFile(path) as archive:
            config = json.loads(archive.read("config.json"))
            data = io.BytesIO(archive.read("model.weights.h5"))
        layers = [(layer["class_name"], layer["config"]["name"])
                  for layer in config["config"]["layers"]]
        groups = weight_groups(layers)
        weights: dict[str, np.ndarray] = {}
        with h5py.File(data, "r") as h5:
            for name in CONTROL_LAYERS:
                if name not in groups:
                    continue
                values = h5[f"{groups[name]}/vars"]
                arrays = [np.asarray(values[str(k)]) for k in range(len(values))]
                keys = ("kernel", "recurrent", "bias") if name in RECURRENT else ("kernel", "bias")
                weights.update({f"{name}/{key}": array for key, array in zip(keys, arrays,
                                                                               strict=True)})
        for name in ("lstm_w", "lstm_fused", "instruction_class", "fc_scan", "velocity"):
            if f"{name}/kernel" not in weights:
                raise KeyError(f"no layer {name!r}")
    except (KeyError, ValueError, OSError, TypeError) as error:
        raise ModelFileError(f"semantic_nav model {path} is corrupt or unreadable (not one of "
                             f"our networks: {type(error).__name__}: {error}); {FIX}") from error
    return weights


def load_step_policy(path: str | os.PathLike[str]) -> StepPolicy:
    """A StepPolicy of the saved .keras model at `path`, without Keras."""
    return StepPolicy.from_weights(read_keras_weights(path))
