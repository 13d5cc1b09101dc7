"""send_instruction's command line: function, status and destination by name or number, the
names listed in --help, bad names named with the choices (no ROS needed)."""
import pytest
import yaml
from tamp_resources import resource

from task_planner.send_instruction_args import (CodeNames, destination_names, function_names,
                                                instruction_from_args, parse_args, status_names)

REQUIRED = ["--gamma", "2", "--beta", "0.9"]


def yaml_of(*parts):
    return yaml.safe_load(resource(*parts).read_text())


def expected_functions():
    """Independent read of config/robot_functions.yaml: name -> code."""
    return {name: row["code"] for name, row in yaml_of("config", "robot_functions.yaml")
            ["functions"].items()}


def expected_places():
    """Independent read of maps/household.graph.yaml: name -> id."""
    return {node["name"]: node["id"] for node in yaml_of("maps", "household.graph.yaml")["nodes"]}


def test_names_are_those_of_the_configuration_files():
    assert function_names().codes == expected_functions()
    assert status_names().codes == yaml_of("config", "keywords.yaml")["status_codes"]
    assert destination_names().codes == expected_places()
    assert expected_functions()["report_to_caregiver"] == 7 and expected_places()["alley"] == 1


def test_names_and_numbers_give_the_same_instruction():
    functions, places = expected_functions(), expected_places()
    by_name = parse_args(REQUIRED + ["--destination", "dining_room", "--function", "remind",
                                     "--status", "negative"])
    by_number = parse_args(REQUIRED + [f"--destination={places['dining_room']}", "--function",
                                       str(functions["remind"]), "--status", "2",
                                       "--destination-name", "dining_room"])
    assert (by_name.destination, by_name.function, by_name.status) == \
        (places["dining_room"], functions["remind"], 2)
    assert instruction_from_args(by_name, 5.0) == instruction_from_args(by_number, 5.0)
    assert by_name.destination_name == "dining_room"


def test_a_number_passes_as_it_is_and_names_no_place():
    args = parse_args(REQUIRED + ["--destination", "42", "--function", "77"])
    assert (args.destination, args.function, args.status, args.destination_name) == \
        (42, 77, 0, "")
    args = parse_args(REQUIRED + ["--destination", "office", "--destination-name", "study",
                                  "--function", "chat"])
    assert (args.destination, args.destination_name) == (expected_places()["office"], "study")


@pytest.mark.parametrize("option, value, first_choice", [
    ("--function", "fly", "chat (1)"),
    ("--status", "grumpy", "physical (1)"),
    ("--destination", "kitchen", "charging_place (0)"),
])
def test_a_bad_name_names_itself_and_the_choices(option, value, first_choice, capsys):
    argv = REQUIRED + (["--destination", "alley"] if option != "--destination" else []) + (
        ["--function", "chat"] if option != "--function" else [])
    with pytest.raises(SystemExit) as exit_:
        parse_args(argv + [option, value])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    kind = option.lstrip("-")
    assert f"argument {option}: unknown {kind} '{value}'; choose one of {first_choice}," in err


def test_help_lists_every_name(capsys):
    with pytest.raises(SystemExit) as exit_:
        parse_args(["--help"])
    assert exit_.value.code == 0
    out = " ".join(capsys.readouterr().out.split())      # argparse wraps lines
    for names in (expected_functions(), expected_places(),
                  yaml_of("config", "keywords.yaml")["status_codes"]):
        for name, code in names.items():
            assert f"{name} ({code})" in out
    assert "config/robot_functions.yaml" in out and "maps/household.graph.yaml" in out


def test_unreadable_names_say_why(tmp_path):
    missing = status_names(tmp_path / "none.yaml")
    assert missing.codes == {} and "none.yaml" in missing.describe()
    with pytest.raises(Exception, match="unknown status 'calm'; choose one of no names"):
        missing.code("calm")
    assert CodeNames("status", "x", {"b": 2, "a": 1}).describe() == "a (1), b (2)"
