"""Doorways as walls (beyond the seed): a scan in which every opening narrower than a corridor
is closed, for the network, the corner counter and the collision guard.

The route oracle's corridors end at a wall even where a door leads into an office behind it, and
doors are not corners. A network that sees its beams go on through a door at a corridor's end
drives into the office (docs/semantic_nav/EVALUATION.md compares the default follower with its
doorways left open). The generated floors'
corridors (1.8-2.4 m, floor_generator) are wider than their doors (0.8-1.1 m), so a door can be
told from a corridor's opening by its width alone.
"""
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from semantic_nav.laser_layer import LaserModel


@dataclass
class DoorConfig:
    """Which openings count as doors."""

    width: float = 1.4       # openings narrower than this are closed; 0: off [m]
    max_range: float = 10.0  # only openings whose near edge is this close [m]
    depth: float = 0.2       # a beam goes through an opening if it ends this far past it [m]


def segment_ranges(p: NDArray[np.float64], q: NDArray[np.float64],
                   angles: NDArray[np.float64]) -> NDArray[np.float64]:
    """Range along each beam angle from the laser to the line through p and q (inf where the
    beam is parallel to it or points away)."""
    d = np.asarray(q, dtype=float) - p
    cos, sin = np.cos(angles), np.sin(angles)
    denominator = cos * d[1] - sin * d[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (p[0] * d[1] - p[1] * d[0]) / denominator
    return np.where(np.isfinite(t) & (t > 0), t, np.inf)


def close_doorways(ranges: np.ndarray, laser: "LaserModel", config: DoorConfig) -> np.ndarray:
    """Raw ranges of `laser` (laser_layer.LaserModel) with every beam that goes through an
    opening narrower than `config.width` cut at the opening, as if a wall stood there; the
    input is not changed, and with width 0 it is returned as is.

    An opening starts after a valid return p_i whose next beam reaches `depth` further (or has
    no return) and p_i is within `max_range`. It is closed by the first later valid return p_j
    within `width` of p_i, if every beam between them ends `depth` or more beyond the segment
    p_i p_j or has no return. A corridor's side opening is never closed: past its near corner
    the beams run on along the opening's far side, a corridor's width or more from p_i."""
    if config.width <= 0.0:
        return ranges
    out = np.array(ranges, dtype=float)
    angles = laser.angle_min + laser.angle_increment * np.arange(out.size)
    valid = np.isfinite(out) & (out >= laser.range_min) & (out < laser.range_max)
    reach = np.where(valid, out, np.inf)
    xy = np.column_stack((np.cos(angles), np.sin(angles))) * np.where(valid, out, 0.0)[:, None]
    starts = np.flatnonzero(valid[:-1] & (reach[:-1] < config.max_range)
                            & (reach[1:] > reach[:-1] + config.depth))
    returns = np.flatnonzero(valid)
    for i in starts:
        # a return within `width` of p_i is at most asin(width / r_i) away in bearing
        span = np.arcsin(min(1.0, config.width / reach[i])) if reach[i] > config.width else np.pi
        last = i + int(span / laser.angle_increment) + 1
        later = returns[np.searchsorted(returns, i + 2):np.searchsorted(returns, last, "right")]
        near = later[np.hypot(*(xy[later] - xy[i]).T) < config.width]
        if len(near) == 0:
            continue
        j = near[0]
        cut = segment_ranges(xy[i], xy[j], angles[i + 1:j])
        if np.all(reach[i + 1:j] >= cut + config.depth):
            out[i + 1:j] = cut
    return out


def cut_beam_ends(ranges: np.ndarray, closed: np.ndarray,
                  laser: "LaserModel") -> NDArray[np.float64]:
    """(M, 2) ends, in the laser frame, of the beams that close_doorways cut: where `closed`
    reads shorter than the raw `ranges` (NaN readings are never cut)."""
    if closed is ranges:
        return np.zeros((0, 2))
    raw = np.nan_to_num(np.asarray(ranges, dtype=float), nan=np.inf)
    cut = np.flatnonzero(closed < raw)
    angles = laser.angle_min + laser.angle_increment * cut
    return closed[cut, None] * np.column_stack((np.cos(angles), np.sin(angles)))
