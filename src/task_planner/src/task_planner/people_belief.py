"""What the robot believes about the people (ROS-free): where each was last seen, where their
schedule puts them, which places it looked at when; and the two choices built on that belief,
where to search for a person and where to patrol when idle (thesis 000 §4.2.1: the robot
observes the home to keep the human database fresh).

The belief is filled only from perception (human_db's table, whose locations perception writes)
and from the robot's own looks: a look that did not find a person believed at that place moves
the person out of it.
"""
import math
from collections import deque
from collections.abc import Container, Iterable, Mapping, Sequence
from typing import TypeVar

from human_db.schedule import UPCOMING_S, starts_within   # an entry starting within
#                                                           UPCOMING_S draws its person

Place = TypeVar("Place")   # a schedule's place: a graph node or a place name

DAY_S = 86400.0   # [s]
FRAMES_KEPT = 100  # stamps of analysed camera frames kept for frames_since
SIGHTINGS_KEPT = 30  # sightings kept per place, of the people perception told and of those it
#                      could not tell
APART_M = 1.0      # [m] sightings this close are taken for one person
SAME_M = 0.5       # [m] someone perception could not tell this close to where it told someone
#                    is that person (a seat's neighbour sits farther off)
UNSEEN_MISS = 0.5  # [-] chance a person is not at a place no sighting puts them at (their
#                    schedule's, a search's next)
HABITUAL_WEIGHT = 2.0  # [-] how much likelier a search takes a place the person's schedule
#                        names at some time of day than one it never names


class PeopleAtPlaces:
    """Where each person is now (graph node, or None when not known) and was before."""

    def __init__(self, now: Mapping[str, int | None] | None = None,
                 before: Mapping[str, Iterable[int]] | None = None) -> None:
        self.now: dict[str, int | None] = dict(now or {})  # name -> node the person is at now,
                                                           # None = not known
        self.before = {name: list(places) for name, places in (before or {}).items()}
        # name -> earlier nodes, most recent first
        self.seen_s: dict[str, float] = {}  # name -> when perception last saw them [s]
        self.predicted: dict[str, int | None] = {}  # name -> node their schedule puts them at now
        self.upcoming: dict[str, int | None] = {}  # name -> node of their schedule's next entry
        #                                            when it starts within UPCOMING_S
        self.habitual: dict[str, set[int]] = {}  # name -> nodes their schedule puts them at at
        #                                          any time of day
        self.frames: deque[float] = deque(maxlen=FRAMES_KEPT)  # stamps [s] of the camera frames
                                                 # perception analysed, oldest first
        self.unidentified: dict[int, deque[tuple[float, float, float]]] = {}
        # node -> (stamp [s], x, y [m]) of the latest people perception saw there but could not
        # tell who, oldest first
        self.unidentified_shirt: dict[int, tuple[float, float, float]] = {}
        # the same for those whose whole shirt (joints 1, 2, 5) it saw: someone new, or in
        # new clothes, whom the introduction node can meet
        self.identified: dict[int, deque[tuple[float, str, float, float]]] = {}
        # node -> (stamp [s], name, x, y [m]) of the latest people perception told there,
        # oldest first

    def take_frame(self, stamp: float, seen: Iterable[tuple[str, int, float, float]],
                   unidentified: Iterable[tuple[int, float, float, bool]]) -> None:
        """One camera frame perception analysed, taken at `stamp` [s]: the people it identified
        ([(name, node, x, y)]) and those it saw at a place but could not tell
        ([(node, x, y, whole shirt seen)])."""
        for name, node, x, y in seen:
            self.seen(name, node, stamp)
            self.identified.setdefault(node, deque(maxlen=SIGHTINGS_KEPT)).append(
                (stamp, name, x, y))
        for node, x, y, shirt in unidentified:
            self.someone_unidentified(node, x, y, stamp, shirt)
        self.analysed(stamp)

    def someone_unidentified(self, node: int, x: float, y: float, stamp: float,
                             shirt: bool = False) -> None:
        """Perception saw a person at `node`, at map position (x, y), whose shirt named nobody
        (seen from behind, half hidden, or in clothes nobody registered; `shirt`: all three
        shirt joints seen): they may be the one looked for."""
        self.unidentified.setdefault(node, deque(maxlen=SIGHTINGS_KEPT)).append((stamp, x, y))
        if shirt and stamp >= self.unidentified_shirt.get(node, (-math.inf,))[0]:
            self.unidentified_shirt[node] = (stamp, x, y)

    def unidentified_at(self, node: int, since: float, shirt: bool = False,
                        away_from: Iterable[tuple[float, float]] = ()
                        ) -> tuple[float, float] | None:
        """(x, y) of the latest person seen at `node` at or after `since` [s] whom perception
        could not tell (with `shirt`: whose whole shirt it saw), or None; with `away_from`,
        the latest more than APART_M from each of those positions (someone else)."""
        if shirt:
            stamp, x, y = self.unidentified_shirt.get(node, (-math.inf, 0.0, 0.0))
            return (x, y) if stamp >= since else None
        for stamp, x, y in reversed(self.unidentified.get(node, ())):
            if stamp < since:
                continue
            if all(math.hypot(x - ax, y - ay) > APART_M for ax, ay in away_from):
                return x, y
        return None

    def told_near(self, node: int, x: float, y: float, since: float) -> set[str]:
        """Names of the people perception identified at `node` within SAME_M of (x, y) at or
        after `since` [s]: whom someone it could not tell there is likely to be."""
        return {name for stamp, name, px, py in self.identified.get(node, ())
                if stamp >= since and math.hypot(px - x, py - y) <= SAME_M}

    def analysed(self, stamp: float) -> None:
        """Perception finished a camera frame taken at `stamp` [s] (whoever it saw was
        reported with `seen`)."""
        self.frames.append(stamp)

    def perceiving(self) -> bool:
        """True once perception reported an analysed frame: how far it got can be waited for."""
        return bool(self.frames)

    def frames_since(self, stamp: float) -> int:
        """How many analysed frames were taken at or after `stamp` [s]."""
        return sum(1 for frame in self.frames if frame >= stamp)

    def knows(self, name: str) -> bool:
        """True once the person has been seen anywhere (or reported out of sight)."""
        return name in self.now or bool(self.before.get(name))

    def is_at(self, name: str, node: int, since: float = -math.inf) -> bool:
        """Believed at `node`, seen there at or after `since` [s] (no stamp: any time)."""
        return self.now.get(name) == node and self.seen_s.get(name, math.inf) >= since

    def last_known_places(self, name: str) -> list[int]:
        """Current place first, then earlier ones, each once."""
        places = [self.now.get(name)] + self.before.get(name, [])
        return list(dict.fromkeys(p for p in places if p is not None))

    def seen(self, name: str, node: int | None, stamp: float | None = None) -> None:
        """`name` seen at `node` (None: out of sight) at `stamp` [s]; an older report than the
        last one taken is ignored. The previous place becomes history."""
        if stamp is not None:
            if stamp <= self.seen_s.get(name, -math.inf):
                return
            self.seen_s[name] = stamp
        self._move(name, node)

    def take_table(self, sightings: Mapping[str, tuple[int | None, float]],
                   schedules: Mapping[str, Iterable[tuple[float, float, int | None]]],
                   day_s: float) -> None:
        """human_db's table (conversions.people_from_msg): each sighting, and the places the
        schedules predict at time of day `day_s` [s since midnight]."""
        for name, (node, stamp) in sightings.items():
            self.seen(name, node, stamp)
        self.predict(schedules, day_s)

    def predict(self, schedules: Mapping[str, Iterable[tuple[float, float, int | None]]],
                day_s: float) -> None:
        """Where each person's schedule puts them at time of day `day_s` [s since midnight],
        where it puts them next when that starts within UPCOMING_S, and at any time of day."""
        for name, entries in schedules.items():
            entries = list(entries)
            self.predicted[name] = scheduled_place(entries, day_s)
            self.upcoming[name] = scheduled_place(entries, day_s + UPCOMING_S,
                                                  starting_after=day_s)
            self.habitual[name] = {place for _, _, place in entries if place not in (None, "")}

    def missed(self, name: str, node: int) -> None:
        """A look at `node` did not find `name`: they are no longer believed there."""
        if self.now.get(name) == node:
            self._move(name, None)

    def expected_at(self, node: int) -> int:
        """How many people the belief or their schedule put at `node`."""
        names = set(self.now) | set(self.predicted)
        return sum(self.now.get(n) == node or self.predicted.get(n) == node for n in names)

    def _move(self, name: str, node: int | None) -> None:
        previous = self.now.get(name)
        if previous is not None and previous != node:
            self.before[name] = [previous] + [p for p in self.before.get(name, [])
                                              if p != previous]
        self.now[name] = node


def miss_chance(people: PeopleAtPlaces, name: str, node: int, now: float,
                stay_s: float) -> float:
    """Chance that `name` is no longer at `node` when the robot looks there, for the expected
    cost of a search (beyond the seed): a person stays at a place for an exponentially
    distributed time of mean `stay_s` [s], counted from their last sighting there; at a place
    no sighting puts them at, UNSEEN_MISS."""
    seen_s = people.seen_s.get(name)
    if people.now.get(name) != node or seen_s is None:
        return UNSEEN_MISS
    return 1.0 - math.exp(-max(0.0, now - seen_s) / stay_s)


def scheduled_place(entries: Iterable[tuple[float, float, Place | None]],
                    seconds_since_midnight: float,
                    starting_after: float | None = None) -> Place | None:
    """The place of the schedule entry covering the time of day, or None; with
    `starting_after` [s since midnight], only an entry that starts after that time (and by
    the time of day: the next one).

    entries: (start, end, place) [s since midnight]; an entry whose end is before its start runs
    past midnight (as human_db's schedules). A place may be a name or a graph node; None and ""
    are no place.
    """
    t = seconds_since_midnight % DAY_S
    for start, end, place in entries:
        inside = start <= t < end if start <= end else (t >= start or t < end)
        if starting_after is not None:
            inside = inside and starts_within(start, starting_after,
                                              (t - starting_after) % DAY_S)
        if inside and place not in (None, ""):
            return place
    return None


def search_order(name: str, people: PeopleAtPlaces, looked_s: Mapping[int, float],
                 places: Iterable[int], searched: Container[int],
                 distance_m: Sequence[float] | None = None,
                 swept: Mapping[int, tuple[float, float]] | None = None,
                 last: Container[int] = ()) -> list[int]:
    """Where to look for `name` next: where the belief and the schedule point first (the place
    they were last seen, the place their schedule predicts, the place of its entry starting
    within UPCOMING_S, then the places they were seen before, most recent first), then every
    other place: first those not looked at since the
    person was last seen (a look before says nothing of where they went since), the nearest
    first (`distance_m[n]`: from the robot [m]), then those looked at since, the longest
    unlooked-at first, the nearest first among equally stale ones. For someone
    never seen (not met yet: perception cannot tell them) the places where anyone's schedule
    puts someone now come before the others: the household gathers there, and a stranger seen
    there is met, perhaps the person looked for; and with nothing seen of them, the places are
    taken by distance over likelihood (the search rule of the most probability per cost
    first), a place their schedule names at some time of day (`habitual`: the living room of
    someone who watches TV in the evenings) HABITUAL_WEIGHT times as likely as another. Once
    seen, where they were seen says more (someone who left the living room is likelier in
    the hall next door than in a room of their schedule). A place where
    they were seen that was looked all around after their last sighting (`swept[n]`: (start,
    end) [s] of the latest look all around n) missed them: it ranks with the other places.
    Places people only pass through (`last`: an alley, the robot's dock) come after every other
    place unless the belief or the schedule points there. Places already searched for this
    instruction are left out."""
    last_seen = people.seen_s.get(name, -math.inf)
    swept = swept or {}

    def missed_since_seen(node: int | None) -> bool:
        return node is not None and swept.get(node, (-math.inf,))[0] > last_seen

    def looked_since_seen(node: int) -> float:
        """When `node` was looked at, if after the last sighting; else -inf."""
        looked = looked_s.get(node, -math.inf)
        return looked if looked > last_seen else -math.inf

    seen_at = [people.now.get(name), *people.before.get(name, [])]
    expected = {people.predicted.get(name), people.upcoming.get(name)} - {None}
    first = [seen_at[0], people.predicted.get(name), people.upcoming.get(name), *seen_at[1:]]
    first = [n for n in first if n in expected or not missed_since_seen(n)]
    scheduled = set() if people.knows(name) else set(people.predicted.values())
    habitual = () if people.knows(name) else people.habitual.get(name, ())

    def likelihood(node: int) -> float:
        return HABITUAL_WEIGHT if node in habitual else 1.0

    rest = sorted(places, key=lambda n: (n in last, n not in scheduled, looked_since_seen(n),
                                         (0.0 if distance_m is None else distance_m[n])
                                         / likelihood(n), -likelihood(n), n))
    return [n for n in dict.fromkeys([*first, *rest]) if n is not None and n not in searched]


def patrol_target(places: Iterable[int], people: PeopleAtPlaces, looked_s: Mapping[int, float],
                  now: float, min_interval_s: float, distance_m: Sequence[float] | None = None,
                  never_looked_s: float = 600.0) -> int | None:
    """The place an idle robot should look at: the stalest (a place never looked at counts as
    `never_looked_s` [s] stale), weighted by how many people the belief or the schedules put
    there, the nearest first among equals (`distance_m[n]`: from the robot [m]); None when every
    place was looked at within `min_interval_s` [s]."""
    def score(node: int) -> tuple[float, float, int]:

        staleness = now - looked_s.get(node, now - never_looked_s)
        near = 0.0 if distance_m is None else distance_m[node]
        return staleness * (1 + people.expected_at(node)), -near, -node

    stale = [n for n in places if now - looked_s.get(n, -math.inf) >= min_interval_s]
    return max(stale, key=score) if stale else None
