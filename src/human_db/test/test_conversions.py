"""tamp_msgs/Human <-> Human, including the bytes genpy hands over for uint8[9]."""
from io import BytesIO

import pytest
from conftest import make_human

from human_db.conversions import human_from_msg, human_to_msg
from human_db.errors import InvalidHuman
from tamp_msgs.msg import Human as HumanMsg


def _over_the_wire(msg):
    buffer = BytesIO()
    msg.serialize(buffer)
    received = HumanMsg()
    received.deserialize(buffer.getvalue())
    return received


def test_round_trip_through_serialisation(alice):
    seen = make_human(location="office", activity="work", last_seen=1234.5,
                      schedules=alice.schedules)
    received = _over_the_wire(human_to_msg(seen))
    assert isinstance(received.shirt_color, bytes)
    assert received.gender == HumanMsg.GENDER_FEMALE
    assert human_from_msg(received) == seen
    never = human_from_msg(_over_the_wire(human_to_msg(alice)))
    assert never.last_seen is None and never == alice


def test_a_bad_message_is_refused_naming_the_field():
    msg = human_to_msg(make_human())
    msg.ip = "not-an-ip"
    with pytest.raises(InvalidHuman, match="not an IP address"):
        human_from_msg(msg)
