import numpy as np

from sim2d.camera import CameraFrame, ObjectDetection, SkeletonDetection
from sim2d.camera_plot import plot_camera_frame


def test_plot_camera_frame_writes_a_png(tmp_path):
    confidence = np.zeros(18)
    confidence[[0, 1, 2, 5]] = 0.9
    skeleton = SkeletonDetection(x=np.linspace(100, 200, 18), y=np.linspace(50, 400, 18),
                                 confidence=confidence, depth=np.full(18, 2.0),
                                 joint_colours=np.full((3, 3), 200, np.uint8))
    box = ObjectDetection(label="cup", confidence=0.8, x=10, y=20, width=30, height=40, depth=1.5)
    out = tmp_path / "frame.png"
    plot_camera_frame(CameraFrame(640, 960, [box], [skeleton]), title="t", out_path=out)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
