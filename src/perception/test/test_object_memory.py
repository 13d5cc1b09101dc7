"""Fixed objects remembered in the map (perception.object_memory) and what the activity reading
makes of them."""
import os

import numpy as np
import pytest

from perception.activity import (ActivityConfig, SeenObject, hand_object_eyesight_sets,
                                 load_affordances, recognise_activity)
from perception.keypoints import (L_HIP, L_SHOULDER, L_WRIST, NECK, NUM_KEYPOINTS, R_HIP,
                                  R_SHOULDER, R_WRIST)
from perception.object_memory import FIXED_CLASSES, ObjectMemory, ObjectMemoryConfig
from tamp_resources import resource

AFFORDANCES = os.path.join(resource("config"), "affordances.yaml")
LAPTOP = ((0.7, 11.2, 0.75), (1.0, 11.4, 0.95))     # on the office desk [m]
CUP = ((0.3, 11.25, 0.75), (0.4, 11.35, 0.85))


def seated_at_the_desk():
    """A person seen from behind at the desk: image joints [px] and joints in the map [m], the
    hands 0.1 m in front of the laptop's box (forearm unknown: the 0.26 m default reach)."""
    image = np.full((NUM_KEYPOINTS, 2), np.nan)
    image[NECK], image[R_SHOULDER], image[L_SHOULDER] = (320, 100), (300, 110), (340, 110)
    image[R_WRIST], image[L_WRIST] = (310, 180), (330, 180)
    image[R_HIP], image[L_HIP] = (310, 200), (330, 200)
    body = np.full((NUM_KEYPOINTS, 3), np.nan)
    body[R_WRIST], body[L_WRIST] = (0.8, 11.1, 0.8), (0.9, 11.1, 0.8)
    body[NECK] = (0.85, 10.75, 1.2)
    return image, body


def detect(memory, stamps, *detections):
    for stamp in stamps:
        memory.update(stamp, detections)


def test_a_fixed_object_seen_a_few_times_and_missed_by_a_frame_is_recalled():
    memory = ObjectMemory(ObjectMemoryConfig(confirm=3))
    detect(memory, [0.0, 1.0], ("laptop", 0.6, LAPTOP), ("cup", 0.7, CUP), ("tv", 0.5, None))
    assert memory.recall(2.0) == []                      # two votes: not yet confirmed
    detect(memory, [2.0], ("laptop", 0.5, LAPTOP), ("cup", 0.7, CUP))
    assert memory.recall(2.0) == []                      # detected now: the detection counts
    recalled = memory.recall(3.0)
    assert [(o.label, o.confidence, o.extent) for o in recalled] == [("laptop", 0.5, LAPTOP)]
    assert not recalled[0].in_image                      # a cup is held: never recalled,
    assert "cup" not in FIXED_CLASSES and len(memory.spots) == 2   # nor a box without depth


def test_a_confused_label_loses_the_vote_at_its_spot():
    """A desk now and then called a laptop, a one-off false laptop elsewhere: neither is
    recalled; a spot whose label is contested below the share is not either."""
    desk = ((0.4, 11.0, 0.0), (1.3, 11.6, 0.75))
    memory = ObjectMemory(ObjectMemoryConfig(confirm=3, share=0.5))
    detect(memory, range(20), ("dining table", 0.9, desk))
    detect(memory, range(20, 25), ("laptop", 0.4, desk))
    detect(memory, [26.0], ("laptop", 0.4, ((3.0, 3.0, 0.5), (3.2, 3.2, 0.6))))
    assert memory.recall(30.0) == []
    detect(memory, range(40, 46), ("mouse", 0.4, LAPTOP))
    detect(memory, range(46, 50), ("laptop", 0.6, LAPTOP))
    assert [o.label for o in memory.recall(60.0)] == ["mouse"]    # 6 of 10 votes
    detect(memory, range(60, 65), ("keyboard", 0.6, LAPTOP))
    assert memory.recall(70.0) == []                              # 6 of 15: below the share


def test_a_spot_follows_its_detections_and_is_forgotten_unseen():
    memory = ObjectMemory(ObjectMemoryConfig(keep_s=100.0, merge_m=0.3, confirm=1))
    moved = ((0.8, 11.2, 0.75), (1.1, 11.4, 0.95))       # 0.1 m along: the same spot
    detect(memory, [0.0], ("laptop", 0.6, LAPTOP))
    detect(memory, [90.0], ("laptop", 0.4, moved))
    assert [(s.extent, s.stamp, s.votes["laptop"]) for s in memory.spots] == [(moved, 90.0, 2)]
    far = ((2.0, 11.2, 0.75), (2.3, 11.4, 0.95))          # 1.0 m away: a second spot
    detect(memory, [95.0], ("laptop", 0.5, far))
    assert len(memory.spots) == 2
    detect(memory, [191.0])                                 # the first unseen for 101 s
    assert [s.extent for s in memory.spots] == [far]
    assert memory.recall(296.0) == []                     # and the second for 201 s


def test_memory_stays_bounded_and_keeps_the_newest():
    memory = ObjectMemory(ObjectMemoryConfig(max_spots=3))
    for i in range(5):
        detect(memory, [float(i)], ("chair", 0.5, ((float(i), 0.0, 0.0), (i + 0.2, 0.2, 0.5))))
    assert [s.stamp for s in memory.spots] == [2.0, 3.0, 4.0]


def test_zero_keep_is_the_seeds_framewise_reading():
    memory = ObjectMemory(ObjectMemoryConfig(keep_s=0.0, confirm=1))
    detect(memory, [0.0], ("laptop", 0.6, LAPTOP))
    assert memory.spots == [] and memory.recall(1.0) == []


@pytest.mark.parametrize("field, value, words", [
    ("keep_s", -1.0, "object_memory must be a finite time"),
    ("keep_s", float("inf"), "object_memory must be a finite time"),
    ("merge_m", 0.0, "object_memory_merge must be a distance > 0"),
    ("confirm", 0, "object_memory_confirm must be >= 1"),
    ("share", 0.0, "object_memory_share must be in"),
    ("max_spots", 0, "object_memory_max must be >= 1"),
])
def test_a_bad_setting_is_named(field, value, words):
    with pytest.raises(ValueError, match=words):
        ObjectMemoryConfig(**{field: value})


def test_a_remembered_laptop_within_reach_reads_work_and_is_never_in_the_eyesight():
    """The frame misses the laptop; the remembered one is 0.1 m from the hands in the map, so
    the person works. It has no box in the image: neither the image hand test nor the eyesight
    test can use it, and without the joints in the map it is not near either."""
    image, body = seated_at_the_desk()
    table = load_affordances(AFFORDANCES)
    memory = ObjectMemory()
    detect(memory, [0.0, 1.0, 2.0], ("laptop", 0.6, LAPTOP))
    remembered = memory.recall(5.0)
    config = ActivityConfig()
    near, seen, _ = hand_object_eyesight_sets(image, remembered, config, body=body)
    assert [o.label for o in near] == ["laptop"] and seen == []
    assert recognise_activity(image, remembered, table, config, body=body).activity == "work"
    assert recognise_activity(image, [], table, config, body=body).activity == "sitting"
    near, seen, _ = hand_object_eyesight_sets(image, remembered, config, body=None)
    assert near == [] and seen == []
    away = body.copy()
    away[R_WRIST], away[L_WRIST] = (0.8, 10.5, 0.8), (0.9, 10.5, 0.8)   # 0.7 m off the desk
    near, _, _ = hand_object_eyesight_sets(image, remembered, config, body=away)
    assert near == []


def test_a_seen_object_keeps_its_image_box():
    assert SeenObject("laptop", 0.6, 100.0, 50.0).in_image
