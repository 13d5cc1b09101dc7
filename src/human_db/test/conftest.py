"""Shared fixtures: small, valid household members."""
import pytest

from human_factories import make_human

from human_db.model import ScheduleEntry


@pytest.fixture
def alice():
    return make_human(schedules=(ScheduleEntry(9 * 3600.0, 12 * 3600.0, "office", "work"),
                                 ScheduleEntry(22.5 * 3600.0, 6.5 * 3600.0, "bedroom", "sleep")))


@pytest.fixture
def bob():
    return make_human("Bob", "192.168.1.102", ((35, 70, 190),) * 3, gender="male", age=37)
