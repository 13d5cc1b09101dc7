"""The ~update service handler refuses future stamps (no roscore: the ROS clock is stubbed)."""
import pytest
import rospy
from human_factories import make_human

from human_db import ros_node
from human_db.ros_node import HumanDbNode, NodeParams
from human_db.store import HumanStore
from tamp_msgs.srv import UpdateHumanRequest


@pytest.fixture
def node(tmp_path, monkeypatch):
    monkeypatch.setattr(ros_node.rospy, "get_time", lambda: 100.0)  # the node's present [s]
    node = HumanDbNode(NodeParams(db_path=str(tmp_path / "humans.sqlite")))
    node.store = HumanStore(node.params.db_path)
    node.store.register(make_human(), now=50.0)
    yield node
    node.store.close()


def _update(node, stamp_s, location):
    return node._update(UpdateHumanRequest(name="Alice", location=location, source="perception",
                                           stamp=rospy.Time.from_sec(stamp_s)))


def test_an_update_stamped_4e9_is_refused_and_later_updates_still_count(node):
    refused = _update(node, 4.0e9, "kitchen")
    assert not refused.success
    assert refused.message == ("update of 'Alice': stamp 4000000000.000 s is 3999999900.000 s "
                               "after the present 100.000 s (tolerance 5 s)")
    assert node._counts["refused"] == 1
    assert _update(node, 104.0, "office").success   # within the 5 s tolerance
    assert node.store.get("Alice").location == "office"
    assert _update(node, 120.0, "bedroom").success is False
    assert node.store.get("Alice").location == "office"


def test_an_update_without_a_stamp_is_recorded_now(node):
    assert _update(node, 0.0, "office").success
    assert node.store.get("Alice").last_seen == 100.0
