"""Corners counted so far from the side beams of a laser (beyond the seed; no ROS).

The network's optional `counts` input (network.py): how many corners the robot has reached in
the current simple instruction, counted over both sides as the route oracle counts them for "the
second / third corner" (route_oracle, classes 5-8). A network left to count on its own counts
only the openings on its turning side and turns one corner late wherever a corner on the other
side comes first (EVALUATION.md, "Corners on the other side"); here the counting is done outside
the network, the same way in training (over the records) and in control (over live scans).

The records keep no poses, so the corners come from the scans: the shortest range in a few
degrees round each side (±90°) is "open" when it reaches `open_range` (a branch leads on past
the wall line); an opening that stays open for `min_width` metres of travel (integrated from v)
is a branch (narrower: a door); an opening that overlaps one already counted on the other side
is the same corner (a crossroad), as route_oracle.group_corners.

Counting one side ("take the second right": instruction_classes.COUNT_SIDE): the counter counts
the branches on that side only, each opening once, and the openings on the other side not at
all, as route_oracle.nth_branch_on_side. The follower passes N - 1 counted corners (or that
side's branches) before it gives the network the side's first turn
(follower.DirectionFollower._turn_when_passed; `opening_beside` tells when the last is behind).
"""
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from semantic_nav.instruction_classes import COUNTINGS


@dataclass
class CornerCountConfig:
    """What a corner looks like from the side beams."""

    open_range: float = 2.5     # side range from which a side counts as open [m]
    window_deg: float = 5.0     # half width of the side windows round ±90° [deg]
    min_width: float = 1.0      # narrower openings are doors [m] (route_oracle: 1.3 m on the
    #                             centre line; a window of beams sees an opening narrower)
    max_count: int = 3          # counts above are "3 or more" (classes 0 … max_count) [1]


def side_ranges(ranges: ArrayLike, angle_min: float, angle_increment: float,
                window_deg: float) -> NDArray[np.float32]:
    """Raw scans (N, beams) -> (N, 2) shortest range within ±window_deg of +90° (left) and
    -90° (right), laser angles counter-clockwise from the front [rad]."""
    ranges = np.asarray(ranges, dtype=np.float64)
    angles = angle_min + angle_increment * np.arange(ranges.shape[1])
    out = np.empty((len(ranges), 2), np.float32)
    for column, centre in enumerate((np.pi / 2, -np.pi / 2)):
        beams = np.abs(angles - centre) <= np.radians(window_deg) + 1e-9
        if not beams.any():
            raise ValueError(f"the laser covers no beam within {window_deg}° of "
                             f"{np.degrees(centre):+.0f}°")
        out[:, column] = np.nanmin(ranges[:, beams], axis=1)
    return out


SIDE_COLUMNS = {"left": 0, "right": 1}   # columns of side_ranges


class CornerCounter:
    """Corners counted step by step: a corner counts once one of its openings has run for
    min_width; an opening that overlaps an opening already counted on the other side belongs to
    the same corner. Causal, so training (count_inputs over the records) and control
    (follower, live scans) see the same counts."""

    def __init__(self, config: CornerCountConfig | None = None) -> None:
        self.config = config or CornerCountConfig()
        self.reset()

    def reset(self, side: str | None = None) -> None:
        """A new simple instruction: nothing counted, no travel; `side` "left" / "right" counts
        the branches on that side only, None every corner over both sides."""
        if side not in (None, *SIDE_COLUMNS):
            raise ValueError(f"side must be None, 'left' or 'right', got {side!r}")
        self.side = side
        self.travel = 0.0
        self.count = 0
        # travel where each side's current opening began
        self.run_start: list[float | None] = [None, None]
        self.counted = [False, False]     # that opening belongs to a counted corner
        self.corner_end = -np.inf         # travel where the last counted opening closed

    def observe(self, sides: Sequence[float] | np.ndarray) -> int:
        """Side ranges (left, right) [m] at this step -> corners counted so far (capped at
        max_count)."""
        config = self.config
        for side in range(2):
            if self.side is not None and side != SIDE_COLUMNS[self.side]:
                continue                      # one side counted: the other is not looked at
            is_open = bool(sides[side] >= config.open_range)
            start = self.run_start[side]
            if not is_open:
                if start is not None and self.counted[side]:
                    self.corner_end = max(self.corner_end, self.travel)
                self.run_start[side] = None
                continue
            if start is None:
                start = self.run_start[side] = self.travel
                self.counted[side] = False
            if not self.counted[side] and self.travel - start >= config.min_width:
                self.counted[side] = True
                other = 1 - side
                same = self.side is None and (
                    (self.run_start[other] is not None and self.counted[other])
                    or start <= self.corner_end)
                self.count += 0 if same else 1
        return min(self.count, config.max_count)

    def opening_beside(self) -> bool:
        """Whether an opening runs beside the robot now on a counted side (one side: that
        side; else either)."""
        sides = [SIDE_COLUMNS[self.side]] if self.side is not None else [0, 1]
        return any(self.run_start[side] is not None for side in sides)

    def advance(self, distance: float) -> None:
        """The robot drove `distance` [m] (its sign is ignored) before the next step."""
        self.travel += abs(float(distance))


def count_inputs(sides: Iterable[Sequence[float] | np.ndarray],
                 commands: Sequence[Sequence[float]] | np.ndarray, rate: float,
                 config: CornerCountConfig | None, side: str | None = None) -> NDArray[np.int64]:
    """The `counts` input (or count target) of a recorded sequence: CornerCounter over its side
    ranges (`side`: that side's branches only, CornerCounter.reset), travel from the expert's v
    -> (N,) int64."""
    counter = CornerCounter(config)
    counter.reset(side=side)
    counts = np.zeros(len(commands), np.int64)
    for step, (row, v) in enumerate(zip(sides, np.asarray(commands, dtype=np.float64)[:, 0])):
        counts[step] = counter.observe(row)
        counter.advance(v / rate)
    return counts


def one_hot_counts(counts: ArrayLike, max_count: int) -> NDArray[np.float32]:

    """(N,) counts -> (N, max_count + 1) float32 one-hot rows."""
    return np.eye(max_count + 1, dtype=np.float32)[np.asarray(counts)]


def one_hot_counting(mode: str) -> NDArray[np.float32]:
    """A counting mode (instruction_classes.COUNTINGS) -> the `counting` input row of a network
    that counts itself (network.FUSED_EXTRAS)."""
    if mode not in COUNTINGS:
        raise ValueError(f"counting mode must be one of {COUNTINGS}, got {mode!r}")
    return np.eye(len(COUNTINGS), dtype=np.float32)[COUNTINGS.index(mode)]
