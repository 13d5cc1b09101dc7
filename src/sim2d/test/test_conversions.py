"""Core types -> ROS messages (needs Debian's ROS Python packages, no roscore)."""
import math

import numpy as np
import pytest
from sim2d_fixtures import LASER_DIR
from sensor_msgs.msg import JointState

from sim2d.camera import CameraFrame, ObjectDetection, SkeletonDetection
from sim2d.conversions import (ObjectMarkers, encoder_msg, frame_msg, object_markers, scan_msg,
                               wheel_command, yaw_quaternion)
from sim2d.laser import find_laser_model
from sim2d.world import Scan, SimObject


def test_scan_message_carries_the_model_and_inf():
    model = find_laser_model("utm_30lx", LASER_DIR)
    ranges = np.full(model.num_beams, 2.5, dtype=np.float32)
    ranges[0] = np.inf
    msg = scan_msg(Scan(12.5, ranges, 3), model, "base_laser")
    assert msg.header.stamp.to_sec() == pytest.approx(12.5)
    assert len(msg.ranges) == 1081 and math.isinf(msg.ranges[0])
    assert msg.angle_min == pytest.approx(-math.radians(135))
    assert msg.angle_max == pytest.approx(math.radians(135))
    assert msg.scan_time == pytest.approx(0.025)
    assert msg.time_increment == pytest.approx(0.025 / 1440)


def test_wheel_command_by_name_in_any_order_or_by_position():
    by_name = JointState(name=["right_wheel_joint", "left_wheel_joint"], velocity=[2.0, 1.0])
    assert wheel_command(by_name) == (1.0, 2.0)
    assert wheel_command(JointState(velocity=[1.0, 2.0])) == (1.0, 2.0)
    with pytest.raises(ValueError, match="left_wheel_joint"):
        wheel_command(JointState(name=["caster"], velocity=[1.0]))


def test_encoder_positions_are_whole_ticks():
    msg = encoder_msg(1.0, [1.0, -1.0], [0.5, 0.6], ticks_per_rev=100)
    tick = 2 * math.pi / 100
    assert msg.position[0] == pytest.approx(15 * tick)       # 1.0 rad = 15.9 ticks
    assert msg.position[1] == pytest.approx(-16 * tick)
    assert list(msg.velocity) == [0.5, 0.6]


def test_perception_frame_keeps_boxes_keypoints_and_shirt_colour():
    skeleton = SkeletonDetection(np.arange(18.0), np.arange(18.0) + 100, np.full(18, 0.9),
                                 np.full(18, 2.0), np.array([[1, 2, 3], [4, 5, 6], [7, 8, 9]],
                                                            dtype=np.uint8))
    frame = CameraFrame(640, 960, [ObjectDetection("cup", 0.8, 10, 20, 30, 40, 1.5)], [skeleton])
    msg = frame_msg(frame, 3.0, "camera_top_optical")
    assert (msg.image_width, msg.image_height) == (640, 960)
    assert (msg.objects[0].label, msg.objects[0].width) == ("cup", 30)
    assert list(msg.skeletons[0].joint_rgb) == [1, 2, 3, 4, 5, 6, 7, 8, 9]
    assert msg.skeletons[0].y[17] == pytest.approx(117.0)


def test_yaw_quaternion_is_unit_and_half_angle():
    q = yaw_quaternion(math.pi / 2)
    assert (q.z, q.w) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))


def test_object_markers_are_rebuilt_only_for_changed_objects():
    cup = SimObject("cup", "cup", (1.0, 2.0, 0.0), 0.7, (0.1, 0.1, 0.12))
    sofa = SimObject("sofa", "couch", (3.0, 1.0, 1.5), 0.0, (2.0, 0.9, 0.8))
    cache = ObjectMarkers()
    first = cache.update(1.0, [cup, sofa])
    fresh = object_markers(1.0, [cup, sofa])
    assert [(m.ns, m.id, m.pose, m.scale, m.text) for m in first] == \
        [(m.ns, m.id, m.pose, m.scale, m.text) for m in fresh]
    cup.pose = (1.5, 2.0, 0.0)               # carried away: its markers move, the sofa's are kept
    second = cache.update(2.0, [cup, sofa])
    assert second[0].pose.position.x == pytest.approx(1.5)
    assert second[0] is not first[0] and second[2] is first[2]
    assert all(m.header.stamp.to_sec() == pytest.approx(2.0) for m in second)
