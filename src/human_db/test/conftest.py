"""Shared fixtures: small, valid household members."""
import pytest

from human_db.model import Human, ScheduleEntry


def make_human(name="Alice", ip="192.168.1.101", colour=((196, 38, 45),) * 3, **fields):
    return Human(name=name, ip=ip, gender=fields.pop("gender", "female"),
                 age=fields.pop("age", 34), shirt_colour=colour, **fields)


@pytest.fixture
def alice():
    return make_human(schedules=(ScheduleEntry(9 * 3600.0, 12 * 3600.0, "office", "work"),
                                 ScheduleEntry(22.5 * 3600.0, 6.5 * 3600.0, "bedroom", "sleep")))


@pytest.fixture
def bob():
    return make_human("Bob", "192.168.1.102", ((35, 70, 190),) * 3, gender="male", age=37)
