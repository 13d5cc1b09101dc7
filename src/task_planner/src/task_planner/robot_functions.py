"""Robot functions of thesis 000 Table 4-1 (`function`): what the robot says and does on arrival.

A chained follow-up (§4.2.1: "check Bob" then "report to the care giver") is about the person its
predecessor served, not about whoever launched it. Table 4-1 has no field for that person, so the
follow-up's text carries them in a leading "[about NAME] " (about_text), which speech reads back
(subject_of) for the `{about}` placeholder.
"""
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import yaml

from task_planner.instruction import HUMAN, Instruction


INTRODUCE = "introduce"   # the robot function that meets a stranger (config/robot_functions.yaml)
_ABOUT = re.compile(r"\[about ([^\]]+)\] ")


class RobotFunctionError(ValueError):
    """The robot function file is malformed, or an instruction names an unknown function code."""


@dataclass(frozen=True)
class RobotFunction:
    """One row of config/robot_functions.yaml."""

    code: int          # tamp_msgs/Instruction.function
    name: str
    duration_s: float  # execution time for self-generated instructions [s]
    say: str           # spoken on start; {target}, {source}, {about}, {place} are filled in
    expected_s: float | None = None  # what planning takes a function that usually ends early
    #                                  to last (a meeting's dialogue), the duration staying its
    #                                  time limit [s]; None: its duration

    def speech(self, instruction: Instruction, place: str) -> str:
        """The sentence the robot speaks when it starts this function for `instruction`."""
        return self.say.format(target=instruction.target or "everyone",
                               source=instruction.source or "the household",
                               about=subject_of(instruction) or "the household", place=place)


def about_text(person: str, text: str) -> str:
    """Text of a chained instruction about `person` (its predecessor's target)."""
    return f"[about {person}] {text}"


def subject_of(instruction: Instruction) -> str:
    """Whom an instruction is about: the person of a leading "[about NAME] " in its text (a
    chained report on the person checked), else its source ("tell the nurse I fell")."""
    match = _ABOUT.match(instruction.text or "")
    return match.group(1) if match else instruction.source


def load_robot_functions(path: str | Path) -> dict[int, RobotFunction]:
    """Read config/robot_functions.yaml into {code: RobotFunction}; errors name the bad entry."""
    try:
        document = yaml.safe_load(Path(path).read_text())
    except (OSError, yaml.YAMLError) as error:
        raise RobotFunctionError(f"{path}: cannot read robot functions: {error}") from error
    table = document.get("functions") if isinstance(document, dict) else None
    if not isinstance(table, dict) or not table:
        raise RobotFunctionError(f"{path}: expected a non-empty mapping under 'functions'")
    functions: dict[int, RobotFunction] = {}
    for name, row in table.items():
        try:
            function = RobotFunction(int(row["code"]), str(name), float(row["duration_s"]),
                                     str(row["say"]), None if row.get("expected_s") is None
                                     else float(row["expected_s"]))
        except (TypeError, KeyError, ValueError) as error:
            raise RobotFunctionError(f"{path}: function '{name}' needs code, duration_s and "
                                     f"say") from error
        if function.code in functions:
            raise RobotFunctionError(f"{path}: function '{name}' reuses code {function.code} "
                                     f"of '{functions[function.code].name}'")
        if function.duration_s < 0:
            raise RobotFunctionError(f"{path}: function '{name}': duration_s must be >= 0")
        if function.expected_s is not None and not 0 <= function.expected_s <= \
                function.duration_s:
            raise RobotFunctionError(f"{path}: function '{name}': expected_s must lie in "
                                     f"0..duration_s ({function.duration_s:g} s)")
        functions[function.code] = function
    return functions


def function_for(functions: Mapping[int, RobotFunction],
                 instruction: Instruction) -> RobotFunction:
    """The RobotFunction an instruction asks for; RobotFunctionError names an unknown code."""
    try:
        return functions[instruction.function]
    except KeyError:
        known = ", ".join(f"{f.code}={f.name}" for f in functions.values())
        raise RobotFunctionError(f"instruction {instruction.id}: unknown robot function code "
                                 f"{instruction.function} (known: {known})") from None


def is_meeting(functions: Mapping[int, RobotFunction], instruction: Instruction) -> bool:
    """An `introduce` instruction of the robot's own: meeting a stranger, whoever perception
    cannot tell at its place (it names no target)."""
    function = functions.get(instruction.function)
    return (instruction.type != HUMAN and not instruction.target and function is not None
            and function.name == INTRODUCE)
