"""Real backends on Debian darknet's sample photos: YOLOv3-tiny (cv2.dnn) and mediapipe pose
-> COCO-18; plus stitching and the landmark mapping on hand-made inputs."""
import os
from pathlib import Path

import numpy as np
import pytest

from perception.detectors import (
    DarknetConfig, DarknetDetector, MediapipePose, check_image, coco18_from_mediapipe, stitch)
from perception.keypoints import L_HIP, L_SHOULDER, NECK, NOSE, R_HIP, R_SHOULDER, R_WRIST

PHOTOS = Path("/usr/share/darknet/data")          # Debian package `darknet` (scripts/setup)
MODELS = Path(os.environ.get("TAMP_MODEL_CACHE",
                             Path.home() / ".cache" / "tamp_ws" / "models")) / "yolov3_tiny"
# Boxes (x, y, w, h) [px] read by hand off the photos.
PERSON_IN_PERSON_JPG = (190, 98, 85, 277)
DOG_IN_PERSON_JPG = (65, 263, 140, 82)
DOG_IN_DOG_JPG = (133, 222, 177, 318)


def iou(a, b):
    ax1, ay1, bx1, by1 = a[0] + a[2], a[1] + a[3], b[0] + b[2], b[1] + b[3]
    w = max(0.0, min(ax1, bx1) - max(a[0], b[0]))
    h = max(0.0, min(ay1, by1) - max(a[1], b[1]))
    inter = w * h
    return inter / (a[2] * a[3] + b[2] * b[3] - inter)


def read(name):
    import cv2
    image = cv2.imread(str(PHOTOS / name))
    assert image is not None, f"{PHOTOS / name} missing: scripts/setup installs Debian's darknet"
    return image


@pytest.fixture(scope="module")
def yolo():
    return DarknetDetector(DarknetConfig(str(MODELS / "yolov3-tiny.cfg"),
                                         str(MODELS / "yolov3-tiny.weights"),
                                         str(MODELS / "coco.names")))


@pytest.fixture(scope="module")
def pose():
    backend = MediapipePose()
    yield backend
    backend.close()


def best_overlap(detections, label, box):
    return max((iou((d.x, d.y, d.width, d.height), box) for d in detections if d.label == label),
               default=0.0)


def test_yolov3_tiny_finds_person_and_dog(yolo):
    found = yolo.detect(read("person.jpg"))
    assert best_overlap(found, "person", PERSON_IN_PERSON_JPG) > 0.7
    assert best_overlap(found, "dog", DOG_IN_PERSON_JPG) > 0.6
    assert best_overlap(yolo.detect(read("dog.jpg")), "dog", DOG_IN_DOG_JPG) > 0.6


def test_mediapipe_skeleton_is_plausible_coco18(pose):
    skeletons = pose.skeletons(read("person.jpg"))
    assert len(skeletons) == 1
    points, confidence = skeletons[0]
    assert points.shape == (18, 2)
    for joint in (NOSE, NECK, R_SHOULDER, L_SHOULDER, R_HIP, L_HIP):
        assert confidence[joint] > 0.5
    x, y, w, h = PERSON_IN_PERSON_JPG
    inside = (points[:, 0] > x - 10) & (points[:, 0] < x + w + 10) & \
             (points[:, 1] > y - 10) & (points[:, 1] < y + h + 10)
    assert inside[confidence > 0].all()
    assert points[NOSE, 1] < points[NECK, 1] < points[R_HIP, 1]        # head above hips
    assert points[NECK] == pytest.approx((points[R_SHOULDER] + points[L_SHOULDER]) / 2)
    # the person stands with her back to the camera: her right shoulder is on the image right
    assert points[R_SHOULDER, 0] > points[L_SHOULDER, 0]


def test_detectors_reject_empty_image(yolo, pose):
    empty = np.zeros((0, 0, 3), np.uint8)
    with pytest.raises(ValueError, match="non-empty"):
        yolo.detect(empty)
    with pytest.raises(ValueError, match="non-empty"):
        pose.skeletons(empty)
    with pytest.raises(ValueError, match="missing"):
        check_image(None)


def test_no_person_gives_no_skeleton(pose):
    assert pose.skeletons(np.full((240, 320, 3), 127, np.uint8)) == []


def test_stitch_stacks_top_over_bottom():
    top, bottom = np.zeros((4, 6, 3), np.uint8), np.full((5, 6, 3), 9, np.uint8)
    frame = stitch(top, bottom)
    assert frame.shape == (9, 6, 3) and frame[3, 0, 0] == 0 and frame[4, 0, 0] == 9
    with pytest.raises(ValueError, match="widths"):
        stitch(top, np.zeros((5, 7, 3), np.uint8))


def test_mediapipe_landmarks_map_to_coco18_order():
    lm = np.zeros((33, 3))
    lm[:, 2] = 1.0
    lm[12] = (0.4, 0.3, 0.9)     # mediapipe right shoulder
    lm[11] = (0.6, 0.3, 0.8)     # left shoulder
    lm[16] = (0.3, 0.6, 0.2)     # right wrist, barely visible
    points, conf = coco18_from_mediapipe(lm, 200, 100, min_visibility=0.5)
    assert points[R_SHOULDER] == pytest.approx((80, 30))
    assert points[L_SHOULDER] == pytest.approx((120, 30))
    assert points[NECK] == pytest.approx((100, 30)) and conf[NECK] == pytest.approx(0.8)
    assert np.isnan(points[R_WRIST]).all() and conf[R_WRIST] == 0.0
    with pytest.raises(ValueError, match="33 landmarks"):
        coco18_from_mediapipe(np.zeros((17, 3)), 1, 1, 0.5)
