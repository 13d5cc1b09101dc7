"""Schedule entries and the schedule-deviation check perception uses for reminders."""
import pytest
from human_factories import make_human

from human_db.errors import InvalidHuman
from human_db.model import ScheduleEntry
from human_db.schedule import (check_schedule, doubted_match, entry_in_force, entry_upcoming,
                               expected_instead, not_met_yet, same_label, time_of_day)

H = 3600.0  # [s]
WORK = ScheduleEntry(9 * H, 12 * H, "office", "work")
SLEEP = ScheduleEntry(22.5 * H, 6.5 * H, "bedroom", "sleep")   # wraps midnight
READ = ScheduleEntry(14 * H, 15 * H, "", "read")               # anywhere


@pytest.fixture
def carol():
    return make_human("Carol", schedules=(WORK, SLEEP, READ))


def test_entries_cover_half_open_intervals_and_wrap_midnight():
    assert WORK.covers(9 * H) and WORK.covers(12 * H - 1) and not WORK.covers(12 * H)
    assert SLEEP.covers(23 * H) and SLEEP.covers(0.0) and SLEEP.covers(6 * H)
    assert not SLEEP.covers(6.5 * H) and not SLEEP.covers(22 * H)


def test_entry_in_force(carol):
    assert entry_in_force(carol.schedules, 10 * H) == WORK
    assert entry_in_force(carol.schedules, 3 * H) == SLEEP
    assert entry_in_force(carol.schedules, 13 * H) is None


def test_following_the_schedule_is_no_deviation(carol):
    check = check_schedule(carol, 10 * H, location="office", activity="work")
    assert check.entry == WORK and not check.deviates


def test_wrong_place_and_wrong_activity_are_told_apart(carol):
    wrong_place = check_schedule(carol, 10 * H, location="living_room", activity="work")
    assert (wrong_place.location_differs, wrong_place.activity_differs) == (True, False)
    wrong_activity = check_schedule(carol, 2 * H, location="bedroom", activity="watch TV")
    assert (wrong_activity.location_differs, wrong_activity.activity_differs) == (False, True)
    assert wrong_activity.deviates and wrong_activity.entry == SLEEP


def test_unknown_observations_and_free_time_are_no_deviation(carol):
    assert not check_schedule(carol, 10 * H, location="", activity="").deviates
    assert not check_schedule(carol, 14.5 * H, location="alley", activity="read").deviates
    free = check_schedule(carol, 13 * H, location="alley", activity="eat")
    assert free.entry is None and not free.deviates


def test_defaults_to_the_stored_state():
    dozing = make_human("Carol", schedules=(WORK,), location="bedroom", activity="sleep")
    check = check_schedule(dozing, 11 * H)
    assert check.location_differs and check.activity_differs


def test_labels_compare_case_blind_with_underscores_as_spaces():
    assert same_label("watch TV", "watch_tv") and same_label("Living-Room", "living_room")
    assert not same_label("read", "eat")
    assert not check_schedule(make_human(schedules=(ScheduleEntry(0.0, H, "", "watch TV"),)),
                              60.0, activity="watch_tv").deviates


def test_time_of_day_with_utc_offset():
    assert time_of_day(86400.0 * 3 + 36000.0) == 36000.0
    assert time_of_day(3600.0, utc_offset=8 * H) == 9 * H
    assert time_of_day(3600.0, utc_offset=-2 * H) == 23 * H


@pytest.mark.parametrize("start, end, place, activity, needle", [
    (-1.0, 10.0, "office", "", "start must lie"),
    (86400.0, 10.0, "office", "", "start must lie"),
    (0.0, 86401.0, "office", "", "end must lie"),
    (100.0, 100.0, "office", "", "coincide"),
    (0.0, 86400.0, "", "", "place or an activity"),
])
def test_bad_schedule_entries_are_refused(start, end, place, activity, needle):
    with pytest.raises(InvalidHuman, match=needle):
        ScheduleEntry(start, end, place, activity)


def test_overlapping_entries_are_refused_touching_ones_are_not():
    with pytest.raises(InvalidHuman, match="overlap"):
        make_human(schedules=(SLEEP, ScheduleEntry(6 * H, 7 * H, "dining_room", "eat")))
    ok = make_human(schedules=(SLEEP, ScheduleEntry(6.5 * H, 7 * H, "dining_room", "eat")))
    assert [e.start for e in ok.schedules] == [6.5 * H, 22.5 * H]   # sorted by start


def test_a_match_the_schedules_contradict_names_who_is_expected_instead():
    """Alice works in the office 13:00-17:30, Carol naps in the bedroom 14:00-15:00 (the
    household's schedules): a sighting in the bedroom at 14:30 that the colours give to Alice
    is doubted in favour of Carol; in the office, or before Carol's nap, it stands."""
    alice = make_human("Alice", schedules=(ScheduleEntry(13 * H, 17.5 * H, "office", "work"),))
    carol = make_human("Carol", schedules=(ScheduleEntry(14 * H, 15 * H, "bedroom", "sleep"),))
    bob = make_human("Bob", schedules=(ScheduleEntry(14 * H, 15 * H, "", "read"),))
    people = [alice, bob, carol]
    assert expected_instead("Alice", "bedroom", 14.5 * H, people) == "Carol"
    assert expected_instead("Alice", "office", 14.5 * H, people) == ""     # where she should be
    assert expected_instead("Alice", "bedroom", 13.5 * H, people) == ""    # nobody expected
    # Carol goes to bed a few minutes early: from 13:50 her nap draws her to the bedroom
    assert expected_instead("Alice", "bedroom", 13 * H + 55 * 60, people) == "Carol"
    assert expected_instead("Alice", "bedroom", 13 * H + 49 * 60, people) == ""
    assert expected_instead("Carol", "office", 14.5 * H, people) == "Alice"
    # Bob's entry names no place: neither doubts nor is doubted; nor is an unknown name or place
    assert expected_instead("Bob", "bedroom", 14.5 * H, people) == ""
    assert expected_instead("Frank", "bedroom", 14.5 * H, people) == ""
    assert expected_instead("Alice", "", 14.5 * H, people) == ""



def test_the_entry_starting_within_ten_minutes_is_upcoming():
    nap = ScheduleEntry(14 * H, 15 * H, "bedroom", "sleep")
    sleep = ScheduleEntry(23 * H, 6 * H, "bedroom", "sleep")
    assert entry_upcoming((nap, sleep), 13 * H + 55 * 60) == nap
    assert entry_upcoming((nap, sleep), 13 * H + 50 * 60) == nap         # 600 s ahead
    assert entry_upcoming((nap, sleep), 13 * H + 49 * 60) is None
    assert entry_upcoming((nap, sleep), 14 * H) is None                   # in force, not upcoming
    assert entry_upcoming((nap, sleep), 22 * H + 55 * 60, lead_s=600.0) == sleep
    assert entry_upcoming((ScheduleEntry(0.0, 1 * H, "bedroom", "sleep"),), 24 * H - 60) \
        is not None                                                       # past midnight


def test_only_a_weak_match_is_doubted():
    """Alice's shirt 120 from the sighting in the bedroom at 14:30, where Carol naps: doubted
    from a sure distance of 80, not from 150; a close one (60) or sure distance 0 never is."""
    alice = make_human("Alice", schedules=(ScheduleEntry(13 * H, 17.5 * H, "office", "work"),))
    carol = make_human("Carol", schedules=(ScheduleEntry(14 * H, 15 * H, "bedroom", "sleep"),))
    people = [alice, carol]
    assert doubted_match("Alice", 120.0, 80.0, "bedroom", 14.5 * H, people) == "Carol"
    assert doubted_match("Alice", 80.0, 80.0, "bedroom", 14.5 * H, people) == "Carol"
    assert doubted_match("Alice", 120.0, 150.0, "bedroom", 14.5 * H, people) == ""
    assert doubted_match("Alice", 60.0, 80.0, "bedroom", 14.5 * H, people) == ""
    assert doubted_match("Alice", 120.0, 0.0, "bedroom", 14.5 * H, people) == ""
    assert doubted_match("Alice", 120.0, 80.0, "office", 14.5 * H, people) == ""


def test_a_weak_match_may_be_a_resident_not_met_yet():
    """David met, Alice not yet (no shirt), nothing in force in their schedules: a sighting in the
    office 120 from David's shirt may be Alice, wherever it is; a close one stands, and once
    everyone is met a weak match stands unless the schedules doubt it."""
    david = make_human("David", colour=((228, 205, 52),) * 3,
                       schedules=(ScheduleEntry(16 * H, 18 * H, "office", "read"),))
    alice = make_human("Alice", colour=None,
                       schedules=(ScheduleEntry(13 * H, 17.5 * H, "office", "work"),))
    assert not_met_yet("David", [david, alice]) == "Alice"
    assert not_met_yet("Alice", [david, alice]) == ""        # herself
    assert doubted_match("David", 120.0, 80.0, "office", 18.5 * H, [david, alice]) == "Alice"
    assert doubted_match("David", 120.0, 80.0, "bedroom", 18.5 * H, (h for h in [david, alice])) \
        == "Alice"
    assert doubted_match("David", 60.0, 80.0, "office", 18.5 * H, [david, alice]) == ""
    met = make_human("Alice", schedules=alice.schedules)
    assert doubted_match("David", 120.0, 80.0, "office", 18.5 * H, [david, met]) == ""
