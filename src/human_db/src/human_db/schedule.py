"""Schedule checks (thesis 000 §4.2.1: "remind his/her schedule if the current action is not
identical to the preset schedule"): does what perception observes differ from the schedule?
"""
from collections.abc import Iterable
from dataclasses import dataclass

from human_db.model import DAY, Human, ScheduleEntry

UPCOMING_S = 600.0   # [s] a schedule entry starting this soon already draws its person: people
#                      go to bed or to the table some minutes early

@dataclass(frozen=True)
class ScheduleCheck:
    """The outcome of comparing an observation with the schedule entry in force."""

    entry: ScheduleEntry | None   # the entry in force, or None when none covers the time
    location_differs: bool    # the entry names a place and the observed location is another one
    activity_differs: bool    # the entry names an activity and the observed one is another one

    @property
    def deviates(self) -> bool:
        return self.location_differs or self.activity_differs


def time_of_day(stamp: float, utc_offset: float = 0.0) -> float:
    """Seconds since local midnight of a time stamp [s since the epoch]; utc_offset [s]."""
    return (stamp + utc_offset) % DAY


def entry_in_force(schedules: Iterable[ScheduleEntry],
                   seconds_since_midnight: float) -> ScheduleEntry | None:
    """The schedule entry covering the given time of day, or None."""
    for entry in schedules:
        if entry.covers(seconds_since_midnight):
            return entry
    return None


def starts_within(start: float, seconds_since_midnight: float, lead_s: float) -> bool:
    """Whether an entry starting at `start` [s since midnight] starts after the time of day and
    within `lead_s` [s] of it (across midnight too)."""
    return 0.0 < (start - seconds_since_midnight) % DAY <= lead_s


def entry_upcoming(schedules: Iterable[ScheduleEntry], seconds_since_midnight: float,
                   lead_s: float = UPCOMING_S) -> ScheduleEntry | None:
    """The schedule entry that starts within `lead_s` [s] after the time of day (the first
    such in the list), or None."""
    for entry in schedules:
        if starts_within(entry.start, seconds_since_midnight, lead_s):
            return entry
    return None


def same_label(a: str, b: str) -> bool:
    """Labels compare case-blind, with '_' and '-' read as spaces ("watch_TV" == "watch tv")."""
    def norm(label: str) -> str:
        return " ".join(label.replace("_", " ").replace("-", " ").lower().split())
    return norm(a) == norm(b)


def check_schedule(human: Human, seconds_since_midnight: float, location: str | None = None,
                   activity: str | None = None) -> ScheduleCheck:
    """Compare an observation (default: the person's stored location and activity) with the
    schedule entry in force; an unknown ("") observation never counts as a deviation."""
    location = human.location if location is None else location
    activity = human.activity if activity is None else activity
    entry = entry_in_force(human.schedules, seconds_since_midnight)
    if entry is None:
        return ScheduleCheck(None, False, False)
    return ScheduleCheck(
        entry,
        location_differs=bool(entry.place and location and not same_label(entry.place, location)),
        activity_differs=bool(entry.activity and activity
                              and not same_label(entry.activity, activity)))


def expected_instead(name: str, place: str, seconds_since_midnight: float,
                     humans: Iterable[Human]) -> str:
    """Who the schedules expect at `place` now instead of `name`, or "" when nothing doubts a
    sighting there that the shirt colours give to `name`.

    Thesis 000 §3.2.3 learns a person's colours once and "needs to update once the human changes
    his/her clothes": a resident in new clothes may then fall within the threshold of someone
    else's shirt (magenta pyjamas under tungsten light near a red shirt). When `name`'s
    schedule puts them at another place now and another resident's puts that resident here,
    now or with an entry starting within UPCOMING_S (`entry_upcoming`: Carol goes to bed for her
    14:00 nap at 13:55, in her pyjamas), the sighting is doubted and the robot asks rather than
    guess (the first such resident in `humans`' order is named)."""
    humans = list(humans)
    matched = next((h for h in humans if h.name == name), None)
    if matched is None or not place:
        return ""
    own = entry_in_force(matched.schedules, seconds_since_midnight)
    if own is None or not own.place or same_label(own.place, place):
        return ""
    for human in humans:
        if human.name == name:
            continue
        for entry in (entry_in_force(human.schedules, seconds_since_midnight),
                      entry_upcoming(human.schedules, seconds_since_midnight)):
            if entry is not None and entry.place and same_label(entry.place, place):
                return human.name
    return ""


def not_met_yet(name: str, humans: Iterable[Human]) -> str:
    """The first resident other than `name` whose shirt is not known yet, or "".

    Recall (thesis 000 §3.2.3) chooses among the shirts learned so far: while a resident has not
    been met, a weak match may be them, whatever the schedules say."""
    return next((h.name for h in humans if h.name != name and h.shirt_colour is None), "")


def doubted_match(name: str, distance: float, sure_distance: float, place: str,
                  seconds_since_midnight: float, humans: Iterable[Human]) -> str:
    """Who else a colour match `distance` (mean Eq. 3-10) from `name`'s shirt may be when it is
    `sure_distance` or farther: the resident `expected_instead` names, else one not met yet
    (`not_met_yet`); "" when the match stands (a close one always does; `sure_distance` <= 0:
    every match stands)."""
    if sure_distance <= 0 or distance < sure_distance:
        return ""
    humans = list(humans)
    return (expected_instead(name, place, seconds_since_midnight, humans)
            or not_met_yet(name, humans))
