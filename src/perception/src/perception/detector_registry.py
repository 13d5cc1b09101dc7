"""The one registry of perception's image models: object detectors and pose estimators.

The image front end node (`~detector`, `~pose`), the benchmark and the tests make their models
here by name; adding a model is one entry in DETECTORS or POSE_ESTIMATORS (see the package
README, "Adding a detector")."""
from dataclasses import dataclass
from typing import Any, Protocol
from collections.abc import Callable, Mapping

import numpy as np
from numpy.typing import NDArray

from perception.detectors import DarknetConfig, DarknetDetector, Detection, MediapipePose


class Detector(Protocol):
    """Finds objects (COCO names) in a BGR image."""

    def detect(self, image: np.ndarray) -> list[Detection]: ...


class PoseEstimator(Protocol):
    """COCO-18 skeletons in a BGR image: [(points (18, 2) [px], confidence (18,))]."""

    def skeletons(self, image: np.ndarray) -> list[tuple[NDArray[np.float64],
                                                          NDArray[np.float64]]]: ...


@dataclass(frozen=True)
class ModelEntry:
    name: str              # registry name: ~detector / ~pose of the image front end
    description: str       # one line for tables and --help
    make: Callable         # settings (dict) -> the model


def _darknet(settings: dict[str, Any]) -> DarknetDetector:
    """cfg, weights, names and any other DarknetConfig field (its defaults otherwise)."""
    return DarknetDetector(DarknetConfig(**settings))


DETECTORS = {
    "darknet": ModelEntry("darknet", "YOLO through cv2.dnn.readNetFromDarknet (any Darknet cfg, "
                                     "weights and class names; yolov3-tiny by default)", _darknet),
}
POSE_ESTIMATORS = {
    "mediapipe": ModelEntry("mediapipe", "mediapipe solutions.pose, one person per image (the "
                                         "front end runs it on each person box)",
                            lambda settings: MediapipePose()),
}


def _make(table: Mapping[str, ModelEntry], kind: str, name: str,
          settings: Mapping[str, Any] | None) -> Any:
    if name not in table:
        raise ValueError(f"unknown {kind} {name!r}; known: {', '.join(sorted(table))}")
    return table[name].make(dict(settings or {}))


def make_detector(name: str, settings: Mapping[str, Any] | None = None) -> Detector:
    """The detector registered as `name`, made from `settings` (its entry says which keys)."""
    return _make(DETECTORS, "detector", name, settings)


def make_pose_estimator(name: str,
                        settings: Mapping[str, Any] | None = None) -> PoseEstimator:
    """The pose estimator registered as `name`."""
    return _make(POSE_ESTIMATORS, "pose estimator", name, settings)
