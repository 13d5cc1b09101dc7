"""Factories shared by the task_planner tests (uniquely named: every package has a conftest)."""
from task_planner.instruction import Instruction


def make_instruction(id, node, gamma=3.0, beta=0.94, duration=0, **more):
    return Instruction(id=id, gamma=gamma, beta=beta, destination=node, duration=duration, **more)
