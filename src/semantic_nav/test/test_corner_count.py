"""Corners counted so far from the side beams (corner_count): the network's count input."""
import math

import numpy as np
import pytest

from semantic_nav.corner_count import (CornerCountConfig, CornerCounter, count_inputs,
                                       one_hot_counts, side_ranges)


def test_side_ranges_take_the_shortest_beam_round_each_side():
    # 9 beams every 45° from -180°: +90° is beam 6, -90° is beam 2
    ranges = np.full((1, 9), 5.0)
    ranges[0, 6], ranges[0, 2] = 1.5, 2.0
    sides = side_ranges(ranges, -math.pi, math.pi / 4, 5.0)
    assert sides.tolist() == [[1.5, 2.0]]
    with pytest.raises(ValueError, match="no beam within 5.0° of"):
        side_ranges(np.ones((1, 2)), 0.0, 0.1, 5.0)      # 0° … 5.7°: no side beam


def _travel(commands, rate):
    """Distance [m] driven before each step."""
    return np.concatenate([[0.0], np.cumsum(np.abs(commands[:, 0]) / rate)[:-1]])


def _corridor(openings, length=20.0, speed=0.5, rate=10.0):
    """A drive at `speed` along a corridor with walls 1 m to each side; `openings`: (side
    column, from [m], to [m]) where that side reads 4 m."""
    commands = np.tile([speed, 0.0], (int(length / speed * rate), 1)).astype(np.float32)
    s = _travel(commands, rate)
    sides = np.ones((len(commands), 2), np.float32)
    for column, first, last in openings:
        sides[(s >= first) & (s <= last), column] = 4.0
    return sides, commands


def test_each_corner_counts_once_it_is_min_width_long_doors_never():
    """Left branch 3-5 m, a 0.8 m door on the right at 7 m, a crossroad 10-12 m (its right side
    opens a little later: the same corner), a right branch 15-17 m: the count rises 1 m
    (min_width) into each corner, within a step of 5 cm."""
    sides, commands = _corridor([(0, 3.0, 5.0), (1, 7.0, 7.8), (0, 10.0, 12.0),
                                 (1, 10.5, 12.5), (1, 15.0, 17.0)])
    counts = count_inputs(sides, commands, 10.0, CornerCountConfig())
    s = _travel(commands, 10.0)
    rises = s[np.flatnonzero(np.diff(counts)) + 1]
    assert counts[0] == 0 and np.all(np.diff(counts) >= 0) and counts[-1] == 3
    assert rises == pytest.approx([4.0, 11.0, 16.0], abs=0.11)


def test_counts_saturate_at_max_count():
    sides, commands = _corridor([(0, 2.0, 3.5), (1, 5.0, 6.5), (0, 8.0, 9.5), (1, 11.0, 12.5),
                                 (0, 14.0, 15.5)])
    counts = count_inputs(sides, commands, 10.0, CornerCountConfig(max_count=3))
    assert counts.max() == 3 and sorted(set(counts.tolist())) == [0, 1, 2, 3]


def test_online_counter_joins_the_other_side_of_a_crossroad_and_resets():
    counter = CornerCounter(CornerCountConfig(min_width=1.0))
    seen = []
    for step in range(80):               # 0.1 m per step: left open 1-4 m, right open 3-6 m
        sides = (4.0 if 10 <= step < 40 else 1.0, 4.0 if 30 <= step < 60 else 1.0)
        seen.append(counter.observe(sides))
        counter.advance(-0.1)            # reversing drives as far
    assert seen[19] == 0 and seen[20] == 1 and seen[-1] == 1
    counter.reset()
    assert counter.observe((1.0, 1.0)) == 0 and counter.travel == 0.0


def _online_counts(sides_per_step, side):
    counter = CornerCounter(CornerCountConfig(min_width=1.0))
    counter.reset(side=side)
    seen = []
    for sides in sides_per_step:
        seen.append(counter.observe(sides))
        counter.advance(0.1)
    return seen


def test_one_side_counts_only_its_branches_each_once():
    """Branches alternate left 2-4 m, right 6-8 m, left 10-12 m, right 14-16 m, then a
    crossroad 18-20 m; 0.1 m per step. Over both sides the second right branch is the fourth
    corner; counting the right side only it is the second."""
    def side(step, spans):
        return 4.0 if any(a <= step * 0.1 < b for a, b in spans) else 1.0

    left, right = [(2, 4), (10, 12), (18, 20)], [(6, 8), (14, 16), (18, 20)]
    steps = [(side(k, left), side(k, right)) for k in range(220)]
    both = _online_counts(steps, None)
    rights = _online_counts(steps, "right")
    lefts = _online_counts(steps, "left")
    assert both[150] == 3 and both[-1] == 3          # capped: 5 corners
    assert [rights[k] for k in (69, 71, 149, 151, 189, 191)] == [0, 1, 1, 2, 2, 3]
    assert [lefts[k] for k in (29, 31, 109, 111, 189, 191)] == [0, 1, 1, 2, 2, 3]
    with pytest.raises(ValueError, match="side must be None, 'left' or 'right', got 'up'"):
        CornerCounter().reset(side="up")


def test_one_hot_counts():
    assert one_hot_counts([0, 3, 1], 3).tolist() == [[1, 0, 0, 0], [0, 0, 0, 1], [0, 1, 0, 0]]
