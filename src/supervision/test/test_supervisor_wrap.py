"""Supervisor.wrap: a callback's fault is counted, except a rospy.ROSException raised while the
node shuts down (a publisher closed under the callback)."""
import pytest
import rospy

from supervision.health import Health, HealthConfig
from supervision.ros_supervisor import Supervisor


def supervisor():
    sup = Supervisor.__new__(Supervisor)   # no ROS master: only the guard is under test
    sup.health = Health("node", HealthConfig(), log=lambda *args: None)
    return sup


def closed_publisher(_arg):
    raise rospy.ROSException("topic was closed during publish()")


@pytest.mark.parametrize("is_shutdown, requested", [
    (True, True),     # rospy shut down
    (False, True),    # the node's own rospy.on_shutdown hooks run before is_shutdown() turns true
])
def test_a_closed_publisher_at_shutdown_is_not_a_fault(monkeypatch, is_shutdown, requested):
    sup = supervisor()
    monkeypatch.setattr(rospy, "is_shutdown", lambda: is_shutdown)
    monkeypatch.setattr(rospy.core, "is_shutdown_requested", lambda: requested)
    assert sup.wrap("control", closed_publisher)(None) is None
    assert sup.health.faults == 0


def test_the_same_error_while_running_is_a_fault(monkeypatch):
    sup = supervisor()
    monkeypatch.setattr(rospy, "is_shutdown", lambda: False)
    monkeypatch.setattr(rospy.core, "is_shutdown_requested", lambda: False)
    errors = []
    sup.wrap("control", closed_publisher, on_error=errors.append)(None)
    assert sup.health.faults == 1 and len(errors) == 1
