"""Pinhole camera model: what YOLO and OpenPose would report for the visible people and objects.

Two identical cameras stacked vertically as on Pepper (thesis 000 Sec. 3.2.1, image stitching):
the top camera's image lies above the bottom camera's, so the stitched frame is width x 2*height.
Projection is the inverse of the thesis' Eqs. 3-3..3-5: u = fx * x / z + cx, v = fy * y / z + cy.
An object's box is the bounding box of its visible projection, as a detector run on the stitched
frame reports it: the object's 3D box is cut at the near plane, projected, cut to each camera's
image, and the parts seen by the top and the bottom camera are joined across the seam.
"""
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from sim2d.detection_model import DetectionConfig, DetectionModel, IdealModel
from sim2d.raycast import GridGeometry, segments_clear
from sim2d.skeleton import (
    L_EAR, L_EYE, L_SHOULDER, NECK, NOSE, NUM_KEYPOINTS, R_EAR, R_EYE, R_SHOULDER)

COLOUR_JOINTS = (NECK, R_SHOULDER, L_SHOULDER)   # shirt colour sampled here (thesis 000 Sec. 3.2.3)
FACE_AWAY = math.radians(100.0)   # [rad] head-to-robot angle beyond which the face is unseen
FACE_KEYPOINTS = (NOSE, R_EYE, L_EYE)
NEAR_PLANE = 0.05   # [m] optical z below which nothing projects (as in `project`)
# The 12 edges of an object's box: index pairs into SimObject.corners() (index 4 ix + 2 iy + iz).
BOX_EDGES = tuple((i, i | bit) for bit in (1, 2, 4) for i in range(8) if not i & bit)
Extent = tuple[float, float, float, float]   # (u0, v0, u1, v1) [px]


@dataclass
class CameraConfig:
    """One pinhole camera on the robot (REP 103 optical frame: z forward, x right, y down)."""

    fx: float = 583.9           # [px] Pepper 640x480: 57.2 deg horizontal field of view
    fy: float = 588.5           # [px] 44.3 deg vertical field of view
    cx: float = 320.0           # [px]
    cy: float = 240.0           # [px]
    width: int = 640            # [px]
    height: int = 480           # [px]
    mount_x: float = 0.09       # [m] ahead of base_link
    mount_height: float = 1.15  # [m] above the floor
    tilt: float = 0.0           # [rad] pitch down


@dataclass
class ObjectDetection:
    label: str
    confidence: float
    x: int                      # box top-left [px]
    y: int
    width: int                  # [px]
    height: int
    depth: float                # [m]
    truth: str = ""             # simulator ground truth (object or person name), not published


@dataclass
class SkeletonDetection:
    x: np.ndarray               # (18,) [px]
    y: np.ndarray               # (18,) [px]
    confidence: np.ndarray      # (18,) 0 = not detected
    depth: np.ndarray           # (18,) [m], NaN when not detected
    joint_colours: np.ndarray   # (3, 3) uint8 RGB at joints 1, 2, 5
    truth: str = ""


@dataclass
class CameraFrame:
    width: int
    height: int
    objects: list = field(default_factory=list)
    skeletons: list = field(default_factory=list)


def camera_points(points: np.ndarray, robot_pose: Sequence[float],
                  camera: CameraConfig) -> npt.NDArray[np.float64]:
    """Map-frame points (N, 3) -> camera optical-frame points (N, 3) [m]."""
    x, y, yaw = robot_pose
    c, s = math.cos(yaw), math.sin(yaw)
    dx = points[:, 0] - (x + c * camera.mount_x)
    dy = points[:, 1] - (y + s * camera.mount_x)
    forward, left = c * dx + s * dy, -s * dx + c * dy
    up = points[:, 2] - camera.mount_height
    ct, st = math.cos(camera.tilt), math.sin(camera.tilt)
    z = ct * forward - st * up
    y_down = -st * forward - ct * up
    return np.column_stack([-left, y_down, z])


def project(points_cam: np.ndarray,
            camera: CameraConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pinhole projection (inverse of thesis 000 Eqs. 3-3, 3-4): (u, v, in_image) per point."""
    z = points_cam[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = camera.fx * points_cam[:, 0] / z + camera.cx
        v = camera.fy * points_cam[:, 1] / z + camera.cy
    inside = (z > 0.05) & (u >= 0) & (u < camera.width) & (v >= 0) & (v < camera.height)
    return u, v, inside


def project_stacked(points: np.ndarray, robot_pose: Sequence[float], top: CameraConfig,
                    bottom: CameraConfig) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                   np.ndarray]:
    """Project into the stitched frame: top image rows 0..H-1, bottom image rows H..2H-1.

    Returns u, v, visible, depth (optical z of the camera that sees the point).
    """
    u, v, depth = (np.full(len(points), np.nan) for _ in range(3))
    visible = np.zeros(len(points), dtype=bool)
    for camera, row_offset in ((top, 0.0), (bottom, float(top.height))):
        pc = camera_points(points, robot_pose, camera)
        cu, cv, inside = project(pc, camera)
        take = inside & ~visible
        u[take], v[take], depth[take] = cu[take], cv[take] + row_offset, pc[take, 2]
        visible |= take
    return u, v, visible, depth


def hidden_face(keypoints: np.ndarray, robot_pose: Sequence[float]) -> tuple[int, ...]:
    """Nose and eyes when the head (18, 3 map-frame keypoints) faces away from the robot by more
    than FACE_AWAY: what a person seen from behind hides from the pose detector."""
    head = keypoints[[R_EAR, L_EAR]].mean(axis=0)
    facing = keypoints[NOSE, :2] - head[:2]
    to_robot = np.array(robot_pose[:2]) - head[:2]
    cos = float(facing @ to_robot) / (np.linalg.norm(facing) * np.linalg.norm(to_robot) + 1e-12)
    return FACE_KEYPOINTS if cos < math.cos(FACE_AWAY) else ()


def clip_to_near_plane(points_cam: np.ndarray,
                       edges: Iterable[tuple[int, int]] = BOX_EDGES,
                       near: float = NEAR_PLANE) -> npt.NDArray[np.float64]:
    """Vertices (n, 3) of a convex solid cut at optical z = near: its corners in front of the
    plane plus the points where its edges cross it (empty when wholly behind)."""
    z = points_cam[:, 2]
    kept = list(points_cam[z >= near])
    for i, j in edges:
        if (z[i] - near) * (z[j] - near) < 0:
            t = (near - z[i]) / (z[j] - z[i])
            kept.append(points_cam[i] + t * (points_cam[j] - points_cam[i]))
    return np.array(kept).reshape(-1, 3)


def convex_hull(points: npt.ArrayLike) -> np.ndarray:
    """Counter-clockwise convex hull (m, 2) of 2D points (Andrew's monotone chain)."""
    pts = sorted(set(map(tuple, np.asarray(points, dtype=float))))
    if len(pts) < 3:
        return np.array(pts).reshape(-1, 2)

    def turns_left(a: Sequence[float], b: Sequence[float], c: Sequence[float]) -> bool:
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0

    def half(seq: Iterable[tuple[float, ...]]) -> list[tuple[float, ...]]:
        chain: list[tuple[float, ...]] = []
        for p in seq:
            while len(chain) >= 2 and not turns_left(chain[-2], chain[-1], p):
                chain.pop()
            chain.append(p)
        return chain

    lower, upper = half(pts), half(reversed(pts))
    return np.array(lower[:-1] + upper[:-1])


def clip_polygon(polygon: Iterable[Sequence[float]], width: float,
                 height: float) -> npt.NDArray[np.float64]:
    """Sutherland-Hodgman: the convex polygon (m, 2) cut to the image [0, width] x [0, height]."""
    poly = [tuple(p) for p in polygon]
    for axis, bound, keep_below in ((0, 0.0, False), (0, width, True),
                                    (1, 0.0, False), (1, height, True)):
        def inside(p: Sequence[float]) -> bool:
            return p[axis] <= bound if keep_below else p[axis] >= bound
        out: list[tuple[float, ...]] = []
        for k, p in enumerate(poly):
            q = poly[k - 1]
            if inside(p) != inside(q):
                t = (bound - q[axis]) / (p[axis] - q[axis])
                out.append((q[0] + t * (p[0] - q[0]), q[1] + t * (p[1] - q[1])))
            if inside(p):
                out.append(p)
        poly = out
        if not poly:
            break
    return np.array(poly).reshape(-1, 2)


def visible_extent(corners: np.ndarray, robot_pose: Sequence[float],
                   camera: CameraConfig) -> Extent | None:
    """(u0, v0, u1, v1) [px] bounding the part of the object's box (8 map-frame corners) that one
    camera's image shows, or None when none of it is in the image."""
    pc = clip_to_near_plane(camera_points(corners, robot_pose, camera))
    if len(pc) < 3:
        return None
    uv = np.column_stack([camera.fx * pc[:, 0] / pc[:, 2] + camera.cx,
                          camera.fy * pc[:, 1] / pc[:, 2] + camera.cy])
    hull = convex_hull(uv)
    if len(hull) < 3:
        return None
    seen = clip_polygon(hull, camera.width, camera.height)
    if len(seen) < 3:
        return None
    (u0, v0), (u1, v1) = seen.min(axis=0), seen.max(axis=0)
    if u1 - u0 <= 0.0 or v1 - v0 <= 0.0:
        return None
    return u0, v0, u1, v1


def stitched_extent(corners: np.ndarray, robot_pose: Sequence[float], top: CameraConfig,
                    bottom: CameraConfig) -> Extent | None:
    """Visible extent of an object in the stitched frame: the top and bottom cameras' parts
    (bottom rows offset by the top image's height) joined into one box, or None."""
    parts: list[Extent] = []
    for camera, row_offset in ((top, 0.0), (bottom, float(top.height))):
        part = visible_extent(corners, robot_pose, camera)
        if part is not None:
            parts.append((part[0], part[1] + row_offset, part[2], part[3] + row_offset))
    if not parts:
        return None
    joined = np.array(parts)
    (u0, v0), (u1, v1) = joined[:, :2].min(axis=0), joined[:, 2:].max(axis=0)
    return u0, v0, u1, v1


def hidden_by_boxes(points: npt.ArrayLike, eye: np.ndarray, boxes: Iterable[Sequence[Any]],
                    margin: float = 0.2) -> npt.NDArray[np.bool_]:
    """True for each map-frame point (n, 3) that a solid box hides from `eye` (3,): the sight
    line, stopped `margin` m short of the point (a body touching a sofa is not behind it),
    crosses a box [(x, y, yaw, elevation, (sx, sy, sz))] (slab test in the box's frame)."""
    points = np.asarray(points, dtype=float)
    hidden = np.zeros(len(points), dtype=bool)
    direction = points - eye
    length = np.linalg.norm(direction, axis=1)
    stop = np.clip((length - margin) / np.maximum(length, 1e-9), 0.0, 1.0)
    for x, y, yaw, elevation, size in boxes:
        c, s = math.cos(yaw), math.sin(yaw)
        ex, ey = eye[0] - x, eye[1] - y
        origin = np.array([c * ex + s * ey, -s * ex + c * ey, eye[2] - elevation])
        d = np.column_stack([c * direction[:, 0] + s * direction[:, 1],
                             -s * direction[:, 0] + c * direction[:, 1], direction[:, 2]])
        low = np.array([-size[0] / 2.0, -size[1] / 2.0, 0.0])
        high = np.array([size[0] / 2.0, size[1] / 2.0, size[2]])
        with np.errstate(divide="ignore", invalid="ignore"):
            t0, t1 = (low - origin) / d, (high - origin) / d
        near = np.where(d == 0, np.where((origin >= low) & (origin <= high), -np.inf, np.inf),
                        np.minimum(t0, t1)).max(axis=1)
        far = np.where(d == 0, np.where((origin >= low) & (origin <= high), np.inf, -np.inf),
                       np.maximum(t0, t1)).min(axis=1)
        hidden |= (near <= far) & (far >= 0.0) & (near <= stop)
    return hidden


class Camera:
    """The robot's stacked cameras plus the detector models that read them."""

    def __init__(self, top: CameraConfig, bottom: CameraConfig, detection: DetectionConfig,
                 occluders: GridGeometry, model: DetectionModel | None = None) -> None:
        self.top, self.bottom, self.detection = top, bottom, detection
        self.occluders = occluders          # GridGeometry of what blocks the view (walls)
        self.model: DetectionModel = model if model is not None else IdealModel(detection)
        self.rng = np.random.default_rng(detection.seed)

    @property
    def frame_size(self) -> tuple[int, int]:
        return self.top.width, self.top.height + self.bottom.height

    def eye(self, robot_pose: Sequence[float]) -> npt.NDArray[np.float64]:
        """Map-frame (3,) position of the top camera."""
        x, y, yaw = robot_pose
        return np.array([x + math.cos(yaw) * self.top.mount_x,
                         y + math.sin(yaw) * self.top.mount_x, self.top.mount_height])

    def apparent_height(self, points: np.ndarray, robot_pose: Sequence[float]) -> float:
        """[px] the body (n, 3 map-frame points) would span in an unbounded image: its larger
        extent (height, or length across the view for a lying body) over its depth."""
        eye = self.eye(robot_pose)
        centre = points.mean(axis=0)
        depth = max(float(np.hypot(*(centre[:2] - eye[:2]))), NEAR_PLANE)
        spread = max(float(np.ptp(points[:, 2])), float(np.hypot(np.ptp(points[:, 0]),
                                                                 np.ptp(points[:, 1]))))
        return self.top.fy * spread / depth

    def in_line_of_sight(self, robot_pose: Sequence[float],
                         targets: Sequence[Sequence[float]]) -> npt.NDArray[np.bool_]:
        """True for each map-frame (x, y) target that no occluder hides from the camera."""
        if len(targets) == 0:
            return np.zeros(0, dtype=bool)
        x, y, yaw = robot_pose
        ox, oy = x + math.cos(yaw) * self.top.mount_x, y + math.sin(yaw) * self.top.mount_x
        t = np.asarray(targets, dtype=float)
        dist = np.hypot(t[:, 0] - ox, t[:, 1] - oy)
        bearing = np.arctan2(t[:, 1] - oy, t[:, 0] - ox) - yaw
        bearing = (bearing + np.pi) % (2 * np.pi) - np.pi
        # candidates: in range and not behind the camera (the projection decides the rest)
        candidate = (dist <= self.detection.max_range) & (np.abs(bearing) < np.pi / 2)
        clear = np.zeros(len(t), dtype=bool)
        clear[candidate] = segments_clear(self.occluders, ox, oy, t[candidate])
        return clear

    def _confidence(self) -> float:
        low, high = self.detection.confidence_range
        return float(self.rng.uniform(low, high))

    def _box(self, u: np.ndarray, v: np.ndarray) -> tuple[int, int, int, int]:
        w, h = self.frame_size
        x0, x1 = max(0, int(np.floor(u.min()))), min(w - 1, int(np.ceil(u.max())))
        y0, y1 = max(0, int(np.floor(v.min()))), min(h - 1, int(np.ceil(v.max())))
        return x0, y0, x1 - x0, y1 - y0

    def detect_objects(self, objects: Sequence[tuple[str, str, npt.ArrayLike, np.ndarray]],
                       robot_pose: Sequence[float], lighting: Sequence[str] | None = None,
                       labels: Iterable[str] = ()) -> list[ObjectDetection]:
        """YOLO-like boxes of the objects [(name, label, corners (8, 3), centre (3,))]: the box of
        each object's visible projection in the stitched frame (see `stitched_extent`).

        `lighting` (name per object) turns on the calibrated model's misses by apparent size and
        its label confusions among `labels`; without it every object in view is boxed."""
        if not objects:
            return []
        centres = np.array([o[3] for o in objects])
        depth = camera_points(centres, robot_pose, self.top)[:, 2]
        detections = []
        for i, (name, label, corners, _) in enumerate(objects):
            extent = stitched_extent(np.asarray(corners, dtype=float), robot_pose,
                                     self.top, self.bottom)
            if extent is None:
                continue
            u0, v0, u1, v1 = extent
            if lighting is not None:
                if self.model.object_missed(self.rng, math.sqrt((u1 - u0) * (v1 - v0)),
                                            lighting[i]):
                    continue
                label = self.model.label(self.rng, label, lighting[i], labels)
            x, y, w, h = self._box(np.array([u0, u1]), np.array([v0, v1]))
            d = float(depth[i])
            detections.append(ObjectDetection(label, self._confidence(), x, y, w, h,
                                              d + self._depth_noise(d), truth=name))
        return detections

    def false_detections(self, lighting: str, labels: Iterable[str]) -> list[ObjectDetection]:
        """Boxes of nothing (a calibrated detector's false people and objects) for one frame."""
        people, others = self.model.false_counts(self.rng, lighting)
        width, height = self.frame_size
        out = []
        for label in ["person"] * people + [str(self.rng.choice(sorted(labels)))
                                            for _ in range(others if labels else 0)]:
            w, h = (int(v) for v in self.rng.uniform(20, 200, 2))
            x, y = int(self.rng.uniform(0, width - w)), int(self.rng.uniform(0, height - h))
            out.append(ObjectDetection(label, self._confidence(), x, y, w, h,
                                       float(self.rng.uniform(1.0, self.detection.max_range))))
        return out

    def _depth_noise(self, depth: float) -> float:
        sigma = self.detection.depth_noise + self.detection.depth_noise_fraction * abs(depth)
        return float(self.rng.normal(0.0, sigma))

    def detect_person(self, name: str, keypoints: np.ndarray, shirt_colour: Sequence[Any],
                      robot_pose: Sequence[float], hidden: Iterable[int] = (),
                      lighting: str = "daylight", hidden_fraction: float = 0.0
                      ) -> tuple[SkeletonDetection | None, ObjectDetection | None]:
        """OpenPose-like skeleton plus a YOLO 'person' box that contains every keypoint; the
        skeleton is None when the pose model misses a person the box detector found.

        `hidden` lists keypoints the body itself or the furniture hides (the face of a person
        seen from behind, legs behind a sofa); `hidden_fraction` is furniture's share of them.
        """
        u, v, visible, depth = project_stacked(keypoints, robot_pose, self.top, self.bottom)
        visible[list(hidden)] = False
        if visible.sum() < 2:
            return None, None
        det = self.detection
        sigma = self.model.keypoint_sigma(self.apparent_height(keypoints, robot_pose))
        noise = self.rng.normal(0.0, sigma, size=(2, NUM_KEYPOINTS))
        w, h = self.frame_size
        u = np.clip(u + noise[0], 0, w - 1)
        v = np.clip(v + noise[1], 0, h - 1)
        low, high = det.confidence_range
        conf = np.where(visible, self.rng.uniform(low, high, NUM_KEYPOINTS), 0.0)
        depth_sigma = det.depth_noise + det.depth_noise_fraction * np.nan_to_num(depth)
        depth = np.where(visible, depth + self.rng.normal(0.0, 1.0, NUM_KEYPOINTS) * depth_sigma,
                         np.nan)
        u, v = np.where(visible, u, 0.0), np.where(visible, v, 0.0)
        colours = np.zeros((3, 3), dtype=np.uint8)
        for i, joint in enumerate(COLOUR_JOINTS):
            if visible[joint]:
                colours[i] = self.model.observed_colour(self.rng, shirt_colour[i], lighting)
        skeleton = SkeletonDetection(u, v, conf, depth, colours, truth=name)
        bu, bv = u[visible], v[visible]
        mu = det.box_margin * max(bu.max() - bu.min(), 1.0)
        mv = det.box_margin * max(bv.max() - bv.min(), 1.0)
        x, y, bw, bh = self._box(np.array([bu.min() - mu, bu.max() + mu]),
                                 np.array([bv.min() - mv, bv.max() + mv]))
        box = ObjectDetection("person", self._confidence(), x, y, bw, bh,
                              float(np.nanmean(depth[visible])), truth=name)
        if self.model.pose_missed(self.rng, hidden_fraction, lighting):
            return None, box
        return skeleton, box

    def person_missed(self, keypoints: np.ndarray, robot_pose: Sequence[float],
                      hidden_fraction: float, lighting: str) -> bool:
        """Whether the box detector misses this person (the model's miss rate)."""
        return self.model.person_missed(self.rng, self.apparent_height(keypoints, robot_pose),
                                        hidden_fraction, lighting)

    def missed(self) -> bool:
        return self.rng.random() < self.detection.miss_probability
