"""Scans of several lasers of one model taken at one instant, cast together, ROS-free.

A world with several robots scans their lasers at the same instants. Per laser the work is a
handful of small numpy calls, so eight robots cost eight times one. Here the lasers that share a
model and a range table are cast together: the table lookup, the windowed overlay of people and
robots (laser.overlay_circles over every laser's circles at once) and the noise are each one
call over (lasers x beams). Each laser keeps its own noise stream and the arithmetic is the
same, element for element, so every scan equals the one LaserSensor.scan returns, bit for bit
(test_laser_batch.py).
"""
import math

import numpy as np

from sim2d.laser import beam_windows, box_ranges


def batch_key(laser):
    """Lasers with equal keys can be cast together: one model, one range table, windowed
    overlay; None for a laser that casts alone (no table, or every beam against every circle)."""
    if laser.table is None or not laser.windowed:
        return None
    return laser.model_key, id(laser.table)


def scan_many(lasers, poses, circles=None, owners=None, boxes=()):
    """One noisy scan [m] per laser (rows of a float32 (lasers, beams) array), as
    `laser.scan(pose, circles without the laser's own robot, boxes)` gives each; None when a
    laser stands where its table has no sample (the caller casts those alone).

    lasers: LaserSensors with one batch_key; poses: their robots' poses (x, y, yaw);
    circles: (N, 3) array of every robot's and person's (x, y, r) or None; owners: per laser
    the row of its own robot in `circles` (-1: none); boxes: closed doors (x0, y0, x1, y1).
    """
    first = lasers[0]
    at = np.array([laser.pose_in_map(pose) for laser, pose in zip(lasers, poses)])  # (K, 3)
    ranges = table_ranges(lasers, at)
    if ranges is None:
        return None
    if circles is not None and len(circles):
        ranges = overlay_many(ranges, at, circles, np.asarray(owners), first)
    if len(boxes):   # rounded to float32 before the minimum, as the circles' hits
        world_angles = first.angles[None, :] + at[:, 2:3]
        for k in range(len(lasers)):
            np.minimum(ranges[k], box_ranges(at[k, 0], at[k, 1], world_angles[k],
                                             boxes).astype(np.float32), out=ranges[k])
    return add_noise(lasers, ranges)


def table_ranges(lasers, at):
    """Static-map ranges (float32, lasers x beams) from the lasers' shared range table at the
    laser poses `at` (K x 3, map frame), as RangeTable.cast_fan / cast give each; None when a
    laser stands where the table has no sample."""
    first = lasers[0]
    table, model = first.table, first.model
    found = nearest_samples(table, at)
    if found is None:
        return None
    entries, dx, dy = found
    work = _workspace(first, len(lasers))
    count = table.config.angle_bins
    bins = work.bins
    if first._fan_step:
        k0 = [int(round((float(yaw) + model.angle_min) / table.bin_width)) % count
              for yaw in at[:, 2]]
        np.add(np.array(k0)[:, None], np.arange(model.num_beams) * first._fan_step, out=bins)
        np.take(table._inv_cos, bins, out=work.inv_cos)   # stored twice over: no wrap needed
        np.take(table._inv_sin, bins, out=work.inv_sin)
        np.subtract(bins, count, out=bins, where=bins >= count)
    else:   # as RangeTable.cast: rint(world angle / bin width) modulo the bins
        angles = work.angles
        np.add(first.angles, at[:, 2:3], out=angles)
        np.divide(angles, table.bin_width, out=angles)
        np.rint(angles, out=angles)
        np.copyto(bins, angles, casting="unsafe")
        if bins.min() >= -count and bins.max() < count:   # the usual case: cheaper than %
            np.add(bins, count, out=bins, where=bins < 0)
        else:
            np.remainder(bins, count, out=bins)
        np.take(table._inv_cos, bins, out=work.inv_cos)
        np.take(table._inv_sin, bins, out=work.inv_sin)
    bins += (entries * count)[:, None]
    raw = np.take(table.table.reshape(-1), bins, out=work.raw)
    ranges = work.ranges
    np.copyto(ranges, np.bitwise_and(raw, table.RANGE_MASK, out=work.millimetres))
    ranges *= np.float32(1.0 / table.MM)
    shift = np.multiply(dx, work.inv_cos, out=work.shift)       # x faces ...
    y_face = np.greater_equal(raw, table.FACE_BIT, out=work.mask)
    np.multiply(dy, work.inv_sin, out=shift, where=y_face)      # ... and y faces
    ranges -= shift
    return ranges


def nearest_samples(table, at):
    """RangeTable._nearest for each laser pose of `at`: (table rows, dx, dy as float32
    columns), or None when a pose has no sample."""
    found = [table._nearest(x, y) for x, y in at[:, :2].tolist()]
    if None in found:
        return None
    entries, dx, dy = zip(*found)
    return (np.array(entries), np.array(dx, dtype=np.float32)[:, None],
            np.array(dy, dtype=np.float32)[:, None])


class _Workspace:
    """Arrays of one shape reused from scan to scan (allocating them cost as much as the
    arithmetic)."""

    def __init__(self, shape):
        self.angles = np.empty(shape)
        self.bins = np.empty(shape, dtype=np.int64)
        self.inv_cos = np.empty(shape, dtype=np.float32)
        self.inv_sin = np.empty(shape, dtype=np.float32)
        self.shift = np.empty(shape, dtype=np.float32)
        self.raw = np.empty(shape, dtype=np.uint16)
        self.millimetres = np.empty(shape, dtype=np.uint16)
        self.mask = np.empty(shape, dtype=bool)
        self.ranges = np.empty(shape, dtype=np.float32)   # true ranges; the scans are copies
        self.sigma = np.empty(shape, dtype=np.float32)
        self.draws = np.empty(shape, dtype=np.float32)


def _workspace(laser, count):
    """The workspace for `count` lasers like `laser` (kept on the laser that leads the batch)."""
    shape = (count, laser.model.num_beams)
    work = getattr(laser, "_batch_workspace", None)
    if work is None or work.bins.shape != shape:
        work = laser._batch_workspace = _Workspace(shape)
    return work


def overlay_many(ranges, at, circles, owners, laser):
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
    fx, fy = cy * dx + sy * dy, -sy * dx + cy * dy                # centres in each laser frame
    halves = np.arcsin(np.sqrt(r2 / d2))
    pair, beam = beam_windows(np.arctan2(fy, fx), halves, model.angle_min,
                              model.angle_increment, model.num_beams)
    if not len(beam):
        return ranges
    along = fx[pair] * laser._cos[beam] + fy[pair] * laser._sin[beam]
    perp2 = d2[pair] - along * along
    r2 = r2[pair]
    t = along - np.sqrt(np.maximum(r2 - perp2, 0.0))
    hit = np.flatnonzero((perp2 <= r2) & (t > 0))
    np.minimum.at(ranges.reshape(-1), k[pair[hit]] * model.num_beams + beam[hit],
                  t[hit].astype(np.float32))
    return ranges


def add_noise(lasers, ranges):
    """LaserSensor.scan's noise, dropouts and range limits on (lasers x beams) float32 true
    ranges, each laser drawing from its own noise stream; returns new arrays."""
    m = lasers[0].model
    work = _workspace(lasers[0], len(lasers))
    draws = work.draws
    if m.noise_fraction > 0:
        sigma = np.minimum(ranges, np.float32(m.range_max), out=work.sigma)   # no inf * noise
        sigma *= np.float32(m.noise_fraction)
        np.maximum(np.float32(m.noise_std), sigma, out=sigma)
        for k, laser in enumerate(lasers):
            draws[k] = laser._pool_slice(laser._normal_pool)
        sigma *= draws
        scans = ranges + sigma
        for k, laser in enumerate(lasers):
            draws[k] = laser._pool_slice(laser._dropout_pool)
        scans += draws
    else:
        for k, laser in enumerate(lasers):
            draws[k] = laser._pool_slice(laser._noise_pool)
        scans = ranges + draws
    scans[np.greater(scans, m.range_max, out=work.mask)] = np.inf
    scans[np.less(scans, m.range_min, out=work.mask)] = -np.inf
    return scans
