"""PeopleDirectory over the human database's latched table (/humans/known, tamp_msgs/HumanArray)."""
import threading

import rospy
from tamp_msgs.msg import HumanArray

from perception.conversions import person_from_msg
from perception.verbal_instructions import DictPeopleDirectory, PeopleDirectory


class HumanTableDirectory(PeopleDirectory):
    """Latest table of human_db; lookups read a snapshot, the callback only swaps it in."""

    def __init__(self, topic="humans/known"):
        self.topic = topic
        self._lock = threading.Lock()
        self._table = None  # DictPeopleDirectory, None until the first table arrives
        self._stamp = None  # [s] header stamp of that table
        self._subscriber = None

    def setup(self, sup=None):
        """Subscribe to the table; under the node's supervision.ros_supervisor.Supervisor `sup`
        when given (a malformed table is then a counted fault, the previous table stays)."""
        subscribe = rospy.Subscriber if sup is None else sup.subscriber
        self._subscriber = subscribe(self.topic, HumanArray, self._on_table, queue_size=1)

    def _on_table(self, msg):
        table = DictPeopleDirectory([person_from_msg(h) for h in msg.humans])
        with self._lock:
            self._table, self._stamp = table, msg.header.stamp.to_sec()

    def received(self):
        with self._lock:
            return self._table is not None

    def stamp(self):
        """Header stamp [s] of the table in use (None before the first): which of human_db's
        tables a lookup reads, for the node's diagnostics."""
        with self._lock:
            return self._stamp

    def _snapshot(self):
        with self._lock:
            return self._table

    def lookup_by_ip(self, ip):
        table = self._snapshot()
        return table.lookup_by_ip(ip) if table else None

    def lookup_by_name(self, name):
        table = self._snapshot()
        return table.lookup_by_name(name) if table else None
