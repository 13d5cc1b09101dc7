"""Human localisation from RGB-D detections (thesis 000 Sec. 3.2.2).

A box's depth is the mean of valid depth pixels in a rectangle around its centre whose size is a
fraction of the box; the box centre is back-projected with the pinhole model (Eqs. 3-3 ... 3-5)
into the camera optical frame (REP 103: x right, y down, z forward), transformed into the map
frame by a 4x4 homogeneous transform (from tf in the node), and named by the graph region
containing it.
"""
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from floorplan.semantic_graph import SemanticGraph
from numpy.typing import ArrayLike, NDArray


@dataclass
class Intrinsics:
    """Pinhole intrinsics of one camera."""

    fx: float       # [px]
    fy: float       # [px]
    cx: float       # [px]
    cy: float       # [px]
    width: int      # [px]
    height: int     # [px]


@dataclass
class DepthWindowConfig:
    """Adaptive depth rectangle around the box centre (Fig. 3-10 (b))."""

    fraction: float = 0.2       # [-] rectangle side = this fraction of the box side
    min_side: int = 3           # [px] never smaller than this
    min_depth: float = 0.3      # [m] closer readings are invalid (sensor minimum)
    max_depth: float = 8.0      # [m] farther readings are invalid


def pixel_to_camera(px: ArrayLike, py: ArrayLike, depth: ArrayLike,
                    intrinsics: Intrinsics) -> NDArray[np.float64]:
    """Eqs. 3-3, 3-4, 3-5: pixel (px, py) at depth d -> (x_r, y_r, z_r) [m], optical frame;
    arrays of n pixels give (3, n)."""
    d = np.asarray(depth, dtype=float)
    x = (np.asarray(px, dtype=float) - intrinsics.cx) / intrinsics.fx * d
    y = (np.asarray(py, dtype=float) - intrinsics.cy) / intrinsics.fy * d
    return np.array([x, y, d], dtype=float)


def depth_window(box: Sequence[float], config: DepthWindowConfig,
                 image_shape: tuple[int, ...]) -> tuple[int, int, int, int]:
    """Rectangle (x0, y0, x1, y1) [px, exclusive end] centred on the box, sized by the box."""
    x, y, w, h = box
    cx, cy = x + w / 2.0, y + h / 2.0
    half_w = max(config.min_side, config.fraction * w) / 2.0
    half_h = max(config.min_side, config.fraction * h) / 2.0
    rows, cols = image_shape[:2]
    x0, x1 = int(max(0, math.floor(cx - half_w))), int(min(cols, math.ceil(cx + half_w)))
    y0, y1 = int(max(0, math.floor(cy - half_h))), int(min(rows, math.ceil(cy + half_h)))
    return x0, y0, x1, y1


def box_depth(depth_image: ArrayLike, box: Sequence[float],
              config: DepthWindowConfig) -> float | None:
    """Mean valid depth [m] in the adaptive rectangle, or None when no pixel there is valid.

    Args:
        depth_image: (H, W) float depth [m]; NaN, 0 and out-of-range pixels are ignored.
        box: (x, y, width, height) [px].
    """
    depth = np.asarray(depth_image, dtype=float)
    if depth.ndim != 2 or depth.size == 0:
        raise ValueError(f"depth image must be a non-empty 2-D array, got shape {depth.shape}")
    x0, y0, x1, y1 = depth_window(box, config, depth.shape)
    patch = depth[y0:y1, x0:x1]
    valid = patch[np.isfinite(patch) & (patch >= config.min_depth) & (patch <= config.max_depth)]
    return float(valid.mean()) if valid.size else None


def optical_to_map_transform(robot_pose: Sequence[float], mount_x: float, mount_height: float,
                             tilt: float) -> NDArray[np.float64]:
    """4x4 transform map <- camera optical frame for a camera on a planar robot.

    Args:
        robot_pose: (x, y, yaw) of base_link in the map [m, m, rad].
        mount_x: camera ahead of base_link [m]; mount_height: above the floor [m];
        tilt: pitch down [rad].
    """
    x, y, yaw = robot_pose
    ct, st = math.cos(tilt), math.sin(tilt)
    # optical (x right, y down, z forward) -> body (forward, left, up), pitched down by tilt
    optical_to_body = np.array([[0.0, -st, ct], [-1.0, 0.0, 0.0], [0.0, -ct, -st]])
    cy, sy = math.cos(yaw), math.sin(yaw)
    body_to_map = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    transform = np.eye(4)
    transform[:3, :3] = body_to_map @ optical_to_body
    transform[:3, 3] = (x + cy * mount_x, y + sy * mount_x, mount_height)
    return transform


def transform_point(transform: ArrayLike, point: ArrayLike) -> NDArray[np.float64]:
    """Apply a 4x4 homogeneous transform to a 3-D point (3,), or to n points (n, 3)."""
    p = np.asarray(point, dtype=float)
    homogeneous = np.concatenate([p, np.ones(p.shape[:-1] + (1,))], axis=-1)
    return (homogeneous @ np.asarray(transform, dtype=float).T)[..., :3]


def point_in_polygon(x: float, y: float, polygon: Sequence[Sequence[float]]) -> bool:
    """Even-odd ray casting: is (x, y) inside the polygon [[x, y], ...]?"""
    inside = False
    n = len(polygon)
    for i in range(n):
        (x1, y1), (x2, y2) = polygon[i], polygon[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def semantic_place(graph: SemanticGraph, x: float, y: float) -> str:
    """Name of the graph place whose region contains (x, y) [m], or "" if none does."""
    for place in graph.places:
        if point_in_polygon(x, y, place.region):
            return place.name
    return ""


def stitched_rows(v: ArrayLike, top_height: int) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Rows v of the stitched pair (top camera's image over the bottom's): (seen by the top
    camera, the row in the camera that saw it)."""
    rows = np.asarray(v, dtype=float)
    in_top = rows < top_height
    return in_top, np.where(in_top, rows, rows - top_height)


def stitched_pixel(u: float, v: float, top_height: int) -> tuple[str, float, float]:
    """Camera of the stitched pair that saw pixel (u, v): ('top'|'bottom', u, v_camera)."""
    in_top, row = stitched_rows(v, top_height)
    return ("top" if in_top else "bottom"), u, float(row)


def localise_box(depth_image: ArrayLike, box: Sequence[float], intrinsics: Intrinsics,
                 camera_to_map: ArrayLike, config: DepthWindowConfig) -> NDArray[np.float64] | None:
    """Box in one camera's image -> map (x, y, z) [m], or None when the depth there is invalid."""
    d = box_depth(depth_image, box, config)
    if d is None:
        return None
    x, y, w, h = box
    return transform_point(camera_to_map, pixel_to_camera(x + w / 2.0, y + h / 2.0, d, intrinsics))
