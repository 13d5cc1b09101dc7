"""A person's activity over the last few frames (beyond the seed; thesis 000 Sec. 3.2.4 reads
each frame alone).

A real detector misses a cup or a fork in most frames (docs/perception/camera_calibration.md),
so a framewise reading flickers between the detailed activity and the posture. Per identified
person, the frames of the last `window_s` seconds at the same place are fused: the mean of each
detailed activity's probability over those frames (a frame without a score adds 0) decides when
it reaches `min_probability` and no other activity ties with it; else the posture most frames
read; else "unknown". A person seen at another place starts a new window (they moved, so they
may do something else).

The robot mostly sees people from across a room, where a cup or a bowl is too small for the
detector, and someone at the front door from the dock 4 m away, too far for the umbrella beside
them or their hands: a detailed activity read is kept for `hold_s` seconds after the last
window that read it, while the person stays at the place and no frame reads another posture
than the one it was read in (someone who stood up has stopped eating). A window that reads a
detailed activity replaces the one kept.

What the hands hold outranks what lies within their reach (perception.activity's
`hold_distance`): when at least FIRM_FRAMES frames of the window read an activity holding the
same thing, that is the window's reading, whatever the other frames read (the bowl in Bob's hands,
found now and then, against the bottle standing on the table within reach, found more often);
and while it is kept, a window whose reading nothing held showed does not replace it.

`window_s` 0 is the seed's framewise reading (nothing is kept either).
"""
import math
from collections import Counter, deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from perception.activity import POSTURES, UNKNOWN_POSTURE

FIRM_FRAMES = 2   # frames of a window showing the same thing held that an activity read from
#                   it must stand on: a false box at a hand (a "cup", then a "laptop", at a
#                   sleeper's) is a one-off, a cup really held shows again


@dataclass
class ActivityTrackConfig:
    window_s: float = 8.0          # [s] frames of a person this recent are fused (0: framewise)
    min_probability: float = 0.2   # [-] mean P(a) over the window for a detailed activity
    hold_s: float = 600.0          # [s] a detailed activity is kept this long after the last
    #                                window that read it (same place and posture; 0: not kept)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.window_s) and self.window_s >= 0):
            raise ValueError(f"activity_window must be a finite time >= 0 [s]; "
                             f"got {self.window_s}")
        if not 0.0 <= self.min_probability <= 1.0:
            raise ValueError(f"activity_min_probability must be in [0, 1]; "
                             f"got {self.min_probability}")
        if not (math.isfinite(self.hold_s) and self.hold_s >= 0):
            raise ValueError(f"activity_hold must be a finite time >= 0 [s]; got {self.hold_s}")


@dataclass
class _Frame:
    stamp: float
    probabilities: Mapping[str, float]
    posture: str
    holding: tuple = ()     # labels of the things held (the hand term came from them)


@dataclass
class _Held:
    activity: str
    posture: str     # the posture it was read in (the last known one; "unknown": none)
    stamp: float     # [s] the last frame whose window read it
    holding: bool = False   # read from frames showing the same thing held


@dataclass
class _Track:
    place: str
    frames: deque = field(default_factory=deque)
    held: _Held | None = None


def is_detailed(activity: str) -> bool:
    """True for a detailed activity, False for a posture or "unknown"."""
    return activity not in POSTURES and activity != UNKNOWN_POSTURE


def same_posture(a: str, b: str) -> bool:
    """False only when both are postures and differ (an unknown posture contradicts nothing)."""
    return a not in POSTURES or b not in POSTURES or a == b


def held_reading(frames: Sequence[_Frame] | deque) -> str | None:
    """The detailed activity that at least FIRM_FRAMES frames of the window read while holding
    the same thing (the most such frames; None when there is none)."""
    reads: Counter = Counter()
    for frame in frames:
        if frame.holding and frame.probabilities:
            activity = max(frame.probabilities, key=frame.probabilities.__getitem__)
            reads.update((activity, label) for label in set(frame.holding))
    if not reads:
        return None
    (activity, _), count = max(reads.items(), key=lambda kv: (kv[1], kv[0]))
    return activity if count >= FIRM_FRAMES else None


def mean_reading(frames: Sequence[_Frame] | deque, config: ActivityTrackConfig) -> str:
    """The window's detailed activity by its frames' mean probabilities, else the posture most
    frames read, else "unknown" (what nothing held decides)."""
    total: Counter = Counter()
    for frame in frames:
        total.update(frame.probabilities)
    if total:
        ranked = sorted(total.items(), key=lambda kv: (-kv[1], kv[0]))
        (best, score), runner_up = ranked[0], ranked[1][1] if len(ranked) > 1 else 0.0
        # a tie singles out nothing (a chair near the hands spreads over the seated activities)
        if score / len(frames) >= config.min_probability and not math.isclose(score, runner_up):
            return best
    postures = Counter(f.posture for f in frames if f.posture in POSTURES)
    if postures:
        return max(postures.items(), key=lambda kv: (kv[1], kv[0]))[0]
    return UNKNOWN_POSTURE


class ActivityTracks:
    """Per person name: the fused activity of their recent frames."""

    def __init__(self, config: ActivityTrackConfig | None = None) -> None:
        self.config = config or ActivityTrackConfig()
        self._tracks: dict[str, _Track] = {}

    def update(self, name: str, stamp: float, place: str, framewise: str,
               probabilities: Mapping[str, float], posture: str,
               holding: Sequence[str] = ()) -> str:
        """Add one frame of `name` (time [s], place, the frame's own reading; `holding`: the
        labels of the things held, whose hand term it is) -> the activity of their window, else
        the detailed activity kept for them; `framewise` is returned unchanged when fusion is
        off."""
        if self.config.window_s <= 0:
            return framewise
        track = self._tracks.get(name)
        if track is None or track.place != place:
            track = self._tracks[name] = _Track(place)
        frames = track.frames
        while frames and (frames[0].stamp <= stamp - self.config.window_s
                          or frames[0].stamp > stamp):    # old, or a clock that went back
            frames.popleft()
        frames.append(_Frame(stamp, dict(probabilities), posture, tuple(holding)))
        held_now = held_reading(frames)   # the window's activity: what is held, else the mean
        activity = held_now if held_now is not None else mean_reading(frames, self.config)
        if is_detailed(activity):
            firm = held_now == activity
            held = track.held
            if not firm and held is not None and held.holding and held.activity != activity:
                kept = self._kept(track, stamp, posture)   # read from a held thing: it stands
                if kept is not None:
                    return kept
            read_in = held.posture if held is not None and held.activity == activity \
                else UNKNOWN_POSTURE
            track.held = _Held(activity, posture if posture in POSTURES else read_in, stamp,
                               firm or (held is not None and held.activity == activity
                                        and held.holding))
            return activity
        return self._kept(track, stamp, posture) or activity

    def _kept(self, track: _Track, stamp: float, posture: str) -> str | None:
        """The detailed activity kept for the track at `stamp` in `posture`, or None."""
        held = track.held
        if held is None:
            return None
        if not same_posture(held.posture, posture) or not (
                0.0 <= stamp - held.stamp <= self.config.hold_s):
            track.held = None
            return None
        return held.activity
