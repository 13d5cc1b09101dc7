"""config/household.yaml and YAML import/export."""
import itertools

import pytest

from human_db.colour import ColourIndex, mean_shirt_distance
from human_db.errors import DuplicateHuman, InvalidHuman
from human_db.household import (dump_household, export_household, format_clock,
                                import_household, load_household, parse_clock)
from human_db.store import HumanStore
from tamp_resources import resource

HOUSEHOLD = resource("config") / "household.yaml"
MAP_PLACES = {"office", "bedroom", "charging_place", "alley", "living_room", "dining_room",
              "welcome"}


def test_demo_household_has_four_people_with_distinct_shirts():
    places, humans = load_household(HOUSEHOLD)
    assert set(places) == MAP_PLACES
    assert [h.name for h in humans] == ["Alice", "Bob", "Carol", "David"]
    assert len({h.ip for h in humans}) == 4 and all(h.ip for h in humans)
    assert {h.gender for h in humans} == {"female", "male"}
    for a, b in itertools.combinations(humans, 2):
        assert mean_shirt_distance(a.shirt_colour, b.shirt_colour) > 200.0, (a.name, b.name)
    index = ColourIndex.from_humans(humans)
    assert [index.identify(h.shirt_colour).name for h in humans] == [h.name for h in humans]
    for human in humans:
        assert human.schedules and {e.place for e in human.schedules} <= MAP_PLACES


def test_export_then_import_gives_the_same_people(tmp_path):
    first = HumanStore(tmp_path / "a.sqlite")
    assert import_household(first, HOUSEHOLD, now=0.0) == ["Alice", "Bob", "Carol", "David"]
    first.update("Bob", now=50.0, location="living_room", activity="watch TV", source="test")
    exported = tmp_path / "exported.yaml"
    export_household(first, exported, places=sorted(MAP_PLACES))
    second = HumanStore(tmp_path / "b.sqlite")
    import_household(second, exported, now=0.0)
    assert second.humans() == first.humans()
    with pytest.raises(DuplicateHuman, match="already registered"):
        import_household(second, exported)
    import_household(second, exported, replace=True)
    first.close()
    second.close()


def test_clock_strings():
    assert parse_clock("07:30", "t") == 27000.0
    assert parse_clock("23:59:59", "t") == 86399.0
    assert parse_clock("24:00", "t") == 86400.0
    assert format_clock(27000.0) == "07:30" and format_clock(86399.0) == "23:59:59"
    for bad in ("7h30", "25:00", "12:60", 750):
        with pytest.raises(InvalidHuman, match="HH:MM|not a time of day"):
            parse_clock(bad, "t")


GOOD = """
places: [office, bedroom]
humans:
  - name: Zoe
    ip: 10.0.0.5
    gender: female
    age: 30
    shirt_color: {joint1: [1, 2, 3], joint2: [4, 5, 6], joint5: [7, 8, 9]}
    schedules:
      - {start: "09:00", end: "12:00", place: office, activity: work}
"""


@pytest.mark.parametrize("old, new, needle", [
    ("age: 30", "age: 30\n    shoe_size: 42", r"humans\[0\] \(Zoe\): unknown keys \['shoe_size'\]"),
    ("    gender: female\n", "", r"missing keys \['gender'\]"),
    ('start: "09:00"', "start: 10:30", "quoted 'HH:MM'.*got 630"),   # base-60 int in YAML 1.1
    ("joint5: [7, 8, 9]", "joint5: [7, 8, 900]", "shirt colour: channel 900 is outside 0-255"),
    ("joint5: [7, 8, 9]", "joint5: [7, 8]", "9 values"),
    ("place: office", "place: kitchen", r"places \['kitchen'\] are not in the household"),
    ("ip: 10.0.0.5", "ip: 10.0.0", "not an IP address"),
    ("humans:", "people:", "unknown top-level keys|'humans' list"),
])
def test_bad_household_files_are_refused_naming_file_and_entry(tmp_path, old, new, needle):
    path = tmp_path / "household.yaml"
    assert old in GOOD
    path.write_text(GOOD.replace(old, new))
    with pytest.raises(InvalidHuman, match=needle) as caught:
        load_household(path)
    assert str(path) in str(caught.value)


def test_the_good_file_loads(tmp_path):
    path = tmp_path / "household.yaml"
    path.write_text(GOOD)
    places, (zoe,) = load_household(path)
    assert places == ["office", "bedroom"] and zoe.schedules[0].start == 9 * 3600.0
    assert load_household(path)[1][0] == zoe
    assert "Zoe" in dump_household([zoe])


def test_a_missing_or_broken_file_is_named(tmp_path):
    with pytest.raises(InvalidHuman, match="nowhere.yaml: cannot read"):
        load_household(tmp_path / "nowhere.yaml")
    broken = tmp_path / "broken.yaml"
    broken.write_text("humans: [\n")
    with pytest.raises(InvalidHuman, match="broken.yaml: cannot read"):
        load_household(broken)
