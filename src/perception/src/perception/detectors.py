"""Real image backends of the visual perception (thesis 000 Sec. 3.2): Darknet YOLO object
detection through OpenCV's DNN module, mediapipe pose mapped to COCO-18 (OpenPose order,
Fig. 3-4), and the stitching of the robot's two vertically stacked cameras (Sec. 3.2.1).

Both detectors take a BGR uint8 image (OpenCV convention) and raise ValueError on an empty or
malformed image; callers decide how to report it.
"""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from perception.keypoints import NECK, NUM_KEYPOINTS


@dataclass
class Detection:
    """One detected object: class, confidence P(o) and box [px] (top-left x, y, width, height)."""

    label: str
    confidence: float
    x: float
    y: float
    width: float
    height: float

    @property
    def centre(self) -> tuple[float, float]:
        return self.x + self.width / 2.0, self.y + self.height / 2.0


@dataclass
class DarknetConfig:
    """Darknet YOLO files and thresholds (any cfg+weights pair, e.g. YOLOv3-tiny or YOLOv3)."""

    cfg: str
    weights: str
    names: str
    input_size: int = 416              # [px] network input side (multiple of 32)
    confidence_threshold: float = 0.25  # [-] class score to keep a box
    nms_threshold: float = 0.45        # [-] IoU above which the weaker box is suppressed


def check_image(image: ArrayLike | None, what: str = "image") -> NDArray[np.uint8]:
    """A BGR uint8 image (H, W, 3) with H, W > 0, else ValueError naming what is wrong."""
    if image is None:
        raise ValueError(f"{what} is missing")
    array = np.asarray(image)
    if array.ndim != 3 or array.shape[2] != 3 or array.shape[0] == 0 or array.shape[1] == 0:
        raise ValueError(f"{what} must be a non-empty HxWx3 BGR image, got shape {array.shape}")
    if array.dtype != np.uint8:
        raise ValueError(f"{what} must be uint8, got {array.dtype}")
    return array


def stitch(top: ArrayLike | None, bottom: ArrayLike | None) -> NDArray[np.uint8]:
    """Sec. 3.2.1: the top camera's image above the bottom camera's (same width) -> one frame."""
    top, bottom = check_image(top, "top image"), check_image(bottom, "bottom image")
    if top.shape[1] != bottom.shape[1]:
        raise ValueError(f"cannot stitch images of widths {top.shape[1]} and {bottom.shape[1]}")
    return np.vstack([top, bottom])


Box = tuple[list[float], float, int]   # ([x, y, width, height] [px], score, class index)


class DarknetDetector:
    """YOLO through cv2.dnn.readNetFromDarknet."""

    def __init__(self, config: DarknetConfig) -> None:
        import cv2
        for path in (config.cfg, config.weights, config.names):
            if not Path(path).is_file():
                raise FileNotFoundError(f"Darknet file {path} not found (run scripts/setup)")
        self.config = config
        self.names = [n.strip() for n in Path(config.names).read_text().splitlines() if n.strip()]
        self.net = cv2.dnn.readNetFromDarknet(config.cfg, config.weights)
        self.outputs = self.net.getUnconnectedOutLayersNames()
        self._cv2 = cv2

    def detect(self, image: ArrayLike | None) -> list[Detection]:
        """Objects in a BGR image: [Detection] after per-class non-maximum suppression."""
        image = check_image(image)
        h, w = image.shape[:2]
        side = self.config.input_size
        blob = self._cv2.dnn.blobFromImage(image, 1 / 255.0, (side, side), swapRB=True, crop=False)
        self.net.setInput(blob)
        rows = np.vstack(self.net.forward(self.outputs))
        scores = rows[:, 5:]
        classes = scores.argmax(axis=1)
        confidence = scores[np.arange(len(rows)), classes]
        keep = confidence >= self.config.confidence_threshold
        boxes: list[Box] = []
        for (cx, cy, bw, bh), score, cls in zip(rows[keep, :4], confidence[keep], classes[keep]):
            boxes.append(([float((cx - bw / 2) * w), float((cy - bh / 2) * h),
                           float(bw * w), float(bh * h)], float(score), int(cls)))
        return self._suppress(boxes)

    def _suppress(self, boxes: list[Box]) -> list[Detection]:
        found: list[Detection] = []
        for cls in sorted({b[2] for b in boxes}):
            group = [b for b in boxes if b[2] == cls]
            idx = self._cv2.dnn.NMSBoxes([b[0] for b in group], [b[1] for b in group],
                                         self.config.confidence_threshold,
                                         self.config.nms_threshold)
            for i in np.asarray(idx).reshape(-1):
                box, score, _ = group[int(i)]
                label = self.names[cls] if cls < len(self.names) else f"class_{cls}"
                found.append(Detection(label, score, *box))
        return sorted(found, key=lambda d: -d.confidence)


# mediapipe Pose landmark index for each COCO-18 joint (OpenPose order); the neck has none.
MEDIAPIPE_FOR_COCO = (0, None, 12, 14, 16, 11, 13, 15, 24, 26, 28, 23, 25, 27, 5, 2, 8, 7)


def coco18_from_mediapipe(landmarks_xyv: ArrayLike, width: float, height: float,
                          min_visibility: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Mediapipe's 33 landmarks (normalised x, y, visibility) -> COCO-18 (18, 2) [px] + confidence.

    The neck (joint 1) is the mid-point of the shoulders when both are visible enough.
    """
    lm = np.asarray(landmarks_xyv, dtype=float)
    if lm.shape != (33, 3):
        raise ValueError(f"mediapipe pose gives 33 landmarks (x, y, visibility), got {lm.shape}")
    points = np.full((NUM_KEYPOINTS, 2), np.nan)
    confidence = np.zeros(NUM_KEYPOINTS)
    for coco, mp_index in enumerate(MEDIAPIPE_FOR_COCO):
        if mp_index is None:
            continue
        confidence[coco] = lm[mp_index, 2]
        points[coco] = lm[mp_index, 0] * width, lm[mp_index, 1] * height
    confidence[NECK] = min(confidence[2], confidence[5])
    points[NECK] = (points[2] + points[5]) / 2.0
    hidden = confidence < min_visibility
    points[hidden] = np.nan
    confidence[hidden] = 0.0
    return points, confidence


class MediapipePose:
    """Human pose with mediapipe 0.10.21 solutions.pose (bundled model, one person per image;
    image_frontend runs it on each person box for several people)."""

    def __init__(self, model_complexity: int = 1, min_detection_confidence: float = 0.5,
                 min_visibility: float = 0.5) -> None:
        import mediapipe as mp
        self.min_visibility = min_visibility        # [-] landmarks below it are "not detected"
        self.pose = mp.solutions.pose.Pose(static_image_mode=True,
                                           model_complexity=model_complexity,
                                           min_detection_confidence=min_detection_confidence)

    def skeletons(self,
                  image: ArrayLike | None) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
        """COCO-18 skeletons in a BGR image: [(points (18, 2) [px], confidence (18,))]."""
        image = check_image(image)
        rgb = np.ascontiguousarray(image[:, :, ::-1])
        result = self.pose.process(rgb)
        if result.pose_landmarks is None:
            return []
        lm = [(p.x, p.y, p.visibility) for p in result.pose_landmarks.landmark]
        h, w = image.shape[:2]
        return [coco18_from_mediapipe(lm, w, h, self.min_visibility)]

    def close(self) -> None:
        self.pose.close()
