"""Image front end of the visual perception: the two camera images (and their depth images) ->
one camera-level FrameView, as the simulator publishes it (thesis 000 Fig. 3-7): stitching
(Sec. 3.2.1), object boxes from YOLO, COCO-18 skeletons from mediapipe, depth per box (adaptive
rectangle, Sec. 3.2.2) and per joint, shirt colour at joints 1, 2, 5 (Sec. 3.2.3).

Pose is top-down: mediapipe finds one person per image, so it runs on each YOLO 'person' box
(padded crop) and the keypoints are mapped back, one skeleton per person, as OpenPose gives.
"""
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from perception.detector_registry import Detector, PoseEstimator
from perception.detectors import check_image, stitch
from perception.keypoints import L_SHOULDER, NECK, R_SHOULDER
from perception.localisation import DepthWindowConfig, box_depth
from perception.visual_pipeline import FrameView, ObjectBox, PersonView

COLOUR_JOINTS = (NECK, R_SHOULDER, L_SHOULDER)


@dataclass
class FrontEndConfig:
    colour_patch: int = 5        # [px] side of the square averaged for a joint's shirt colour
    joint_depth_patch: int = 5   # [px] side of the square whose valid median is a joint's depth
    top_down: bool = True        # pose per YOLO person box (False: mediapipe on the whole image)
    crop_padding: float = 0.15   # [-] person box grown by this share of its size on each side
    min_crop: int = 32           # [px] person boxes narrower or lower than this are skipped
    depth: DepthWindowConfig = field(default_factory=DepthWindowConfig)


def _patch(image: np.ndarray, x: float, y: float, side: int) -> np.ndarray:
    half = side // 2
    h, w = image.shape[:2]
    xi, yi = int(round(x)), int(round(y))
    return image[max(0, yi - half):min(h, yi + half + 1), max(0, xi - half):min(w, xi + half + 1)]


def joint_colours(image_bgr: np.ndarray, points: NDArray[np.float64],
                  confidence: NDArray[np.float64], side: int) -> NDArray[np.uint8]:
    """(3, 3) uint8 RGB at joints 1, 2, 5 (patch mean); zeros where a joint is not seen."""
    colours = np.zeros((3, 3), np.uint8)
    for i, joint in enumerate(COLOUR_JOINTS):
        if confidence[joint] > 0 and np.isfinite(points[joint]).all():
            x, y = points[joint]
            patch = _patch(image_bgr, x, y, side)
            if patch.size:
                colours[i] = patch.reshape(-1, 3).mean(axis=0)[::-1].round().astype(np.uint8)
    return colours


def joint_depths(depth: np.ndarray | None, points: NDArray[np.float64],
                 confidence: NDArray[np.float64], config: FrontEndConfig) -> NDArray[np.float64]:
    """(18,) depth [m] per joint: median of valid pixels in a small patch, NaN if none."""
    out = np.full(len(points), np.nan)
    if depth is None:
        return out
    for j, (x, y) in enumerate(points):
        if confidence[j] > 0 and np.isfinite([x, y]).all():
            patch = _patch(depth, x, y, config.joint_depth_patch)
            valid = patch[np.isfinite(patch) & (patch >= config.depth.min_depth)
                          & (patch <= config.depth.max_depth)]
            if valid.size:
                out[j] = float(np.median(valid))
    return out


def person_crop(box: Sequence[float], shape: tuple[int, ...],
                padding: float) -> tuple[int, int, int, int]:
    """Integer (x0, y0, x1, y1) of a padded (x, y, width, height) box, clipped to the image."""
    x, y, w, h = box
    height, width = shape[:2]
    x0, y0 = max(0, int(x - padding * w)), max(0, int(y - padding * h))
    x1, y1 = min(width, int(np.ceil(x + w + padding * w))), min(height,
                                                                 int(np.ceil(y + h + padding * h)))
    return x0, y0, x1, y1


def top_down_skeletons(
        image: np.ndarray, person_boxes: Iterable[Sequence[float]], pose: PoseEstimator,
        config: FrontEndConfig) -> list[tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """One COCO-18 skeleton per person box: pose on the padded crop, keypoints shifted back to
    the image [(points (18, 2) [px], confidence (18,))]; a crop with no pose gives none."""
    skeletons: list[tuple[NDArray[np.float64], NDArray[np.float64]]] = []
    for box in person_boxes:
        x0, y0, x1, y1 = person_crop(box, image.shape, config.crop_padding)
        if x1 - x0 < config.min_crop or y1 - y0 < config.min_crop:
            continue
        for points, confidence in pose.skeletons(np.ascontiguousarray(image[y0:y1, x0:x1]))[:1]:
            skeletons.append((points + np.array([x0, y0], dtype=float), confidence))
    return skeletons


def build_frame(top: ArrayLike, bottom: ArrayLike | None, depth_top: ArrayLike | None,
                depth_bottom: ArrayLike | None, detector: Detector, pose: PoseEstimator,
                config: FrontEndConfig) -> FrameView:
    """Stitched frame of detections; depth images may be None (then depths are NaN).

    Raises ValueError for an empty image or mismatched sizes (the message says which).
    """
    image = stitch(top, bottom) if bottom is not None else check_image(top, "top image")
    depth: NDArray[np.float64] | None = None
    if depth_top is not None:
        parts = [np.asarray(depth_top, float)] + (
            [np.asarray(depth_bottom, float)] if bottom is not None and depth_bottom is not None
            else [])
        depth = np.vstack(parts)
        if depth.shape[1] != image.shape[1]:
            raise ValueError(f"depth width {depth.shape[1]} differs from image width "
                             f"{image.shape[1]}")
        if depth.shape[0] < image.shape[0]:   # no bottom depth: pad the bottom rows as unknown
            depth = np.vstack([depth, np.full((image.shape[0] - depth.shape[0], depth.shape[1]),
                                              np.nan)])
    frame = FrameView(image.shape[1], image.shape[0])
    detections = detector.detect(image)
    for det in detections:
        box = (det.x, det.y, det.width, det.height)
        d = box_depth(depth, box, config.depth) if depth is not None else None
        frame.objects.append(ObjectBox(det.label, det.confidence, det.x, det.y, det.width,
                                       det.height, float("nan") if d is None else d))
    if config.top_down:
        boxes = [(d.x, d.y, d.width, d.height) for d in detections if d.label == "person"]
        skeletons = top_down_skeletons(image, boxes, pose, config)
    else:
        skeletons = pose.skeletons(image)
    for points, confidence in skeletons:
        frame.people.append(PersonView(points, confidence,
                                       joint_depths(depth, points, confidence, config),
                                       joint_colours(image, points, confidence,
                                                     config.colour_patch)))
    return frame
