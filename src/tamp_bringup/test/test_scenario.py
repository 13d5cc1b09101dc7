"""Scenario files: requests, the people's initial places and moves from the world, bad input."""
import math

import numpy as np
import pytest

from tamp_bringup.scenario import (CALL, DIALOGUE_END_PHRASES, GIVE_UP_PHRASE,
                                   IDENTITY_QUESTION, INTRODUCE_TEXT, ScenarioError, Visitor,
                                   faced_person, identity_answer, load_scenario, person_asked,
                                   place_of, resident_answer, residents, seen_shirt, timeline,
                                   visitor_answer, who_answers)
from tamp_resources import resource

ROOT = resource()
GRAPH_SPEC = {"nodes": [{"name": "west", "region": [[0, 0], [2, 0], [2, 2], [0, 2]]},
                        {"name": "east", "region": [[2, 0], [4, 0], [4, 2], [2, 2]]}]}


def write_scenario(tmp_path, requests, extra=""):
    path = tmp_path / "scenario.yaml"
    path.write_text(f"world: {ROOT}/config/worlds/household_day.yaml\n"
                    f"household: {ROOT}/config/household.yaml\n"
                    f"graph: {ROOT}/maps/household.graph.yaml\n{extra}requests:\n{requests}")
    return path


FRANK = ("visitors:\n  - {name: Frank, gender: male, age: 72, ip: 192.168.1.150, answers: "
         "{name: My name is Frank., gender: I am a man., age: I am 72.}}\n")


def write_with_frank(tmp_path, requests, extra=""):
    """household_day's world has the visitor Frank, whom every scenario on it must declare."""
    path = write_scenario(tmp_path, requests, extra)
    path.write_text(FRANK + path.read_text())
    return path


def test_place_of_regions():
    assert place_of(GRAPH_SPEC, 1.0, 1.0) == "west"
    assert place_of(GRAPH_SPEC, 3.0, 0.5) == "east"
    assert place_of(GRAPH_SPEC, 5.0, 1.0) == ""


def test_the_demo_scenario(tmp_path):
    scenario = load_scenario(ROOT / "config/scenarios/household_day.yaml")
    assert scenario.name == "household_day" and scenario.planner == "rollout"
    assert [(r.time_s, r.person, r.spoken, r.visitor) for r in scenario.requests] == [
        (70.0, "Bob", False, False), (74.0, "David", True, False), (85.0, "Alice", False, False),
        (90.0, "Frank", False, True), (130.0, "Carol", False, False), (160.0, "Bob", False, False),
        (200.0, "David", False, False)]
    assert scenario.day_start_s == 18 * 3600 + 28 * 60 and scenario.timeout_s == 900.0
    # Frank stands at (2.9, 0.7): the living room; his requests come from his phone
    (frank,) = scenario.visitors
    assert (frank.name, frank.gender, frank.age, frank.ip, frank.place) == (
        "Frank", "male", 72, "192.168.1.150", "living_room")
    assert scenario.requests[3].ip == "192.168.1.150"
    assert scenario.requests[0].ip == "192.168.1.102"  # Bob's phone, config/household.yaml
    # world poses: Alice (0.85, 10.75) office, Bob (1.2, 1.35) and Carol (2.6, 2.9) living room,
    # David (5.0, 7.6) bedroom
    assert scenario.initial == {"Alice": ("office", "work"), "Bob": ("living_room", "watch TV"),
                                "Carol": ("living_room", "read"),
                                "David": ("bedroom", "read"), "Frank": ("living_room", "standing")}
    # moves: Carol to (0.5, 5.8) at 105 s, Bob to (1.4, 4.95) at 120 s, Alice to (5.95, 10.9)
    # at 210 s
    assert [(m.time_s, m.person, m.place) for m in scenario.moves] == [
        (105.0, "Carol", "dining_room"), (120.0, "Bob", "dining_room"),
        (210.0, "Alice", "bedroom")]
    kinds = [kind for _, kind, _ in timeline(scenario)]
    # 70, 74, 85, 90 requests; 105, 120 moves; 130, 160, 200 requests; 210 move
    assert kinds == ["request"] * 4 + ["move"] * 2 + ["request"] * 3 + ["move"]


def test_requests_are_sorted_and_the_timeout_read(tmp_path):
    path = write_with_frank(tmp_path, '  - {time: 9, person: Bob, text: "b"}\n'
                                    '  - {time: 3, person: Alice, text: "a", spoken: true}\n',
                          "timeout_s: 50\nplanner: seed\n")
    scenario = load_scenario(path)
    assert [(r.person, r.ip, r.spoken) for r in scenario.requests] == [
        ("Alice", "192.168.1.101", True), ("Bob", "192.168.1.102", False)]
    assert (scenario.timeout_s, scenario.planner) == (50.0, "seed")
    assert not scenario.finish_own


def test_finish_own_is_read_and_must_be_a_boolean(tmp_path):
    request = '  - {time: 3, person: Alice, text: "a"}\n'
    (tmp_path / "yes").mkdir()
    assert load_scenario(write_with_frank(tmp_path / "yes", request,
                                          "finish_own: true\n")).finish_own
    (tmp_path / "bad").mkdir()
    with pytest.raises(ScenarioError, match="finish_own must be true or false, got 'yes'"):
        load_scenario(write_with_frank(tmp_path / "bad", request, "finish_own: 'yes'\n"))


@pytest.mark.parametrize("requests, message", [
    ('  - {time: 1, person: Zed, text: "hi"}\n', "unknown person 'Zed'"),
    ('  - {time: -1, person: Bob, text: "hi"}\n', "time must be a number"),
    ('  - {time: 1, person: Bob, text: "  "}\n', "empty text"),
    ("  []\n", "no requests"),
])
def test_bad_scenarios_are_named(tmp_path, requests, message):
    with pytest.raises(ScenarioError, match=message):
        load_scenario(write_with_frank(tmp_path, requests))


def test_missing_key_and_file(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("world: x.yaml\n")
    with pytest.raises(ScenarioError, match="missing 'household'"):
        load_scenario(path)
    with pytest.raises(ScenarioError, match="none.yaml: no such scenario file$"):
        load_scenario(tmp_path / "none.yaml")


@pytest.mark.parametrize("extra, requests, message", [
    ("planer: fcfs\n", '  - {time: 1, person: Bob, text: "hi"}\n',
     r"scenario.yaml: unknown key 'planer' \(did you mean 'planner'\?\)"),
    ("", '  - {time: 1, person: Bob, txt: "hi"}\n',
     r"request 1: unknown key 'txt' \(did you mean 'text'\?\)"),
    ("planner: fcsf\n", '  - {time: 1, person: Bob, text: "hi"}\n',
     r"planner: unknown planner 'fcsf' \(known: .*fcfs"),
    ("timeout_s: soon\n", '  - {time: 1, person: Bob, text: "hi"}\n',
     "timeout_s must be a number of seconds > 0, got 'soon'"),
])
def test_unknown_keys_and_values_are_refused_with_the_nearest(tmp_path, extra, requests, message):
    with pytest.raises(ScenarioError, match=message):
        load_scenario(write_with_frank(tmp_path, requests, extra))


def test_a_visitors_misspelt_key_is_refused(tmp_path):
    path = write_scenario(tmp_path, '  - {time: 1, person: Bob, text: "hi"}\n')
    path.write_text(FRANK.replace("gender:", "gendre:") + path.read_text())
    with pytest.raises(ScenarioError, match=r"visitor 1: unknown key 'gendre' \(did you mean "
                                            r"'gender'\?\)"):
        load_scenario(path)


@pytest.mark.parametrize("name", ["household_short.yaml", "household_day.yaml",
                                  "household_clothes.yaml"])
def test_a_scenario_copied_out_of_the_workspace_loads_as_it_is(tmp_path, name):
    original = resource("config", "scenarios", name)
    copy = tmp_path / name
    copy.write_text(original.read_text())
    scenario, there = load_scenario(copy), load_scenario(original)
    assert scenario == there
    assert scenario.world == resource("config", "worlds", scenario.world.name).resolve()


def test_a_file_next_to_the_scenario_wins_and_a_missing_one_is_named(tmp_path):
    path = write_with_frank(tmp_path, '  - {time: 1, person: Bob, text: "hi"}\n')
    (tmp_path / "household.yaml").write_text(resource("config", "household.yaml").read_text())
    path.write_text(path.read_text().replace(f"household: {ROOT}/config/household.yaml",
                                             "household: household.yaml"))
    assert load_scenario(path).requests[0].ip == "192.168.1.102"
    path.write_text(path.read_text().replace("household: household.yaml",
                                             "household: ../elsewhere/household.yaml"))
    with pytest.raises(ScenarioError, match=r"household: '../elsewhere/household.yaml' is "
                                            r"neither next to the scenario nor among"):
        load_scenario(path)


def test_a_visitor_answers_the_robots_introduction_questions():
    frank = Visitor("Frank", "male", 72, "192.168.1.150", "welcome",
                    {"name": "My name is Frank.", "gender": "I am a man.", "age": "I am 72."})
    # the questions as the robot says them: the introduce greeting (config/robot_functions.yaml)
    # and perception's dialogue (IntroductionConfig), so a reworded question fails here
    from perception.introduction import IntroductionConfig
    from task_planner.robot_functions import load_robot_functions
    dialogue = IntroductionConfig()
    greeting = next(f.say for f in load_robot_functions(
        ROOT / "config/robot_functions.yaml").values() if f.name == "introduce")
    asked = {
        greeting: "My name is Frank.",
        f"Sorry, I did not catch a name in 'Hi.'. {dialogue.name_question}": "My name is Frank.",
        f"{dialogue.thanks.format(name='Frank')} {dialogue.gender_question}": "I am a man.",
        dialogue.age_question: "I am 72.", dialogue.welcome.format(name="Frank"): "",
        "Frank, here is some music for you.": ""}
    assert {said: visitor_answer(frank, said) for said in asked} == asked


@pytest.mark.parametrize("visitors, message", [
    ("visitors:\n  - {name: Zed, gender: male, age: 3, ip: 10.0.0.1, answers: {}}\n",
     "'Zed' is not a person of the world"),
    ("visitors:\n  - {name: Bob, gender: male, age: 3, ip: 10.0.0.1, answers: {}}\n",
     "Bob is in the household"),
    (FRANK.replace("gender: male", "gender: robot"), "gender must be female or male"),
    (FRANK.replace("age: I am 72.", "years: 72"), "answers must give a sentence for each"),
    ("", "people neither in the household nor visitors: Frank"),
])
def test_bad_visitors_are_named(tmp_path, visitors, message):
    path = write_scenario(tmp_path, '  - {time: 1, person: Bob, text: "hi"}\n')
    path.write_text(visitors + path.read_text())
    with pytest.raises(ScenarioError, match=message):
        load_scenario(path)


def test_day_start_is_a_time_of_day():
    from tamp_bringup.scenario import ScenarioError, clock_seconds
    assert clock_seconds("18:28:10", "day_start") == 18 * 3600 + 28 * 60 + 10
    assert clock_seconds("07:05", "day_start") == 7 * 3600 + 5 * 60
    with pytest.raises(ScenarioError, match="day_start: expected a quoted time of day"):
        clock_seconds(1105, "day_start")       # unquoted 18:25 is a base-60 number in YAML


def test_a_resident_in_new_clothes_answers_her_name_and_whether_it_was_heard_right():
    from perception.introduction import IntroductionConfig
    dialogue = IntroductionConfig()
    assert resident_answer("Carol", dialogue.name_question) == "My name is Carol."
    assert resident_answer("Carol", dialogue.confirm_question.format(name="Carol")) == "Yes."
    assert resident_answer("Carol", dialogue.confirm_question.format(name="Alice")) == "No."
    assert resident_answer("Carol", dialogue.recalled.format(name="Carol")) == ""


def test_anyone_asked_whether_they_are_someone_answers_yes_or_no():
    from perception.identity_question import QuestionConfig
    config = QuestionConfig()
    assert config.question == IDENTITY_QUESTION   # the scenario answers what the node asks
    assert identity_answer("Carol", config.question.format(name="Carol")) == "Yes."
    assert identity_answer("Frank", config.question.format(name="Carol")) == "No."
    assert identity_answer("Carol", config.thanks.format(name="Carol")) == ""
    assert identity_answer("Carol", "Carol, how are you feeling right now?") == ""
    assert identity_answer("Frank", "Thank you, Frank. Are you a man or a woman?") == ""
    assert config.call == CALL
    assert identity_answer("Bob", config.call.format(name="Bob")) == "Yes."
    assert identity_answer("Carol", config.call.format(name="Bob")) == ""   # not her name


def test_the_person_asked_is_the_one_the_robot_faces():
    people = {"Bob": (1.0, 1.0), "Carol": (0.0, 1.0), "Frank": (6.0, 0.0)}
    assert faced_person((0.0, 0.0, math.pi / 2), people) == "Carol"      # facing north
    assert faced_person((0.0, 0.0, math.pi / 4), people) == "Bob"        # north-east
    assert faced_person((0.0, 0.0, 0.0), people) == "Bob"   # Frank is east, but 6 m away
    assert faced_person((0.0, 0.0, 0.0), {"Frank": (6.0, 0.0)}) is None


def test_who_answers_an_identity_question_or_a_call():
    people = {"Bob": (1.0, 1.0), "Carol": (0.0, 1.0), "Frank": (3.0, 1.0)}
    place = lambda x, y: "west" if x < 2.0 else "east"   # noqa: E731
    robot = [(0.0, 0.0, math.pi / 2)]                     # in the west, facing north
    assert person_asked("Excuse me, are you Bob?", robot, people, place) == "Carol"
    assert person_asked("Bob, are you here?", robot, people, place) == "Bob"
    assert person_asked("Frank, are you here?", robot, people, place) is None   # east
    assert person_asked("Excuse me, are you Bob?", [], people, place) is None


def test_moves_that_change_clothes_carry_the_new_shirt():
    scenario = load_scenario(ROOT / "config" / "scenarios" / "household_clothes.yaml")
    pyjamas = ((200, 30, 200), (186, 26, 188), (190, 28, 192))
    assert [(m.person, m.place, m.shirt) for m in scenario.moves] == [
        ("Carol", "bedroom", pyjamas)]
    assert scenario.shirts == {"Carol": ((46, 160, 72), (40, 146, 64), (42, 150, 66))}
    assert residents(scenario) == ("Carol",)
    day = load_scenario(ROOT / "config" / "scenarios" / "household_day.yaml")
    assert not any(m.clothes for m in day.moves)
    assert residents(day) == ("Alice", "Bob", "Carol", "David")     # Frank is a visitor


def test_the_person_asked_is_the_one_whose_shirt_the_robot_saw():
    """Carol and Frank both in the living room: the introduce instruction names the shirt the
    robot saw (perception's text), and the nearest shirt answers."""
    from perception.introduction import IntroductionConfig, NewcomerWatch
    from task_planner.reward import Priority
    watch = NewcomerWatch(IntroductionConfig(min_sightings=1), (9, 20),
                          Priority("self_generated", 3.0, 0.9), {"living_room": 2})
    frank_seen = np.array([[220, 226, 219], [209, 218, 205], [230, 221, 222]])
    text = watch.observe(frank_seen, "living_room", 1.0, []).text
    assert text.startswith(INTRODUCE_TEXT)
    assert seen_shirt(text) == tuple(tuple(int(c) for c in rgb) for rgb in frank_seen)
    wearing = {"Carol": ((46, 160, 72),) * 3, "Frank": ((236, 236, 230),) * 3}
    assert who_answers(seen_shirt(text), wearing) == "Frank"
    assert who_answers(None, wearing) == "Carol" and who_answers(None, {}) is None
    assert seen_shirt("remind Bob: time to eat") is None
    said = IntroductionConfig()
    assert GIVE_UP_PHRASE in said.give_up.lower()
    # the ends of a dialogue the scenario hears, and no question
    ends = [said.welcome, said.recalled, said.give_up, said.not_seen]
    assert all(any(phrase in end.format(name="Frank").lower()
                   for phrase in DIALOGUE_END_PHRASES) for end in ends)
    assert not any(phrase in question.lower() for phrase in DIALOGUE_END_PHRASES
                   for question in (said.name_question, said.gender_question, said.age_question,
                                    said.thanks, said.confirm_question))
