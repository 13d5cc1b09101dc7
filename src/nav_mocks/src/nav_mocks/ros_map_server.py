"""map_server / GMapping mock node: latched /map and /map_metadata, static_map and dynamic_map.

In "static" mode the map file is served as map_server does. In "mapping" mode the map grows
from the laser as GMapping's would: each /scan reveals the cells its beams crossed, located with
the simulator's ground truth (/base_pose_ground_truth) and the base -> laser transform from tf.

Every timer, subscriber and service runs under one supervision.ros_supervisor.Supervisor
("nav_mocks: map_server: supervision"): a faulted scan integration is recorded and the next one
runs as usual; a faulted map request is answered with the service error naming the reason.
"""
import threading
from dataclasses import dataclass

import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from nav_msgs.msg import MapMetaData, OccupancyGrid, Odometry
from nav_msgs.srv import GetMap, GetMapResponse
from sensor_msgs.msg import LaserScan
from floorplan.occupancy_map import MapError, load_map

from nav_mocks.conversions import (map_metadata, map_to_msg, pose_from_msg,
                                   pose_from_transform, scan_from_msg)
from nav_mocks.mapping import RevealedMap
from nav_mocks.param_checks import positive_number
from nav_mocks.pose2d import compose
from supervision.ros_params import config_from_params, refuse_unknown_params
from supervision.ros_supervisor import Supervisor

MODES = ("static", "mapping")


@dataclass(frozen=True)
class MapServerParams:
    """~parameters of the node (the map file is its argument or ~map_file; ~map_file wins)."""

    map_file: str = ""
    frame_id: str = "map"
    mode: str = "static"             # one of MODES
    base_frame: str = "base_link"
    map_update_interval: float = 1.0  # [s] mapping mode: how often the map grows
    max_urange: float = 8.0          # [m] GMapping's maxUrange: beams reveal cells this far


class MapServerNode:
    def __init__(self, params):
        map_file = params.map_file
        self.frame_id = params.frame_id
        self.mode = params.mode
        if self.mode not in MODES:
            raise ValueError(f"~mode must be one of {MODES}, got {self.mode!r}")
        self.base_frame = params.base_frame
        self.update_interval = positive_number(   # [s]
            rospy.resolve_name("~map_update_interval"), params.map_update_interval, "s")
        self.truth = load_map(map_file)
        self.map_file = map_file
        self.lock = threading.Lock()
        self.latest_scan = None
        self.latest_truth_pose = None
        self.mapping = None
        if self.mode == "mapping":
            self.mapping = RevealedMap(self.truth, params.max_urange)
        self.map_pub = rospy.Publisher("map", OccupancyGrid, queue_size=1, latch=True)
        self.meta_pub = rospy.Publisher("map_metadata", MapMetaData, queue_size=1, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.current = None
        self._publish(self.truth if self.mapping is None else self.mapping.current())
        self.sup = sup = Supervisor("nav_mocks: map_server", hardware_id=map_file)
        sup.service("static_map", GetMap, self._serve)
        sup.service("dynamic_map", GetMap, self._serve)
        if self.mapping is not None:
            self.tf_buffer = tf2_ros.Buffer()
            self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
            sup.subscriber("scan", LaserScan, self._on_scan, queue_size=1)
            sup.subscriber("base_pose_ground_truth", Odometry, self._on_truth, queue_size=1)
            sup.timer(self.update_interval, self._integrate, worker="mapping")
        sup.timer(1.0, self._diagnose, worker="diagnostics")
        rospy.loginfo("map_server mock: %s (%dx%d at %.3f m) in %s mode", map_file,
                      self.truth.width, self.truth.height, self.truth.resolution, self.mode)

    def _publish(self, grid):
        stamp = rospy.Time.now()
        msg = map_to_msg(grid, self.frame_id, stamp)
        with self.lock:
            self.current = msg
        self.map_pub.publish(msg)
        self.meta_pub.publish(map_metadata(grid, stamp))

    def _serve(self, _request):
        with self.lock:
            return GetMapResponse(map=self.current)

    def _on_scan(self, msg):
        with self.lock:
            self.latest_scan = msg

    def _on_truth(self, msg):
        with self.lock:
            self.latest_truth_pose = msg.pose.pose

    def _integrate(self, _event):
        with self.lock:
            scan, truth = self.latest_scan, self.latest_truth_pose
            self.latest_scan = None
        if scan is None or truth is None:
            return
        try:
            mount = self.tf_buffer.lookup_transform(self.base_frame, scan.header.frame_id,
                                                    rospy.Time(0), rospy.Duration(0.1))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as error:
            rospy.logwarn_throttle(10.0, "map_server mock: no %s -> %s transform: %s",
                                   self.base_frame, scan.header.frame_id, error)
            return
        laser_pose = compose(pose_from_msg(truth), pose_from_transform(mount.transform))
        if self.mapping.integrate_scan(scan_from_msg(scan), laser_pose):
            self._publish(self.mapping.current())

    def _diagnose(self, _event):
        status = DiagnosticStatus(level=DiagnosticStatus.OK, name="nav_mocks: map_server",
                                  hardware_id=self.map_file, message=f"serving ({self.mode})")
        status.values = [KeyValue("mode", self.mode),
                         KeyValue("size", f"{self.truth.width}x{self.truth.height}")]
        if self.mapping is not None:
            status.values.append(KeyValue("explored_fraction",
                                          f"{self.mapping.explored_fraction():.3f}"))
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diag_pub.publish(array)


def main(argv):
    rospy.init_node("map_server")
    try:
        params = config_from_params(MapServerParams, map_file=argv[0] if argv else "")
        refuse_unknown_params({"": MapServerParams})
        if not params.map_file:
            rospy.logfatal("map_server mock: give the map YAML as argument or ~map_file")
            return 1
        MapServerNode(params)
    except (MapError, ValueError) as error:
        rospy.logfatal("map_server mock: %s", error)
        return 1
    rospy.spin()
    return 0
