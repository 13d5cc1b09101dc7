"""Shirt-colour identification: thesis 000 §3.2.3, Eq. 3-6 ... 3-10 and Algorithm 3-1.

Colour layout everywhere: an array of shape (3, 3) = (joint, channel) with joints in the order
of `JOINTS` (COCO-18 1 = neck/chest, 2 = right shoulder, 5 = left shoulder) and channels R, G, B.
A batch of people is (N, 3, 3).
"""
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from numbers import Integral
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from human_db.errors import InvalidColour

class Shirted(Protocol):
    """What ColourIndex.from_humans reads of a person (human_db.model.Human, which imports this
    module)."""

    name: str
    shirt_colour: tuple | None


JOINTS = (1, 2, 5)   # COCO-18 joints whose shirt colour is stored (§3.2.3)
CHANNEL_MAX = 255    # 8-bit RGB
Rgb = Sequence[float] | np.ndarray          # (r, g, b) of one joint
Shirt = Sequence[Sequence[float]] | np.ndarray   # (3, 3): joints 1, 2, 5 x RGB


@dataclass(frozen=True)
class IdentificationConfig:
    threshold: float = 200.0  # mean approximate colour distance below which people match (§5.2.3)
    margin: float = 0.0       # > 0: a runner-up also below threshold and within this of the
                              # closest makes the sighting ambiguous: nobody (ask, never guess)


@dataclass(frozen=True)
class Match:
    name: str
    distance: float  # mean approximate colour distance over joints 1, 2, 5 (Eq. 3-10)


def shirt_colours(value: Any, what: str = "shirt colour") -> npt.NDArray[np.int64]:
    """Validate 9 integers (r1 g1 b1 r2 g2 b2 r5 g5 b5) or 3 x RGB; return a (3, 3) int array.

    Raises InvalidColour naming `what` and the offending value.
    """
    if isinstance(value, str):
        raise InvalidColour(f"{what}: expected 3 joints x RGB, got the text {value!r}")
    try:
        flat = [channel for joint in value for channel in joint] if _nested(value) else list(value)
    except TypeError:
        raise InvalidColour(f"{what}: expected 3 joints x RGB, got {value!r}") from None
    if len(flat) != 3 * len(JOINTS):
        raise InvalidColour(f"{what}: expected 3 joints x RGB = 9 values, got {len(flat)}: "
                            f"{value!r}")
    for channel in flat:
        if isinstance(channel, bool) or not isinstance(channel, Integral | np.integer):
            raise InvalidColour(f"{what}: channel {channel!r} is not an integer in 0-255")
        if not 0 <= int(channel) <= CHANNEL_MAX:
            raise InvalidColour(f"{what}: channel {channel} is outside 0-255")
    return np.array(flat, dtype=np.int64).reshape(len(JOINTS), 3)


def _nested(value: Any) -> bool:
    return len(value) == len(JOINTS) and all(
        hasattr(joint, "__len__") and not isinstance(joint, str | bytes) for joint in value)


def approximate_colour_distance(c1: Rgb, c2: Rgb) -> float:
    """Eq. 3-6 ... 3-10: approximate (red-weighted Euclidean) distance between two RGB colours."""
    r_mean = (c1[0] + c2[0]) / 2                      # Eq. 3-6
    d_r = c1[0] - c2[0]                               # Eq. 3-7
    d_g = c1[1] - c2[1]                               # Eq. 3-8
    d_b = c1[2] - c2[2]                               # Eq. 3-9
    return float(np.sqrt((2 + r_mean / 256) * d_r * d_r + 4 * d_g * d_g
                         + (2 + (255 - r_mean) / 256) * d_b * d_b))   # Eq. 3-10


def mean_shirt_distance(query: Shirt, test: Shirt) -> float:
    """Algorithm 3-1 line 17's mean ΔC: Eq. 3-10 averaged over joints 1, 2 and 5."""
    distances = [approximate_colour_distance(q, t) for q, t in zip(query, test)]
    return sum(distances) / len(distances)


def shirt_distance_matrix(observed: npt.ArrayLike, stored: npt.ArrayLike
                          ) -> npt.NDArray[np.float64]:
    """Eq. 3-6 ... 3-10 averaged over joints, vectorised: (N, 3, 3) x (M, 3, 3) -> (N, M)."""
    a = np.asarray(observed, dtype=np.float64)[:, None, :, :]   # (N, 1, joint, channel)
    b = np.asarray(stored, dtype=np.float64)[None, :, :, :]     # (1, M, joint, channel)
    r_mean = (a[..., 0] + b[..., 0]) / 2
    diff_sq = (a - b) ** 2
    delta = np.sqrt((2 + r_mean / 256) * diff_sq[..., 0] + 4 * diff_sq[..., 1]
                    + (2 + (255 - r_mean) / 256) * diff_sq[..., 2])
    return delta.mean(axis=-1)


def identify_first_below_threshold(observed: Shirt, names: Iterable[str],
                                   stored: Iterable[Shirt], threshold: float) -> str | None:
    """Algorithm 3-1 as the seed writes it: the first stored person whose mean ΔC < threshold."""
    for name, colours in zip(names, stored):
        if mean_shirt_distance(observed, colours) < threshold:
            return name
    return None


def best_matches(distances: npt.ArrayLike, names: Sequence[str], threshold: float,
                 margin: float = 0.0) -> list[Match | None]:
    """Per row of `distances` (N, M): the closest person below threshold and the distance, or None.

    Improves Algorithm 3-1 (which returns the first person below threshold) by returning the
    closest one and its distance. With `margin` > 0 a row whose runner-up is also below the
    threshold and within `margin` of the closest is ambiguous (two people in similar shirts):
    None, so the robot asks instead of guessing.
    """
    distances = np.asarray(distances, dtype=np.float64)
    if distances.shape[1] == 0:
        return [None] * distances.shape[0]
    order = np.argsort(distances, axis=1)
    matches: list[Match | None] = []
    for row, ranked in zip(distances, order):
        best = row[ranked[0]]
        runner_up = row[ranked[1]] if len(ranked) > 1 else np.inf
        ambiguous = margin > 0 and runner_up < threshold and runner_up - best < margin
        matches.append(Match(names[ranked[0]], float(best))
                       if best < threshold and not ambiguous else None)
    return matches


def identifies(observed: npt.ArrayLike, shirts: Sequence[Shirt],
               config: IdentificationConfig) -> bool:
    """True when the sighting's shirt (3, 3) names exactly one of `shirts` [(3, 3)] under
    `config` (below the threshold, not ambiguous)."""
    if len(shirts) == 0:
        return False
    distances = shirt_distance_matrix(np.asarray(observed)[None], np.asarray(shirts))
    return best_matches(distances, [str(i) for i in range(len(shirts))], config.threshold,
                        config.margin)[0] is not None


class ColourIndex:
    """The stored shirt colours as one array, so N observations cost one vectorised pass."""

    def __init__(self, names: Iterable[str], colours: npt.ArrayLike,
                 config: IdentificationConfig = IdentificationConfig()) -> None:
        self.names = list(names)
        self.colours = np.asarray(colours, dtype=np.float64).reshape(len(self.names), 3, 3)
        self.config = config

    @classmethod
    def from_humans(cls, humans: Iterable[Shirted],
                    config: IdentificationConfig = IdentificationConfig()) -> "ColourIndex":
        """The people with a shirt (those not met yet have none and match nobody)."""
        met = [(h.name, h.shirt_colour) for h in humans if h.shirt_colour is not None]
        return cls([name for name, _ in met], [colour for _, colour in met], config)

    def identify_many(self, observed: npt.ArrayLike) -> list[Match | None]:
        """(N, 3, 3) observed colours -> N Matches (or None)."""
        observed = np.asarray(observed, dtype=np.float64).reshape(-1, 3, 3)
        distances = shirt_distance_matrix(observed, self.colours)
        return best_matches(distances, self.names, self.config.threshold, self.config.margin)

    def identify(self, observed: Any) -> Match | None:
        """One observation (9 values or 3 x RGB) -> best Match below threshold, or None."""
        return self.identify_many(shirt_colours(observed, "observed shirt colour")[None])[0]
