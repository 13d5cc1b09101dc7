"""The calibrated detection model against the calibration table it is made from
(config/camera_calibration.yaml, written by scripts/calibrate_camera): on a fixed scene, the
simulated detector's miss rate and colour errors are the table's."""
import math

import numpy as np
import pytest
from sim2d_fixtures import REPO

from sim2d.camera import Camera, CameraConfig, hidden_by_boxes
from sim2d.detection_model import (
    CalibratedModel, CalibrationError, DetectionConfig, combined, load_calibration, logistic_miss,
    make_detection_model, occlusion_misses)
from sim2d.skeleton import person_keypoints

TABLE = REPO / "config" / "camera_calibration.yaml"
TOP = CameraConfig(mount_x=0.09, mount_height=1.15, tilt=0.1)
BOTTOM = CameraConfig(mount_x=0.09, mount_height=1.05, tilt=0.8)
ROBOT = (0.0, 0.0, 0.0)
SHIRT = np.array([[196, 38, 45], [180, 30, 40], [184, 33, 42]])
FRAMES = 3000


@pytest.fixture(scope="module")
def calibration():
    return load_calibration(TABLE)


def calibrated_camera(calibration, seed=7):
    detection = DetectionConfig(model="calibrated", calibration=str(TABLE), seed=seed)
    return Camera(TOP, BOTTOM, detection, occluders=None,
                  model=make_detection_model(detection, calibration))


def standing_at(distance):
    """Keypoints of a person standing `distance` m ahead, facing the robot."""
    keypoints, _ = person_keypoints("standing", (distance, 0.0, math.pi))
    return keypoints


def binomial_bound(p, n):
    """Four standard errors of a rate p measured over n trials (plus one count)."""
    return 4.0 * math.sqrt(p * (1.0 - p) / n) + 1.0 / n


@pytest.mark.parametrize("distance, lighting", [(3.0, "daylight"), (5.5, "daylight"),
                                                (4.5, "dark"), (4.5, "dim")])
def test_miss_rate_on_a_fixed_scene_is_the_tables(calibration, distance, lighting):
    camera = calibrated_camera(calibration)
    keypoints = standing_at(distance)
    height = camera.apparent_height(keypoints, ROBOT)
    # the table's own figures, read independently of the model's code
    h50, width = calibration.person_curve
    expected = 1.0 - (1.0 - 1.0 / (1.0 + math.exp((height - h50) / width))) * (
        1.0 - calibration.lighting[lighting].miss_rate)
    missed = sum(camera.person_missed(keypoints, ROBOT, 0.0, lighting) for _ in range(FRAMES))
    assert missed / FRAMES == pytest.approx(expected, abs=binomial_bound(expected, FRAMES))


def test_apparent_height_is_the_pinhole_projection(calibration):
    """A standing body's height over its distance, times fy: the size the table's curve reads."""
    camera = calibrated_camera(calibration)
    keypoints = standing_at(4.0)
    spread = np.ptp(keypoints[:, 2])
    depth = np.hypot(*(keypoints.mean(axis=0)[:2] - camera.eye(ROBOT)[:2]))
    assert camera.apparent_height(keypoints, ROBOT) == pytest.approx(TOP.fy * spread / depth)
    assert 150.0 < camera.apparent_height(keypoints, ROBOT) < 300.0


@pytest.mark.parametrize("lighting", ["daylight", "tungsten", "dark"])
def test_colour_error_on_a_fixed_scene_is_the_tables(calibration, lighting):
    """Colours seen at joints 1, 2, 5: their per-channel factor (least squares) and the residual
    noise around it are the table's row for the room's light."""
    camera = calibrated_camera(calibration)
    keypoints = standing_at(2.5)
    seen, true = [], []
    for _ in range(600):
        skeleton, _ = camera.detect_person("Alice", keypoints, SHIRT, ROBOT, lighting=lighting)
        if skeleton is None:
            continue
        for colour, shirt in zip(skeleton.joint_colours, SHIRT):
            if colour.any():
                seen.append(colour.astype(float))
                true.append(shirt.astype(float))
    seen, true = np.array(seen), np.array(true)
    assert len(seen) > 600
    row = calibration.lighting[lighting]
    factor = (seen * true).sum(axis=0) / (true * true).sum(axis=0)
    assert factor == pytest.approx(row.colour_factor, abs=0.05)
    residual = np.sqrt(np.mean((seen - true * np.array(row.colour_factor)) ** 2))
    # clipping at 0 shortens the tail of dark channels a little
    assert residual == pytest.approx(row.colour_residual, rel=0.15)


def test_keypoint_error_is_the_tables_share_of_the_height(calibration):
    camera = calibrated_camera(calibration)
    keypoints = standing_at(3.0)
    height = camera.apparent_height(keypoints, ROBOT)
    exact = Camera(TOP, BOTTOM, DetectionConfig(keypoint_noise=0.0, seed=1), occluders=None)
    clean, _ = exact.detect_person("A", keypoints, SHIRT, ROBOT)
    errors = []
    for _ in range(300):
        skeleton, _ = camera.detect_person("A", keypoints, SHIRT, ROBOT)
        if skeleton is None:
            continue
        seen = (skeleton.confidence > 0) & (clean.confidence > 0)
        inside = seen & (skeleton.x > 0) & (skeleton.x < 639) & (skeleton.y > 0) & (
            skeleton.y < 959)
        errors += list(np.hypot(skeleton.x - clean.x, skeleton.y - clean.y)[inside])
    rms = math.sqrt(np.mean(np.square(errors)))
    assert rms / height == pytest.approx(calibration.keypoint_error, rel=0.1)


def test_pose_misses_follow_the_room_and_the_hidden_share(calibration):
    camera = calibrated_camera(calibration)
    keypoints = standing_at(2.5)
    for lighting, hidden in (("dark", 0.0), ("daylight", 0.5)):
        rate = combined(occlusion_misses(calibration, hidden)[1],
                        calibration.lighting[lighting].pose_miss_rate)
        posed = [camera.detect_person("A", keypoints, SHIRT, ROBOT, lighting=lighting,
                                      hidden_fraction=hidden)[0] is None for _ in range(2000)]
        assert np.mean(posed) == pytest.approx(rate, abs=binomial_bound(rate, 2000))


def test_a_sofa_hides_the_legs_not_the_head():
    """A 0.85 m tall sofa between the camera and a person standing 3 m ahead: the sight lines
    to the ankles and knees cross it, the ones to the head pass above it."""
    keypoints = standing_at(3.0)
    sofa = [(1.5, 0.0, 0.0, 0.0, (0.8, 2.0, 0.85))]
    eye = np.array([0.09, 0.0, 1.15])
    hidden = hidden_by_boxes(keypoints, eye, sofa)
    low = keypoints[:, 2] < 0.6
    assert hidden[low].all()
    assert not hidden[keypoints[:, 2] > 1.2].any()
    # a body touching the box is not behind it; nothing hides anything without boxes
    assert not hidden_by_boxes(keypoints, eye, [(3.2, 0.0, 0.0, 0.0, (0.3, 2.0, 0.5))]).any()


def test_labels_are_confused_at_the_tables_rate(calibration):
    model = CalibratedModel(calibration)
    rng = np.random.default_rng(3)
    row = calibration.lighting["dark"]
    labels = ["cup", "book", "tv", "chair"]
    changed = [model.label(rng, "cup", "dark", labels) != "cup" for _ in range(4000)]
    assert np.mean(changed) == pytest.approx(row.label_confusion_rate,
                                             abs=binomial_bound(row.label_confusion_rate, 4000))


def test_the_logistic_is_the_tables_fit(calibration):
    h50, width = calibration.person_curve
    assert logistic_miss(h50, calibration.person_curve) == pytest.approx(0.5)
    assert logistic_miss(h50 + 3 * width, calibration.person_curve) < 0.05
    assert occlusion_misses(calibration, 0.0) == (0.0, 0.0)
    assert occlusion_misses(calibration, 1.0)[0] == pytest.approx(1.0)


def test_a_table_that_cannot_be_read_is_named(tmp_path):
    with pytest.raises(CalibrationError, match="nowhere.yaml.*scripts/calibrate_camera"):
        load_calibration(tmp_path / "nowhere.yaml")
    broken = tmp_path / "broken.yaml"
    broken.write_text("lighting: [{name: daylight}]\nscale: []\n")
    with pytest.raises(CalibrationError, match="broken.yaml: missing or malformed field"):
        load_calibration(broken)


def test_ideal_model_is_kept_and_named(calibration):
    detection = DetectionConfig()
    assert detection.model == "ideal"
    assert make_detection_model(detection).name == "ideal"
    with pytest.raises(CalibrationError, match="unknown detection model 'perfect'"):
        make_detection_model(DetectionConfig(model="perfect"))
