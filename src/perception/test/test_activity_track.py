"""An identified person's activity fused over their recent frames (activity_track)."""
from perception.activity_track import ActivityTrackConfig, ActivityTracks

DRINK = {"drink": 0.66, "store": 0.34}


def test_a_cup_seen_in_one_frame_of_three_reads_drink_in_every_frame_after_it():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=8.0, min_probability=0.2))
    read = []
    for k in range(9):
        scored = k % 3 == 0
        read.append(tracks.update("Carol", 0.2 * k, "dining_room",
                                  "drink" if scored else "sitting",
                                  DRINK if scored else {}, "sitting"))
    assert read == ["drink"] * 9           # mean P(drink) at least 0.66 / 3 = 0.22 >= 0.2


def test_too_rare_a_score_falls_back_to_the_posture_most_frames_read():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=8.0, min_probability=0.2))
    for k in range(7):
        activity = tracks.update("Bob", float(k), "office", "sitting", {}, "sitting")
    assert activity == "sitting"
    activity = tracks.update("Bob", 7.0, "office", "read", {"read": 1.0}, "unknown")
    assert activity == "sitting"           # 1.0 over 8 frames = 0.125 < 0.2
    assert tracks.update("Bob", 7.2, "office", "read", {"read": 1.0}, "unknown") == "read"


def test_old_frames_leave_the_window_and_a_new_place_starts_a_new_one():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=0.0))
    tracks.update("Alice", 0.0, "office", "work", {"work": 1.0}, "sitting")
    assert tracks.update("Alice", 1.0, "office", "sitting", {}, "sitting") == "work"
    assert tracks.update("Alice", 2.5, "office", "sitting", {}, "sitting") == "sitting"
    tracks.update("Alice", 3.0, "office", "work", {"work": 1.0}, "sitting")
    assert tracks.update("Alice", 3.2, "bedroom", "lying", {}, "lying") == "lying"
    assert tracks.update("Alice", 3.4, "bedroom", "unknown", {}, "unknown") == "lying"


def test_people_are_fused_apart_and_nothing_known_is_unknown():
    tracks = ActivityTracks()
    tracks.update("Alice", 0.0, "office", "work", {"work": 1.0}, "sitting")
    assert tracks.update("Bob", 0.2, "office", "unknown", {}, "unknown") == "unknown"


def test_window_zero_is_the_seeds_framewise_reading():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=0.0))
    tracks.update("Carol", 0.0, "dining_room", "drink", DRINK, "sitting")
    assert tracks.update("Carol", 0.2, "dining_room", "sitting", {}, "sitting") == "sitting"


def test_an_activity_read_close_up_is_kept_while_the_person_sits_at_the_place():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=60.0))
    assert tracks.update("Carol", 0.0, "dining_room", "drink", DRINK, "sitting") == "drink"
    # seen from across the room: no cup, the posture alone, or no posture at all
    assert tracks.update("Carol", 30.0, "dining_room", "sitting", {}, "sitting") == "drink"
    assert tracks.update("Carol", 59.0, "dining_room", "unknown", {}, "unknown") == "drink"
    assert tracks.update("Carol", 60.5, "dining_room", "sitting", {}, "sitting") == "sitting"


def test_a_kept_activity_ends_when_the_posture_changes_or_the_person_moves():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=60.0))
    tracks.update("Bob", 0.0, "dining_room", "eat", {"eat": 1.0}, "sitting")
    assert tracks.update("Bob", 5.0, "dining_room", "standing", {}, "standing") == "standing"
    assert tracks.update("Bob", 8.0, "dining_room", "sitting", {}, "sitting") == "sitting"
    tracks.update("Bob", 10.0, "dining_room", "eat", {"eat": 1.0}, "unknown")
    tracks.update("Bob", 10.2, "dining_room", "eat", {"eat": 1.0}, "sitting")
    assert tracks.update("Bob", 20.0, "living_room", "sitting", {}, "sitting") == "sitting"


def test_hold_zero_keeps_nothing_and_a_later_reading_replaces_the_kept_one():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=0.0))
    tracks.update("Alice", 0.0, "office", "work", {"work": 1.0}, "sitting")
    assert tracks.update("Alice", 3.0, "office", "sitting", {}, "sitting") == "sitting"
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=60.0))
    tracks.update("Alice", 0.0, "office", "work", {"work": 1.0}, "sitting")
    tracks.update("Alice", 10.0, "office", "read", {"read": 1.0}, "sitting")
    assert tracks.update("Alice", 20.0, "office", "sitting", {}, "sitting") == "read"


def test_an_activity_read_from_a_held_thing_stands_in_windows_where_other_things_outnumber_it():
    """The bowl in Bob's hands is found in one frame of three, the bottle standing on the table
    within reach in the other two: the window's mean reads drink, but eat was read from the
    held bowl, and nothing held shows drink."""
    tracks = ActivityTracks(ActivityTrackConfig(window_s=8.0))
    read = []
    for k in range(12):
        held = k % 3 == 0
        read.append(tracks.update("Bob", 0.2 * k, "dining_room", "eat" if held else "drink",
                                  {"eat": 1.0} if held else {"drink": 1.0}, "sitting",
                                  ("bowl",) if held else ()))
    assert read[:4] == ["eat", "eat", "drink", "eat"]   # one held frame is not enough to stand
    assert read[4:] == ["eat"] * 8
    plain = ActivityTracks(ActivityTrackConfig(window_s=8.0))   # the same frames, none held
    for k in range(12):
        last = plain.update("Bob", 0.2 * k, "dining_room", "eat" if k % 3 == 0 else "drink",
                            {"eat": 1.0} if k % 3 == 0 else {"drink": 1.0}, "sitting")
    assert last == "drink"


def test_an_activity_read_from_a_held_thing_stands_against_windows_that_saw_nothing_held():
    tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=60.0))
    for k in range(2):   # the bowl held in two frames
        tracks.update("Bob", 0.2 * k, "dining_room", "eat", {"eat": 1.0}, "sitting", ["bowl"])
    # later, from across the room: only the bottle on the table, never anything held
    assert tracks.update("Bob", 30.0, "dining_room", "drink", {"drink": 1.0}, "sitting") == "eat"
    assert tracks.update("Bob", 59.0, "dining_room", "drink", {"drink": 1.0}, "sitting") == "eat"
    assert tracks.update("Bob", 61.0, "dining_room", "drink", {"drink": 1.0},
                         "sitting") == "drink"       # kept 60 s, then what is seen


def test_one_off_held_boxes_do_not_stand_against_what_the_frames_after_them_read():
    """False boxes at a sleeper's hand, a "laptop" and then a "mouse": no thing is held twice,
    so the next window reads sleep from the bed; the same "laptop" twice would stand."""
    for second, expected in (("mouse", "sleep"), ("laptop", "work")):
        tracks = ActivityTracks(ActivityTrackConfig(window_s=2.0, hold_s=60.0))
        tracks.update("Alice", 0.0, "bedroom", "work", {"work": 1.0}, "lying", ["laptop"])
        assert tracks.update("Alice", 0.2, "bedroom", "work", {"work": 1.0}, "lying",
                             [second]) == "work"
        assert tracks.update("Alice", 3.0, "bedroom", "sleep", {"sleep": 1.0},
                             "lying") == expected


def test_a_window_or_threshold_that_cannot_work_is_named():
    import pytest
    with pytest.raises(ValueError, match=r"activity_window must be a finite time >= 0 \[s\]; "
                                         r"got -1.0"):
        ActivityTrackConfig(window_s=-1.0)
    with pytest.raises(ValueError, match=r"activity_min_probability must be in \[0, 1\]; got 2"):
        ActivityTrackConfig(min_probability=2)
    with pytest.raises(ValueError, match=r"activity_hold must be a finite time >= 0 \[s\]; "
                                         r"got inf"):
        ActivityTrackConfig(hold_s=float("inf"))
