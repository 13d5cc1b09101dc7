"""tamp_msgs/Instruction <-> Instruction; task buffer -> InstructionState, TaskBufferState;
tamp_msgs/HumanArray -> the sightings and schedules of people_belief."""
from tamp_msgs.msg import Instruction as InstructionMsg
from tamp_msgs.msg import InstructionState as InstructionStateMsg
from tamp_msgs.msg import TaskBufferState as TaskBufferStateMsg

from task_planner.instruction import Instruction

_FIELDS = ("id", "previous_id", "gamma", "beta", "start_time", "duration", "source", "target",
           "status", "function", "destination", "destination_name", "text")


def instruction_to_msg(instruction):
    msg = InstructionMsg(**{name: getattr(instruction, name) for name in _FIELDS})
    msg.type = bool(instruction.type)
    return msg


def people_from_msg(msg, names):
    """human_db's table -> ({name: (node or None, last seen [s]) for people ever seen},
    {name: [(start, end, node or None)] schedules}); `names`: the graph's place names."""
    def node_of(place):
        return names.index(place) if place in names else None
    sightings = {h.name: (node_of(h.location), h.last_seen.to_sec()) for h in msg.humans
                 if not h.last_seen.is_zero()}   # never seen: nobody knows where they are
    schedules = {h.name: [(e.start, e.end, node_of(e.place)) for e in h.schedules]
                 for h in msg.humans}
    return sightings, schedules


def sightings_from_observed(msg, names):
    """One analysed camera frame (/humans/observed) -> (its stamp [s], [(name, node, x, y)] of
    the people perception identified at a place of the graph, [(node, x, y, whole shirt seen)]
    of those it saw at a place but could not tell)."""
    placed = [h for h in msg.humans if h.localised and h.location in names]
    seen = [(h.name, names.index(h.location), h.x, h.y) for h in placed if h.name]
    unidentified = [(names.index(h.location), h.x, h.y, any(bytearray(h.shirt_color)))
                    for h in placed if not h.name]
    return msg.header.stamp.to_sec(), seen, unidentified


def instruction_from_msg(msg):
    """Raises InvalidInstruction naming the offending field."""
    return Instruction(type=int(msg.type), **{name: getattr(msg, name) for name in _FIELDS})


def record_to_msg(record):
    """task_buffer.Record -> tamp_msgs/InstructionState."""
    return InstructionStateMsg(instruction=instruction_to_msg(record.instruction),
                               state=record.state, received_time=record.received_time,
                               completion_time=record.completion_time,
                               reward_earned=record.reward_earned, reason=record.reason)


def buffer_to_msg(buffer, stamp, complete=False):
    """tamp_msgs/TaskBufferState of a task buffer: its open records and its most recently
    finished ones (TaskBuffer.snapshot, bounded: what /task_planner/state carries), or with
    `complete` every record (/task_planner/get_buffer); counts per state of the whole buffer."""
    records = buffer.records() if complete else buffer.snapshot()
    msg = TaskBufferStateMsg(instructions=[record_to_msg(r) for r in records],
                             counts=list(buffer.counts()), complete=complete,
                             active_id=buffer.active_id(), total_reward=buffer.total_reward())
    msg.header.stamp = stamp
    return msg
