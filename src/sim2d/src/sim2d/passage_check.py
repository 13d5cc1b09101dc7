"""People never block the home: a person's resting pose must leave every route between places open.

The robot's centre fits on a cell of the world's occupancy grid when the cell's clearance is at
least the robot's radius (the simulator's own collision test); those cells are the free space. A
person is a disc of `person_radius`: it closes every cell whose centre lies closer than
person_radius + robot_radius to the person. A pose blocks the home when two places of the
semantic graph whose poses are joined through free space without the person are no longer joined
with them (8-connected components, as the move_base mock's A* moves). Doors count as open.
"""
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from scipy import ndimage

from floorplan.occupancy_map import OccupancyMap
from floorplan.semantic_graph import Place
from sim2d.people import Person
from sim2d.raycast import CLEARANCE_LOSS, distance_transform

EIGHT_CONNECTED = np.ones((3, 3), dtype=bool)


@dataclass
class PassageConfig:
    """What a resting person takes on the floor."""

    # [m] disc of a resting person: the 0.2 m disc the lasers see (people.Person.radius) plus
    # 0.05 m for elbows, knees and a chair pushed back
    person_radius: float = 0.25


@dataclass
class Blockage:
    """A pose that cuts places apart: the pairs of place names it disconnects."""

    pose: tuple                 # (x, y) [m]
    pairs: list                 # [(name, name)], graph edges first, then nearest to the pose
    covered: list               # names of the places whose own pose the person closes


def robot_free_space(grid: OccupancyMap, robot_radius: float) -> npt.NDArray[np.bool_]:
    """Cells where a robot of `robot_radius` [m] fits: clearance >= radius (World's own test)."""
    dist = distance_transform(grid.occupied_mask())
    clearance = np.maximum(dist - CLEARANCE_LOSS, 0.0) * grid.resolution * (dist > 0)
    return clearance >= robot_radius


def disc_mask(grid: OccupancyMap, x: float, y: float, radius: float) -> npt.NDArray[np.bool_]:
    """Cells whose centres lie closer than `radius` [m] to (x, y)."""
    xs, _ = grid.cell_to_world(0, np.arange(grid.width))
    _, ys = grid.cell_to_world(np.arange(grid.height), 0)
    return (xs[None, :] - x) ** 2 + (ys[:, None] - y) ** 2 < radius ** 2


class PassageCheck:
    """Connectivity of the graph's places on one map for one robot radius, probed pose by pose."""

    def __init__(self, grid: OccupancyMap, places: Iterable[Place],
                 edges: Iterable[Sequence[str]], robot_radius: float,
                 config: PassageConfig | None = None) -> None:
        """grid: OccupancyMap; places: [Place]; edges: [(name, name)]; robot_radius [m]."""
        self.grid = grid
        self.config = config or PassageConfig()
        self.robot_radius = float(robot_radius)
        self.free = robot_free_space(grid, self.robot_radius)
        self.labels, _ = ndimage.label(self.free, structure=EIGHT_CONNECTED)
        self.places = [p for p in places if self._label_at(self.labels, p.pose) > 0]
        self.edges = {frozenset(e) for e in edges}

    def _label_at(self, labels: np.ndarray, pose: Sequence[float]) -> int:
        row, col = self.grid.world_to_cell(pose[0], pose[1])
        return int(labels[row, col]) if self.grid.inside(row, col) else 0

    def joined_pairs(self, labels: np.ndarray) -> set[tuple[str, str]]:
        """Pairs of place names whose poses share a connected component of `labels`."""
        ids = [self._label_at(labels, p.pose) for p in self.places]
        return {(a.name, b.name)
                for i, a in enumerate(self.places) for j, b in enumerate(self.places)
                if i < j and ids[i] > 0 and ids[i] == ids[j]}

    def blockage(self, x: float, y: float) -> Blockage | None:
        """The Blockage of a person resting at (x, y) [m], or None if every route stays open."""
        reach = self.config.person_radius + self.robot_radius
        person = disc_mask(self.grid, x, y, reach)
        if not (person & self.free).any():
            return None
        labels, _ = ndimage.label(self.free & ~person, structure=EIGHT_CONNECTED)
        cut = self.joined_pairs(self.labels) - self.joined_pairs(labels)
        if not cut:
            return None
        distance = {p.name: math.hypot(p.pose[0] - x, p.pose[1] - y) for p in self.places}

        def relevance(pair: tuple[str, str]) -> tuple[bool, float, tuple[str, str]]:
            return (frozenset(pair) not in self.edges, distance[pair[0]] + distance[pair[1]], pair)

        covered = [p.name for p in self.places if not self._label_at(labels, p.pose)]
        return Blockage((x, y), sorted(cut, key=relevance), covered)


def resting_poses(person: Person) -> list[tuple[str, tuple]]:
    """(label, pose) of a person's start pose and of every schedule pose (via points pass)."""
    return [("pose", person.pose)] + [(f"schedule pose at {entry.time:g} s", entry.pose)
                                      for entry in person.schedule]


def blockage_message(name: str, label: str, blockage: Blockage, check: PassageCheck) -> str:
    """The error for a blocking pose: who, where, which two places it cuts apart and why."""
    (a, b), others = blockage.pairs[0], len(blockage.pairs) - 1
    x, y = blockage.pose
    person_radius, robot_radius = check.config.person_radius, check.robot_radius
    on = next((n for n in (a, b) if n in blockage.covered), None)
    if on is None:
        what = f"blocks the only way between places {a!r} and {b!r}"
    else:
        what = (f"stands on place {on!r} (within {person_radius + robot_radius:.2f} m of its "
                f"pose, the robot's goal there) and so cuts places {a!r} and {b!r} apart")
    more = f" (and {others} other pair(s) of places)" if others else ""
    return (f"person {name!r} {label} ({x:.2f}, {y:.2f}) {what}{more}: with a person's radius of "
            f"{person_radius:.2f} m and the robot's of {robot_radius:.2f} m no way past is left; "
            f"put the pose in a room, clear of doorways, corridors and place poses "
            f"(config/worlds/README.md, 'People never block the home')")
