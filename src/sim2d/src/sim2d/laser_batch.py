"""Scans of several lasers of one model taken at one instant, cast together, ROS-free.

A world with several robots scans their lasers at the same instants. Per laser the work is a
handful of small numpy calls, so eight robots cost eight times one. Here the lasers that share a
model and a range table are cast together: the table lookup (RangeTable.cast_rows), the windowed
overlay of people and robots (laser.window_hits over every laser's circles at once) and the
noise (laser.noisy_ranges) are each one pass over (lasers x beams). Each laser keeps its own
noise stream and the arithmetic is the same, element for element, so every scan equals the one
LaserSensor.scan returns, bit for bit (test_laser_batch.py).
"""
import math
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from sim2d.laser import Boxes, LaserSensor, box_ranges, noisy_ranges, window_hits


def batch_key(laser: LaserSensor) -> tuple[tuple, int] | None:
    """Lasers with equal keys can be cast together: one model, one range table, windowed
    overlay; None for a laser that casts alone (no table, or every beam against every circle)."""
    if laser.table is None or not laser.windowed:
        return None
    return laser.model_key, id(laser.table)


def scan_many(lasers: Sequence[LaserSensor], poses: Sequence[Sequence[float]],
              circles: np.ndarray | None = None, owners: Sequence[int] | None = None,
              boxes: Boxes = ()) -> np.ndarray | None:
    """One noisy scan [m] per laser (rows of a float32 (lasers, beams) array), as
    `laser.scan(pose, circles without the laser's own robot, boxes)` gives each; None when a
    laser stands where its table has no sample (the caller casts those alone).

    lasers: LaserSensors with one batch_key; poses: their robots' poses (x, y, yaw);
    circles: (N, 3) array of every robot's and person's (x, y, r) or None; owners: per laser
    the row of its own robot in `circles` (-1: none); boxes: closed doors (x0, y0, x1, y1).
    """
    first = lasers[0]
    if first.table is None:
        raise ValueError("scan_many casts lasers with a range table only (see batch_key)")
    in_map = [laser.pose_in_map(pose) for laser, pose in zip(lasers, poses)]
    xs, ys, yaws = zip(*in_map)
    ranges = first.table.cast_rows(xs, ys, yaws, first.angles, first.fan_step)
    if ranges is None:
        return None
    at = np.array(in_map)   # (K, 3) laser poses in the map
    if circles is not None and len(circles):
        ranges = overlay_many(ranges, at, circles, np.asarray(owners), first)
    if len(boxes):   # rounded to float32 before the minimum, as the circles' hits
        world_angles = first.angles[None, :] + at[:, 2:3]
        for k in range(len(lasers)):
            np.minimum(ranges[k], box_ranges(at[k, 0], at[k, 1], world_angles[k],
                                             boxes).astype(np.float32), out=ranges[k])
    return add_noise(lasers, ranges)


def overlay_many(ranges: np.ndarray, at: np.ndarray, circles: npt.ArrayLike, owners: np.ndarray,
                 laser: LaserSensor) -> np.ndarray:
    """laser.overlay_circles for every laser pose of `at` at once, in place on the float32
    (lasers x beams) `ranges`: each circle of `circles` (N x 3) but the laser's own robot
    (`owners`) is cast on the beams of its angular window. The hits are rounded to float32
    before the minimum, which gives what rounding the float64 minimum gives (rounding is
    monotonic and the table's ranges are float32 already)."""
    model = laser.model
    c = np.asarray(circles, dtype=float)
    dx, dy = c[:, 0] - at[:, 0:1], c[:, 1] - at[:, 1:2]           # (K, N)
    d2, r2 = dx * dx + dy * dy, c[:, 2] * c[:, 2]
    seen = (d2 > r2) & (d2 < (laser._reach + c[:, 2]) ** 2)
    own = owners >= 0
    seen[np.flatnonzero(own), owners[own]] = False
    k, n = np.nonzero(seen)
    if not len(k):
        return ranges
    dx, dy, d2, r2 = dx[k, n], dy[k, n], d2[k, n], r2[n]
    turns = np.array([(math.cos(yaw), math.sin(yaw)) for yaw in at[:, 2].tolist()])[k]
    cy, sy = turns[:, 0], turns[:, 1]                         # math's, as overlay_circles
    pair, beam, t = window_hits(cy * dx + sy * dy, -sy * dx + cy * dy, d2, r2, laser._cos,
                                laser._sin, model.angle_min, model.angle_increment,
                                model.num_beams)
    np.minimum.at(ranges.reshape(-1), k[pair] * model.num_beams + beam, t.astype(np.float32))
    return ranges


def add_noise(lasers: Sequence[LaserSensor], ranges: np.ndarray) -> np.ndarray:
    """LaserSensor.scan's noise, dropouts and range limits (laser.noisy_ranges) on (lasers x
    beams) float32 true ranges, each laser drawing from its own noise stream."""
    shape = ranges.shape   # one concatenate: a third of np.stack's cost on these rows
    return noisy_ranges(lasers[0].model, ranges, lambda pool: np.concatenate(
        [laser._pool_slice(laser._pools[pool]) for laser in lasers]).reshape(shape))
