"""People of the simulated home: pose, posture, activity, what they hold and look at, schedules.

A schedule is a list of timed moves: at `time` [s] the person walks (standing, activity
"walking") along the optional `via` waypoints to `pose`, then takes the entry's posture and
activity there, and puts on the entry's shirt if it names one (pyjamas before bed, a coat to go
out): thesis 000 §3.2.3's "needs to update once the human changes his/her clothes".
"""
import math
from dataclasses import dataclass, field

POSTURES = ("standing", "sitting", "lying")
WALKING = "walking"


@dataclass
class ScheduleEntry:
    time: float                 # [s] sim time at which the move starts
    pose: tuple                 # (x, y, yaw) destination [m, m, rad]
    posture: str = "standing"
    activity: str = "standing"
    holding: str = ""           # name of the object in the hands ("" = none)
    looking_at: str = ""        # name of the object looked at ("" = straight ahead)
    via: list = field(default_factory=list)   # [[x, y], ...] waypoints [m]
    shirt_colour: tuple | None = None  # clothes put on there (as Person's); None = same


@dataclass
class Person:
    name: str
    shirt_colour: tuple         # ((r, g, b) at joint 1, joint 2, joint 5), 0-255
    pose: tuple                 # (x, y, yaw) [m, m, rad]
    posture: str = "standing"
    activity: str = "standing"
    holding: str = ""
    looking_at: str = ""
    schedule: list = field(default_factory=list)   # [ScheduleEntry] sorted by time
    walking_speed: float = 0.8  # [m/s]
    radius: float = 0.2         # [m] footprint seen by lasers
    _path: list = field(default_factory=list, repr=False)
    _next_entry: int = 0
    _arrival: ScheduleEntry | None = None

    @property
    def walking(self) -> bool:
        return bool(self._path)

    def step(self, now: float, dt: float) -> None:
        """Start the schedule's moves that are due and walk along the current path."""
        while self._next_entry < len(self.schedule) and self.schedule[self._next_entry].time <= now:
            entry = self.schedule[self._next_entry]
            self._next_entry += 1
            self._path = [tuple(p[:2]) for p in entry.via] + [tuple(entry.pose[:2])]
            self._arrival = entry
            self.posture, self.activity, self.holding, self.looking_at = (
                "standing", WALKING, entry.holding, "")
        if self._path:
            self._walk(self.walking_speed * dt)

    def _walk(self, distance: float) -> None:
        x, y, yaw = self.pose
        while self._path and distance > 0:
            tx, ty = self._path[0]
            gap = math.hypot(tx - x, ty - y)
            if gap > 1e-9:
                yaw = math.atan2(ty - y, tx - x)
            if gap <= distance:
                x, y, distance = tx, ty, distance - gap
                self._path.pop(0)
            else:
                x += distance * math.cos(yaw)
                y += distance * math.sin(yaw)
                distance = 0.0
        self.pose = (x, y, yaw)
        if not self._path:
            entry = self._arrival
            if entry is None:   # a path is only ever set together with its schedule entry
                raise RuntimeError(f"person {self.name!r} walked a path of no schedule entry")
            self.pose = tuple(entry.pose)
            self.posture, self.activity = entry.posture, entry.activity
            self.holding, self.looking_at = entry.holding, entry.looking_at
            if entry.shirt_colour is not None:
                self.shirt_colour = entry.shirt_colour
