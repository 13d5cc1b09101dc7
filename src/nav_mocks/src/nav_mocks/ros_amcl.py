"""AMCL mock node: /amcl_pose and tf map -> odom from ground truth plus the AMCL noise model.

Subscribes /base_pose_ground_truth (nav_msgs/Odometry, map frame), /odom (nav_msgs/Odometry) and
/initialpose (PoseWithCovarianceStamped); publishes /amcl_pose and the map -> odom transform
(post-dated by ~transform_tolerance, as amcl does) at ~update_rate, and /diagnostics.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor ("nav_mocks:
amcl: supervision"): a faulted update is recorded and the next one runs as usual.
"""
import collections
import threading
from dataclasses import dataclass

import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseWithCovarianceStamped
from nav_msgs.msg import Odometry

from nav_mocks.amcl_model import AmclConfig, AmclModel, latest_pair, map_to_odom
from nav_mocks.conversions import pose_from_msg, pose_to_msg, transform_msg
from nav_mocks.param_checks import positive_number
from supervision.ros_params import config_from_params, refuse_unknown_params
from supervision.ros_supervisor import Supervisor

HISTORY = 50          # samples kept per stream: 1 s of sim2d's 50 Hz odometry
MAX_PAIR_GAP = 0.011  # [s] a truth this close to an odometry sample is of the same instant
                      # (sim2d stamps both alike; a base's own odometry within half a 50 Hz step)


@dataclass(frozen=True)
class AmclNodeParams:
    """~parameters of the node besides AmclConfig's."""

    global_frame_id: str = "map"
    odom_frame_id: str = "odom"
    transform_tolerance: float = 0.1  # [s] map -> odom is post-dated by this
    update_rate: float = 10.0         # [Hz]
    seed: int = 0                     # of the noise model


class AmclNode:
    def __init__(self):
        params = config_from_params(AmclNodeParams)
        self.global_frame = params.global_frame_id
        self.odom_frame = params.odom_frame_id
        self.tolerance = rospy.Duration(params.transform_tolerance)
        rate = positive_number(rospy.resolve_name("~update_rate"), params.update_rate, "Hz")
        self.model = AmclModel(config_from_params(AmclConfig), seed=params.seed)
        refuse_unknown_params({"": (AmclNodeParams, AmclConfig)})
        self.lock = threading.Lock()
        # recent (stamp, pose) samples of each stream, to pair them by time (latest_pair)
        self.truths = collections.deque(maxlen=HISTORY)
        self.odoms = collections.deque(maxlen=HISTORY)
        self.initial = None
        self.correction = None   # last map -> odom, re-sent while no new pair is found
        self.published = 0
        self.pose_pub = rospy.Publisher("amcl_pose", PoseWithCovarianceStamped, queue_size=2,
                                        latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.tf_pub = tf2_ros.TransformBroadcaster()
        # Every sample is queued: with queue_size=1 each callback keeps only the newest message,
        # and under load the two streams can drop alternate instants so that no pair exists.
        self.sup = sup = Supervisor("nav_mocks: amcl", hardware_id="amcl_mock")
        sup.subscriber("base_pose_ground_truth", Odometry, self._on_truth, queue_size=HISTORY)
        sup.subscriber("odom", Odometry, self._on_odom, queue_size=HISTORY)
        sup.subscriber("initialpose", PoseWithCovarianceStamped, self._on_initial, queue_size=1)
        sup.timer(1.0 / rate, self._update, worker="update")
        sup.timer(1.0, self._diagnose, worker="diagnostics")

    def _on_truth(self, msg):
        with self.lock:
            self.truths.append((msg.header.stamp.to_sec(), pose_from_msg(msg.pose.pose)))

    def _on_odom(self, msg):
        with self.lock:
            self.odoms.append((msg.header.stamp.to_sec(), pose_from_msg(msg.pose.pose)))

    def _on_initial(self, msg):
        with self.lock:
            self.initial = msg

    def _update(self, _event):
        with self.lock:
            pair = latest_pair(list(self.truths), list(self.odoms), MAX_PAIR_GAP)
            if pair is None:
                self._resend_correction()
                return
            initial, self.initial = self.initial, None
        true_pose, odom_pose = pair
        now = rospy.Time.now()
        if initial is not None:
            if initial.header.frame_id.lstrip("/") not in ("", self.global_frame):
                rospy.logwarn("amcl mock: ignored /initialpose in frame %r (expected %r)",
                              initial.header.frame_id, self.global_frame)
            else:
                try:
                    start = pose_from_msg(initial.pose.pose)
                except ValueError as error:
                    rospy.logwarn("amcl mock: ignored /initialpose: %s", error)
                else:
                    self.model.set_initial_pose(now.to_sec(), start, true_pose)
                    rospy.loginfo("amcl mock: initial pose (%.2f, %.2f, %.2f)", *start)
        result = self.model.estimate(now.to_sec(), true_pose)
        if result is None:
            rospy.logwarn_throttle(10.0, "amcl mock: not localised; waiting for /initialpose")
            return
        estimate, covariance = result
        msg = PoseWithCovarianceStamped()
        msg.header.stamp, msg.header.frame_id = now, self.global_frame
        pose_to_msg(estimate, msg.pose.pose)
        msg.pose.covariance = covariance
        self.pose_pub.publish(msg)
        self.correction = map_to_odom(estimate, odom_pose)
        self._send_correction(now)
        self.published += 1

    def _send_correction(self, now):
        """The last map -> odom, post-dated by ~transform_tolerance, as amcl does."""
        self.tf_pub.sendTransform(transform_msg(self.correction, self.global_frame,
                                                self.odom_frame, now + self.tolerance))

    def _resend_correction(self):
        """amcl re-sends its last map -> odom between updates: without it the transform
        expires and every consumer (move_base) loses the robot's pose."""
        if self.correction is None:
            return
        rospy.logwarn_throttle(10.0, "amcl mock: no odometry and ground truth of one instant; "
                               "re-sending the last map -> odom")
        self._send_correction(rospy.Time.now())

    def _diagnose(self, _event):
        localised = self.model.localised
        status = DiagnosticStatus(
            level=DiagnosticStatus.OK if localised else DiagnosticStatus.WARN,
            name="nav_mocks: amcl", hardware_id="amcl_mock",
            message="localised" if localised else "not localised: waiting for /initialpose")
        status.values = [KeyValue("estimates_published", str(self.published)),
                         KeyValue("converging", str(self.model.converging))]
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diag_pub.publish(array)


def main(_argv):
    rospy.init_node("amcl")
    try:
        AmclNode()
    except ValueError as error:
        rospy.logfatal("amcl mock: %s", error)
        return 1
    rospy.spin()
    return 0
