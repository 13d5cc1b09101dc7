"""config/household.yaml and YAML import/export."""
import itertools

import pytest
import yaml

from human_db.colour import ColourIndex, mean_shirt_distance
from human_db.errors import DuplicateHuman, InvalidHuman, UnknownHuman
from human_db.household import (dump_household, export_household, format_clock,
                                import_household, load_household, load_shirts, parse_clock,
                                register_shirts)
from human_db.store import HumanStore
from tamp_resources import resource

HOUSEHOLD = resource("config") / "household.yaml"
SHIRTS = resource("config") / "household_shirts.yaml"
MAP_PLACES = {"office", "bedroom", "charging_place", "alley", "living_room", "dining_room",
              "welcome"}


def test_demo_household_has_four_people_the_robot_has_not_met():
    places, humans = load_household(HOUSEHOLD)
    assert set(places) == MAP_PLACES
    assert [h.name for h in humans] == ["Alice", "Bob", "Carol", "David"]
    assert len({h.ip for h in humans}) == 4 and all(h.ip for h in humans)
    assert {h.gender for h in humans} == {"female", "male"}
    assert all(h.shirt_colour is None for h in humans)     # registered when met (§3.2.3)
    for human in humans:
        assert human.schedules and {e.place for e in human.schedules} <= MAP_PLACES


def test_the_shirts_file_dresses_them_as_the_worlds_do_and_apart():
    shirts = load_shirts(SHIRTS)
    assert sorted(shirts) == ["Alice", "Bob", "Carol", "David"]
    for a, b in itertools.combinations(shirts, 2):
        assert mean_shirt_distance(shirts[a], shirts[b]) > 200.0, (a, b)
    for world in ("household.yaml", "household_day.yaml"):
        people = yaml.safe_load((resource("config") / "worlds" / world).read_text())["people"]
        for person in people:
            if person["name"] in shirts:
                worn = tuple(tuple(person["shirt_colour"][k]) for k in ("joint1", "joint2",
                                                                         "joint5"))
                assert worn == shirts[person["name"]], (world, person["name"])


def test_registered_shirts_make_everyone_met(tmp_path):
    store = HumanStore(tmp_path / "h.sqlite")
    import_household(store, HOUSEHOLD, now=0.0)
    assert ColourIndex.from_humans(store.humans()).names == []
    assert register_shirts(store, SHIRTS, now=0.0) == ["Alice", "Bob", "Carol", "David"]
    index = ColourIndex.from_humans(store.humans())
    shirts = load_shirts(SHIRTS)
    assert [index.identify(shirts[n]).name for n in sorted(shirts)] == sorted(shirts)
    bad = tmp_path / "bad.yaml"
    bad.write_text("shirts:\n  Zoe: {joint1: [1, 2, 3], joint2: [1, 2, 3], joint5: [1, 2, 3]}\n")
    with pytest.raises(UnknownHuman, match="Zoe"):
        register_shirts(store, bad)
    bad.write_text("shirts:\n  Bob: {joint1: [1, 2, 3], joint2: [1, 2, 3]}\n")
    with pytest.raises(InvalidHuman, match=r"bad.yaml: shirts: Bob: missing keys \['joint5'\]"):
        load_shirts(bad)
    store.close()


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
    ("age: 30", "age: 30\n    shoe_size: 42",
     r"humans\[0\] \(Zoe\): unknown key 'shoe_size' \(valid keys: "),
    ("age: 30", "age: 30\n    gendre: female",
     r"humans\[0\] \(Zoe\): unknown key 'gendre' \(did you mean 'gender'\?\)"),
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
    with pytest.raises(InvalidHuman, match="nowhere.yaml: no such household file$"):
        load_household(tmp_path / "nowhere.yaml")
    broken = tmp_path / "broken.yaml"
    broken.write_text("humans: [\n")
    with pytest.raises(InvalidHuman, match=r"broken.yaml: not valid YAML \(line 2, column 1: "):
        load_household(broken)
