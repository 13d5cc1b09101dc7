"""The camera calibration's measures (perception.camera_calibration) on hand-made cases, and one
photo through the real detectors."""
import math
from pathlib import Path

import numpy as np
import pytest

from perception.camera_calibration import (
    CANVAS_GREY, FRAME, Condition, Lighting, Tally, box_error, colour_model, conditions,
    fit_frame, fit_miss_curve, iou, keypoint_error, occlude, shrink, summarise, visible_part)

PHOTO = Path("/usr/share/darknet/data/person.jpg")


def test_iou_of_known_boxes():
    assert iou((0, 0, 10, 10), (0, 0, 10, 10)) == 1.0
    assert iou((0, 0, 10, 10), (5, 0, 10, 10)) == pytest.approx(50 / 150)
    assert iou((0, 0, 10, 10), (20, 20, 5, 5)) == 0.0


def test_box_and_keypoint_errors_are_shares_of_the_height():
    assert box_error((0, 0, 50, 100), (2, 4, 50, 100)) == pytest.approx((2 + 4 + 2 + 4) / 4 / 100)
    points = np.zeros((18, 2))
    confidence = np.ones(18)
    moved = points + [3.0, 4.0]            # every joint 5 px away
    confidence_found = confidence.copy()
    confidence_found[5:] = 0.0             # only joints both see count
    assert keypoint_error((points, confidence), (moved, confidence_found), 100.0) == \
        pytest.approx(0.05)
    assert math.isnan(keypoint_error((points, 0 * confidence), (moved, confidence), 100.0))


def test_visible_part_and_occlusion_hide_the_same_band():
    image = np.zeros((100, 100, 3), np.uint8)
    box = (10, 20, 40, 60)
    assert visible_part(box, "bottom", 0.25) == (10, 20, 40, 45)
    assert visible_part(box, "side", 0.5) == (10, 20, 20, 60)
    out = occlude(image, [box], "bottom", 0.25)
    grey = np.argwhere(out[:, :, 0] == CANVAS_GREY)
    assert grey[:, 0].min() == 65 and grey[:, 0].max() == 79       # rows 65..79: the lower 15
    assert grey[:, 1].min() == 10 and grey[:, 1].max() == 49


def test_shrink_maps_reference_pixels_into_the_smaller_scene():
    reference = fit_frame(np.full((480, 640, 3), 200, np.uint8))
    assert reference.shape == (2 * FRAME[1], FRAME[0], 3)
    assert (reference[FRAME[1]:] == CANVAS_GREY).all()           # bottom camera's half grey
    small, (s, x0, y0) = shrink(reference, 0.5)
    assert (s, x0, y0) == (0.5, 160.0, 120.0)
    assert (small[120:360, 160:480] == 200).all() and small[100, 100, 0] == CANVAS_GREY


def test_lighting_keeps_daylight_and_casts_colour():
    rng = np.random.default_rng(0)
    image = np.full((50, 50, 3), 120, np.uint8)
    day = Lighting("daylight", read_noise=0.0).render(image, rng)
    assert (day == image).all()
    warm = Lighting("warm", light=1.0, white_balance=(1.0, 0.8, 0.5), read_noise=0.0)
    b, g, r = warm.render(image, rng)[0, 0]
    assert (r, g, b) == (120, 96, 60)
    dark = Lighting("dark", light=0.1, read_noise=2.0).render(image, rng)
    assert abs(float(dark.mean()) - 120) < 3 and dark.std() > 10        # amplified noise


def test_colour_model_recovers_a_factor_and_its_noise():
    rng = np.random.default_rng(1)
    ref = rng.uniform(40, 200, (4000, 3))
    got = ref * [0.9, 0.8, 0.6] + rng.normal(0, 5.0, ref.shape)
    factor, residual = colour_model(list(zip(ref, got)))
    assert factor == pytest.approx([0.9, 0.8, 0.6], abs=0.01)
    assert residual == pytest.approx(5.0, rel=0.05)


def test_miss_curve_fit_recovers_a_logistic():
    rng = np.random.default_rng(2)
    heights = rng.uniform(20, 300, 3000).round(1)
    missed = rng.random(3000) < 1 / (1 + np.exp((heights - 120) / 30))
    rows = [{"heights": list(heights), "missed_heights": list(heights[missed])}]
    curve = fit_miss_curve(rows)
    assert curve["h50"] == pytest.approx(120, abs=6)
    assert curve["width"] == pytest.approx(30, abs=4)
    assert curve["samples"] == 3000 and curve["missed"] == int(missed.sum())


def test_every_factor_is_varied_alone():
    kinds = {c.kind for c in conditions()}
    assert kinds == {"scale", "occlusion", "lighting"}
    for c in conditions():
        assert (c.scale < 1.0) + bool(c.occlusion) + (c.lighting.name != "daylight") <= 1


def test_summary_counts_misses_and_confusions():
    tally = Tally(people=4, missed=1, posed=3, pose_missed=1, objects=5, objects_missed=1,
                  confusions={"horse -> cow": 2}, false_people=1, images=2)
    row = summarise(Condition("lighting", "daylight"), tally, [])
    assert row["miss_rate"] == 0.25 and row["pose_miss_rate"] == pytest.approx(0.333)
    assert row["label_confusion_rate"] == 0.5 and row["false_people_per_image"] == 0.5


@pytest.mark.skipif(not PHOTO.is_file(), reason="Debian's darknet photos are installed by setup")
def test_real_detectors_lose_a_far_person_and_keep_a_near_one():
    """person.jpg through YOLOv3-tiny and mediapipe: nothing added at full size in daylight,
    everyone lost at a tenth of the size."""
    import cv2
    from perception.camera_calibration import calibrate
    from perception.detector_registry import make_detector, make_pose_estimator
    from perception.stt import model_cache_root
    models = model_cache_root() / "yolov3_tiny"
    detector = make_detector("darknet", {"cfg": str(models / "yolov3-tiny.cfg"),
                                         "weights": str(models / "yolov3-tiny.weights"),
                                         "names": str(models / "coco.names")})
    table = calibrate([("person.jpg", cv2.imread(str(PHOTO)))], detector,
                      make_pose_estimator("mediapipe"))
    rows = {row["name"]: row for kind in ("scale", "lighting") for row in table[kind]}
    assert rows["scale 1"]["people"] >= 1 and rows["scale 1"]["miss_rate"] == 0.0
    assert rows["daylight"]["keypoint_error"] < 0.05
    assert rows["scale 0.09"]["miss_rate"] == 1.0
