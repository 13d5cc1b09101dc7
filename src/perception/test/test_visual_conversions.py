"""sensor_msgs/Image and PerceptionFrame conversions of the visual perception."""
import numpy as np
import pytest
from sensor_msgs.msg import Image
from std_msgs.msg import Header

from perception.conversions import depth_from_msg, frame_from_msg, frame_to_msg, image_from_msg
from perception.visual_pipeline import FrameView, ObjectBox, PersonView


def test_rgb8_with_row_padding_becomes_bgr():
    rgb = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3)
    padded = np.zeros((2, 12), np.uint8)
    padded[:, :9] = rgb.reshape(2, 9)
    msg = Image(height=2, width=3, encoding="rgb8", step=12, data=padded.tobytes())
    assert (image_from_msg(msg) == rgb[:, :, ::-1]).all()
    with pytest.raises(ValueError, match="mono16"):
        image_from_msg(Image(height=1, width=1, encoding="mono16", step=2, data=b"\0\0"))
    with pytest.raises(ValueError, match="empty"):
        image_from_msg(Image(encoding="bgr8"))


def test_depth_16uc1_millimetres_and_32fc1_metres():
    mm = np.array([[1500, 0]], dtype="<u2")
    msg = Image(height=1, width=2, encoding="16UC1", step=4, data=mm.tobytes())
    assert depth_from_msg(msg).tolist() == [[1.5, 0.0]]
    m = np.array([[2.25, np.nan]], dtype="<f4")
    got = depth_from_msg(Image(height=1, width=2, encoding="32FC1", step=8, data=m.tobytes()))
    assert got[0, 0] == 2.25 and np.isnan(got[0, 1])


def test_frame_round_trip():
    pts = np.arange(36, dtype=float).reshape(18, 2)
    conf = np.ones(18)
    conf[3] = 0.0
    pts[3] = np.nan
    shirt = np.array([[1, 2, 3], [4, 5, 6], [7, 8, 9]], np.uint8)
    frame = FrameView(640, 960, [ObjectBox("cup", 0.5, 10, 20, 30, 40, 1.25)],
                      [PersonView(pts, conf, np.full(18, 2.0), shirt)])
    back = frame_from_msg(frame_to_msg(frame, Header(frame_id="camera")))
    assert (back.width, back.height) == (640, 960)
    assert back.objects[0] == ObjectBox("cup", 0.5, 10, 20, 30, 40, 1.25)
    assert back.people[0].points[4].tolist() == [8.0, 9.0]
    assert back.people[0].confidence[3] == 0.0
    assert (back.people[0].shirt == shirt).all()
