"""ROS node `recorder`: records /scan, /cmd_vel, /odom and the instruction class into a rosbag.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor: a fault while
cached messages are written (e.g. a full disk) counts them as lost (logged at close) and shows
"penguin_base: recorder: supervision" as ERROR on /diagnostics; the next flush tries again.
"""
import os
import signal
import threading
import time
from dataclasses import dataclass

import rosbag
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import UInt8
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor

from penguin_base.record_format import NUM_CLASSES

FLUSH_PERIOD = 0.2  # [s] how often cached messages are written to the bag


@dataclass(frozen=True)
class RecorderParams:
    """~parameters of the node."""

    bag: str                    # path of the bag to write (required)
    instruction_class: int = 0  # class recorded until one arrives; 0: wait for one


class RecorderNode:
    """Callbacks cache (topic, message, time) under a lock; a timer writes them to the bag."""

    def __init__(self):
        try:
            params = config_from_params(RecorderParams)
        except KeyError:
            raise ValueError("parameter ~bag (path of the bag to write) is required") from None
        self.path = os.path.expanduser(params.bag)
        self.initial_class = params.instruction_class
        if not 0 <= self.initial_class <= NUM_CLASSES:
            raise ValueError(f"~instruction_class must be 0..{NUM_CLASSES} (0: wait for "
                             f"{rospy.resolve_name('instruction_class')}), "
                             f"got {self.initial_class}")
        self._lock = threading.Lock()
        self._pending = []
        self.counts = {}
        self.lost = 0        # messages a failed flush could not write
        self._flushing = 0   # messages of the flush under way not yet written
        self.bag = None

    def start(self, sup):
        """Open the bag and subscribe under the node's Supervisor `sup`."""
        self.bag = rosbag.Bag(self.path, "w")
        self.class_topic = rospy.resolve_name("instruction_class")
        if self.initial_class:
            self._cache(self.class_topic, UInt8(data=self.initial_class))
        for name, kind in (("scan", LaserScan), ("cmd_vel", Twist), ("odom", Odometry),
                           ("instruction_class", UInt8)):
            topic = rospy.resolve_name(name)
            sup.subscriber(topic, kind, self._cache_from(topic), queue_size=50)
        self.timer = sup.timer(FLUSH_PERIOD, self._flush, worker="flush",
                               on_error=self._count_lost)
        rospy.loginfo("recorder: writing %s", self.path)

    def _cache_from(self, topic):
        return lambda msg: self._cache(topic, msg)

    def _cache(self, topic, msg):
        with self._lock:
            self._pending.append((topic, msg, rospy.Time.now()))

    def _flush(self, _event=None):
        with self._lock:
            pending, self._pending = self._pending, []
            self._flushing = len(pending)
            for topic, msg, stamp in pending:
                self.bag.write(topic, msg, stamp)
                self.counts[topic] = self.counts.get(topic, 0) + 1
                self._flushing -= 1

    def _count_lost(self, _error):
        """A flush failed: the messages it had not written yet are lost."""
        with self._lock:
            self.lost, self._flushing = self.lost + self._flushing, 0

    def close(self):
        """Flush, end an open sequence started by ~instruction_class, close the bag."""
        self.timer.shutdown()
        if self.initial_class:
            self._cache(self.class_topic, UInt8(data=0))
        self._flush()
        with self._lock:
            self.bag.close()
        rospy.loginfo("recorder: closed %s with %s", self.path, self.counts)
        if self.lost:
            rospy.logerr("recorder: %d message(s) could not be written to %s", self.lost,
                         self.path)


def _raise_interrupt(_signum, _frame):
    raise KeyboardInterrupt


def main():
    rospy.init_node("recorder", disable_signals=True)
    signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        node = RecorderNode()
        node.start(Supervisor("penguin_base: recorder"))
    except (ValueError, OSError) as error:
        rospy.logfatal("recorder: %s", error)
        return 2
    try:
        while not rospy.is_shutdown():
            time.sleep(0.1)
    except KeyboardInterrupt:
        pass
    finally:
        node.close()
        rospy.signal_shutdown("recorder exiting")
    return 0
