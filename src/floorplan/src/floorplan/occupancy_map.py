"""Occupancy grids in ROS `map_server` format: load (YAML + image) and save (YAML + PGM)."""
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray

FREE, OCCUPIED, UNKNOWN = 0, 100, -1   # nav_msgs/OccupancyGrid cell values
PGM_FREE, PGM_OCCUPIED, PGM_UNKNOWN = 254, 0, 205  # map_saver's trinary pixel values
DEFAULT_OCCUPIED_THRESH = 0.65
DEFAULT_FREE_THRESH = 0.196


class MapError(ValueError):
    """A map file that cannot be used; the message names the file and the problem."""


@dataclass
class OccupancyMap:
    """A 2D grid; cells[row, col] with row 0 at the origin (bottom of the image), as in ROS."""

    cells: np.ndarray            # int8 (H, W): FREE, OCCUPIED, UNKNOWN or 1..99 (mode scale)
    resolution: float            # [m/cell]
    origin: tuple = (0.0, 0.0, 0.0)  # pose of cell (0, 0)'s corner in the map frame [m, m, rad]

    @property
    def height(self) -> int:
        return self.cells.shape[0]

    @property
    def width(self) -> int:
        return self.cells.shape[1]

    def world_to_cell(self, x: ArrayLike,
                      y: ArrayLike) -> tuple[NDArray[np.int_], NDArray[np.int_]]:
        """Map-frame metres -> (row, col) integer indices (unrotated origins only)."""
        col = np.floor((np.asarray(x) - self.origin[0]) / self.resolution).astype(int)
        row = np.floor((np.asarray(y) - self.origin[1]) / self.resolution).astype(int)
        return row, col

    def cell_to_world(self, row: ArrayLike,
                      col: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(row, col) -> map-frame metres of the cell centre."""
        x = self.origin[0] + (np.asarray(col) + 0.5) * self.resolution
        y = self.origin[1] + (np.asarray(row) + 0.5) * self.resolution
        return x, y

    def inside(self, row: ArrayLike, col: ArrayLike) -> NDArray[np.bool_]:
        rows, cols = np.asarray(row), np.asarray(col)
        return (rows >= 0) & (rows < self.height) & (cols >= 0) & (cols < self.width)

    def occupied_mask(self) -> NDArray[np.bool_]:
        """True where a cell is an obstacle; unknown cells count as obstacles."""
        return (self.cells >= OCCUPIED // 2) | (self.cells == UNKNOWN)


def _metadata(yaml_path: Path) -> dict[str, Any]:
    try:
        meta = yaml.safe_load(Path(yaml_path).read_text())
    except (OSError, yaml.YAMLError) as error:
        raise MapError(f"{yaml_path}: cannot read map YAML: {error}") from error
    if not isinstance(meta, dict):
        raise MapError(f"{yaml_path}: map YAML must be a mapping")
    missing = [key for key in ("image", "resolution", "origin") if key not in meta]
    if missing:
        raise MapError(f"{yaml_path}: missing key(s) {', '.join(missing)}")
    if not float(meta["resolution"]) > 0:
        raise MapError(f"{yaml_path}: resolution must be > 0, got {meta['resolution']}")
    if len(meta["origin"]) != 3:
        raise MapError(f"{yaml_path}: origin must be [x, y, yaw], got {meta['origin']}")
    return meta


def _read_image(image_path: Path) -> NDArray[np.float64]:
    image = cv2.imread(str(image_path), cv2.IMREAD_UNCHANGED) if image_path.is_file() else None
    if image is None:
        raise MapError(f"{image_path}: map image missing or unreadable")
    if image.ndim == 3:  # colour: map_server averages the colour channels (alpha ignored)
        image = image[:, :, :3].mean(axis=2)
    return np.flipud(image.astype(np.float64))  # image row 0 is the top; grid row 0 is the origin


def cells_from_pixels(pixels: NDArray[np.float64], meta: Mapping[str, Any]) -> NDArray[np.int8]:
    """map_server's image_loader: pixel values -> occupancy values for modes trinary/scale/raw."""
    mode = meta.get("mode", "trinary")
    if mode == "raw":
        return np.clip(pixels, -1, 100).astype(np.int8)
    occupancy = pixels / 255.0 if int(meta.get("negate", 0)) else (255.0 - pixels) / 255.0
    occupied_thresh = float(meta.get("occupied_thresh", DEFAULT_OCCUPIED_THRESH))
    free_thresh = float(meta.get("free_thresh", DEFAULT_FREE_THRESH))
    cells = np.full(pixels.shape, UNKNOWN, dtype=np.int8)
    cells[occupancy > occupied_thresh] = OCCUPIED
    cells[occupancy < free_thresh] = FREE
    if mode == "scale":
        between = (occupancy >= free_thresh) & (occupancy <= occupied_thresh)
        scaled = 99.0 * (occupancy - free_thresh) / (occupied_thresh - free_thresh)
        cells[between] = np.round(scaled[between]).astype(np.int8)
    elif mode != "trinary":
        raise MapError(f"unknown map mode {mode!r} (trinary, scale or raw)")
    return cells


def load_map(yaml_path: str | Path) -> OccupancyMap:
    """Load a map_server YAML + image into an OccupancyMap; MapError names what is wrong."""
    yaml_path = Path(yaml_path)
    meta = _metadata(yaml_path)
    image_path = Path(meta["image"])
    if not image_path.is_absolute():
        image_path = yaml_path.parent / image_path
    try:
        cells = cells_from_pixels(_read_image(image_path), meta)
    except MapError as error:
        raise MapError(f"{yaml_path}: {error}") from error
    origin = tuple(float(v) for v in meta["origin"])
    return OccupancyMap(cells=cells, resolution=float(meta["resolution"]), origin=origin)


def save_map(grid: OccupancyMap, yaml_path: str | Path) -> None:
    """Write `grid` as map_saver does: trinary PGM beside a YAML with the standard keys."""
    yaml_path = Path(yaml_path)
    image_path = yaml_path.with_suffix(".pgm")
    pixels = np.full(grid.cells.shape, PGM_UNKNOWN, dtype=np.uint8)
    pixels[grid.cells == FREE] = PGM_FREE
    pixels[grid.cells >= OCCUPIED // 2] = PGM_OCCUPIED
    if not cv2.imwrite(str(image_path), np.flipud(pixels)):
        raise MapError(f"{image_path}: cannot write map image")
    meta = {"image": image_path.name, "resolution": grid.resolution,
            "origin": [float(v) for v in grid.origin], "negate": 0,
            "occupied_thresh": DEFAULT_OCCUPIED_THRESH, "free_thresh": DEFAULT_FREE_THRESH,
            "mode": "trinary"}
    yaml_path.write_text(yaml.safe_dump(meta, sort_keys=False))
