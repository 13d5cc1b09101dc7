"""Factories shared by the human_db tests (unique module name: every package has a conftest)."""
from human_db.model import Human


def make_human(name="Alice", ip="192.168.1.101", colour=((196, 38, 45),) * 3, **fields):
    return Human(name=name, ip=ip, gender=fields.pop("gender", "female"),
                 age=fields.pop("age", 34), shirt_colour=colour, **fields)
