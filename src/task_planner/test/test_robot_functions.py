"""Robot functions (Table 4-1 `function`): the config agrees with verbal perception's codes."""

import pytest
import yaml
from planner_factories import make_instruction

from task_planner.robot_functions import (RobotFunctionError, about_text, function_for,
                                          load_robot_functions, subject_of)
from tamp_resources import resource

CONFIG = resource("config")


def test_codes_and_durations_match_the_verbal_keywords():
    functions = load_robot_functions(CONFIG / "robot_functions.yaml")
    keywords = yaml.safe_load((CONFIG / "keywords.yaml").read_text())["functions"]
    for name, row in keywords.items():
        function = functions[row["code"]]
        assert (function.name, function.duration_s) == (name, row["duration_s"])
    assert functions[8].name == "charge"


def test_speech_fills_in_the_instruction():
    functions = load_robot_functions(CONFIG / "robot_functions.yaml")
    report = make_instruction(3, 0, function=7, source="Bob", target="Alice")
    assert function_for(functions, report).speech(report, "office") == \
        "Alice, here is my report on Bob."
    with pytest.raises(RobotFunctionError, match="instruction 3: unknown robot function code 99"):
        function_for(functions, make_instruction(3, 0, function=99))


def test_chained_report_names_the_person_checked_on():
    """§4.2.1: David asks to check on Alice; the report served to David is on Alice."""
    functions = load_robot_functions(CONFIG / "robot_functions.yaml")
    report = make_instruction(5, 0, previous_id=4, function=7, source="David", target="David",
                              text=about_text("Alice", "Please check on Alice"))
    assert report.text == "[about Alice] Please check on Alice"
    assert subject_of(report) == "Alice"
    assert function_for(functions, report).speech(report, "dining_room") == \
        "David, here is my report on Alice."


@pytest.mark.parametrize("text, subject", [
    ("Tell the nurse I fell", "Bob"), ("", "Bob"), ("[about] x", "Bob"),
    ("I said [about Carol] later", "Bob"), ("[about Mary Ann] check Mary Ann", "Mary Ann")])
def test_subject_is_the_about_prefix_else_the_source(text, subject):
    assert subject_of(make_instruction(1, 0, source="Bob", text=text)) == subject


@pytest.mark.parametrize("text, message", [
    ("functions: {}", "non-empty mapping"),
    ("functions: {chat: {code: 1, say: hi}}", "'chat' needs code, duration_s and say"),
    ("functions: {a: {code: 1, duration_s: 1, say: x}, b: {code: 1, duration_s: 1, say: y}}",
     "'b' reuses code 1 of 'a'"),
    ("functions: {a: {code: 1, duration_s: -1, say: x}}", "duration_s must be >= 0"),
    ("functions: {a: {code: 1, duration_s: 10, expected_s: 20, say: x}}",
     r"'a': expected_s must lie in 0..duration_s \(10 s\)"),
])
def test_bad_files_are_named(tmp_path, text, message):
    path = tmp_path / "functions.yaml"
    path.write_text(text)
    with pytest.raises(RobotFunctionError, match=message):
        load_robot_functions(path)
