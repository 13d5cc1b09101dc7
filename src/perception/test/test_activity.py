"""Framewise hierarchical activity recognition (thesis 000 Sec. 3.2.4) on hand-made skeletons."""
import dataclasses
import math
import os

import numpy as np
import pytest

from perception.activity import (
    ActivityConfig, AffordanceTable, BodyView, SeenObject, activity_probabilities, activity_scores,
    body_heading, chat_partners, forearm_length, hand_object_eyesight_sets, load_affordances,
    posture_from_body, posture_from_skeleton, recognise_activity)
from perception.keypoints import (
    L_ANKLE, L_EAR, L_ELBOW, L_EYE, L_HIP, L_KNEE, L_SHOULDER, L_WRIST, NECK, NOSE, NUM_KEYPOINTS,
    R_ANKLE, R_EAR, R_ELBOW, R_EYE, R_HIP, R_KNEE, R_SHOULDER, R_WRIST, as_skeleton)
from tamp_resources import resource

AFFORDANCES = os.path.join(resource("config"),
                           "affordances.yaml")


def skeleton(**joints):
    pts = np.full((NUM_KEYPOINTS, 2), np.nan)
    for index, xy in joints.items():
        pts[int(index)] = xy
    return pts


def profile_worker():
    """A person seen from the side, facing +x (right), head level, right forearm 50 px."""
    return skeleton(**{
        str(R_EAR): (100, 100), str(R_EYE): (110, 100), str(NOSE): (114, 104),
        str(NECK): (100, 130), str(R_SHOULDER): (100, 135), str(R_ELBOW): (100, 190),
        str(R_WRIST): (130, 230), str(R_HIP): (100, 250), str(R_KNEE): (160, 250),
        str(R_ANKLE): (160, 320)})


SEED_TABLE = AffordanceTable(
    activities=("work", "watch TV", "read"),
    hands={"mouse": {"work": 1.0}},
    eyes={"monitor": {"work": 0.5, "watch TV": 0.5}})


def test_seed_example_work_075_watch_tv_025():
    """Eqs. 3-14, 3-15: mouse near the hands, monitor in eyesight, w_h = w_e."""
    config = ActivityConfig(weight_hands=1.0, weight_eyes=1.0)
    objects = [SeenObject("mouse", 1.0, 135, 235), SeenObject("monitor", 1.0, 400, 98)]
    result = recognise_activity(profile_worker(), objects, SEED_TABLE, config)
    assert result.near_hands == ["mouse"]
    assert result.in_eyesight == ["monitor"]
    assert result.looking_at_hands is False
    assert result.probabilities["work"] == pytest.approx(0.75)
    assert result.probabilities["watch TV"] == pytest.approx(0.25)
    assert result.activity == "work"


def test_seed_example_with_workspace_table():
    """The same scene through config/affordances.yaml, where COCO's monitor class is 'tv'."""
    table = load_affordances(AFFORDANCES)
    assert len(table.activities) == 12
    objects = [SeenObject("mouse", 0.8, 135, 235), SeenObject("tv", 0.8, 400, 98)]
    result = recognise_activity(profile_worker(), objects, table, ActivityConfig())
    assert result.probabilities == pytest.approx({"work": 0.75, "watch TV": 0.25})


def test_confidence_weights_scores_eq_3_12():
    """P(o) multiplies P_h(a|o): a 0.5-confidence mouse with a 1.0 monitor -> 0.5/(0.5+0.5+0.5)."""
    config = ActivityConfig()
    near = [SeenObject("mouse", 0.5, 0, 0)]
    seen = [SeenObject("monitor", 1.0, 0, 0)]
    probs = activity_probabilities(activity_scores(near, seen, False, SEED_TABLE, config))
    assert probs["work"] == pytest.approx(1.0 / 1.5)
    assert probs["watch TV"] == pytest.approx(0.5 / 1.5)


def test_hand_weight_changes_balance():
    """w_h = 2 w_e: work = (2 + 0.5) / 3 = 0.8333."""
    config = ActivityConfig(weight_hands=2.0, weight_eyes=1.0)
    near, seen = [SeenObject("mouse", 1.0, 0, 0)], [SeenObject("monitor", 1.0, 0, 0)]
    probs = activity_probabilities(activity_scores(near, seen, False, SEED_TABLE, config))
    assert probs["work"] == pytest.approx(2.5 / 3.0)


def test_forearm_length_takes_the_longer_arm():
    sk = profile_worker()
    assert forearm_length(sk) == pytest.approx(50.0)
    sk[L_ELBOW], sk[L_WRIST] = (90, 190), (90, 260)
    assert forearm_length(sk) == pytest.approx(70.0)


def test_an_object_far_behind_the_hands_is_not_near_them():
    """A fridge box touching the hand in the image, 1.3 m beyond the hands in depth, is not in
    O_h (hand_depth_gap 0.6 m); 0.5 m beyond it is; with the gap off, or without depths, the
    image alone decides (Algorithm 3-2)."""
    sk = profile_worker()
    depth = np.full(NUM_KEYPOINTS, 1.5)
    fridge = SeenObject("refrigerator", 1.0, 130, 260, 40, 40, depth=2.8)
    cup = SeenObject("cup", 1.0, 132, 240, 10, 10, depth=2.0)
    near, _, _ = hand_object_eyesight_sets(sk, [fridge, cup], ActivityConfig(), depth)
    assert [o.label for o in near] == ["cup"]
    near, _, _ = hand_object_eyesight_sets(sk, [fridge, cup], ActivityConfig(hand_depth_gap=0.0),
                                           depth)
    assert [o.label for o in near] == ["refrigerator", "cup"]
    near, _, _ = hand_object_eyesight_sets(sk, [fridge, cup], ActivityConfig())
    assert [o.label for o in near] == ["refrigerator", "cup"]


def test_algorithm_3_2_range_factor_boundary():
    """Near the hand means d_hand < alpha_hand x forearm (50 px): 49 px in, 51 px out."""
    sk = profile_worker()
    inside = SeenObject("cup", 1.0, 130, 230 + 49)
    outside = SeenObject("book", 1.0, 130 + 51, 230)
    near, _, _ = hand_object_eyesight_sets(sk, [inside, outside], ActivityConfig(range_factor=1.0))
    assert [o.label for o in near] == ["cup"]
    near, _, _ = hand_object_eyesight_sets(sk, [inside, outside], ActivityConfig(range_factor=1.1))
    assert [o.label for o in near] == ["cup", "book"]


def test_algorithm_3_2_eyesight_angle():
    """Ear->eye points along +x; an object 15 deg off is inside a 20 deg cone, 25 deg is not."""
    sk = profile_worker()
    config = ActivityConfig(eyesight_angle=math.radians(20))
    at15 = SeenObject("tv", 1.0, 100 + 200 * math.cos(math.radians(15)),
                      100 + 200 * math.sin(math.radians(15)))
    at25 = SeenObject("book", 1.0, 100 + 200 * math.cos(math.radians(25)),
                      100 - 200 * math.sin(math.radians(25)))
    _, seen, _ = hand_object_eyesight_sets(sk, [at15, at25], config)
    assert [o.label for o in seen] == ["tv"]


def test_algorithm_3_2_looking_at_hands():
    """Head bowed toward the wrist: ear->eye and ear->wrist within delta_eye sets E_h,e."""
    sk = profile_worker()
    config = ActivityConfig(eyesight_angle=math.radians(20))
    _, _, looking = hand_object_eyesight_sets(sk, [], config)
    assert looking is False
    direction = np.array([30.0, 130.0]) / np.hypot(30.0, 130.0)   # ear (100,100) -> wrist (130,230)
    sk[R_EYE] = np.array([100.0, 100.0]) + 10.0 * direction
    _, _, looking = hand_object_eyesight_sets(sk, [], config)
    assert looking is True


def test_facing_the_robot_has_no_eyesight_objects():
    """Fig. 3-12 (a): both ears and eyes visible, nose between the ears -> looking at the robot."""
    sk = skeleton(**{
        str(R_EAR): (90, 100), str(L_EAR): (130, 100), str(R_EYE): (103, 98), str(L_EYE): (117, 98),
        str(NOSE): (110, 106), str(NECK): (110, 130), str(R_WRIST): (95, 220),
        str(R_ELBOW): (90, 180)})
    objects = [SeenObject("tv", 1.0, 110, 80)]
    _, seen, _ = hand_object_eyesight_sets(sk, objects, ActivityConfig(eyesight_angle=math.pi))
    assert seen == []


def test_missing_joints_do_not_raise():
    """No hands, no ears: empty sets, posture from torso only; all-NaN skeleton -> unknown."""
    sk = profile_worker()
    sk[[R_WRIST, R_EAR]] = np.nan
    near, seen, looking = hand_object_eyesight_sets(sk, [SeenObject("cup", 1.0, 130, 230)],
                                                    ActivityConfig())
    assert (near, seen, looking) == ([], [], False)
    empty = np.full((NUM_KEYPOINTS, 2), np.nan)
    result = recognise_activity(empty, [SeenObject("cup", 1.0, 0, 0)], SEED_TABLE, ActivityConfig())
    assert result.activity == "unknown"


def test_unknown_object_class_is_ignored():
    objects = [SeenObject("zeppelin", 0.9, 135, 235)]
    result = recognise_activity(profile_worker(), objects, SEED_TABLE, ActivityConfig())
    assert result.near_hands == ["zeppelin"]
    assert result.probabilities == {}
    assert result.activity == "sitting"


def _front(neck, hips, knees, ankles):
    return skeleton(**{str(NECK): neck, str(R_HIP): hips[0], str(L_HIP): hips[1],
                       str(R_KNEE): knees[0], str(L_KNEE): knees[1],
                       str(R_ANKLE): ankles[0], str(L_ANKLE): ankles[1]})


def test_posture_standing_sitting_lying():
    config = ActivityConfig()
    standing = _front((200, 100), [(190, 200), (210, 200)], [(190, 290), (210, 290)],
                      [(190, 380), (210, 380)])
    assert posture_from_skeleton(standing, config) == "standing"
    # Seen from the front a sitting person's thighs point at the camera: knees barely below hips.
    sitting = _front((200, 100), [(190, 200), (210, 200)], [(188, 215), (212, 215)],
                     [(188, 300), (212, 300)])
    assert posture_from_skeleton(sitting, config) == "sitting"
    lying = _front((100, 300), [(200, 295), (200, 305)], [(290, 295), (290, 305)],
                   [(380, 295), (380, 305)])
    assert posture_from_skeleton(lying, config) == "lying"
    knees_hidden = standing.copy()
    knees_hidden[[R_KNEE, L_KNEE]] = np.nan
    assert posture_from_skeleton(knees_hidden, config) == "standing"  # ankles: 180 > 1.1 x 100
    sitting_no_knees = sitting.copy()
    sitting_no_knees[[R_KNEE, L_KNEE]] = np.nan
    assert posture_from_skeleton(sitting_no_knees, config) == "sitting"  # ankles: 100 px < 110
    assert posture_from_skeleton(standing[[0] * 18], config) == "unknown"


def _body(neck, hips=None):
    """(18, 3) joints in the map [m]: the neck and the two hips 0.2 m apart; the rest unknown."""
    body = np.full((NUM_KEYPOINTS, 3), np.nan)
    body[NECK] = neck
    if hips is not None:
        body[R_HIP], body[L_HIP] = np.add(hips, (0, -0.1, 0)), np.add(hips, (0, 0.1, 0))
    return body


def test_posture_from_the_body_in_the_map():
    """Neck heights of an adult: 1.45 m standing, 1.03 m sitting on a chair, 0.6 m lying."""
    config = ActivityConfig()
    assert posture_from_body(_body((2, 3, 1.45), (2, 3, 0.95)), config) == "standing"
    assert posture_from_body(_body((2, 3, 1.03), (2, 3, 0.48)), config) == "sitting"
    # lying seen from the feet: in the image the neck is above the hips, in the map beside them
    assert posture_from_body(_body((2.5, 3, 0.55), (2, 3, 0.52)), config) == "lying"
    # sitting behind a table that hides the hips: the neck's height alone
    assert posture_from_body(_body((2, 3, 1.05)), config) == "sitting"
    assert posture_from_body(_body((2, 3, 1.40)), config) == "standing"
    assert posture_from_body(_body((2, 3, 0.60)), config) == "lying"
    shoulders = np.full((NUM_KEYPOINTS, 3), np.nan)     # no neck: mid-shoulders
    shoulders[R_SHOULDER], shoulders[L_SHOULDER] = (2, 2.8, 1.42), (2, 3.2, 1.42)
    assert posture_from_body(shoulders, config) == "standing"
    assert posture_from_body(np.full((NUM_KEYPOINTS, 3), np.nan), config) == "unknown"


def test_the_body_in_the_map_decides_the_posture_and_the_image_is_the_fallback():
    """A lying person seen from the feet: the image puts the neck above the hips (standing)."""
    image = _front((200, 100), [(190, 200), (210, 200)], [(190, 290), (210, 290)],
                   [(190, 380), (210, 380)])
    table = load_affordances(AFFORDANCES)
    lying = _body((2.5, 3, 0.55), (2, 3, 0.52))
    assert recognise_activity(image, [], table, ActivityConfig(), body=lying).posture == "lying"
    assert recognise_activity(image, [], table, ActivityConfig(posture_3d=False),
                              body=lying).posture == "standing"
    unknown = np.full((NUM_KEYPOINTS, 3), np.nan)
    assert recognise_activity(image, [], table, ActivityConfig(), body=unknown).posture == \
        "standing"


def test_near_the_hands_in_metres_when_the_joints_and_boxes_are_in_the_map():
    """Seen from the front the forearms point at the camera: a few pixels long, so the image
    test finds no book in the hands that hold it. In the map the hands are inside the book's
    box; a cup 0.5 m beside them is beyond the 0.26 m forearm (the elbows hidden behind the
    book, the adult's forearm length), and a fridge 1.2 m behind them is not near at all."""
    image = skeleton(**{str(NECK): (320, 100), str(R_SHOULDER): (300, 110),
                        str(L_SHOULDER): (340, 110), str(R_WRIST): (315, 200),
                        str(L_WRIST): (325, 200), str(R_HIP): (310, 260),
                        str(L_HIP): (330, 260)})
    body = np.full((NUM_KEYPOINTS, 3), np.nan)
    body[R_WRIST], body[L_WRIST] = (2.0, 2.95, 0.7), (2.0, 3.05, 0.7)
    book = SeenObject("book", 0.8, 500, 500, 10, 10, 1.0, ((1.95, 2.9, 0.65), (2.1, 3.1, 0.75)))
    cup = SeenObject("cup", 0.8, 500, 500, 10, 10, 1.0, ((2.0, 3.5, 0.7), (2.05, 3.55, 0.8)))
    fridge = SeenObject("refrigerator", 0.9, 500, 500, 10, 10, 2.2,
                        ((3.2, 2.6, 0.0), (3.9, 3.3, 1.8)))
    config = ActivityConfig()
    near, _, _ = hand_object_eyesight_sets(image, [book, cup, fridge], config, body=body)
    assert [o.label for o in near] == ["book"]
    near, _, _ = hand_object_eyesight_sets(image, [book, cup, fridge],
                                           ActivityConfig(reach_3d=False), body=body)
    assert near == []                              # in the image: 300 px away, no forearm
    body[R_ELBOW] = (2.0, 2.95 - 0.6, 0.7)         # a 0.6 m forearm seen: the cup is in reach
    near, _, _ = hand_object_eyesight_sets(image, [book, cup, fridge], config, body=body)
    assert [o.label for o in near] == ["book", "cup"]
    no_box = dataclasses.replace(book, extent=None)   # no depth at the box: the image decides
    near, _, _ = hand_object_eyesight_sets(image, [no_box], config, body=body)
    assert near == []


def test_what_a_hand_holds_decides_over_what_lies_within_reach():
    """Seated at the dining table with a bowl in the hands and a bottle standing 0.2 m from them:
    within the 0.26 m forearm both are near the hands, and the seed's sum over O_h ties eat with
    drink; the bowl is held (a hand inside its box), so eat alone. The chair under a hand is not
    held: furniture is not in the table's `handheld`."""
    image = skeleton(**{str(NECK): (320, 100), str(R_SHOULDER): (300, 110),
                        str(L_SHOULDER): (340, 110), str(R_WRIST): (315, 200),
                        str(L_WRIST): (325, 200), str(R_HIP): (310, 260),
                        str(L_HIP): (330, 260)})
    body = _body((1.4, 4.95, 1.05))
    body[R_WRIST], body[L_WRIST] = (1.35, 5.40, 0.8), (1.45, 5.40, 0.8)
    bowl = SeenObject("bowl", 0.8, 500, 500, 10, 10, 1.0, ((1.32, 5.37, 0.75), (1.48, 5.53, 0.82)))
    bottle = SeenObject("bottle", 0.8, 520, 500, 10, 10, 1.0,
                        ((1.07, 5.47, 0.75), (1.14, 5.54, 1.03)))
    chair = SeenObject("chair", 0.9, 500, 600, 10, 10, 1.0, ((1.2, 4.7, 0.0), (1.6, 5.4, 0.9)))
    table = load_affordances(AFFORDANCES)
    held = recognise_activity(image, [bowl, bottle], table, ActivityConfig(), body=body)
    assert (held.activity, held.holding) == ("eat", ["bowl"])
    assert held.probabilities == {"eat": pytest.approx(1.0)}
    assert sorted(held.near_hands) == ["bottle", "bowl"]
    seed = recognise_activity(image, [bowl, bottle], table, ActivityConfig(hold_distance=0.0),
                              body=body)
    assert seed.holding == []
    assert seed.probabilities == {"eat": pytest.approx(0.5), "drink": pytest.approx(0.5)}
    bottle_alone = recognise_activity(image, [bottle, chair], table, ActivityConfig(), body=body)
    assert bottle_alone.holding == []                 # not the chair; the bottle 0.2 m off
    assert bottle_alone.activity == "drink"           # within reach, alone: the seed's reading


def test_a_handheld_class_without_a_hand_affordance_is_named(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("activities: [eat]\nhands: {fork: {eat: 1.0}}\neyes: {}\n"
                    "looking_at_hands: {}\nhandheld: [fork, spoon]\n")
    with pytest.raises(ValueError, match=r"handheld: \['spoon'\] not in 'hands'"):
        load_affordances(str(path))
    assert load_affordances(AFFORDANCES).handheld >= {"cup", "bowl", "fork", "bottle"}


def test_an_activity_scores_nothing_in_a_posture_it_is_not_done_in():
    """A fridge in view of someone sitting at the dining table: not store (postures: store is
    done standing); standing by it, store."""
    table = load_affordances(AFFORDANCES)
    fridge, cup = SeenObject("refrigerator", 0.9, 0, 0), SeenObject("cup", 0.3, 0, 0)
    sitting = activity_probabilities(activity_scores([cup], [fridge], False, table,
                                                     ActivityConfig(), posture="sitting"))
    assert sitting == {"drink": pytest.approx(1.0)}
    standing = activity_probabilities(activity_scores([cup], [fridge], False, table,
                                                      ActivityConfig(), posture="standing"))
    assert standing["store"] == pytest.approx(0.75)
    unknown = activity_probabilities(activity_scores([cup], [fridge], False, table,
                                                     ActivityConfig(), posture="unknown"))
    assert unknown == standing


def test_a_posture_list_that_cannot_work_is_named(tmp_path):
    base = "activities: [eat, store]\nhands: {}\neyes: {}\nlooking_at_hands: {}\n"
    for postures, message in (("{stroe: [standing]}", "unknown activity 'stroe'"),
                              ("{store: [kneeling]}", r"postures.store: \['kneeling'\]"),
                              ("{store: []}", "postures.store: no posture")):
        path = tmp_path / "bad.yaml"
        path.write_text(base + f"postures: {postures}\n")
        with pytest.raises(ValueError, match=message):
            load_affordances(str(path))


def test_threshold_falls_back_to_posture():
    """Six equally likely activities (P = 1/6 each) are below P_th = 0.4 -> posture."""
    table = AffordanceTable(activities=tuple("abcdef"),
                            hands={"thing": dict.fromkeys("abcdef", 1.0)})
    result = recognise_activity(profile_worker(), [SeenObject("thing", 1.0, 135, 235)], table,
                                ActivityConfig(probability_threshold=0.4))
    assert result.probabilities["a"] == pytest.approx(1 / 6)
    assert result.activity == result.posture == "sitting"


def test_as_skeleton_rejects_bad_shape_and_masks_zero_confidence():
    with pytest.raises(ValueError, match="shape"):
        as_skeleton(np.zeros((17, 2)))
    conf = np.ones(NUM_KEYPOINTS)
    conf[L_SHOULDER] = 0
    sk = as_skeleton(np.ones((NUM_KEYPOINTS, 2)), conf)
    assert np.isnan(sk[L_SHOULDER]).all() and np.isfinite(sk[NECK]).all()


def test_affordance_table_rejects_unknown_activity(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("activities: [eat]\nhands: {cup: {drnk: 1.0}}\neyes: {}\n"
                    "looking_at_hands: {}\n")
    with pytest.raises(ValueError, match="drnk"):
        load_affordances(str(path))


def _probabilities(near, seen, table, looking=False):
    return activity_probabilities(activity_scores(near, seen, looking, table, ActivityConfig()))


def test_table_5_3_sofa_and_remote_give_watch_tv_085():
    """Table 5-3: O_h = {sofa, remote}, O_e = {chair, chair, sofa, remote} -> watch TV 0.85.

    P(o) of the sofa and remote are not printed; p(TV|O_h) = 0.7 = (c_r + c_s/6) / (c_r + c_s)
    fixes c_s / (c_r + c_s) = 0.36, e.g. remote 0.80, sofa 0.45 (COCO's sofa is 'couch').
    """
    table = load_affordances(AFFORDANCES)
    remote, sofa = SeenObject("remote", 0.80, 0, 0), SeenObject("couch", 0.45, 0, 0)
    chairs = [SeenObject("chair", 0.70, 0, 0), SeenObject("chair", 0.60, 0, 0)]
    hands = _probabilities([sofa, remote], [], table)
    assert {a: round(p, 2) for a, p in hands.items()} == {
        "watch TV": 0.7, "chat": 0.06, "call": 0.06, "read": 0.06, "work": 0.06, "sleep": 0.06}
    assert _probabilities([], chairs + [sofa, remote], table) == pytest.approx({"watch TV": 1.0})
    both = _probabilities([sofa, remote], chairs + [sofa, remote], table)
    assert both["watch TV"] == pytest.approx(0.85, abs=1e-4)
    assert {a: round(p, 2) for a, p in both.items() if a != "watch TV"} == dict.fromkeys(
        ("chat", "call", "read", "work", "sleep"), 0.03)


def test_table_5_4_chair_and_person_give_chat_062():
    """Table 5-4: O_h = {chair}, O_e = {person} -> chat 0.62, the other seated activities 0.076.

    p(a|O_h) = 1/6 = 0.17 each; 0.076 = (c_c/6) / (c_c + c_p) fixes c_c / (c_c + c_p) = 0.456,
    e.g. chair 0.71, person 0.85.
    """
    table = load_affordances(AFFORDANCES)
    chair, person = SeenObject("chair", 0.71, 0, 0), SeenObject("person", 0.85, 0, 0)
    hands = _probabilities([chair], [], table)
    assert {a: round(p, 2) for a, p in hands.items()} == dict.fromkeys(
        ("watch TV", "chat", "call", "read", "work", "sleep"), 0.17)
    both = _probabilities([chair], [person], table)
    assert round(both["chat"], 2) == 0.62
    assert {a: round(p, 3) for a, p in both.items() if a != "chat"} == dict.fromkeys(
        ("watch TV", "call", "read", "work", "sleep"), 0.076)
    result = recognise_activity(profile_worker(), [], table, ActivityConfig())
    assert result.activity == "sitting"


def test_reach_is_measured_to_the_box():
    """A hand on a fridge door: 100 px from the box centre, 0 px from the box (forearm 50 px)."""
    fridge = SeenObject("refrigerator", 0.9, 230, 230, 200, 400)
    near, _, _ = hand_object_eyesight_sets(profile_worker(), [fridge], ActivityConfig())
    assert [o.label for o in near] == ["refrigerator"]
    near, _, _ = hand_object_eyesight_sets(profile_worker(), [fridge], ActivityConfig(to_box=False))
    assert near == []


def test_lying_on_a_bed_is_sleeping_lying_elsewhere_is_lying():
    table = load_affordances(AFFORDANCES)
    lying = _front((100, 300), [(200, 295), (200, 305)], [(290, 295), (290, 305)],
                   [(380, 295), (380, 305)])
    bed = SeenObject("bed", 0.8, 220, 320, 400, 120)
    result = recognise_activity(lying, [bed], table, ActivityConfig())
    assert (result.posture, result.resting_on, result.activity) == ("lying", ["bed"], "sleep")
    assert result.probabilities == pytest.approx({"sleep": 1.0})
    far_bed = SeenObject("bed", 0.8, 220, 600, 400, 120)   # 240 px below the hips: not under them
    assert recognise_activity(lying, [far_bed], table, ActivityConfig()).activity == "lying"
    off = ActivityConfig(weight_support=0.0)
    assert recognise_activity(lying, [bed], table, off).activity == "lying"


def test_posture_without_neck_uses_shoulders():
    lying = _front((100, 300), [(200, 295), (200, 305)], [(290, 295), (290, 305)],
                   [(380, 295), (380, 305)])
    lying[NECK] = np.nan
    lying[R_SHOULDER], lying[L_SHOULDER] = (110, 290), (110, 310)
    assert posture_from_skeleton(lying, ActivityConfig()) == "lying"


def test_furniture_without_affordance_is_known():
    table = load_affordances(AFFORDANCES)
    assert table.known("dining table") and table.known("chair") and table.known("couch")
    assert not table.known("zeppelin")


def frontal_person(x=300.0):
    """A standing person facing the camera, torso (neck -> hip midpoint) 100 px long."""
    return skeleton(**{
        str(R_EAR): (x - 10, 100), str(L_EAR): (x + 10, 100), str(R_EYE): (x - 4, 98),
        str(L_EYE): (x + 4, 98), str(NOSE): (x, 104), str(NECK): (x, 130),
        str(R_SHOULDER): (x - 19, 135), str(L_SHOULDER): (x + 19, 135),
        str(R_HIP): (x - 10, 230), str(L_HIP): (x + 10, 230), str(R_KNEE): (x - 10, 320),
        str(L_KNEE): (x + 10, 320), str(R_ANKLE): (x - 10, 400), str(L_ANKLE): (x + 10, 400)})


def profile_partner(x, depth, facing_left=True):
    """A standing person seen side-on at column x and depth [m]; facing left (-x) their right
    shoulder is 0.19 m farther from the camera than their left."""
    body = frontal_person(x)
    body[[R_SHOULDER, L_SHOULDER], 0] = x
    d = np.full(NUM_KEYPOINTS, float(depth))
    d[R_SHOULDER], d[L_SHOULDER] = (depth + 0.19, depth - 0.19) if facing_left else (
        depth - 0.19, depth + 0.19)
    return BodyView(body, d, 0.85)


def test_body_heading_from_shoulder_depths():
    """Facing the camera: right shoulder on the image's left at equal depth -> heading -z;
    side-on facing left: right shoulder 0.38 m deeper -> heading -x."""
    front = frontal_person()
    assert body_heading(front, np.full(NUM_KEYPOINTS, 3.0), 0.005) == pytest.approx([0.0, -1.0])
    left = profile_partner(540, 3.0)
    assert body_heading(left.skeleton, left.depth, 0.005) == pytest.approx([-1.0, 0.0])


def test_partner_near_and_facing_the_person_is_a_chat_partner():
    """Torso 100 px = 0.5 m, so 240 px across at equal depth is 1.2 m: within 2.1 m."""
    depth = np.full(NUM_KEYPOINTS, 3.0)
    config = ActivityConfig()
    near = profile_partner(540, 3.0)
    assert chat_partners(frontal_person(), depth, [near], config) == [near]
    turned_away = profile_partner(540, 3.0, facing_left=False)
    assert chat_partners(frontal_person(), depth, [turned_away], config) == []
    far_across = profile_partner(300 + 500, 3.0)        # 500 px = 2.5 m away
    assert chat_partners(frontal_person(), depth, [far_across], config) == []
    behind = profile_partner(540, 5.5)                   # 1.2 m across, 2.5 m deeper: 2.77 m
    assert chat_partners(frontal_person(), depth, [behind], config) == []


def test_table_5_4_with_the_partner_from_a_skeleton():
    """The person faces the camera (Fig. 3-12 (a): no box is in the eyesight), yet the partner
    facing them is the person of Table 5-4's O_e: chair 0.71 near the hands, partner 0.85 ->
    chat 0.62, the other seated activities 0.076. Without the switch: the posture. (The seed
    has no posture gate: this frontal skeleton reads standing, where sleep would score 0.)"""
    table = dataclasses.replace(load_affordances(AFFORDANCES), postures={})
    chair = SeenObject("chair", 0.71, 300, 232, 120, 160)       # the hands rest on it
    person = frontal_person()
    person[[R_WRIST, L_WRIST]] = [(285, 220), (315, 220)]
    person[[R_ELBOW, L_ELBOW]] = [(280, 180), (320, 180)]
    depth = np.full(NUM_KEYPOINTS, 3.0)
    result = recognise_activity(person, [chair], table, ActivityConfig(), depth,
                                [profile_partner(540, 3.0)])
    assert result.in_eyesight == ["person"]
    assert round(result.probabilities["chat"], 2) == 0.62
    assert round(result.probabilities["read"], 3) == 0.076
    assert result.activity == "chat"
    off = ActivityConfig(partners_from_skeletons=False)
    result = recognise_activity(person, [chair], table, off, depth, [profile_partner(540, 3.0)])
    assert result.in_eyesight == [] and result.activity == "standing"
