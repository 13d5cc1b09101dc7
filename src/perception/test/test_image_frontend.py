"""Image front end on darknet's person.jpg split into a top and a bottom camera image."""
import os
from pathlib import Path

import cv2
import numpy as np
import pytest

from perception.detector_registry import (DETECTORS, POSE_ESTIMATORS, make_detector,
                                          make_pose_estimator)
from perception.detectors import DarknetDetector, MediapipePose
from perception.image_frontend import FrontEndConfig, build_frame, joint_depths, person_crop
from perception.keypoints import NECK

MODELS = Path(os.environ.get("TAMP_MODEL_CACHE",
                             Path.home() / ".cache" / "tamp_ws" / "models")) / "yolov3_tiny"
PHOTO = "/usr/share/darknet/data/person.jpg"     # 640x424, the woman wears a blue jacket


@pytest.fixture(scope="module")
def backends():
    yolo = make_detector("darknet", {"cfg": str(MODELS / "yolov3-tiny.cfg"),
                                     "weights": str(MODELS / "yolov3-tiny.weights"),
                                     "names": str(MODELS / "coco.names")})
    pose = make_pose_estimator("mediapipe")
    yield yolo, pose
    pose.close()


def test_split_photo_gives_person_with_depth_and_blue_shirt(backends):
    image = cv2.imread(PHOTO)
    assert image is not None, "scripts/setup installs Debian's darknet sample photos"
    top, bottom = image[:212], image[212:]
    depth_top = np.full(top.shape[:2], 3.0)
    depth_bottom = np.full(bottom.shape[:2], 3.0)
    depth_top[:, :100] = 0.0                         # no return on the left edge
    frame = build_frame(top, bottom, depth_top, depth_bottom, *backends, FrontEndConfig())
    assert (frame.width, frame.height) == (640, 424)
    person = next(o for o in frame.objects if o.label == "person")
    assert person.depth == pytest.approx(3.0)
    [view] = frame.people
    assert np.nanmedian(view.depth) == pytest.approx(3.0)
    r, g, b = view.shirt[0].astype(int)               # neck: blue jacket
    assert b > r + 40 and b > g


def test_missing_depth_gives_nan_not_errors(backends):
    image = cv2.imread(PHOTO)
    frame = build_frame(image, None, None, None, *backends, FrontEndConfig())
    assert all(np.isnan(o.depth) for o in frame.objects)
    assert np.isnan(frame.people[0].depth).all()


def two_people_photo(yolo):
    """person.jpg's person (padded crop) pasted twice side by side, the second mirrored."""
    image = cv2.imread(PHOTO)
    person = next(d for d in yolo.detect(image) if d.label == "person")
    x0, y0, x1, y1 = person_crop((person.x, person.y, person.width, person.height), image.shape,
                                 0.2)
    crop = image[y0:y1, x0:x1]
    return np.hstack([crop, crop[:, ::-1]]), crop.shape[1]


def test_two_people_give_two_skeletons_top_down(backends):
    """Issue 32: mediapipe finds one person per image; pose per YOLO person box finds both."""
    image, half = two_people_photo(backends[0])
    frame = build_frame(image, None, None, None, *backends, FrontEndConfig())
    boxes = [o for o in frame.objects if o.label == "person"]
    assert len(boxes) == 2
    assert len(frame.people) == 2
    necks = sorted(float(view.points[NECK][0]) for view in frame.people)
    assert necks[0] < half < necks[1]                      # one skeleton on each person
    for view, box in zip(sorted(frame.people, key=lambda v: v.points[NECK][0]),
                         sorted(boxes, key=lambda b: b.x)):
        x, y = view.points[NECK]
        assert box.x <= x <= box.x + box.width and box.y <= y <= box.y + box.height
    whole = build_frame(image, None, None, None, *backends, FrontEndConfig(top_down=False))
    assert len(whole.people) == 1                          # the whole-image pose of before


def test_person_crop_is_padded_and_clipped():
    assert person_crop((10, 20, 100, 200), (300, 400, 3), 0.1) == (0, 0, 120, 240)
    assert person_crop((350, 250, 100, 100), (300, 400, 3), 0.0) == (350, 250, 400, 300)


def test_empty_and_mismatched_images_are_refused(backends):
    with pytest.raises(ValueError, match="non-empty"):
        build_frame(np.zeros((0, 0, 3), np.uint8), None, None, None, *backends, FrontEndConfig())
    with pytest.raises(ValueError, match="widths"):
        build_frame(np.zeros((4, 4, 3), np.uint8), np.zeros((4, 5, 3), np.uint8), None, None,
                    *backends, FrontEndConfig())


def test_joint_depth_ignores_zero_and_nan():
    depth = np.full((20, 20), 2.0)
    depth[8:13, 8:13] = np.nan
    depth[10, 12] = 0.0
    points = np.array([[10.0, 10.0], [3.0, 3.0]])
    got = joint_depths(depth, points, np.array([1.0, 1.0]), FrontEndConfig())
    assert np.isnan(got[0]) and got[1] == pytest.approx(2.0)


def test_the_registry_makes_each_model_by_name_and_names_an_unknown_one(backends):
    yolo, pose = backends
    assert isinstance(yolo, DarknetDetector) and isinstance(pose, MediapipePose)
    assert yolo.config.input_size == 416 and yolo.config.confidence_threshold == 0.25
    assert set(DETECTORS) == {"darknet"} and set(POSE_ESTIMATORS) == {"mediapipe"}
    with pytest.raises(ValueError, match="unknown detector 'yolo9'; known: darknet"):
        make_detector("yolo9", {})
    with pytest.raises(ValueError, match="unknown pose estimator 'openpose'; known: mediapipe"):
        make_pose_estimator("openpose")
