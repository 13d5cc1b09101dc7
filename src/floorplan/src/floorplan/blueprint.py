"""Render a building blueprint (walls, doors, furniture as rectangles) into an occupancy grid."""
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import NDArray

from floorplan.occupancy_map import FREE, OCCUPIED, MapError, OccupancyMap


def rect_cells(rect: Sequence[float], resolution: float,
               shape: tuple[int, ...]) -> tuple[slice, slice]:
    """(row slice, col slice) of the cells of a grid of `shape` whose centres lie in
    rect = [x0, y0, x1, y1] (metres, origin (0, 0), corners in any order), clipped to the grid."""
    x0, x1 = sorted((rect[0], rect[2]))
    y0, y1 = sorted((rect[1], rect[3]))
    c0, c1 = int(np.ceil(x0 / resolution - 0.5)), int(np.floor(x1 / resolution - 0.5)) + 1
    r0, r1 = int(np.ceil(y0 / resolution - 0.5)), int(np.floor(y1 / resolution - 0.5)) + 1
    rows, cols = shape
    return (slice(min(max(r0, 0), rows), min(max(r1, 0), rows)),
            slice(min(max(c0, 0), cols), min(max(c1, 0), cols)))


def _fill(cells: NDArray[np.int8], rect: Sequence[float], value: int,
          resolution: float) -> None:
    """Set every cell whose centre lies in rect = [x0, y0, x1, y1] (metres) to value."""
    cells[rect_cells(rect, resolution, cells.shape)] = value


def render_blueprint(blueprint: Mapping[str, Any]) -> OccupancyMap:
    """Blueprint dict (see maps/blueprints/*.yaml) -> OccupancyMap with origin (0, 0, 0)."""
    width, depth = blueprint["size"]
    resolution = float(blueprint["resolution"])
    half = float(blueprint["wall_thickness"]) / 2.0
    cells = np.full((round(depth / resolution), round(width / resolution)), FREE, dtype=np.int8)
    outline = [[0, 0, width, 0], [0, depth, width, depth],
               [0, 0, 0, depth], [width, 0, width, depth]]
    for x0, y0, x1, y1 in outline + list(blueprint.get("walls", [])):
        _fill(cells, [min(x0, x1) - half, min(y0, y1) - half, max(x0, x1) + half,
                      max(y0, y1) + half], OCCUPIED, resolution)
    for rect in blueprint.get("doors", []):
        _fill(cells, rect, FREE, resolution)
    for rect in blueprint.get("furniture", []):
        _fill(cells, rect, OCCUPIED, resolution)
    return OccupancyMap(cells=cells, resolution=resolution, origin=(0.0, 0.0, 0.0))


def load_blueprint(path: str | Path) -> dict[str, Any]:
    blueprint = yaml.safe_load(Path(path).read_text())
    missing = [k for k in ("name", "size", "resolution", "wall_thickness") if k not in blueprint]
    if missing:
        raise MapError(f"{path}: blueprint misses key(s) {', '.join(missing)}")
    return blueprint
