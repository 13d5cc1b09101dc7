"""The image front end node: camera images (+ depth) -> /camera/detections
(tamp_msgs/PerceptionFrame) through stitching, YOLO (cv2.dnn Darknet) and mediapipe pose."""
import os
import threading
import time
from pathlib import Path

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import Image
from tamp_msgs.msg import PerceptionFrame

from perception.conversions import depth_from_msg, frame_to_msg, image_from_msg
from perception.detectors import DarknetConfig, DarknetDetector, MediapipePose
from perception.image_frontend import FrontEndConfig, build_frame

MODELS = Path(os.environ.get("TAMP_MODEL_CACHE", Path.home() / ".cache" / "tamp_ws" / "models"))
STREAMS = ("top", "bottom", "depth_top", "depth_bottom")


class ImageFrontEnd:
    def __init__(self):
        yolo = MODELS / "yolov3_tiny"
        self.darknet = DarknetConfig(
            rospy.get_param("~cfg", str(yolo / "yolov3-tiny.cfg")),     # any Darknet cfg ...
            rospy.get_param("~weights", str(yolo / "yolov3-tiny.weights")),  # ... + weights
            rospy.get_param("~names", str(yolo / "coco.names")),
            input_size=int(rospy.get_param("~input_size", 416)),
            confidence_threshold=float(rospy.get_param("~confidence_threshold", 0.25)))
        self.stitch = bool(rospy.get_param("~stitch", True))
        self.top_down = bool(rospy.get_param("~top_down", True))   # pose per YOLO person box
        self.period = float(rospy.get_param("~period", 0.2))
        self._lock = threading.Lock()
        self._latest = dict.fromkeys(STREAMS)
        self._latency, self._counts = 0.0, {"frames": 0, "refused": 0}

    def setup(self):
        self.detector = DarknetDetector(self.darknet)
        self.pose = MediapipePose()
        self.config = FrontEndConfig(top_down=self.top_down)
        self.frames = rospy.Publisher("/camera/detections", PerceptionFrame, queue_size=2)
        self.diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        topics = {"top": "camera/top/image_raw", "bottom": "camera/bottom/image_raw",
                  "depth_top": "camera/top/depth", "depth_bottom": "camera/bottom/depth"}
        for key, topic in topics.items():
            if key == "bottom" and not self.stitch:
                continue
            rospy.Subscriber(topic, Image, self._store, callback_args=key, queue_size=1)
        self._timers = [rospy.Timer(rospy.Duration(self.period), self._on_work),
                        rospy.Timer(rospy.Duration(1.0), self._on_diagnostics)]

    def _store(self, msg, key):
        with self._lock:
            self._latest[key] = msg

    def _on_work(self, _event):
        with self._lock:
            msgs = dict(self._latest)
            self._latest["top"] = None
        if msgs["top"] is None or (self.stitch and msgs["bottom"] is None):
            return
        started = time.perf_counter()
        try:
            images = [image_from_msg(msgs["top"]),
                      image_from_msg(msgs["bottom"]) if self.stitch else None]
            depths = [depth_from_msg(msgs[k]) if msgs[k] is not None else None
                      for k in ("depth_top", "depth_bottom")]
            frame = build_frame(images[0], images[1], depths[0], depths[1], self.detector,
                                self.pose, self.config)
        except ValueError as error:
            with self._lock:
                self._counts["refused"] += 1
            rospy.logwarn_throttle(5.0, "image_frontend: images refused: %s", error)
            return
        self.frames.publish(frame_to_msg(frame, msgs["top"].header))
        with self._lock:
            self._counts["frames"] += 1
            self._latency = time.perf_counter() - started

    def _on_diagnostics(self, _event):
        with self._lock:
            counts, latency = dict(self._counts), self._latency
        status = DiagnosticStatus(
            name="perception: image_frontend", hardware_id="camera",
            level=DiagnosticStatus.OK if counts["frames"] else DiagnosticStatus.WARN,
            message="ok" if counts["frames"] else "no images processed yet",
            values=[KeyValue(k, str(v)) for k, v in sorted(counts.items())]
            + [KeyValue("latency_ms", f"{latency * 1000:.1f}")])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diagnostics.publish(array)


def main():
    rospy.init_node("image_frontend")
    try:
        node = ImageFrontEnd()
        node.setup()
    except (OSError, ValueError) as error:
        rospy.logfatal("image_frontend: cannot start: %s", error)
        return 1
    rospy.spin()
    return 0
