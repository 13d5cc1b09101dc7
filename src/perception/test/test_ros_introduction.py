"""The introduction node's reading of the executors' states (no ROS master needed)."""
import rospy
from tamp_msgs.msg import InstructionState, TaskBufferState

from perception.ros_introduction import greeted_at


def state(stamp_s, *records):
    msg = TaskBufferState(instructions=list(records))
    msg.header.stamp = rospy.Time.from_sec(stamp_s)
    return msg


def test_the_greeting_is_dated_by_the_state_that_reports_the_meeting_active():
    """The executor greets as the meeting starts and stamps the state it publishes then; the
    node may take that state later (here at 404.6 s), and an answer spoken in between (404.2 s)
    belongs to the dialogue."""
    meeting = InstructionState(state=InstructionState.ACTIVE)
    other = InstructionState(state=InstructionState.PENDING)
    states = [state(390.0, other), state(404.1, meeting)]
    assert greeted_at(states, meeting, 404.6) == 404.1
    assert greeted_at([state(0.0, meeting)], meeting, 404.6) == 404.6   # unstamped: now
    assert greeted_at([state(405.0, meeting)], meeting, 404.6) == 404.6  # never after now
