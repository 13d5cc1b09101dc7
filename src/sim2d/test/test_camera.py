"""Object boxes of the simulated camera: the box of the visible projection, checked against a
hand calculation and against a dense sampling of the object's surface."""
import math

import numpy as np
import pytest

from sim2d.camera import (
    Camera, CameraConfig, DetectionConfig, camera_points, project, stitched_extent)
from sim2d.world import SimObject

TOP = CameraConfig(mount_x=0.09, mount_height=1.15, tilt=0.0)
BOTTOM = CameraConfig(mount_x=0.09, mount_height=1.05, tilt=0.8)
ROBOT = (0.0, 0.0, 0.0)


def board(forward, width, height, thickness=0.01):
    """A thin upright board whose near face is `forward` [m] ahead of the cameras."""
    return SimObject("board", "refrigerator", (0.09 + forward + thickness / 2.0, 0.0, 0.0), 0.0,
                     (thickness, width, height))


def sampled_extent(obj, robot_pose, n=80):
    """Bounding box of a dense grid of points on all six faces of the object's box, projected
    point by point into each camera and stitched (bottom rows offset by the top height)."""
    x, y, yaw = obj.pose
    hx, hy, hz = obj.size[0] / 2.0, obj.size[1] / 2.0, obj.size[2] / 2.0
    s = np.linspace(-1.0, 1.0, n)
    a, b = (g.ravel() for g in np.meshgrid(s, s))
    local = []
    for axis in range(3):
        for side in (-1.0, 1.0):
            face = np.zeros((a.size, 3))
            face[:, axis] = side
            face[:, (axis + 1) % 3], face[:, (axis + 2) % 3] = a, b
            local.append(face)
    local = np.vstack(local) * [hx, hy, hz]
    c, s_ = math.cos(yaw), math.sin(yaw)
    points = np.column_stack([x + c * local[:, 0] - s_ * local[:, 1],
                              y + s_ * local[:, 0] + c * local[:, 1],
                              obj.elevation + hz + local[:, 2]])
    us, vs = [], []
    for camera, offset in ((TOP, 0.0), (BOTTOM, float(TOP.height))):
        u, v, inside = project(camera_points(points, robot_pose, camera), camera)
        us.append(u[inside])
        vs.append(v[inside] + offset)
    u, v = np.concatenate(us), np.concatenate(vs)
    return u.min(), v.min(), u.max(), v.max()


def test_board_wider_than_the_image_straddles_both_cameras():
    """A 3 m wide, 1.8 m tall board 2 m ahead: its corners all fall outside the image, yet it
    fills the frame's width from its top edge in the top image to its foot in the bottom one."""
    u0, v0, u1, v1 = stitched_extent(board(2.0, 3.0, 1.8).corners(), ROBOT, TOP, BOTTOM)
    assert (u0, u1) == pytest.approx((0.0, 640.0))
    # top edge in the top camera (level): v = cy - fy (1.8 - 1.15) / 2.0
    assert v0 == pytest.approx(240.0 - 588.5 * 0.65 / 2.0)            # 48.74 px
    # foot in the bottom camera (pitched 0.8 rad down): v = cy + fy tan(atan(1.05 / 2.0) - 0.8)
    foot = 480.0 + 240.0 + 588.5 * math.tan(math.atan2(1.05, 2.0) - 0.8)
    assert v1 == pytest.approx(foot)                                    # 526.5 px
    # the old corner-only box saw no corner at all in the image
    u, v, inside = project(camera_points(board(2.0, 3.0, 1.8).corners(), ROBOT, TOP), TOP)
    assert not inside.any()


def test_detected_box_is_the_visible_projection():
    camera = Camera(TOP, BOTTOM, DetectionConfig(miss_probability=0.0, seed=1), occluders=None)
    fridge = board(2.0, 3.0, 1.8)
    [det] = camera.detect_objects([("f", "refrigerator", fridge.corners(), fridge.centre())],
                                  ROBOT)
    foot = 480.0 + 240.0 + 588.5 * math.tan(math.atan2(1.05, 2.0) - 0.8)
    assert (det.x, det.y, det.width) == (0, 48, 639)
    assert det.y + det.height == math.ceil(foot)


@pytest.mark.parametrize("pose, size", [
    ((1.2, 0.3, 0.4), (0.6, 0.7, 1.8)),      # fridge close by, cut by the image's edges
    ((0.6, 0.9, 1.2), (2.0, 1.4, 0.45)),     # bed beside the robot, partly behind the camera
    ((2.5, -0.8, 0.3), (0.6, 0.7, 1.8)),     # fridge off to the right, across the seam
])
def test_extent_matches_dense_sampling(pose, size):
    obj = SimObject("o", "thing", pose, 0.0, size)
    expected = sampled_extent(obj, ROBOT)
    got = stitched_extent(obj.corners(), ROBOT, TOP, BOTTOM)
    assert got == pytest.approx(expected, abs=3.0)


def test_object_behind_the_camera_has_no_box():
    behind = SimObject("o", "thing", (-1.5, 0.0, 0.0), 0.0, (0.6, 0.7, 1.8))
    assert stitched_extent(behind.corners(), ROBOT, TOP, BOTTOM) is None
