"""Validation of a household member (Table 3-1) on construction."""
import pytest
from human_factories import make_human

from human_db.errors import InvalidColour, InvalidHuman
from human_db.model import check_observation_time


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


def test_an_observation_stamped_in_the_future_beyond_the_tolerance_is_refused():
    assert check_observation_time(105.0, now=100.0, tolerance_s=5.0, name="Alice") == 105.0
    assert check_observation_time(3.0, now=100.0, tolerance_s=5.0, name="Alice") == 3.0
    # issue 35: an update stamped 4e9 pinned the person's location for good
    with pytest.raises(InvalidHuman, match=r"update of 'Alice': stamp 4000000000\.000 s is "
                                           r"3999999900\.000 s after the present 100\.000 s "
                                           r"\(tolerance 5 s\)"):
        check_observation_time(4.0e9, now=100.0, tolerance_s=5.0, name="Alice")
    with pytest.raises(InvalidHuman, match="stamp 105.010 s is 5.010 s after the present"):
        check_observation_time(105.01, now=100.0, tolerance_s=5.0, name="Alice")
