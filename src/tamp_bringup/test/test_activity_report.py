"""tamp_bringup.activity_report: activity recognition in the loop, on hand-made counts."""
from tamp_bringup.activity_report import (activity_markdown, activity_rows, count_frame,
                                          parse_label, weakest)
from tamp_bringup.goals_report import run_goals

CATEGORIES = ("eat", "drink", "watch TV", "read", "sleep")


def test_a_people_label_gives_the_name_and_the_activity():
    assert parse_label("Bob: sitting, watch TV") == ("Bob", "watch TV")
    assert parse_label("Frank: standing") == ("Frank", "")


def test_frames_are_counted_per_true_activity_for_identified_people_only():
    counts = {}
    doing = {"Bob": "eat", "Carol": "drink"}
    count_frame(counts, doing, [("Bob", "eat"), ("Carol", "eat"), ("", "read")])
    count_frame(counts, doing, [("Bob", "drink"), ("Alice", "sleep")])   # Alice: no truth yet
    assert counts == {"eat": {"eat": 1, "drink": 1}, "drink": {"eat": 1}}


def test_rows_give_each_true_activity_its_share_and_misreadings():
    counts = {"eat": {"eat": 6, "drink": 3, "others": 1}, "read": {"read": 2},
              "standing": {"others": 4}}
    assert activity_rows(counts) == [
        ("eat", 10, 0.6, [("drink", 3), ("others", 1)]),
        ("standing", 4, 0.0, [("others", 4)]),
        ("read", 2, 1.0, [])]
    assert weakest(counts, CATEGORIES) == ("eat", 0.6)     # standing is not a category
    text = "\n".join(activity_markdown(counts, CATEGORIES))
    assert "| eat | 10 | 0.60 | drink (3), others (1) |" in text
    assert "| standing (*not a category*) | 4 | 0.00 | others (4) |" in text


def test_the_weakest_category_is_a_goal():
    record = dict(sim_s=1.0, truth={}, belief={},
                  activity_counts={"eat": {"eat": 6, "drink": 4}, "read": {"read": 3}})
    model = type("Model", (), dict(name="m", starts={}, reward=1.0))()
    goals = {g.figure: g for g in run_goals(record, [], [], model, 0.0, CATEGORIES)}
    goal = goals["activity recognition in the loop, weakest category"]
    assert (goal.value, goal.goal, goal.met) == ("0.60 (eat)", "≥ 0.7", False)
