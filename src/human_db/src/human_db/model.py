"""A household member as the database remembers them (thesis 000 Table 3-1 + last_seen) and the
timed schedule entries; both validated on construction.
"""
import ipaddress
from collections.abc import Iterable
from dataclasses import dataclass, field

from human_db.colour import shirt_colours
from human_db.errors import InvalidHuman

GENDERS = ("female", "male")   # Table 3-1 stores gender as a bool: False = female, True = male
MAX_AGE = 150                  # [years]
MAX_NAME_LENGTH = 64           # [characters]
DAY = 86400.0                  # [s]


@dataclass(frozen=True)
class ScheduleEntry:
    """One timed entry of a daily schedule; `end < start` wraps past midnight (e.g. sleep)."""

    start: float          # [s since midnight], in [0, 86400)
    end: float            # [s since midnight], in [0, 86400]
    place: str = ""       # expected semantic location ("" = any)
    activity: str = ""    # expected activity ("" = any)

    def __post_init__(self) -> None:
        if not 0 <= self.start < DAY:
            raise InvalidHuman(f"schedule entry {self}: start must lie in [0, 86400) s")
        if not 0 <= self.end <= DAY:
            raise InvalidHuman(f"schedule entry {self}: end must lie in [0, 86400] s")
        if self.start == self.end:
            raise InvalidHuman(f"schedule entry {self}: start and end coincide")
        if not (self.place.strip() or self.activity.strip()):
            raise InvalidHuman(f"schedule entry {self}: needs a place or an activity")

    def covers(self, time_of_day: float) -> bool:
        """True when `time_of_day` [s since midnight] falls in [start, end)."""
        if self.start < self.end:
            return self.start <= time_of_day < self.end
        return time_of_day >= self.start or time_of_day < self.end

    def intervals(self) -> tuple[tuple[float, float], ...]:
        """[start, end) pieces within one day [s]: one, or two when the entry wraps midnight."""
        if self.start < self.end:
            return ((self.start, self.end),)
        return ((self.start, DAY), (0.0, self.end))

    def overlaps(self, other: "ScheduleEntry") -> bool:
        return any(a0 < b1 and b0 < a1
                   for a0, a1 in self.intervals() for b0, b1 in other.intervals())


@dataclass(frozen=True)
class Human:
    """Table 3-1: one household member, plus when perception last saw them."""

    name: str
    gender: str                      # "female" or "male"
    age: int                         # [years]
    shirt_colour: tuple | None       # ((r, g, b) at joint 1, at joint 2, at joint 5); None =
                                     # not met yet (§3.2.3: stored when the robot meets them)
    ip: str = ""                     # phone IP of the voice app; "" = no phone
    location: str = ""               # semantic location (graph place name); "" = unknown
    activity: str = ""               # current activity; "" = unknown
    schedules: tuple = field(default_factory=tuple)   # ScheduleEntry, sorted by start
    last_seen: float | None = None   # [s] time of the last observation; None = never

    def __post_init__(self) -> None:
        _check_name(self.name)
        where = f"human {self.name!r}"
        if self.gender not in GENDERS:
            raise InvalidHuman(f"{where}: gender must be one of {GENDERS}, got {self.gender!r}")
        if isinstance(self.age, bool) or not isinstance(self.age, int) or \
                not 0 <= self.age <= MAX_AGE:
            raise InvalidHuman(f"{where}: age must be an integer in 0-{MAX_AGE}, got {self.age!r}")
        if self.shirt_colour is not None:
            colours = shirt_colours(self.shirt_colour, f"{where}: shirt colour")
            object.__setattr__(self, "shirt_colour",
                               tuple(tuple(int(c) for c in j) for j in colours))
        object.__setattr__(self, "ip", check_ip(self.ip, where))
        object.__setattr__(self, "schedules", check_schedules(self.schedules, where))


def _check_name(name: object) -> None:
    if not isinstance(name, str) or not name.strip() or name != name.strip() or \
            len(name) > MAX_NAME_LENGTH:
        raise InvalidHuman(f"name must be a non-empty string of at most {MAX_NAME_LENGTH} "
                           f"characters without surrounding spaces, got {name!r}")


def check_ip(ip: str, where: str = "phone IP") -> str:
    """Return the canonical form of an IPv4/IPv6 address ("" stays ""); raise InvalidHuman."""
    if ip == "":
        return ""
    try:
        return str(ipaddress.ip_address(ip))
    except ValueError:
        raise InvalidHuman(f"{where}: {ip!r} is not an IP address") from None


def check_schedules(entries: Iterable[ScheduleEntry],
                    where: str = "schedules") -> tuple[ScheduleEntry, ...]:
    """Return the entries as a tuple sorted by start; raise InvalidHuman when two overlap."""
    entries = tuple(entries)
    for entry in entries:
        if not isinstance(entry, ScheduleEntry):
            raise InvalidHuman(f"{where}: {entry!r} is not a ScheduleEntry")
    entries = tuple(sorted(entries, key=lambda e: (e.start, e.end)))
    for i, entry in enumerate(entries):
        for other in entries[i + 1:]:
            if entry.overlaps(other):
                raise InvalidHuman(f"{where}: schedule entries {entry} and {other} overlap")
    return entries


def check_observation_time(stamp: float, now: float, tolerance_s: float, name: str) -> float:
    """Return `stamp` [s]; raise InvalidHuman when it lies more than `tolerance_s` after `now`.

    The store keeps the newest observation as a person's current state, so one stamped far ahead
    (4e9 s) would hold their location until the clock caught up; only the caller knows `now`.
    """
    if stamp - now > tolerance_s:
        raise InvalidHuman(f"update of {name!r}: stamp {stamp:.3f} s is {stamp - now:.3f} s after "
                           f"the present {now:.3f} s (tolerance {tolerance_s:g} s)")
    return stamp
