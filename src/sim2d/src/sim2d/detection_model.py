"""How wrong the simulated detectors are: the near-ideal model and the model calibrated against
YOLOv3-tiny and mediapipe on real photos.

`ideal` is the simulator's first model, named for what it is: a constant miss probability, 2 px
keypoint noise, sigma 6 shirt-colour noise, true labels and no false detections.

`calibrated` takes every figure from the table `scripts/calibrate_camera` writes
(config/camera_calibration.yaml; docs/perception/camera_calibration.md): the miss rate against
the person's and the object's apparent size (its logistic fit), the misses that hiding the lower
body adds, the room's lighting (misses, pose misses, the colour factor per channel and the residual
colour noise, label confusions, false detections per frame) and the keypoint error as a share of
the person's height.
"""
import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import yaml

DAYLIGHT = "daylight"      # the lighting row every other one is compared with


@dataclass
class DetectionConfig:
    """How good the simulated detectors are (sim2d.detection_model): `ideal` uses the constants
    below; `calibrated` takes misses, keypoint and colour errors, label confusions and false
    detections from the calibration table and uses only max_range, the depth noise, the
    confidences, the box margin and the seed from here."""

    model: str = "ideal"                # "ideal" or "calibrated"
    calibration: str = ""               # calibrated: the table (path relative to the world file)
    max_range: float = 6.0              # [m] nothing is detected farther away
    miss_probability: float = 0.05      # [-] ideal: chance a visible person or object is missed
    keypoint_noise: float = 2.0         # [px] ideal: 1 sigma
    depth_noise: float = 0.02           # [m] 1 sigma, plus depth_noise_fraction * depth
    depth_noise_fraction: float = 0.01  # [-]
    colour_noise: float = 6.0           # [0-255] ideal: 1 sigma on shirt colour channels
    confidence_range: tuple = (0.6, 0.95)  # [-] detector confidences are drawn from this range
    box_margin: float = 0.08            # [-] person box grows by this fraction per side
    seed: int = 0



class CalibrationError(ValueError):
    """A calibration table that cannot be read; the message names the file and the field."""


@dataclass(frozen=True)
class LightingErrors:
    """What one room's lighting adds (a row of the table's `lighting` section)."""

    miss_rate: float
    pose_miss_rate: float
    object_miss_rate: float
    label_confusion_rate: float
    colour_factor: tuple        # (3,) RGB
    colour_residual: float      # [0-255] 1 sigma per channel
    false_people: float         # per frame
    false_objects: float        # per frame


@dataclass(frozen=True)
class Calibration:
    path: str
    person_curve: tuple         # (h50, width) [px] of the person miss rate's logistic
    object_curve: tuple         # (h50, width) [px] of the object miss rate's logistic
    keypoint_error: float       # [-] RMS keypoint error over the person's height
    occlusion: tuple            # ((hidden fraction, miss rate, pose miss rate), ...) sorted
    lighting: dict              # name -> LightingErrors
    confusions: dict            # true label -> ((found label, count), ...)


def _field(row: Mapping[str, Any], key: str) -> float:
    value = row.get(key)
    return 0.0 if value is None else float(value)


def load_calibration(path: str | Path) -> Calibration:
    """The Calibration in `path`; CalibrationError naming the file and the field otherwise."""
    path = Path(path)
    try:
        table = yaml.safe_load(path.read_text())
    except OSError as error:
        raise CalibrationError(f"camera calibration {path}: {error.strerror} (make it with "
                               "scripts/calibrate_camera)") from None
    try:
        lighting: dict[str, LightingErrors] = {}
        for row in table["lighting"]:
            lighting[row["name"]] = LightingErrors(
                _field(row, "miss_rate"), _field(row, "pose_miss_rate"),
                _field(row, "object_miss_rate"), _field(row, "label_confusion_rate"),
                tuple(float(v) for v in row.get("colour_factor") or (1.0, 1.0, 1.0)),
                _field(row, "colour_residual"), _field(row, "false_people_per_image"),
                _field(row, "false_objects_per_image"))
        if DAYLIGHT not in lighting:
            raise CalibrationError(f"camera calibration {path}: no {DAYLIGHT!r} lighting row")
        errors = [row["keypoint_error"] for row in table["scale"]
                  if row.get("keypoint_error") is not None]
        occlusion = [(0.0, 0.0, 0.0)] + [
            (float(row["hidden_fraction"]), float(row["miss_rate"]),
             float(row.get("pose_miss_rate") or 0.0))
            for row in table["occlusion"] if row["side"] == "bottom"]
        confusions: dict[str, dict[str, int]] = {}
        for row in table["scale"] + table["occlusion"] + table["lighting"]:
            for key, count in (row.get("confusions") or {}).items():
                true, found = (part.strip() for part in key.split("->"))
                confusions.setdefault(true, {}).setdefault(found, 0)
                confusions[true][found] += int(count)
        return Calibration(
            str(path), (float(table["miss_curve"]["h50"]), float(table["miss_curve"]["width"])),
            (float(table["object_miss_curve"]["h50"]),
             float(table["object_miss_curve"]["width"])),
            float(np.median(errors)), tuple(sorted(occlusion)), lighting,
            {k: tuple(sorted(v.items())) for k, v in confusions.items()})
    except (KeyError, TypeError, ValueError) as error:
        if isinstance(error, CalibrationError):
            raise
        raise CalibrationError(f"camera calibration {path}: missing or malformed field "
                               f"{error}") from None


def logistic_miss(size: float, curve: Sequence[float]) -> float:
    """Miss rate of something `size` px tall for a logistic (h50, width) [px]."""
    h50, width = curve
    return 1.0 / (1.0 + math.exp(max(-50.0, min(50.0, (size - h50) / width))))


def occlusion_misses(calibration: Calibration, hidden_fraction: float) -> tuple[float, float]:
    """(miss rate, pose miss rate) that hiding `hidden_fraction` of a body adds (linear
    interpolation between the table's rows, 1 beyond the last)."""
    rows = np.array(calibration.occlusion)
    if hidden_fraction >= rows[-1, 0]:
        return float(rows[-1, 1]), float(rows[-1, 2])
    return (float(np.interp(hidden_fraction, rows[:, 0], rows[:, 1])),
            float(np.interp(hidden_fraction, rows[:, 0], rows[:, 2])))


def combined(*rates: float) -> float:
    """Probability that at least one of independent failures happens."""
    kept = 1.0
    for rate in rates:
        kept *= 1.0 - min(1.0, max(0.0, rate))
    return 1.0 - kept


class IdealModel:
    """The near-ideal detectors: DetectionConfig's constant miss probability and noises."""

    name = "ideal"

    def __init__(self, detection: DetectionConfig) -> None:
        self.detection = detection

    def person_missed(self, rng: np.random.Generator, height_px: float, hidden_fraction: float,
                      lighting: str) -> bool:
        return rng.random() < self.detection.miss_probability

    def pose_missed(self, rng: np.random.Generator, hidden_fraction: float,
                    lighting: str) -> bool:
        return False

    def keypoint_sigma(self, height_px: float) -> float:
        return self.detection.keypoint_noise

    def observed_colour(self, rng: np.random.Generator, colour: npt.ArrayLike,
                        lighting: str) -> npt.NDArray[np.uint8]:
        noisy = np.asarray(colour, dtype=float) + rng.normal(0.0, self.detection.colour_noise, 3)
        return np.clip(np.rint(noisy), 0, 255).astype(np.uint8)

    def object_missed(self, rng: np.random.Generator, size_px: float, lighting: str) -> bool:
        return rng.random() < self.detection.miss_probability

    def label(self, rng: np.random.Generator, label: str, lighting: str,
              labels: Iterable[str]) -> str:
        return label

    def false_counts(self, rng: np.random.Generator, lighting: str) -> tuple[int, int]:
        return 0, 0


class CalibratedModel:
    """Detector errors from the calibration table (module docstring)."""

    name = "calibrated"

    def __init__(self, calibration: Calibration) -> None:
        self.calibration = calibration

    def _light(self, lighting: str) -> LightingErrors:
        return self.calibration.lighting[lighting]

    def person_missed(self, rng: np.random.Generator, height_px: float, hidden_fraction: float,
                      lighting: str) -> bool:
        rate = combined(logistic_miss(height_px, self.calibration.person_curve),
                        occlusion_misses(self.calibration, hidden_fraction)[0],
                        self._light(lighting).miss_rate)
        return rng.random() < rate

    def pose_missed(self, rng: np.random.Generator, hidden_fraction: float,
                    lighting: str) -> bool:
        rate = combined(occlusion_misses(self.calibration, hidden_fraction)[1],
                        self._light(lighting).pose_miss_rate)
        return rng.random() < rate

    def keypoint_sigma(self, height_px: float) -> float:
        """Per-axis sigma [px]: the table's RMS distance over the height, split over 2 axes."""
        return self.calibration.keypoint_error * height_px / math.sqrt(2.0)

    def observed_colour(self, rng: np.random.Generator, colour: npt.ArrayLike,
                        lighting: str) -> npt.NDArray[np.uint8]:
        light = self._light(lighting)
        seen = np.asarray(colour, dtype=float) * np.array(light.colour_factor)
        seen = seen + rng.normal(0.0, light.colour_residual, 3)
        return np.clip(np.rint(seen), 0, 255).astype(np.uint8)

    def object_missed(self, rng: np.random.Generator, size_px: float, lighting: str) -> bool:
        rate = combined(logistic_miss(size_px, self.calibration.object_curve),
                        self._light(lighting).object_miss_rate)
        return rng.random() < rate

    def label(self, rng: np.random.Generator, label: str, lighting: str,
              labels: Iterable[str]) -> str:
        """The label the detector gives: now and then a confusion the table saw for this
        label, else another label of the home."""
        if rng.random() >= self._light(lighting).label_confusion_rate:
            return label
        seen = self.calibration.confusions.get(label)
        if seen:
            names, counts = zip(*seen)
            return str(rng.choice(names, p=np.array(counts) / sum(counts)))
        others = sorted(set(labels) - {label})
        return str(rng.choice(others)) if others else label

    def false_counts(self, rng: np.random.Generator, lighting: str) -> tuple[int, int]:
        """(false person boxes, false object boxes) in one frame."""
        light = self._light(lighting)
        return int(rng.poisson(light.false_people)), int(rng.poisson(light.false_objects))


DetectionModel = IdealModel | CalibratedModel


def make_detection_model(detection: DetectionConfig,
                         calibration: Calibration | None = None) -> DetectionModel:
    """The model `detection.model` names; `calibration` is the loaded table it needs."""
    if detection.model == "ideal":
        return IdealModel(detection)
    if detection.model == "calibrated":
        if calibration is None:
            raise CalibrationError("the calibrated detection model needs a calibration table")
        return CalibratedModel(calibration)
    raise CalibrationError(f"unknown detection model {detection.model!r}; known: calibrated, "
                           "ideal")
