"""Factories shared by the bringup tests (uniquely named: every package has a conftest)."""
from task_planner.instruction import Instruction


def instruction(id, node, gamma, beta, duration, **more):
    """An instruction to node `node` with Table 4-1's other fields at their defaults."""
    return Instruction(id=id, gamma=gamma, beta=beta, destination=node, duration=duration, **more)
