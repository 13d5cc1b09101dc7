"""The image front end node: camera images (+ depth) -> /camera/detections
(tamp_msgs/PerceptionFrame) through stitching, YOLO (cv2.dnn Darknet) and mediapipe pose.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor: a fault while
images are turned into a frame refuses those images with the reason (counted in the node's own
diagnostics), raises "perception: image_frontend: supervision" to ERROR, and the next images are
processed as usual."""
import os
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import Image
from tamp_msgs.msg import PerceptionFrame

from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor

from perception.conversions import depth_from_msg, frame_to_msg, image_from_msg
from perception.detector_registry import make_detector, make_pose_estimator
from perception.image_frontend import FrontEndConfig, build_frame

MODELS = Path(os.environ.get("TAMP_MODEL_CACHE", Path.home() / ".cache" / "tamp_ws" / "models"))
YOLO = MODELS / "yolov3_tiny"
STREAMS = ("top", "bottom", "depth_top", "depth_bottom")


@dataclass(frozen=True)
class FrontEndParams:
    """~parameters of the node."""

    detector: str = "darknet"          # perception.detector_registry.DETECTORS
    pose: str = "mediapipe"            # perception.detector_registry.POSE_ESTIMATORS
    cfg: str = str(YOLO / "yolov3-tiny.cfg")          # darknet: any Darknet cfg ...
    weights: str = str(YOLO / "yolov3-tiny.weights")  # ... + weights
    names: str = str(YOLO / "coco.names")
    input_size: int = 416              # [px] network input
    confidence_threshold: float = 0.25
    stitch: bool = True                # stitch the bottom camera under the top one
    top_down: bool = True              # pose per YOLO person box
    period: float = 0.2                # [s] work timer period


class ImageFrontEnd:
    def __init__(self):
        params = config_from_params(FrontEndParams)
        self.params = params
        self.stitch = params.stitch
        self.top_down = params.top_down
        self.period = params.period
        self._lock = threading.Lock()
        self._latest = dict.fromkeys(STREAMS)
        self._latency, self._counts = 0.0, {"frames": 0, "refused": 0}
        self._working = None    # the top image being processed (for a fault's reason)
        self._last_refused = ""  # why the last images were refused

    def setup(self, sup):
        """Load the models and start the ROS API under the node's Supervisor `sup`."""
        p = self.params
        self.detector = make_detector(p.detector, {
            "cfg": p.cfg, "weights": p.weights, "names": p.names, "input_size": p.input_size,
            "confidence_threshold": p.confidence_threshold})
        self.pose = make_pose_estimator(p.pose)
        self.config = FrontEndConfig(top_down=self.top_down)
        self.frames = rospy.Publisher("camera/detections", PerceptionFrame, queue_size=2)
        self.diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        topics = {"top": "camera/top/image_raw", "bottom": "camera/bottom/image_raw",
                  "depth_top": "camera/top/depth", "depth_bottom": "camera/bottom/depth"}
        for key, topic in topics.items():
            if key == "bottom" and not self.stitch:
                continue
            sup.subscriber(topic, Image, self._store_as(key), worker=f"{key} image",
                           queue_size=1)
        self._timers = [sup.timer(self.period, self._on_work, worker="work",
                                  on_error=self._refuse),
                        sup.timer(1.0, self._on_diagnostics, worker="diagnostics")]

    def _store_as(self, key):
        return lambda msg: self._store(msg, key)

    def _store(self, msg, key):
        with self._lock:
            self._latest[key] = msg

    def _on_work(self, _event):
        with self._lock:
            msgs = dict(self._latest)
            self._latest["top"] = None
        if msgs["top"] is None or (self.stitch and msgs["bottom"] is None):
            return
        self._working = msgs["top"]
        started = time.perf_counter()
        # ValueError on an empty image, an unsupported encoding, mismatched widths: _refuse
        images = [image_from_msg(msgs["top"]),
                  image_from_msg(msgs["bottom"]) if self.stitch else None]
        depths = [depth_from_msg(msgs[k]) if msgs[k] is not None else None
                  for k in ("depth_top", "depth_bottom")]
        frame = build_frame(images[0], images[1], depths[0], depths[1], self.detector,
                            self.pose, self.config)
        self.frames.publish(frame_to_msg(frame, msgs["top"].header))
        with self._lock:
            self._counts["frames"] += 1
            self._latency = time.perf_counter() - started
        self._working = None

    def _refuse(self, error):
        """The work timer faulted: the images count as refused, with the reason."""
        msg, self._working = self._working, None
        if msg is None:
            return
        with self._lock:
            self._counts["refused"] += 1
            self._last_refused = (f"images stamped {msg.header.stamp.to_sec():.3f}: "
                                  f"{fault_text(error)}")

    def _on_diagnostics(self, _event):
        with self._lock:
            counts, latency, last_refused = dict(self._counts), self._latency, self._last_refused
        status = DiagnosticStatus(
            name="perception: image_frontend", hardware_id="camera",
            level=DiagnosticStatus.OK if counts["frames"] else DiagnosticStatus.WARN,
            message="ok" if counts["frames"] else "no images processed yet",
            values=[KeyValue(k, str(v)) for k, v in sorted(counts.items())]
            + [KeyValue("latency_ms", f"{latency * 1000:.1f}"),
               KeyValue("last_refused", last_refused or "none")])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diagnostics.publish(array)


def main():
    rospy.init_node("image_frontend")
    sup = Supervisor("perception: image_frontend", hardware_id="camera")
    try:
        node = ImageFrontEnd()
        node.setup(sup)
    except (OSError, ValueError) as error:
        rospy.logfatal("image_frontend: cannot start: %s", error)
        return 1
    rospy.spin()
    return 0
