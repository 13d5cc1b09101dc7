"""The direction-following control loop (thesis 002 §2.2, Fig. 2.2.1) without ROS: a sentence is
split into simple instructions (§2.2.3), each is classified once by LSTM_w, and every control step
turns one laser scan (any laser: laser layer §2.2.2) into a post-processed command (§2.2.5) until
the halting counter has ended every simple instruction.

    follower = DirectionFollower.from_files()          # models/semantic_nav/default.keras
    follower.start("go straight to the end, then turn left")
    every follower.control_period seconds: command = follower.step(scan.ranges, laser_model)
"""
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from semantic_nav.instruction_layer import InstructionError, sentence_vector, split_instruction
from semantic_nav.laser_layer import load_laser_config
from semantic_nav.postprocess import HaltingCounter, PostprocessConfig, adjust_speed, apply_stop

ROOT = Path(__file__).resolve().parents[4]
DEFAULT_MODEL = ROOT / "models" / "semantic_nav" / "default.keras"
DEFAULT_LASER_CONFIG = ROOT / "config" / "semnav_laser.yaml"


class UnknownInstructionError(ValueError):
    """A sentence the instruction layer cannot turn into word vectors (no known word)."""


class ModelMissingError(FileNotFoundError):
    """No trained model file; the message names `make train`."""


@dataclass
class FollowerConfig:
    """Control loop settings."""

    control_period: float = 0.1     # s between steps (the records are subsampled to 10 Hz)
    laser_config: str = str(DEFAULT_LASER_CONFIG)   # canonical scan + preprocessing
    postprocess: PostprocessConfig = field(default_factory=PostprocessConfig)


@dataclass
class FollowerCommand:
    """What one control step decided."""

    v: float                # m/s, after post-processing
    w: float                # rad/s, after post-processing
    index: int              # current simple instruction, 0-based
    predicted_class: int    # 1..10 (argmax Z_w) of the current simple instruction
    done: bool              # every simple instruction has halted


def _step_policy(model):
    """A StepPolicy, a Keras model of build_network, or anything with classify, step, reset."""
    if all(hasattr(model, name) for name in ("classify", "step", "reset")):
        return model
    from semantic_nav.network import StepPolicy
    return StepPolicy.from_keras(model)


class DirectionFollower:
    """Sentence + scans -> velocity commands, one simple instruction after the other."""

    def __init__(self, model, word_vectors, config=None):
        self.config = config or FollowerConfig()
        self.control_period = self.config.control_period
        self.policy = _step_policy(model)
        self.word_vectors = word_vectors
        _, self.canonical, self.preprocess = load_laser_config(self.config.laser_config)
        self.halting = HaltingCounter(self.config.postprocess)
        self.instructions, self.z_w, self.classes = [], [], []
        self.unknown_words = []
        self.index = 0

    @classmethod
    def from_files(cls, model_path=None, word_vectors=None, config=None):
        """Load a .keras model (default models/semantic_nav/default.keras) and the GloVe vectors
        (a WordVectors, a GloVe file / cache directory, or None for the default cache)."""
        path = Path(model_path or os.environ.get("SEMNAV_MODEL", DEFAULT_MODEL))
        if not path.is_file():
            raise ModelMissingError(
                f"semantic_nav model {path} not found: run `make train` (or pass a model path)")
        from semantic_nav.network import StepPolicy, load_network
        from semantic_nav.word_vectors import WordVectors, load_word_vectors
        policy = StepPolicy.from_keras(load_network(str(path)))
        if not isinstance(word_vectors, WordVectors):
            word_vectors = load_word_vectors(word_vectors)
        return cls(policy, word_vectors, config)

    def start(self, sentence):
        """Split and classify a sentence; resets memory. Returns the class (1..10) of each simple
        instruction. UnknownInstructionError if a simple instruction has no known word."""
        try:
            parts = split_instruction(sentence)
        except InstructionError as error:
            raise UnknownInstructionError(str(error)) from error
        vectors, unknown = [], []
        for part in parts:
            try:
                converted = sentence_vector(part, self.word_vectors)
            except InstructionError as error:
                raise UnknownInstructionError(
                    f"unknown instruction {part!r} (in {sentence!r}): {error}") from error
            vectors.append(converted.vectors)
            unknown.extend(converted.oov)
        self.instructions = parts
        self.z_w = [self.policy.classify(v) for v in vectors]
        self.classes = [int(np.argmax(z)) + 1 for z in self.z_w]
        self.unknown_words = unknown
        self.index = 0
        self.policy.reset()
        self.halting.reset()
        return list(self.classes)

    @property
    def done(self):
        return bool(self.instructions) and self.index >= len(self.instructions)

    def step(self, ranges, laser):
        """One control step: raw ranges of `laser` (laser_layer.LaserModel) -> FollowerCommand.

        Scans of any beam count are interpolated to the canonical scan (laser_layer.ScanError
        if that is impossible)."""
        from semantic_nav.laser_layer import preprocess_scan
        if not self.instructions:
            raise RuntimeError("DirectionFollower.step before start(sentence)")
        if self.done:
            return self._command(0.0, 0.0)
        scan, _ = preprocess_scan(ranges, laser, self.canonical, self.preprocess)
        raw_v, raw_w = apply_stop(*self.policy.step(self.z_w[self.index], scan),
                                  getattr(self.policy, "stop_probability", None),
                                  self.config.postprocess)
        v = adjust_speed(raw_v, self.config.postprocess)
        w = adjust_speed(raw_w, self.config.postprocess)
        if self.halting.update(v, w):
            self.index += 1             # §2.2.5.2: next simple instruction, memory cleared
            self.policy.reset()
        return self._command(v, w)

    def _command(self, v, w):
        current = min(self.index, len(self.instructions) - 1)
        return FollowerCommand(v=v, w=w, index=current, predicted_class=self.classes[current],
                               done=self.done)
