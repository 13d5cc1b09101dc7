"""Factories shared by the task_planner tests (uniquely named: every package has a conftest)."""
import sqlite3
from task_planner.instruction import Instruction


def make_instruction(id, node, gamma=3.0, beta=0.94, duration=0, **more):
    return Instruction(id=id, gamma=gamma, beta=beta, destination=node, duration=duration, **more)


def execute_sql(path, *statements):
    """Run `statements` on the SQLite file at `path` and commit, as another program would."""
    db = sqlite3.connect(path)
    try:
        for statement in statements:
            db.execute(statement)
        db.commit()
    finally:
        db.close()
