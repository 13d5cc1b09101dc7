"""The direction-following control loop (thesis 002 §2.2, Fig. 2.2.1) without ROS: a sentence is
split into simple instructions (§2.2.3), each is classified once by LSTM_w, and every control step
turns one laser scan (any laser: laser layer §2.2.2) into a post-processed command (§2.2.5) until
the halting counter has ended every simple instruction.

    follower = DirectionFollower.from_files()          # models/semantic_nav/default.keras
    follower.start("go straight to the end, then turn left")
    every follower.control_period seconds: command = follower.step(scan.ranges, laser_model)
"""
import itertools
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import numpy as np
from numpy.typing import NDArray

from semantic_nav.asking_back import AskConfig
from semantic_nav.collision_guard import (GUARD_ACTIONS, GuardConfig, guard_action,
                                          scan_points, steer_around)
from semantic_nav.doorways import DoorConfig, close_doorways, cut_beam_ends
from semantic_nav.corner_count import CornerCounter, one_hot_counting, one_hot_counts, side_ranges
from semantic_nav.instruction_classes import (CLASS_IDS, COUNT_CORNERS, COUNT_SIDE, SIDE,
                                              STRAIGHT, TURN_CLASSES, get, ids)
from semantic_nav.instruction_layer import (SentenceVector, check_followable, counting_mode,
                                            phrase_vocabulary, sentence_vector, tokenise)
from semantic_nav.laser_layer import LaserModel, load_laser_config
from semantic_nav.misheard import readings, reads_homophones
from semantic_nav.postprocess import HaltingCounter, PostprocessConfig, adjust_speed, apply_stop
from semantic_nav.splitting import SPLITTINGS, TOKEN, InstructionError, split_instruction
from supervision import config_file
from tamp_resources import resource

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

    import keras

    from semantic_nav.step_policy import StepPolicy
    from semantic_nav.word_vectors import WordVectors

ROOT = resource()
DEFAULT_MODEL = ROOT / "models" / "semantic_nav" / "default.keras"
DEFAULT_LASER_CONFIG = ROOT / "config" / "semnav_laser.yaml"
DEFAULT_PHRASES = ROOT / "config" / "semnav_phrases.yaml"


class UnknownInstructionError(ValueError):
    """A sentence the follower will not follow for its words: a simple instruction with no known
    word, or one whose remaining words classify without confidence; `words` are the words it
    did not know."""

    def __init__(self, message: str, words: Iterable[str] = ()) -> None:
        super().__init__(message)
        self.words = list(words)


class ModelMissingError(FileNotFoundError):
    """No trained model file; the message names `make train`."""


@dataclass
class FollowerConfig:
    """Control loop settings."""

    control_period: float = 0.1     # s between steps (the records are subsampled to 10 Hz)
    one_hot_class: bool = True      # beyond the seed: LSTM_fused gets Z_w's class as one-hot
    unknown_min_confidence: float = 0.9   # a simple instruction with words outside the
                                    # vocabulary is followed (those words skipped) only when
                                    # Z_w's largest probability is at least this; else refused
    splitting: str = "spoken"       # splitting.split_instruction: "seed" = at
                                    # punctuation (§3.1); "spoken" also at connectives, with
                                    # motionless pieces joined (beyond the seed)
    side_counting: bool = True      # beyond the seed: "the second right" counts the branches on
                                    # the turning side only (instruction_layer.counting_mode);
                                    # false: every count over both sides (Table 3.1-1)
    side_pass_then_turn: bool = True   # beyond the seed: an instruction counted on one side
                                    # ("take the third left") is driven as class 1 until the
                                    # counter has passed N - 1 branches on that side, then as
                                    # that side's first turn (class 2 / 3); false: the network
                                    # gets the side count and decides
    corner_pass_then_turn: bool = True   # beyond the seed: the same for a count over both
                                    # sides ("turn right at the second corner"): class 1 past
                                    # N - 1 corners, then the side's first turn; false: the
                                    # network gets the count and decides
    corner_count: bool = True       # beyond the seed: a count-input network gets the corners
                                    # counted so far; false: a count of 0 throughout (what the
                                    # network decides without the rule-based counter)
    phrase_vocabulary: str = str(DEFAULT_PHRASES)   # beyond the seed: words outside these
                                    # phrase sets are skipped like words outside GloVe (then
                                    # unknown_min_confidence decides); "" = every GloVe word
    common_words_known: int = 500   # GloVe's this many most frequent words ("your", "just")
                                    # are known besides the phrase sets' words: function words
                                    # name no direction
    misheard_edits: int = 1         # beyond the seed: a skipped word may stand for a
                                    # phrase-set word this many letter edits away ("lift" for
                                    # "left", misheard.readings); such readings are followed when
                                    # those Z_w reads with confidence agree on the class, in
                                    # place of skipping the word; 0 = never
    laser_config: str = str(DEFAULT_LASER_CONFIG)   # canonical scan + preprocessing
    postprocess: PostprocessConfig = field(default_factory=PostprocessConfig)
    guard: GuardConfig = field(default_factory=GuardConfig)   # beyond the seed
    doors: DoorConfig = field(default_factory=DoorConfig)     # beyond the seed
    ask: AskConfig = field(default_factory=AskConfig)         # beyond the seed: asking back


Section = TypeVar("Section", bound="DataclassInstance")


def _section(cls: type[Section], values: Mapping[str, Any], where: str) -> Section:
    """A config dataclass from a YAML mapping; unknown keys are named."""
    config_file.check_keys(values, [f.name for f in fields(cls)], where)
    default = cls()
    converted: dict[str, Any] = {}
    for key, value in values.items():
        kind = type(getattr(default, key))
        if kind is bool and not isinstance(value, bool):
            raise config_file.ConfigError(f"{where}.{key}: expected true or false, got "
                                          f"{value!r}")
        try:
            converted[key] = kind(value)
        except (TypeError, ValueError):
            raise config_file.ConfigError(f"{where}.{key}: expected a {kind.__name__}, got "
                                          f"{value!r}") \
                from None
    return replace(default, **converted)


def load_follower_config(path: str | os.PathLike[str]) -> FollowerConfig:
    """A FollowerConfig from a YAML file (config/semnav_follower.yaml lists every key with its
    default): top-level control_period and laser_config, sections postprocess, guard and doors. Keys
    left out keep their defaults; an unknown key (with the nearest known one) or a wrong type is a
    ConfigError naming it."""
    path = Path(path)
    data = config_file.read_yaml(path, what="follower config") or {}
    where = str(path)
    if not isinstance(data, dict):
        raise config_file.ConfigError(f"{where}: expected a mapping of follower settings")
    sections = {"postprocess": PostprocessConfig, "guard": GuardConfig, "doors": DoorConfig,
                "ask": AskConfig}
    top = {k: v for k, v in data.items() if k not in sections}
    config = _section(FollowerConfig, top, where)
    for key in ("laser_config", "phrase_vocabulary"):   # relative to the file, like the
        if top.get(key):                                 # world files' paths
            setattr(config, key, str((path.parent / top[key]).resolve()))
    for name, cls in sections.items():
        if name in data:
            setattr(config, name, _section(cls, data[name], f"{where}: {name}"))
    if config.splitting not in SPLITTINGS:
        raise config_file.ConfigError(f"{where}.splitting: one of {', '.join(SPLITTINGS)}, got "
                         f"{config.splitting!r}")
    return config


def model_file(model_path: str | os.PathLike[str] | None = None) -> Path:
    """The follower's model file: `model_path`, else $SEMNAV_MODEL, else the committed default.
    ModelMissingError (naming `make train`) if it does not exist."""
    path = Path(model_path or os.environ.get("SEMNAV_MODEL", DEFAULT_MODEL))
    if not path.is_file():
        raise ModelMissingError(
            f"semantic_nav model {path} not found: run `make train ARGS=--install` (or pass "
            "a model path)")
    return path


@dataclass
class FollowerCommand:
    """What one control step decided."""

    v: float                # m/s, after post-processing
    w: float                # rad/s, after post-processing
    index: int              # current simple instruction, 0-based
    predicted_class: int    # 1..10 (argmax Z_w) of the current simple instruction
    done: bool              # every simple instruction has halted
    corners: int | None = None  # corners counted in this simple instruction (count-input networks)


PASS_CLASS = ids(motion=STRAIGHT)[0]   # the class LSTM_fused gets while corners are passed


def _one_hot(label: int, size: int) -> NDArray[np.float64]:
    """The one-hot class vector of class `label` (Z_w's output order)."""
    return np.eye(size)[CLASS_IDS.index(label)]


def class_one_hot(z_w: NDArray[np.float64]) -> NDArray[np.float64]:
    """Beyond the seed: Z_w -> the one-hot vector of its class (argmax). LSTM_fused learnt on
    Z_w of training phrasings, one-hot to about 1e-7; a classifier trained with noise on the word
    vectors is less sure of some phrasings (the default model's Z_w on office_wings' counting
    phrasings: median 0.94 to 0.96 on the right class), and LSTM_fused then drives differently for
    the same class."""
    return np.eye(len(z_w))[int(np.argmax(z_w))]


def _step_policy(model: "StepPolicy | keras.Model") -> "StepPolicy":
    """A StepPolicy, a Keras model of build_network, or anything with classify, step, reset."""
    if all(hasattr(model, name) for name in ("classify", "step", "reset")):
        return model
    from semantic_nav.step_policy import StepPolicy
    return StepPolicy.from_keras(model)


class DirectionFollower:
    """Sentence + scans -> velocity commands, one simple instruction after the other."""

    def __init__(self, model: "StepPolicy | keras.Model", word_vectors: "WordVectors",
                 config: FollowerConfig | None = None) -> None:
        self.config = config or FollowerConfig()
        self.control_period = self.config.control_period
        self.policy = _step_policy(model)
        self.word_vectors = word_vectors
        self.vocabulary: frozenset[str] | None = None
        self.phrase_words: frozenset[str] | None = None
        if self.config.phrase_vocabulary:   # index keys in row order; GloVe 6B: by frequency
            common = itertools.islice(word_vectors.index, self.config.common_words_known)
            self.phrase_words = phrase_vocabulary(self.config.phrase_vocabulary)
            self.vocabulary = self.phrase_words.union(common)
        _, self.canonical, self.preprocess = load_laser_config(self.config.laser_config)
        self.halting = HaltingCounter(self.config.postprocess)
        # beyond the seed: a network with the count input gets the corners counted so far
        counts = getattr(getattr(self.policy, "config", None), "count_input", False)
        self.counter = CornerCounter() if counts else None
        # beyond the seed: a network that counts itself gets the counting mode instead
        self._counting_input = getattr(getattr(self.policy, "config", None), "counting_input",
                                       False)
        self._sent_w = 0.0      # ω of the last command sent (the guard's estimate of the base's)
        self.guard_actions = dict.fromkeys(GUARD_ACTIONS, 0)   # in the current sentence
        self.doorway_points = np.zeros((0, 2))   # ends of the beams cut at a doorway, last step
        self.instructions: list[str] = []
        self.z_w: list[NDArray[np.float64]] = []
        self.confidences: list[float] = []   # Z_w's largest probability per simple instruction
        self.classes: list[int] = []
        self.countings: list[str] = []
        # the class LSTM_fused gets now (z_w, or a pass / turn class)
        self.z_now: NDArray[np.float64] | None = None
        self.passing = 0        # side branches still to pass before the turn (pass then turn)
        self.unknown_words: list[str] = []
        # (heard, read as) of the current sentence's misheard words
        self.corrections: list[tuple[str, str]] = []
        self.index = 0

    @classmethod
    def from_files(cls, model_path: str | os.PathLike[str] | None = None,
                   word_vectors: "WordVectors | str | os.PathLike[str] | None" = None,
                   config: FollowerConfig | str | Path | None = None) -> "DirectionFollower":
        """Load a .keras model (default models/semantic_nav/default.keras) and the GloVe vectors
        (a WordVectors, a GloVe file / cache directory, or None for the default cache); `config`
        is a FollowerConfig, the path of a follower YAML (load_follower_config) or None."""
        if isinstance(config, (str, Path)):
            config = load_follower_config(config)
        path = model_file(model_path)
        from semantic_nav.step_policy import load_step_policy   # numpy + h5py: no Keras, torch
        from semantic_nav.word_vectors import WordVectors, load_word_vectors
        policy = load_step_policy(path)
        if not isinstance(word_vectors, WordVectors):
            word_vectors = load_word_vectors(word_vectors)
        return cls(policy, word_vectors, config)

    def _reread(self, part: str, skipped: Sequence[str]) -> tuple[
            str, np.ndarray, list[str], NDArray[np.float64], list[tuple[str, str]]] | None:
        """The simple instruction `part` with misheard words replaced (misheard.readings), when
        some readings are read by Z_w with unknown_min_confidence and all of those give one
        class -> (text, vectors, words still skipped, z, [(heard, read as)]) of the most
        confident of them, else None. Readings that read each word with a homophone as it ("ride"
        as "right") are weighed first; the others only when none of those is read with
        confidence."""
        if not self.phrase_words or self.config.misheard_edits < 1:
            return None
        sure: list[tuple[float, str, SentenceVector, NDArray[np.float64],
                         list[tuple[str, str]]]] = []
        for tokens, corrections in readings(tokenise(part), skipped, self.phrase_words,
                                            self.config.misheard_edits):
            text = " ".join(tokens)
            converted = sentence_vector(text, self.word_vectors, self.vocabulary)
            z = self.policy.classify(converted.vectors)
            if float(np.max(z)) >= self.config.unknown_min_confidence:
                sure.append((float(np.max(z)), text, converted, z, list(corrections)))
        sure = [reading for reading in sure if reads_homophones(reading[4], skipped)] or sure
        if not sure or len({int(np.argmax(reading[3])) for reading in sure}) > 1:
            return None
        _, text, converted, z, fixed = max(sure, key=lambda reading: reading[0])
        return text, converted.vectors, converted.oov, z, fixed

    def start(self, sentence: str) -> list[int]:
        """Split and classify a sentence; resets memory. Returns the class (1..10) of each simple
        instruction. UnknownInstructionError if a simple instruction has no known word;
        UnfollowableInstruction if one read with its misheard words (misheard.py) asks for a
        corner the classes do not count."""
        try:
            parts = split_instruction(sentence, self.config.splitting)
        except InstructionError as error:
            raise UnknownInstructionError(str(error)) from error
        vectors: list[np.ndarray] = []
        unknown: list[list[str]] = []
        for part in parts:
            try:
                converted = sentence_vector(part, self.word_vectors, self.vocabulary)
            except InstructionError as error:
                raise UnknownInstructionError(
                    f"unknown instruction {part!r} (in {sentence!r}): {error}",
                    TOKEN.findall(part)) from error
            vectors.append(converted.vectors)
            unknown.append(converted.oov)
        z_w = [self.policy.classify(v) for v in vectors]
        corrections: list[tuple[str, str]] = []
        for k, (part, oov, z) in enumerate(zip(parts, unknown, z_w)):
            # a skipped word that sounds like a phrase-set word most likely was that word: the
            # rest alone may read with confidence and wrongly ("can you make a lift on at the
            # crossroad and wait there": class 1)
            reread = self._reread(part, oov) if oov else None
            if reread is not None:
                parts[k], vectors[k], unknown[k], z_w[k], fixed = reread
                check_followable(parts[k])   # what it now reads may ask for a 4th corner
                corrections += fixed
            elif oov and float(np.max(z)) < self.config.unknown_min_confidence:
                raise UnknownInstructionError(
                    f"{part!r} (in {sentence!r}): without the unknown word(s) "
                    f"{', '.join(oov)} it reads as class {CLASS_IDS[int(np.argmax(z))]} with "
                    f"only {float(np.max(z)):.2f} confidence (< "
                    f"{self.config.unknown_min_confidence})", oov)
        self.corrections = corrections
        self.instructions = parts
        self.classes = [CLASS_IDS[int(np.argmax(z))] for z in z_w]
        self.confidences = [float(np.max(z)) for z in z_w]
        self.countings = [counting_mode(part, label) if self.config.side_counting
                          else COUNT_CORNERS for part, label in zip(parts, self.classes)]
        self.z_w = [class_one_hot(z) for z in z_w] if self.config.one_hot_class else z_w
        self.unknown_words = [word for oov in unknown for word in oov]
        self.index = 0
        self._reset_memory()
        self.halting.reset()
        self._sent_w = 0.0
        self.guard_actions = dict.fromkeys(GUARD_ACTIONS, 0)
        return list(self.classes)

    def _reset_memory(self) -> None:
        """A new simple instruction: LSTM_fused's memory and the corner count start afresh."""
        self.policy.reset()
        self.passing = 0
        if self.index >= len(self.instructions):
            return
        self.z_now = self.z_w[self.index]
        if self._counting_input:    # the counting mode of this instruction, fixed while it runs
            self._counting_row = one_hot_counting(self.countings[self.index])
        if self.counter is not None:
            label, side = self.classes[self.index], None
            one_side = self.countings[self.index] == COUNT_SIDE
            if one_side:
                side = SIDE[label]
            corner = get(label).corner
            if corner and (self.config.side_pass_then_turn if one_side
                           else self.config.corner_pass_then_turn):
                self.passing = corner - 1
                self.z_now = _one_hot(PASS_CLASS, len(self.z_now))
            self.counter.reset(side=side)

    def _turn_when_passed(self, counted: int) -> None:
        """Pass then turn: once N - 1 corners (for a one-side count: branches on that side) are
        counted and the last of them is behind the robot, the instruction is driven as that
        side's first turn, the count afresh (the network turns into the next branch on that
        side). LSTM_fused keeps its memory: a network started afresh just past a crossroad
        takes it for the branch it has turned into and stops."""
        if self.counter is None or self.z_now is None:
            raise RuntimeError("pass then turn needs a corner counter and a started instruction")
        if not self.passing or counted < self.passing or self.counter.opening_beside():
            return
        self.passing = 0
        self.counter.reset()
        self.z_now = _one_hot(TURN_CLASSES[(SIDE[self.classes[self.index]], None)],
                              len(self.z_now))

    @property
    def done(self) -> bool:
        return bool(self.instructions) and self.index >= len(self.instructions)

    def step(self, ranges: np.ndarray, laser: LaserModel) -> FollowerCommand:
        """One control step: raw ranges of `laser` (laser_layer.LaserModel) -> FollowerCommand.

        Scans of any beam count are interpolated to the canonical scan (laser_layer.ScanError
        if that is impossible)."""
        from semantic_nav.laser_layer import preprocess_scan
        if not self.instructions:
            raise RuntimeError("DirectionFollower.step before start(sentence)")
        if self.done:
            return self._command(0.0, 0.0)
        if self.z_now is None:
            raise RuntimeError("DirectionFollower.step: no class for the current instruction")
        ranges = self._close_doorways(ranges, laser)
        scan, _ = preprocess_scan(ranges, laser, self.canonical, self.preprocess)
        if self.counter is not None:
            self._turn_when_passed(self.counter.observe(self._sides(ranges, laser)))
            counts = one_hot_counts(min(self.counter.count, self.counter.config.max_count)
                                    if self.config.corner_count else 0,
                                    self.counter.config.max_count)
            output = self.policy.step(self.z_now, scan, counts)
        elif self._counting_input:       # learned counting: the network counts itself
            output = self.policy.step(self.z_now, scan, counting=self._counting_row)
        else:
            output = self.policy.step(self.z_now, scan)
        raw_v, raw_w = apply_stop(*output, getattr(self.policy, "stop_probability", None),
                                  self.config.postprocess)
        v = adjust_speed(raw_v, self.config.postprocess)
        w = adjust_speed(raw_w, self.config.postprocess)
        v, w = self._guarded(v, w, ranges, laser)
        self._sent_w = w                # the base turns towards it at its angular acceleration
        if self.counter is not None:
            self.counter.advance(v * self.control_period)
        if self.halting.update(v, w):
            self.index += 1             # §2.2.5.2: next simple instruction, memory cleared
            self._reset_memory()
        # the count of the instruction the command's index names (0 when one just began)
        counted = self.counter.count if self.counter is not None else \
            getattr(self.policy, "counted", None)
        return self._command(v, w, counted)

    def _close_doorways(self, ranges: np.ndarray, laser: LaserModel) -> np.ndarray:
        """doorways.close_doorways on the raw scan; keeps the cut beams' ends (laser frame) in
        `doorway_points` for the node's marker."""
        closed = close_doorways(ranges, laser, self.config.doors)
        self.doorway_points = cut_beam_ends(ranges, closed, laser)
        return closed

    def _sides(self, ranges: np.ndarray, laser: LaserModel) -> NDArray[np.float32]:
        """corner_count.side_ranges of one raw scan; invalid readings (NaN, below the laser's
        range_min) count as no opening."""
        if self.counter is None:
            raise RuntimeError("DirectionFollower._sides without a corner counter")
        ranges = np.asarray(ranges, dtype=np.float64)
        ranges = np.where(np.isnan(ranges) | (ranges < laser.range_min), 0.0, ranges)
        return side_ranges(ranges[None], laser.angle_min, laser.angle_increment,
                           self.counter.config.window_deg)[0]

    def _guarded(self, v: float, w: float, ranges: np.ndarray,
                 laser: LaserModel) -> tuple[float, float]:
        """collision_guard on the post-processed command -> (v, ω); a guarded speed the robot
        cannot drive (below v_move, §2.2.5.1) becomes a stop, which the halting counter then
        counts, unless the guard can steer round the wall (GuardConfig.steer)."""
        guard = self.config.guard
        if not guard.enabled or v == 0.0:
            return v, w
        v_move = self.config.postprocess.v_move
        guarded, steered = steer_around(v, w, scan_points(ranges, laser, guard.laser_x), v_move,
                                        guard, self._sent_w)
        guarded = guarded if abs(guarded) >= v_move else 0.0
        action = guard_action(v, w, guarded, steered)
        if action:
            self.guard_actions[action] += 1
        return guarded, steered

    def _command(self, v: float, w: float, corners: int | None = None) -> FollowerCommand:
        current = min(self.index, len(self.instructions) - 1)
        return FollowerCommand(v=v, w=w, index=current, predicted_class=self.classes[current],
                               done=self.done, corners=corners)
