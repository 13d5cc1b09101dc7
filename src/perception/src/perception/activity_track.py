"""A person's activity over the last few frames (beyond the seed; thesis 000 Sec. 3.2.4 reads
each frame alone).

A real detector misses a cup or a fork in most frames (docs/perception/camera_calibration.md),
so a framewise reading flickers between the detailed activity and the posture. Per identified
person, the frames of the last `window_s` seconds at the same place are fused: the mean of each
detailed activity's probability over those frames (a frame without a score adds 0) decides when
it reaches `min_probability`; else the posture most frames read; else "unknown". A person seen at
another place starts a new window (they moved, so they may do something else).

`window_s` 0 is the seed's framewise reading.
"""
import math
from collections import Counter, deque
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from perception.activity import POSTURES, UNKNOWN_POSTURE


@dataclass
class ActivityTrackConfig:
    window_s: float = 8.0          # [s] frames of a person this recent are fused (0: framewise)
    min_probability: float = 0.2   # [-] mean P(a) over the window for a detailed activity

    def __post_init__(self) -> None:
        if not (math.isfinite(self.window_s) and self.window_s >= 0):
            raise ValueError(f"activity_window must be a finite time >= 0 [s]; "
                             f"got {self.window_s}")
        if not 0.0 <= self.min_probability <= 1.0:
            raise ValueError(f"activity_min_probability must be in [0, 1]; "
                             f"got {self.min_probability}")


@dataclass
class _Frame:
    stamp: float
    probabilities: Mapping[str, float]
    posture: str


@dataclass
class _Track:
    place: str
    frames: deque = field(default_factory=deque)


def fuse(frames: Sequence[_Frame] | deque, config: ActivityTrackConfig) -> str:
    """The activity of a window of frames (the rule of the module docstring)."""
    total: Counter = Counter()
    for frame in frames:
        total.update(frame.probabilities)
    if total:
        best, score = max(total.items(), key=lambda kv: (kv[1], kv[0]))
        if score / len(frames) >= config.min_probability:
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
               probabilities: Mapping[str, float], posture: str) -> str:
        """Add one frame of `name` (time [s], place, the frame's own reading) -> the activity
        of their window; `framewise` is returned unchanged when fusion is off."""
        if self.config.window_s <= 0:
            return framewise
        track = self._tracks.get(name)
        if track is None or track.place != place:
            track = self._tracks[name] = _Track(place)
        frames = track.frames
        while frames and (frames[0].stamp <= stamp - self.config.window_s
                          or frames[0].stamp > stamp):    # old, or a clock that went back
            frames.popleft()
        frames.append(_Frame(stamp, dict(probabilities), posture))
        return fuse(frames, self.config)
