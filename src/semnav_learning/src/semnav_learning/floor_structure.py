"""Whole-floor corridor structure: free-space skeleton, its junctions and dead ends, and start
poses sampled on corridor centre lines (for demonstrations on any floor)."""
import math
from dataclasses import dataclass

import cv2
import numpy as np

from semnav_learning.route_oracle import OracleError


@dataclass
class FloorStructure:
    """Skeleton of the traversable free space and its special cells (row, col arrays)."""

    skeleton: np.ndarray     # bool (H, W)
    junctions: np.ndarray    # (K, 2) cells with >= 3 skeleton branches
    dead_ends: np.ndarray    # (M, 2) cells with one skeleton neighbour
    corridors: np.ndarray    # bool (H, W): the corridor network (see corridor_network)


def corridor_network(field, skeleton, min_branch_width):
    """The longest free region that doors cannot split: 8-connected components of the cells with
    at least half a corridor branch's width of clearance, ranked by the skeleton length inside.
    On an office floor this is the corridor network; rooms hang off it through doors and fall
    into other components, and they are compact where corridors are long."""
    wide = (field.clearance >= 0.5 * min_branch_width - 0.1).astype(np.uint8)
    count, labels = cv2.connectedComponents(wide, connectivity=8)
    if count < 2:
        return np.zeros(wide.shape, dtype=bool)
    length = np.bincount(labels[skeleton], minlength=count)
    length[0] = 0
    return labels == int(np.argmax(length))


def _neighbours(image):
    """P2..P9 of Zhang & Suen (N, NE, E, SE, S, SW, W, NW) of every cell, as uint8 arrays."""
    p = np.pad(image, 1).astype(np.uint8)
    h, w = image.shape
    offsets = [(-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)]
    return [p[1 + dr:1 + dr + h, 1 + dc:1 + dc + w] for dr, dc in offsets]


def zhang_suen_skeleton(mask):
    """Zhang & Suen (1984) thinning of a boolean image to a one-cell-wide 8-connected skeleton."""
    image = np.asarray(mask, dtype=bool).copy()
    while True:
        changed = False
        for first in (True, False):
            n = _neighbours(image)
            count = sum(x.astype(int) for x in n)
            ring = n + n[:1]
            transitions = sum(((ring[i] == 0) & (ring[i + 1] == 1)).astype(int) for i in range(8))
            p2, p4, p6, p8 = n[0], n[2], n[4], n[6]
            if first:
                side = (p2 * p4 * p6 == 0) & (p4 * p6 * p8 == 0)
            else:
                side = (p2 * p4 * p8 == 0) & (p2 * p6 * p8 == 0)
            remove = image & (count >= 2) & (count <= 6) & (transitions == 1) & side
            if remove.any():
                image[remove] = False
                changed = True
        if not changed:
            return image


def floor_structure(field, robot_radius, min_branch_width=1.3):
    """Skeleton of the cells a robot of robot_radius fits in, junctions, dead ends, corridors."""
    traversable = field.clearance >= robot_radius
    if not traversable.any():
        raise OracleError(f"no free space with {robot_radius} m clearance on this map")
    skeleton = zhang_suen_skeleton(traversable)
    n = _neighbours(skeleton)
    ring = n + n[:1]
    branches = sum(((ring[i] == 0) & (ring[i + 1] == 1)).astype(int) for i in range(8))
    count = sum(x.astype(int) for x in n)
    junctions = np.argwhere(skeleton & (branches >= 3))
    dead_ends = np.argwhere(skeleton & (count == 1))
    return FloorStructure(skeleton, junctions, dead_ends,
                          corridor_network(field, skeleton, min_branch_width))


def _skeleton_heading(structure, row, col, cells):
    """Direction of the skeleton through (row, col): principal axis of nearby skeleton cells."""
    r0, r1 = max(row - cells, 0), row + cells + 1
    c0, c1 = max(col - cells, 0), col + cells + 1
    local = np.argwhere(structure.skeleton[r0:r1, c0:c1]) + [r0, c0]
    if len(local) < 3:
        return None
    centred = (local - local.mean(axis=0)).astype(float)
    d_row, d_col = np.linalg.svd(centred, full_matrices=False)[2][0]
    return math.atan2(d_row, d_col)


def walled_fraction(walk, window):
    """Share of [-window, window] along the walk where neither side wall has an opening."""
    covered = np.zeros(int(round(2 * window / 0.05)) + 1, dtype=bool)
    s = np.linspace(-window, window, covered.size)
    for opening in walk.openings:
        covered |= (s >= opening.start) & (s <= opening.end)
    return 1.0 - covered.mean()


def sample_corridor_starts(oracle, structure, count, rng, max_corridor_width=3.0,
                           min_walled=0.7, window=1.5, max_tries=None):
    """`count` start poses on corridor centre lines, facing along the corridor either way.

    A candidate skeleton cell of the corridor network (clearance up to half of
    max_corridor_width [m]) is kept when the oracle's walk from it finds a corridor whose axis
    agrees with the skeleton (within 10°), whose walls are both near the centre line, and whose
    side walls are closed over at least `min_walled` of ±`window` [m] round the start (so neither
    junctions nor passages beside furniture in rooms are starts).
    """
    grid = oracle.field.grid
    half = 0.5 * max_corridor_width
    cells = structure.skeleton & structure.corridors & (oracle.field.clearance <= half)
    candidates = np.argwhere(cells)
    if candidates.size == 0:
        raise OracleError("no corridor on this map: no skeleton cell with corridor clearance")
    starts, tries = [], 0
    max_tries = max_tries or 50 * count
    while len(starts) < count and tries < max_tries:
        tries += 1
        row, col = candidates[rng.integers(len(candidates))]
        heading = _skeleton_heading(structure, row, col, int(round(0.5 / grid.resolution)))
        if heading is None:
            continue
        heading += math.pi * rng.integers(2)
        x, y = (float(v) for v in grid.cell_to_world(row, col))
        try:
            walk = oracle.walk((x, y, heading))
        except OracleError:
            continue
        aligned = abs(math.remainder(walk.axis - heading, 2 * math.pi)) < math.radians(10)
        near = oracle.field.at(x, y) <= 1.2 * walk.half_width
        if aligned and near and walk.half_width <= half \
                and walled_fraction(walk, window) >= min_walled:
            starts.append((x, y, math.remainder(walk.axis, 2 * math.pi)))
    if len(starts) < count:
        raise OracleError(f"found only {len(starts)} of {count} corridor starts in {tries} tries")
    return starts
