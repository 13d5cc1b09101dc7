"""tamp_msgs/Instruction <-> task_planner.instruction.Instruction."""
from tamp_msgs.msg import Instruction as InstructionMsg

from task_planner.instruction import Instruction

_FIELDS = ("id", "previous_id", "gamma", "beta", "start_time", "duration", "source", "target",
           "status", "function", "destination", "destination_name", "text")


def instruction_to_msg(instruction):
    msg = InstructionMsg(**{name: getattr(instruction, name) for name in _FIELDS})
    msg.type = bool(instruction.type)
    return msg


def instruction_from_msg(msg):
    """Raises InvalidInstruction naming the offending field."""
    return Instruction(type=int(msg.type), **{name: getattr(msg, name) for name in _FIELDS})
