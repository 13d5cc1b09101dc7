"""Command line of `send_instruction` (ROS-free): arguments, the names it accepts for codes, and
the Instruction it builds.

`--function`, `--status` and `--destination` take a name or a number. The names are those of
the workspace's configuration: robot functions from `config/robot_functions.yaml` (thesis 000
Table 4-1 `function`), human states from `status_codes` in `config/keywords.yaml` (the priority
levels of Table 5-5 that verbal perception writes into `status`; tamp_msgs/Instruction defines no
constants for either) and places of `maps/household.graph.yaml` (node ids in file order, as
`task_planner.graph` numbers them). A number is passed on as it is (another graph, a code of
one's own); an unknown name is an argparse error naming it and the choices.
"""
import argparse
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import yaml
from tamp_resources import resource

from task_planner.graph import GraphError, place_ids
from task_planner.instruction import HUMAN, ROBOT, Instruction
from task_planner.robot_functions import RobotFunctionError, load_robot_functions

FUNCTIONS_FILE = resource("config", "robot_functions.yaml")
KEYWORDS_FILE = resource("config", "keywords.yaml")
GRAPH_FILE = resource("maps", "household.graph.yaml")
NAMESPACE_HELP = ("The service is task_planner/submit in the tool's namespace. A fleet "
                  "(fleet_sim.launch, household_fleet.launch, scripts/run_scenario --fleet) runs "
                  "each robot's executor in its robot's namespace: send with "
                  "ROS_NAMESPACE=robot1 (or robot2) before rosrun; the robots share what either "
                  "receives.")


@dataclass(frozen=True)
class CodeNames:
    """The names of one kind of code: {name: code}, and why there are none if so."""

    kind: str                 # "function", "status", "destination"
    source: str               # where the names come from (for --help)
    codes: dict[str, int] = field(default_factory=dict)
    problem: str = ""         # why the names could not be read ("" when they were)

    def describe(self) -> str:
        """`chat (1), encourage (2), ...` in code order, or the problem."""
        if not self.codes:
            return f"no names ({self.problem})" if self.problem else "no names"
        return ", ".join(f"{name} ({code})"
                         for name, code in sorted(self.codes.items(), key=lambda kv: kv[1]))

    def named(self, text: str) -> tuple[int, str]:
        """argparse type: (code, name) of a known name, (number, "") of a number;
        ArgumentTypeError naming the bad value and the choices otherwise."""
        text = text.strip()
        try:
            return int(text), ""
        except ValueError:
            pass
        if text in self.codes:
            return self.codes[text], text
        raise argparse.ArgumentTypeError(f"unknown {self.kind} {text!r}; choose one of "
                                         f"{self.describe()}, or give a number")

    def code(self, text: str) -> int:
        """argparse type: the code of a name or a number (see `named`)."""
        return self.named(text)[0]


def _shown(path: str | Path) -> str:
    """`path` as --help shows it: relative to tamp_resources when inside it."""
    shown = Path(path)
    try:
        return str(shown.relative_to(resource()))
    except ValueError:
        return str(shown)


def function_names(path: Path = FUNCTIONS_FILE) -> CodeNames:
    """Robot function names -> codes (config/robot_functions.yaml)."""
    try:
        codes = {f.name: code for code, f in load_robot_functions(path).items()}
    except RobotFunctionError as error:
        return CodeNames("function", _shown(path), problem=str(error))
    return CodeNames("function", _shown(path), codes)


def status_names(path: Path = KEYWORDS_FILE) -> CodeNames:
    """Human-state names -> status codes (`status_codes` of config/keywords.yaml)."""
    try:
        table = yaml.safe_load(path.read_text())["status_codes"]
        codes = {str(name): int(code) for name, code in table.items()}
    except (OSError, yaml.YAMLError, TypeError, KeyError, AttributeError, ValueError) as error:
        return CodeNames("status", _shown(path), problem=f"{path}: no status_codes: {error}")
    return CodeNames("status", _shown(path), codes)


def destination_names(path: Path = GRAPH_FILE) -> CodeNames:
    """Place names -> node ids of a semantic graph (task_planner.graph.place_ids)."""
    try:
        codes = place_ids(path)
    except (OSError, GraphError) as error:
        return CodeNames("destination", _shown(path), problem=str(error))
    return CodeNames("destination", _shown(path), codes)


def build_parser(functions: CodeNames, statuses: CodeNames, destinations: CodeNames,
                 description: str = "",
                 service: str = "the service") -> argparse.ArgumentParser:
    """The argument parser; `functions`, `statuses`, `destinations` are CodeNames; `service`
    is the submit service named in --wait's help."""
    parser = argparse.ArgumentParser(prog="send_instruction", description=description,
                                     epilog=NAMESPACE_HELP)
    parser.add_argument("--id", type=int, default=0,
                        help="instruction id; 0 (default): the task buffer allocates it")
    parser.add_argument("--gamma", type=float, required=True, help="initial reward (> 0)")
    parser.add_argument("--beta", type=float, required=True, help="decay per second, in (0, 1)")
    parser.add_argument("--destination", type=destinations.named, required=True,
                        metavar="PLACE|ID",
                        help=f"graph node, by name or id; places of {destinations.source}: "
                             f"{destinations.describe()}")
    parser.add_argument("--destination-name", default=None,
                        help="semantic name of the node; default: the place's name when "
                             "--destination is one of the names above")
    parser.add_argument("--previous-id", type=int, default=0)
    parser.add_argument("--type", choices=("human", "robot"), default="human")
    parser.add_argument("--start-time", type=float, default=None,
                        help="launch time [s, ROS time]; default: now")
    parser.add_argument("--duration", type=int, default=0, help="function duration [s]")
    parser.add_argument("--source", default="")
    parser.add_argument("--target", default="")
    parser.add_argument("--status", type=statuses.code, default=0, metavar="STATE|CODE",
                        help=f"human state that caused it, by name or code (default 0: none); "
                             f"from {statuses.source}: {statuses.describe()}")
    parser.add_argument("--function", type=functions.code, required=True, metavar="NAME|CODE",
                        help=f"robot function, by name or code (the executor refuses a code "
                             f"it does not know); from {functions.source}: "
                             f"{functions.describe()}")
    parser.add_argument("--text", default="")
    parser.add_argument("--wait", type=float, default=5.0,
                        help="wall-clock seconds to wait for ROS time and for "
                             f"{service} before giving up")
    return parser


def parse_args(argv: Sequence[str] | None, description: str = "",
               service: str = "the service") -> argparse.Namespace:
    """Parsed arguments with --function, --status and --destination as codes; a destination
    given by name is also the default --destination-name."""
    parser = build_parser(function_names(), status_names(), destination_names(), description,
                          service)
    args = parser.parse_args(argv)
    args.destination, place = args.destination
    if args.destination_name is None:
        args.destination_name = place
    return args


def instruction_from_args(args: argparse.Namespace, now: float) -> Instruction:
    """The Instruction to submit, checked here; with --id 0 a provisional id stands in for the
    one the task buffer allocates (task_planner.submission)."""
    provisional = args.id or args.previous_id + 1
    return Instruction(
        id=provisional, gamma=args.gamma, beta=args.beta, destination=args.destination,
        previous_id=args.previous_id, type=ROBOT if args.type == "robot" else HUMAN,
        start_time=now if args.start_time is None else args.start_time, duration=args.duration,
        source=args.source, target=args.target, status=args.status, function=args.function,
        destination_name=args.destination_name, text=args.text)
