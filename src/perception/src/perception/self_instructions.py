"""Self-generated instructions (thesis 000 Sec. 4.2.1): while idle the robot observes people and
gives itself robot-type instructions -- a recommendation for an activity ("play piano music for a
person who is reading") and, when the observed activity or place differs from the person's
schedule, a reminder (the seed's `deviation_function`; a deployment may check on the person
instead). Beyond the seed, a reminder when a schedule entry starts. Priority: the self-generated
level of config/priorities.yaml.
"""
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from human_db.model import Human
from human_db.schedule import ScheduleCheck
from task_planner.instruction import ROBOT, Instruction
from task_planner.reward import Priority


@dataclass
class SelfInstructionConfig:
    recommendations: dict = field(default_factory=dict)   # activity -> robot function name
    deviation_function: str = "remind"   # on a schedule deviation (the seed: a reminder)
    remind_function: str = "remind"      # when a schedule entry starts
    timed_reminders: bool = True         # remind people when their schedule entries start
    repeat_after: float = 600.0   # [s] same (person, function) is not generated again before this


@dataclass
class Observation:
    person: str
    activity: str
    place: str        # semantic place ("" when unknown)
    stamp: float      # [s]


class SelfInstructionGenerator:
    """Turns observations into robot-type Instructions, once per person and function per period.

    Each carries the provisional id 1: the node submits it with id 0 and the task buffer allocates
    the id (task_planner.submission).

    Args:
        functions: {function name: (code, duration_s)} (config/keywords.yaml `functions`).
        priority: task_planner.reward.Priority of the self-generated level.
        place_ids: {place name: graph node id}.
        activity_codes: {activity: Instruction.status code}.
    """

    def __init__(self, config: SelfInstructionConfig, functions: Mapping[str, tuple[int, float]],
                 priority: Priority, place_ids: Mapping[str, int],
                 activity_codes: Mapping[str, int]) -> None:
        for name in list(config.recommendations.values()) + [config.remind_function,
                                                             config.deviation_function]:
            if name not in functions:
                raise ValueError(f"self-instruction function '{name}' is not a robot function "
                                 f"(known: {sorted(functions)})")
        self.config, self.functions, self.priority = config, functions, priority
        self.place_ids, self.activity_codes = place_ids, activity_codes
        self._last: dict[tuple[str, str, str], float] = {}   # (person, function, why) -> stamp

    def _make(self, function: str, obs: Observation, text: str,
              why: str = "observed") -> Instruction | None:
        key = (obs.person, function, why)
        if key in self._last and obs.stamp - self._last[key] < self.config.repeat_after:
            return None
        if obs.place not in self.place_ids:
            return None
        self._last[key] = obs.stamp
        code, duration = self.functions[function]
        instruction = Instruction(
            id=1, gamma=self.priority.gamma, beta=self.priority.beta,
            destination=self.place_ids[obs.place], type=ROBOT, start_time=obs.stamp,
            duration=int(duration), source="robot", target=obs.person,
            status=self.activity_codes.get(obs.activity, 0), function=code,
            destination_name=obs.place, text=text)
        return instruction

    def generate(self, obs: Observation,
                 schedule_check: ScheduleCheck | None = None) -> list[Instruction]:
        """Instructions for one observation; schedule_check: human_db ScheduleCheck or None."""
        made: list[Instruction | None] = []
        function = self.config.recommendations.get(obs.activity)
        if function:
            made.append(self._make(function, obs,
                                   f"{function.replace('_', ' ')} for {obs.person} who is "
                                   f"doing '{obs.activity}' in {obs.place}"))
        if schedule_check is not None and schedule_check.deviates:
            entry = schedule_check.entry
            if entry is None:
                raise ValueError("a schedule deviation without the schedule entry in force")
            function = self.config.deviation_function
            made.append(self._make(function, obs,
                                   f"{function.replace('_', ' ')} {obs.person}: schedule says "
                                   f"'{entry.activity}' in {entry.place}, observed "
                                   f"'{obs.activity}' in {obs.place}", why="deviation"))
        return [m for m in made if m is not None]

    def due_reminders(self, humans: Iterable[Human], previous_s: float, now_s: float,
                      stamp: float) -> list[Instruction]:
        """Reminders of the schedule entries that started in (previous_s, now_s] [s since
        midnight], served where the person was last seen (else where the entry is).

        Args:
            humans: human_db Humans (name, location, schedules).
            stamp: the instructions' start time [s].
        """
        if not self.config.timed_reminders:
            return []
        made: list[Instruction | None] = []
        for human in humans:
            for entry in human.schedules:
                if not started_between(entry.start, previous_s, now_s):
                    continue
                place = human.location if human.location in self.place_ids else entry.place
                what = " ".join(w for w in (entry.activity, "in the " + entry.place
                                            if entry.place else "") if w)
                made.append(self._make(self.config.remind_function,
                                       Observation(human.name, "", place, stamp),
                                       f"remind {human.name}: time to {what}", why="timed"))
        return [m for m in made if m is not None]


def started_between(start_s: float, previous_s: float, now_s: float) -> bool:
    """True when a time of day `start_s` lies in (previous_s, now_s], across midnight too."""
    if previous_s <= now_s:
        return previous_s < start_s <= now_s
    return start_s > previous_s or start_s <= now_s
