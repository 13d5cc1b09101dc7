"""Validation of a household member (Table 3-1) on construction."""
import pytest
from conftest import make_human

from human_db.errors import InvalidColour, InvalidHuman


def test_a_valid_human_is_normalised():
    human = make_human(ip="fe80:0:0:0:0:0:0:1", colour=[1, 2, 3, 4, 5, 6, 7, 8, 9])
    assert human.ip == "fe80::1"
    assert human.shirt_colour == ((1, 2, 3), (4, 5, 6), (7, 8, 9))


@pytest.mark.parametrize("fields, error, needle", [
    (dict(name=""), InvalidHuman, "name must be"),
    (dict(name=" Bob"), InvalidHuman, "name must be"),
    (dict(name="x" * 65), InvalidHuman, "at most 64"),
    (dict(gender="robot"), InvalidHuman, "gender must be one of"),
    (dict(age=-1), InvalidHuman, "age must be"),
    (dict(age=151), InvalidHuman, "age must be"),
    (dict(age=30.5), InvalidHuman, "age must be"),
    (dict(ip="999.1.1.1"), InvalidHuman, "not an IP address"),
    (dict(colour=((1, 2, 3), (4, 5, 6))), InvalidColour, "Alice.*9 values"),
    (dict(colour=((1, 2, 3), (4, 5, 6), (7, 8, 256))), InvalidColour, "outside 0-255"),
    (dict(schedules=("office 9-12",)), InvalidHuman, "not a ScheduleEntry"),
])
def test_bad_fields_are_refused_naming_the_field(fields, error, needle):
    with pytest.raises(error, match=needle):
        make_human(**fields)
