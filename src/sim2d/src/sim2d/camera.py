"""Pinhole camera model: what YOLO and OpenPose would report for the visible people and objects.

Two identical cameras stacked vertically as on Pepper (thesis 000 Sec. 3.2.1, image stitching):
the top camera's image lies above the bottom camera's, so the stitched frame is width x 2*height.
Projection is the inverse of the thesis' Eqs. 3-3..3-5: u = fx * x / z + cx, v = fy * y / z + cy.
"""
import math
from dataclasses import dataclass, field

import numpy as np

from sim2d.raycast import segments_clear
from sim2d.skeleton import L_SHOULDER, NECK, NUM_KEYPOINTS, R_SHOULDER

COLOUR_JOINTS = (NECK, R_SHOULDER, L_SHOULDER)   # shirt colour sampled here (thesis 000 Sec. 3.2.3)


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
class DetectionConfig:
    """How good the simulated detectors are."""

    max_range: float = 6.0              # [m] nothing is detected farther away
    miss_probability: float = 0.05      # [-] chance a visible person or object is missed
    keypoint_noise: float = 2.0         # [px] 1 sigma
    depth_noise: float = 0.02           # [m] 1 sigma, plus depth_noise_fraction * depth
    depth_noise_fraction: float = 0.01  # [-]
    colour_noise: float = 6.0           # [0-255] 1 sigma on shirt colour channels
    confidence_range: tuple = (0.6, 0.95)  # [-] detector confidences are drawn from this range
    box_margin: float = 0.08            # [-] person box grows by this fraction per side
    seed: int = 0


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


def camera_points(points, robot_pose, camera):
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


def project(points_cam, camera):
    """Pinhole projection (inverse of thesis 000 Eqs. 3-3, 3-4): (u, v, in_image) per point."""
    z = points_cam[:, 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = camera.fx * points_cam[:, 0] / z + camera.cx
        v = camera.fy * points_cam[:, 1] / z + camera.cy
    inside = (z > 0.05) & (u >= 0) & (u < camera.width) & (v >= 0) & (v < camera.height)
    return u, v, inside


def project_stacked(points, robot_pose, top, bottom):
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


class Camera:
    """The robot's stacked cameras plus the detector models that read them."""

    def __init__(self, top, bottom, detection, occluders):
        self.top, self.bottom, self.detection = top, bottom, detection
        self.occluders = occluders          # GridGeometry of what blocks the view (walls)
        self.rng = np.random.default_rng(detection.seed)

    @property
    def frame_size(self):
        return self.top.width, self.top.height + self.bottom.height

    def in_line_of_sight(self, robot_pose, targets):
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

    def _confidence(self):
        low, high = self.detection.confidence_range
        return float(self.rng.uniform(low, high))

    def _box(self, u, v):
        w, h = self.frame_size
        x0, x1 = max(0, int(np.floor(u.min()))), min(w - 1, int(np.ceil(u.max())))
        y0, y1 = max(0, int(np.floor(v.min()))), min(h - 1, int(np.ceil(v.max())))
        return x0, y0, x1 - x0, y1 - y0

    def detect_objects(self, objects, robot_pose):
        """YOLO-like boxes of the objects [(name, label, corners (8, 3), centre (3,))] whose
        3D box projects into the frame (all objects projected in one call)."""
        if not objects:
            return []
        corners = np.concatenate([o[2] for o in objects])
        centres = np.array([o[3] for o in objects])
        u, v, visible, _ = project_stacked(corners, robot_pose, self.top, self.bottom)
        depth = camera_points(centres, robot_pose, self.top)[:, 2]
        detections = []
        for i, (name, label, _, _) in enumerate(objects):
            seen = visible[8 * i:8 * i + 8]
            if not seen.any():
                continue
            x, y, w, h = self._box(u[8 * i:8 * i + 8][seen], v[8 * i:8 * i + 8][seen])
            d = float(depth[i])
            detections.append(ObjectDetection(label, self._confidence(), x, y, w, h,
                                              d + self._depth_noise(d), truth=name))
        return detections

    def _depth_noise(self, depth):
        sigma = self.detection.depth_noise + self.detection.depth_noise_fraction * abs(depth)
        return float(self.rng.normal(0.0, sigma))

    def detect_person(self, name, keypoints, shirt_colour, robot_pose, hidden=()):
        """OpenPose-like skeleton plus a YOLO 'person' box that contains every keypoint.

        `hidden` lists keypoints the body itself hides (the face of a person seen from behind).
        """
        u, v, visible, depth = project_stacked(keypoints, robot_pose, self.top, self.bottom)
        visible[list(hidden)] = False
        if visible.sum() < 2:
            return None, None
        det = self.detection
        noise = self.rng.normal(0.0, det.keypoint_noise, size=(2, NUM_KEYPOINTS))
        w, h = self.frame_size
        u = np.clip(u + noise[0], 0, w - 1)
        v = np.clip(v + noise[1], 0, h - 1)
        low, high = det.confidence_range
        conf = np.where(visible, self.rng.uniform(low, high, NUM_KEYPOINTS), 0.0)
        sigma = det.depth_noise + det.depth_noise_fraction * np.nan_to_num(depth)
        depth = np.where(visible, depth + self.rng.normal(0.0, 1.0, NUM_KEYPOINTS) * sigma, np.nan)
        u, v = np.where(visible, u, 0.0), np.where(visible, v, 0.0)
        colours = np.zeros((3, 3), dtype=np.uint8)
        for i, joint in enumerate(COLOUR_JOINTS):
            if visible[joint]:
                noisy = np.asarray(shirt_colour[i], dtype=float) + self.rng.normal(
                    0.0, det.colour_noise, 3)
                colours[i] = np.clip(np.rint(noisy), 0, 255).astype(np.uint8)
        skeleton = SkeletonDetection(u, v, conf, depth, colours, truth=name)
        bu, bv = u[visible], v[visible]
        mu = det.box_margin * max(bu.max() - bu.min(), 1.0)
        mv = det.box_margin * max(bv.max() - bv.min(), 1.0)
        x, y, bw, bh = self._box(np.array([bu.min() - mu, bu.max() + mu]),
                                 np.array([bv.min() - mv, bv.max() + mv]))
        box = ObjectDetection("person", self._confidence(), x, y, bw, bh,
                              float(np.nanmean(depth[visible])), truth=name)
        return skeleton, box

    def missed(self):
        return self.rng.random() < self.detection.miss_probability
