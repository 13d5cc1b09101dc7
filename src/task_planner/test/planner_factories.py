"""Factories shared by the task_planner tests (uniquely named: every package has a conftest)."""
import sqlite3
from task_planner.instruction import Instruction


def make_instruction(id, node, gamma=3.0, beta=0.94, duration=0, **more):
    return Instruction(id=id, gamma=gamma, beta=beta, destination=node, duration=duration, **more)


POOL_BACKENDS = ("sqlite", "postgresql")   # where a fleet pool is in the tests (conftest pool_url)


def execute_in_pool(where, statement, args=()):
    """Run one statement (`?` placeholders) on a fleet pool's SQLite file or PostgreSQL database
    and commit, as another program would."""
    if not str(where).startswith("postgresql://"):
        db, placeholder = sqlite3.connect(where), "?"
    else:
        import psycopg2
        db, placeholder = psycopg2.connect(where), "%s"
    try:
        db.cursor().execute(statement.replace("?", placeholder), args)
        db.commit()
    finally:
        db.close()


def execute_sql(path, *statements):
    """Run `statements` on the SQLite file at `path` and commit, as another program would."""
    db = sqlite3.connect(path)
    try:
        for statement in statements:
            db.execute(statement)
        db.commit()
    finally:
        db.close()
