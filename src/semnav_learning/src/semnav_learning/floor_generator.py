"""Random office floors for training (beyond the seed: thesis 002 trained on a handful of real
floors; a network that has seen few buildings learns their walls, not corridors).

A floor is a grid of axis-aligned corridors (1.8-2.4 m wide) that cross, meet in T-junctions and
L corners and end in dead ends, rooms filling the space between them (split into offices by
partition walls) and doors (0.8-1.1 m, narrower than the route oracle's 1.3 m branches) from the
offices into the corridors, some furniture. Optionally (side_branch_rate) short one-sided branches
leave corridors between the crossings (staggered corners), and (end_door_probability) doors open
straight ahead at a corridor's end: in a dead end's wall, in the outer wall of an L corner or in
the far wall of a T-junction (the hand-made test floors have them; the walk ends before them).
The result is an OccupancyMap carved cell by cell: everything starts occupied, corridors and rooms
are cleared, the walls are what remains.
Coordinates in metres, origin at the map's lower-left corner.
"""
from dataclasses import dataclass

import cv2
import numpy as np

from floorplan.blueprint import rect_cells
from floorplan.occupancy_map import FREE, OCCUPIED, OccupancyMap


@dataclass
class FloorGeneratorConfig:
    """Ranges the random floors are drawn from (the hand-made office floors are inside them)."""

    width: tuple = (24.0, 40.0)           # map size along x [m]
    depth: tuple = (18.0, 30.0)           # map size along y [m]
    corridor_width: tuple = (1.8, 2.4)    # [m]
    corridors: tuple = (2, 4)             # corridors per direction (inclusive) [1]
    spacing: float = 6.0                  # min distance of parallel corridor centre lines [m]
    overhang: tuple = (2.5, 12.0)         # a corridor runs on past its last crossing [m]
    flush_probability: float = 0.35       # ... or ends there (an L corner or a T) [1]
    end_gap: float = 2.5                  # a dead end stops this far before the next crossing
    #                                       corridor line's wall, or runs into it [m]
    wall: float = 0.2                     # wall thickness [m]
    room_size: tuple = (3.0, 7.0)         # offices are split when longer than this [m]
    door_width: tuple = (0.8, 1.1)        # [m]
    door_gap: tuple = (1.5, 6.0)          # along a corridor wall between door candidates [m]
    door_probability: float = 0.6         # a candidate place gets a door [1]
    junction_clearance: float = 0.8       # no door this close to a corridor mouth [m]
    furniture_probability: float = 0.5    # per office [1]
    side_branch_rate: float = 0.0         # one-sided T branches per metre of corridor, off
    #                                       the crossings (staggered corners) [1/m]
    side_branch_length: tuple = (3.0, 8.0)  # [m]
    side_branch_gap: float = 1.5          # wall left between a side branch and other mouths [m]
    end_door_probability: float = 0.0     # a corridor end with an office behind it gets a door
    #                                       in its end wall, straight ahead [1]
    resolution: float = 0.05              # [m/cell]


@dataclass
class Corridor:
    """An axis-aligned corridor: centre line from `start` to `end` along x (horizontal) or y."""

    horizontal: bool
    centre: float    # y of a horizontal corridor, x of a vertical one [m]
    start: float     # [m]
    end: float       # [m]
    width: float     # [m]

    def rect(self):
        """[x0, y0, x1, y1] of the free corridor."""
        half = self.width / 2.0
        if self.horizontal:
            return [self.start, self.centre - half, self.end, self.centre + half]
        return [self.centre - half, self.start, self.centre + half, self.end]


def _centres(rng, extent, count, config):
    """Up to `count` centre lines across `extent`, at least `spacing` apart and from the edges."""
    low, high = config.spacing / 2.0 + 1.0, extent - config.spacing / 2.0 - 1.0
    centres = []
    for _ in range(50 * count):
        if len(centres) == count:
            break
        c = float(rng.uniform(low, high))
        if all(abs(c - other) >= config.spacing for other in centres):
            centres.append(c)
    return sorted(centres)


def _end(rng, lines, widths, index, direction, extent, config):
    """Where a corridor ends beyond the crossing line `index` (direction -1: low end, +1: high
    end): flush with that line's outer wall (an L corner or a T) or running on towards the map
    edge or the next line (a dead end), at least end_gap short of the next line's wall."""
    centre, half = lines[index], widths[index] / 2.0
    flush = centre + direction * half
    neighbour = index + direction
    if 0 <= neighbour < len(lines):
        room = abs(lines[neighbour] - centre) - widths[neighbour] / 2.0 - half - config.end_gap
    else:
        room = (extent - centre if direction > 0 else centre) - half - config.wall
    if rng.random() < config.flush_probability or room < config.overhang[0]:
        return flush
    return flush + direction * float(rng.uniform(config.overhang[0],
                                                 min(config.overhang[1], room)))


def random_corridors(rng, width, depth, config):
    """Horizontal corridors over random runs of the vertical lines, then vertical corridors over
    runs of the horizontal corridors that reach them: every corridor meets another one."""
    ys = _centres(rng, depth, int(rng.integers(config.corridors[0], config.corridors[1] + 1)),
                  config)
    xs = _centres(rng, width, int(rng.integers(config.corridors[0], config.corridors[1] + 1)),
                  config)
    wy = [float(rng.uniform(*config.corridor_width)) for _ in ys]
    wx = [float(rng.uniform(*config.corridor_width)) for _ in xs]
    corridors, runs = [], []
    for y, w in zip(ys, wy):
        a = 0 if rng.random() < 0.6 else int(rng.integers(len(xs)))
        b = len(xs) - 1 if rng.random() < 0.6 else int(rng.integers(a, len(xs)))
        start = _end(rng, xs, wx, a, -1, width, config)
        end = _end(rng, xs, wx, b, 1, width, config)
        corridors.append(Corridor(True, y, start, end, w))
        runs.append((start, end))
    for x, w in zip(xs, wx):
        reached = [j for j, (start, end) in enumerate(runs) if start <= x - w / 2 and
                   x + w / 2 <= end]
        if not reached:
            continue
        j = int(rng.choice(reached))
        a = b = j
        while a - 1 in reached and rng.random() < 0.7:
            a -= 1
        while b + 1 in reached and rng.random() < 0.7:
            b += 1
        start = _end(rng, ys, wy, a, -1, depth, config)
        end = _end(rng, ys, wy, b, 1, depth, config)
        corridors.append(Corridor(False, x, start, end, w))
    return corridors


def _mouths(corridor, corridors):
    """(low, high) spans along `corridor` where perpendicular corridors meet or cross it."""
    spans = []
    for other in corridors:
        if other.horizontal == corridor.horizontal:
            continue
        if other.start <= corridor.centre + corridor.width / 2.0 and \
                corridor.centre - corridor.width / 2.0 <= other.end:
            spans.append((other.centre - other.width / 2.0, other.centre + other.width / 2.0))
    return spans


def side_branches(rng, corridors, width, depth, config):
    """Beyond crossings and corridor ends: short corridors leaving one side of a corridor (a T
    with the stem on one side only) at random places at least `side_branch_gap` of wall from
    every other mouth, so a walk meets staggered corners, a left one soon after a right one."""
    branches = []
    for corridor in corridors:
        count = int(rng.poisson(config.side_branch_rate * (corridor.end - corridor.start)))
        for _ in range(count):
            w = float(rng.uniform(*config.corridor_width))
            if corridor.end - corridor.start < 3.0 * w:
                continue
            position = float(rng.uniform(corridor.start + w, corridor.end - w))
            spans = _mouths(corridor, corridors + branches)
            if any(low - config.side_branch_gap < position + w / 2.0 and
                   position - w / 2.0 < high + config.side_branch_gap for low, high in spans):
                continue
            side = 1.0 if rng.random() < 0.5 else -1.0
            wall = corridor.centre + side * corridor.width / 2.0
            extent = depth if corridor.horizontal else width
            limit = extent - 1.0 if side > 0 else 1.0        # stay off the outer wall
            tip = wall + side * float(rng.uniform(*config.side_branch_length))
            tip = min(tip, limit) if side > 0 else max(tip, limit)
            if abs(tip - wall) < config.side_branch_length[0]:
                continue
            branches.append(Corridor(not corridor.horizontal, position, min(wall, tip),
                                     max(wall, tip), w))
    return branches


def _partition(rooms, rng, config, res):
    """Split the room space by full-length partition walls every room_size along x and y."""
    h, w = rooms.shape
    wall = max(1, int(round(config.wall / res)))
    for axis, extent in ((1, w), (0, h)):
        position = float(rng.uniform(*config.room_size))
        while position < extent * res - config.room_size[0]:
            index = int(position / res)
            if axis == 1:
                rooms[:, index:index + wall] = False
            else:
                rooms[index:index + wall, :] = False
            position += float(rng.uniform(*config.room_size))
    return rooms


def _doors(free, corridor_mask, rooms, corridors, rng, config, res):
    """Doors through the wall on both sides of every corridor, where an office lies behind it and
    no corridor mouth is near."""
    shape = free.shape
    for corridor in corridors:
        x0, y0, x1, y1 = corridor.rect()
        length_start, length_end = (x0, x1) if corridor.horizontal else (y0, y1)
        position = length_start + float(rng.uniform(*config.door_gap)) / 2.0
        while position < length_end - 1.0:
            door = float(rng.uniform(*config.door_width))
            a, b = position - door / 2.0, position + door / 2.0
            side = 1 if rng.random() < 0.5 else -1
            for s in (side, -side):
                edge = (y1 if s > 0 else y0) if corridor.horizontal else (x1 if s > 0 else x0)
                far = edge + s * (config.wall + 0.1)
                rect = [a, edge, b, far] if corridor.horizontal else [edge, a, far, b]
                guard = (a - config.junction_clearance, b + config.junction_clearance)
                beyond = [a - 0.1, edge + s * (config.wall + 0.3), b + 0.1,
                          edge + s * (config.wall + 0.5)]
                beside = [guard[0], edge + s * 0.05, guard[1], edge + s * (config.wall + 0.05)]
                if not corridor.horizontal:
                    beyond = [beyond[1], beyond[0], beyond[3], beyond[2]]
                    beside = [beside[1], beside[0], beside[3], beside[2]]
                behind = rooms[rect_cells(beyond, res, shape)]
                wall_band = corridor_mask[rect_cells(beside, res, shape)]
                if behind.size and behind.all() and not wall_band.any() and \
                        rng.random() < config.door_probability:
                    free[rect_cells(rect, res, shape)] = True
                    break
            position += door + float(rng.uniform(*config.door_gap))


def end_doors(free, rooms, corridors, rng, config, res):
    """Doors in the wall straight ahead at either end of a corridor (dead end, L corner, the far
    wall of a T), across the corridor's width at a random offset, where an office lies behind.
    -> [(x0, y0, x1, y1)] of the doors carved."""
    shape, carved = free.shape, []
    for corridor in corridors:
        if corridor.end - corridor.start <= config.corridor_width[1] + 0.1:
            continue                     # no longer than one crossing: no end of its own
        for direction, end in ((-1, corridor.start), (1, corridor.end)):
            if rng.random() >= config.end_door_probability:
                continue
            door = float(rng.uniform(*config.door_width))
            slack = max(corridor.width / 2.0 - door / 2.0 - 0.1, 0.0)
            middle = corridor.centre + float(rng.uniform(-slack, slack))
            a, b = middle - door / 2.0, middle + door / 2.0
            through = sorted((end - direction * 0.1, end + direction * (config.wall + 0.1)))
            beyond = sorted((end + direction * (config.wall + 0.3),
                             end + direction * (config.wall + 0.5)))
            if corridor.horizontal:
                rect, behind = [through[0], a, through[1], b], [beyond[0], a, beyond[1], b]
            else:
                rect, behind = [a, through[0], b, through[1]], [a, beyond[0], b, beyond[1]]
            room = rooms[rect_cells(behind, res, shape)]
            if room.size and room.all():
                free[rect_cells(rect, res, shape)] = True
                carved.append(tuple(rect))
    return carved


def _furniture(free, rooms, rng, config, res):
    """A desk or cupboard in some offices, against the middle of the office, off its walls."""
    count, labels = cv2.connectedComponents(rooms.astype(np.uint8), connectivity=4)
    for label in range(1, count):
        if rng.random() >= config.furniture_probability:
            continue
        rows, cols = np.nonzero(labels == label)
        if rows.size * res * res < 6.0:
            continue
        r0, r1, c0, c1 = rows.min(), rows.max(), cols.min(), cols.max()
        margin = int(0.8 / res)
        if r1 - r0 < 2 * margin + 10 or c1 - c0 < 2 * margin + 10:
            continue
        height = int(rng.integers(10, min(40, r1 - r0 - 2 * margin) + 1))
        width = int(rng.integers(10, min(40, c1 - c0 - 2 * margin) + 1))
        top = int(rng.integers(r0 + margin, r1 - margin - height + 1))
        left = int(rng.integers(c0 + margin, c1 - margin - width + 1))
        box = np.zeros_like(rooms)
        box[top:top + height, left:left + width] = True
        free[box & (labels == label)] = False


def random_floor(seed, config=None):
    """-> (OccupancyMap, [Corridor]) of a random office floor (reproducible for a seed)."""
    config = config or FloorGeneratorConfig()
    rng = np.random.default_rng(seed)
    res = config.resolution
    width = round(float(rng.uniform(*config.width)) / res) * res
    depth = round(float(rng.uniform(*config.depth)) / res) * res
    corridors = random_corridors(rng, width, depth, config)
    if config.side_branch_rate > 0:      # (no draw otherwise: older seeds keep their floors)
        corridors += side_branches(rng, corridors, width, depth, config)
    shape = (int(round(depth / res)), int(round(width / res)))
    corridor_mask = np.zeros(shape, dtype=bool)
    for corridor in corridors:
        corridor_mask[rect_cells(corridor.rect(), res, shape)] = True
    wall = int(round(config.wall / res))
    inner = np.zeros(shape, dtype=bool)
    inner[wall:-wall, wall:-wall] = True
    near_corridor = cv2.dilate(corridor_mask.astype(np.uint8),
                               np.ones((2 * wall + 1, 2 * wall + 1), np.uint8)).astype(bool)
    rooms = inner & ~near_corridor
    rooms = _partition(rooms, rng, config, res)
    free = (corridor_mask & inner) | rooms
    _doors(free, corridor_mask, rooms, corridors, rng, config, res)
    if config.end_door_probability > 0:  # (no draw otherwise: older seeds keep their floors)
        end_doors(free, rooms, corridors, rng, config, res)
    _furniture(free, rooms, rng, config, res)
    cells = np.where(free, FREE, OCCUPIED).astype(np.int8)
    return OccupancyMap(cells=cells, resolution=res, origin=(0.0, 0.0, 0.0)), corridors
