"""Where the robot last saw the things that stay put (beyond the seed; thesis 000 Sec. 3.2.4
reads each frame's detections alone).

A real detector misses a laptop or an umbrella across a room in most frames
(docs/perception/camera_calibration.md: an object 50 px across is missed four times in five).
A person working at the laptop the robot saw there a minute ago is still at that laptop. So the
robot keeps a map of what it detected where, and a frame that misses a fixed object offers the
remembered one to the activity reading of the people within reach of it.

The map is made of spots: each detection with a box in the map votes for its label at the spot
whose centre is within `merge_m` of its own (else it opens a spot). A spot stands for the label
with the most votes once that label has `confirm` votes and at least `share` of them: a false
detection is a one-off at a random place, and a confused label (a dining table called a mouse
now and then) loses the vote to the true one at the same spot. Only spots of the fixed classes
that carry an activity in the hands (`FIXED_CLASSES`: a computer, the fridge, what is left by
the front door) are recalled; what people hold (a cup, a fork, a book, a phone) leaves with them
and is never offered. A remembered object has no box in the image, so it counts only for the
3-D hand test (Algorithm 3-2's O_h with the joints in the map), not for the eyesight or the
support tests. A spot with no detection for `keep_s` is forgotten, as is the oldest one beyond
`max_spots`.

`keep_s` 0 is the seed's reading: each frame's detections alone.
"""
import math
from collections import Counter
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from perception.activity import SeenObject

# COCO classes (the detector's names) that stay where they are put in a home and carry an
# activity in the affordance table's hands (config/affordances.yaml).
FIXED_CLASSES = frozenset({"laptop", "keyboard", "mouse", "refrigerator", "umbrella",
                           "backpack", "handbag", "suitcase"})
MOVING_CLASSES = frozenset({"person"})   # never a spot: people walk off


@dataclass
class ObjectMemoryConfig:
    keep_s: float = 1800.0    # [s] a spot with no detection this long is forgotten (0: off)
    merge_m: float = 0.3      # [m] a detection this close to a spot's centre votes there
    confirm: int = 3          # votes a label needs before its spot is recalled
    share: float = 0.5        # [-] and its share of the spot's votes
    max_spots: int = 500      # the oldest beyond this many are forgotten
    classes: frozenset = field(default_factory=lambda: FIXED_CLASSES)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.keep_s) and self.keep_s >= 0):
            raise ValueError(f"object_memory must be a finite time >= 0 [s]; got {self.keep_s}")
        if not (math.isfinite(self.merge_m) and self.merge_m > 0):
            raise ValueError(f"object_memory_merge must be a distance > 0 [m]; "
                             f"got {self.merge_m}")
        if self.confirm < 1:
            raise ValueError(f"object_memory_confirm must be >= 1; got {self.confirm}")
        if not 0.0 < self.share <= 1.0:
            raise ValueError(f"object_memory_share must be in (0, 1]; got {self.share}")
        if self.max_spots < 1:
            raise ValueError(f"object_memory_max must be >= 1; got {self.max_spots}")


@dataclass
class Spot:
    centre: np.ndarray     # (3,) [m] of the last detection's box
    extent: tuple          # (low, high) corners (3,) [m] of the last box of the leading label
    votes: Counter         # label -> detections here
    confidence: float      # P(o) of the leading label's last detection
    stamp: float           # [s] of the last detection here
    stands_for: str = ""   # the confirmed fixed label it offers ("": none)

    def leader(self) -> tuple[str, int]:
        """(label, votes) with the most votes; ties go to the label first in sorted order."""
        return min(self.votes.items(), key=lambda kv: (-kv[1], kv[0]))


class ObjectMemory:
    """Spots of the map where the robot detected objects, with their labels' votes."""

    def __init__(self, config: ObjectMemoryConfig | None = None) -> None:
        self.config = config or ObjectMemoryConfig()
        self.spots: list[Spot] = []

    def update(self, stamp: float, detected: Iterable[tuple[str, float, tuple | None]]) -> None:
        """Add one frame's detections (label, confidence P(o), map extent or None) at `stamp` [s]
        (each votes at the spot nearest it before the frame, else opens one); forget the spots
        not seen for keep_s."""
        if self.config.keep_s <= 0:
            return
        frame = [(label, float(confidence), extent) for label, confidence, extent in detected
                 if extent is not None and label not in MOVING_CLASSES]
        if frame:
            centres = np.array([(np.asarray(e[0], dtype=float) + np.asarray(e[1], dtype=float))
                                / 2.0 for _, _, e in frame])
            known = list(self.spots)
            if known:
                d = np.linalg.norm(centres[:, None, :]
                                   - np.array([s.centre for s in known])[None, :, :], axis=2)
                nearest = d.argmin(axis=1)
                close = d[np.arange(len(frame)), nearest] <= self.config.merge_m
            for i, (label, confidence, extent) in enumerate(frame):
                if known and close[i]:
                    spot = known[nearest[i]]
                else:
                    spot = Spot(centres[i], extent, Counter(), confidence, stamp)
                    self.spots.append(spot)
                self._vote(spot, label, confidence, extent, centres[i], stamp)
        self.spots = [s for s in self.spots if 0.0 <= stamp - s.stamp <= self.config.keep_s]
        if len(self.spots) > self.config.max_spots:
            self.spots = sorted(self.spots, key=lambda s: s.stamp)[-self.config.max_spots:]

    def recall(self, stamp: float) -> list[SeenObject]:
        """The confirmed fixed objects of the spots with no detection at `stamp`, as SeenObject
        without an image box (centre NaN), with their last confidence and map extent."""
        return [SeenObject(spot.stands_for, spot.confidence, math.nan, math.nan,
                           extent=spot.extent)
                for spot in self.spots
                if spot.stands_for and spot.stamp < stamp
                and stamp - spot.stamp <= self.config.keep_s]

    def _vote(self, spot: Spot, label: str, confidence: float, extent: tuple,
              centre: np.ndarray, stamp: float) -> None:
        spot.votes[label] += 1
        spot.centre, spot.stamp = centre, stamp
        leader, votes = spot.leader()
        if leader == label:
            spot.extent, spot.confidence = extent, confidence
        confirmed = (votes >= self.config.confirm
                     and votes >= self.config.share * sum(spot.votes.values()))
        spot.stands_for = leader if confirmed and leader in self.config.classes else ""
