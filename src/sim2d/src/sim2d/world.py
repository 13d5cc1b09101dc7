"""The simulated world: map, robots with lasers, odometry and cameras, people and objects.

`World.step(dt)` advances everything by dt seconds of simulated time: people follow their
schedules, held objects follow the hands, robots integrate their commands against the map
(stall on contact), odometry drifts, and each laser produces a scan whenever its scan period has
elapsed. Camera frames are computed on request (`camera_frame`).
"""
import copy
import math
import os
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt

from sim2d.camera import Camera, CameraFrame, hidden_by_boxes, hidden_face
from sim2d.detection_model import make_detection_model
from sim2d.kinematics import DIFFERENTIAL, RobotState, step_robot, wheels_to_twist
from sim2d.laser import LaserSensor
from sim2d.laser_batch import batch_key, scan_many
from floorplan.occupancy_map import load_map
from sim2d.odometry import Odometry
from sim2d.people import Person
from sim2d.raycast import GridGeometry, RangeTable, RangeTableConfig, distance_transform
from sim2d.skeleton import L_SHOULDER, R_SHOULDER, person_keypoints
from sim2d.world_config import (LaserMount, RobotConfig, WorldConfig, WorldError,
                                load_world_config)

CACHE_DIR = Path(os.environ.get("SIM2D_CACHE", Path.home() / ".cache" / "sim2d"))
TABLE_MARGIN = 0.05     # [m] extra clearance given up so the table covers every reachable pose
SURFACE_MARGIN = 0.15   # [m] a held point this far off a table's edge still rests on the table
SURFACE_BELOW_SHOULDERS = 0.1   # [m] furniture higher than the shoulders less this is no surface


class CommandError(ValueError):
    """A velocity command that cannot be executed (NaN, infinite)."""


@dataclass
class Scan:
    stamp: float            # [s] sim time at which the scan was taken
    ranges: np.ndarray      # float32 [m]
    count: int              # scans of this laser so far


@dataclass
class SimObject:
    name: str
    label: str
    pose: tuple             # (x, y, yaw)
    elevation: float        # [m]
    size: tuple             # (x, y, z) [m]
    held_by: str = ""

    def centre(self) -> npt.NDArray[np.float64]:
        return np.array([self.pose[0], self.pose[1], self.elevation + self.size[2] / 2.0])

    def covers(self, x: float, y: float, margin: float = 0.0) -> bool:
        """Whether map point (x, y) lies over the object's footprint grown by `margin` [m]."""
        c, s = math.cos(self.pose[2]), math.sin(self.pose[2])
        dx, dy = x - self.pose[0], y - self.pose[1]
        return (abs(c * dx + s * dy) <= self.size[0] / 2.0 + margin
                and abs(-s * dx + c * dy) <= self.size[1] / 2.0 + margin)

    def corners(self) -> npt.NDArray[np.float64]:
        """The 8 corners (8, 3) of the object's box in the map frame."""
        x, y, yaw = self.pose
        hx, hy = self.size[0] / 2.0, self.size[1] / 2.0
        c, s = math.cos(yaw), math.sin(yaw)
        out = []
        for dx in (-hx, hx):
            for dy in (-hy, hy):
                for z in (self.elevation, self.elevation + self.size[2]):
                    out.append((x + c * dx - s * dy, y + s * dx + c * dy, z))
        return np.array(out)


@dataclass
class Robot:
    config: RobotConfig
    state: RobotState
    odometry: Odometry
    lasers: list                         # [LaserSensor]
    laser_mounts: list                   # [LaserMount]
    camera: Camera | None = None
    scans: list = field(default_factory=list)   # latest Scan per laser (None before the first)
    next_scan: list = field(default_factory=list)

    @property
    def name(self) -> str:
        return self.config.name


def new_odometry(robot_config: RobotConfig, pose: Sequence[float]) -> Odometry:
    """Odometry that starts at `pose`, with the noise model of the robot's drive."""
    return Odometry(robot_config.odometry, pose, holonomic=robot_config.drive != DIFFERENTIAL)


class World:
    """Everything in one simulated building, stepped without ROS."""

    def __init__(self, config: WorldConfig, cache_dir: str | Path | None = CACHE_DIR,
                 lazy_tables: bool = False) -> None:
        """cache_dir: where range tables are kept (None: not kept); lazy_tables: a range table
        that is not cached fills its rows as the lasers need them (always so without a
        cache_dir) instead of tabulating the whole map first."""
        self.config = config
        self.time = 0.0
        self.grid = load_map(config.map_path)
        self.geometry = GridGeometry.from_map(self.grid)
        self.camera_geometry = self._camera_geometry(config.camera_transparent)
        self.doors = {d.name: d.closed for d in config.doors}   # name -> closed
        self._door_boxes = {d.name: tuple(d.box) for d in config.doors}
        self.closed_boxes: list[tuple[float, ...]] = []
        self.collision_geometry = self.geometry
        self._apply_doors()
        self.cache_dir = cache_dir
        self.lazy_tables = lazy_tables or cache_dir is None
        self._tables: dict[tuple[float, float], RangeTable] = {}
        self._held: dict[str, tuple] = {}   # person name -> (pose, posture, holding) last applied
        self._surfaces: dict[str, tuple] = {}   # person name -> ((pose, posture, holding),
        #                                         surface_under_hands then)
        self.people = copy.deepcopy(config.people)   # the world's own, moving copies
        self.objects = {o.name: SimObject(o.name, o.label, tuple(o.pose), o.elevation, o.size)
                        for o in config.objects}
        self.robots = [self._make_robot(rc, i) for i, rc in enumerate(config.robots)]
        self.batch_scans = True   # lasers of one model scan together (laser_batch); same scans
        self._update_people(0.0)

    @classmethod
    def from_file(cls, path: str | Path, laser_dir: str | Path | None = None,
                  cache_dir: str | Path | None = CACHE_DIR, raycast: str | None = None,
                  lazy_tables: bool = False) -> "World":
        """Load a world file; raycast ("march" or "table") overrides every laser's choice."""
        config = load_world_config(path, laser_dir)
        if raycast:
            if raycast not in ("march", "table"):
                raise WorldError(f"raycast override must be 'march' or 'table', got {raycast!r}")
            for robot in config.robots:
                for laser in robot.lasers:
                    laser.raycast = raycast
        return cls(config, cache_dir, lazy_tables)

    def _camera_geometry(self, transparent: Sequence[Sequence[float]]) -> GridGeometry:
        if not transparent:
            return self.geometry
        occupied = self.geometry.occupied.copy()
        for x0, y0, x1, y1 in transparent:
            r0, c0 = self.grid.world_to_cell(min(x0, x1), min(y0, y1))
            r1, c1 = self.grid.world_to_cell(max(x0, x1), max(y0, y1))
            occupied[max(r0, 0):r1 + 1, max(c0, 0):c1 + 1] = False
        return GridGeometry(occupied, distance_transform(occupied), self.geometry.resolution,
                            self.geometry.origin_x, self.geometry.origin_y)

    def _table(self, laser_mount: LaserMount, robot_config: RobotConfig) -> RangeTable:
        reach = math.hypot(laser_mount.mount[0], laser_mount.mount[1])
        table_config = RangeTableConfig(max_range=laser_mount.model.range_max)
        table_config.min_clearance = max(
            0.0, robot_config.radius - reach - 0.75 * table_config.cell_size - TABLE_MARGIN)
        key = (table_config.max_range, table_config.min_clearance)
        if key not in self._tables:
            self._tables[key] = RangeTable.build(self.geometry, table_config, self.cache_dir,
                                                 lazy=self.lazy_tables)
        return self._tables[key]

    def _make_robot(self, rc: RobotConfig, index: int) -> Robot:
        clearance = float(self.collision_geometry.clearance(rc.pose[0], rc.pose[1]))
        if clearance < rc.radius:
            raise WorldError(f"{self.config.path}: robot {rc.name!r} at ({rc.pose[0]:.2f}, "
                             f"{rc.pose[1]:.2f}) is inside or touching an obstacle (clearance "
                             f"{clearance:.2f} m < radius {rc.radius:.2f} m)")
        lasers = []
        for j, mount in enumerate(rc.lasers):
            table = self._table(mount, rc) if mount.raycast == "table" else None
            lasers.append(LaserSensor(mount.model, mount.mount, self.geometry, table,
                                      seed=mount.seed + 1000 * index + j))
        camera = None
        if rc.camera is not None:
            camera = Camera(rc.camera.top, rc.camera.bottom, rc.camera.detection,
                            self.camera_geometry,
                            make_detection_model(rc.camera.detection, rc.camera.calibration))
        return Robot(rc, RobotState(pose=tuple(rc.pose)), new_odometry(rc, rc.pose),
                     lasers, list(rc.lasers), camera, [None] * len(lasers),
                     [laser.model.scan_time for laser in lasers])

    def set_door(self, name: str, closed: bool) -> None:
        """Open or close door `name`: a closed door blocks robots and lasers (not the camera).

        The map (and the lasers' range table) stay static: the laser casts the closed doors
        exactly on top of it, and collisions use a copy of the grid with the door cells occupied.
        Raises KeyError naming the known doors for an unknown name.
        """
        if name not in self.doors:
            known = ", ".join(sorted(self.doors)) or "none"
            raise KeyError(f"no door named {name!r} (doors: {known})")
        if self.doors[name] != bool(closed):
            self.doors[name] = bool(closed)
            self._apply_doors()

    def _apply_doors(self) -> None:
        self.closed_boxes = [self._door_boxes[n] for n, closed in self.doors.items() if closed]
        if not self.closed_boxes:
            self.collision_geometry = self.geometry
            return
        occupied = self.geometry.occupied.copy()
        for x0, y0, x1, y1 in self.closed_boxes:
            r0, c0 = self.grid.world_to_cell(x0, y0)
            r1, c1 = self.grid.world_to_cell(x1, y1)
            occupied[max(r0, 0):r1 + 1, max(c0, 0):c1 + 1] = True
        self.collision_geometry = GridGeometry(occupied, distance_transform(occupied),
                                               self.geometry.resolution, self.geometry.origin_x,
                                               self.geometry.origin_y)

    def robot(self, name: str) -> Robot:
        for robot in self.robots:
            if robot.name == name:
                return robot
        raise KeyError(f"no robot named {name!r}")

    def place_robot(self, name: str, pose: Sequence[float]) -> None:
        """Teleport a robot (e.g. to start an episode): at rest, odometry restarted at zero.

        Raises WorldError if the pose is inside or against an obstacle.
        """
        robot = self.robot(name)
        clearance = self.collision_geometry.clearance_at(pose[0], pose[1])
        if clearance < robot.config.radius:
            raise WorldError(f"robot {name!r} cannot be placed at ({pose[0]:.2f}, {pose[1]:.2f}): "
                             f"clearance {clearance:.2f} m < radius {robot.config.radius:.2f} m")
        robot.state = RobotState(pose=tuple(float(v) for v in pose))
        robot.odometry = new_odometry(robot.config, robot.state.pose)
        robot.scans = [None] * len(robot.lasers)
        robot.next_scan = [self.time + laser.model.scan_time for laser in robot.lasers]

    # --- commands -------------------------------------------------------------------------
    def set_twist(self, name: str, vx: float, vy: float, wz: float) -> None:
        """Body twist command [m/s, m/s, rad/s]; a NaN or infinite value is refused."""
        if not all(math.isfinite(v) for v in (vx, vy, wz)):
            raise CommandError(f"robot {name!r}: non-finite velocity command ({vx}, {vy}, {wz})")
        robot = self.robot(name)
        if robot.config.drive == DIFFERENTIAL and abs(vy) > 0.0:
            raise CommandError(f"robot {name!r} is differential drive: lateral velocity {vy} "
                               f"cannot be executed")
        robot.state.command = (float(vx), float(vy), float(wz))

    def set_wheel_speeds(self, name: str, left: float, right: float) -> None:
        """Differential drive: wheel speed command (left, right) [rad/s]."""
        robot = self.robot(name)
        if robot.config.drive != DIFFERENTIAL:
            raise CommandError(f"robot {name!r} is holonomic; it takes twist commands")
        if not (math.isfinite(left) and math.isfinite(right)):
            raise CommandError(f"robot {name!r}: non-finite wheel command ({left}, {right})")
        if robot.config.wheels is None:
            raise CommandError(f"robot {name!r} is differential drive without a wheel config")
        v, w = wheels_to_twist(left, right, robot.config.wheels)
        robot.state.command = (v, 0.0, w)

    # --- stepping -------------------------------------------------------------------------
    def _update_people(self, dt: float) -> None:
        for person in self.people:
            person.step(self.time, dt)
        for person in self.people:
            key = (person.pose, person.posture, person.holding)
            if self._held.get(person.name) == key:
                continue                      # nothing moved: the held object stays put
            self._held[person.name] = key
            for obj in self.objects.values():
                if obj.held_by == person.name:
                    obj.held_by = ""
            if person.holding and person.holding in self.objects:
                _, hold = person_keypoints(person.posture, person.pose, holding=True,
                                           surface=self._surface(person))
                if hold is not None:
                    obj = self.objects[person.holding]
                    obj.pose = (hold[0], hold[1], person.pose[2])
                    obj.elevation = hold[2] - obj.size[2] / 2.0
                    obj.held_by = person.name

    def surface_under_hands(self, person: Person) -> float | None:
        """The top [m] of the furniture a person's held point would otherwise be under (a table
        or desk in front of a seated person, lower than the shoulders), or None: the hands rest
        on it (skeleton.hold_in_hands)."""
        if not person.holding:
            return None
        keypoints, hold = person_keypoints(person.posture, person.pose, holding=True)
        if hold is None:
            return None
        shoulders = float(keypoints[[R_SHOULDER, L_SHOULDER], 2].mean())
        tops = [o.elevation + o.size[2] for o in self.objects.values()
                if not o.held_by and o.name != person.holding
                and hold[2] < o.elevation + o.size[2] < shoulders - SURFACE_BELOW_SHOULDERS
                and o.covers(hold[0], hold[1], SURFACE_MARGIN)]
        return max(tops) if tops else None

    def _surface(self, person: Person) -> float | None:
        """surface_under_hands, computed again only when the person moved, sat or lay down, or
        took something else in hand (every camera frame asks for every person)."""
        key = (person.pose, person.posture, person.holding)
        cached = self._surfaces.get(person.name)
        if cached is None or cached[0] != key:
            cached = self._surfaces[person.name] = (key, self.surface_under_hands(person))
        return cached[1]

    def _obstacle_circles(self, exclude: Robot | None) -> list[tuple[float, float, float]]:
        circles = [(p.pose[0], p.pose[1], p.radius) for p in self.people]
        circles += [(r.state.pose[0], r.state.pose[1], r.config.radius)
                    for r in self.robots if r is not exclude]
        return circles

    def step(self, dt: float) -> None:
        """Advance the world by dt [s]: every robot moves, then the lasers due scan the world as
        it stands at the new time."""
        if not dt > 0:
            raise ValueError(f"step needs dt > 0, got {dt}")
        self.time += dt
        if self.people:
            self._update_people(dt)
        clearance = self.collision_geometry.clearance_at
        due: list[tuple[Robot, int]] = []
        for robot in self.robots:
            rc = robot.config
            step_robot(robot.state, rc.drive, rc.limits, rc.radius,
                       clearance, dt, rc.wheels)
            robot.odometry.update(robot.state.pose)
            due += [(robot, j) for j in range(len(robot.lasers))
                    if self.time + 1e-9 >= robot.next_scan[j]]
        if due:
            self._scan(due)

    def _scan(self, due: Sequence[tuple[Robot, int]]) -> None:
        """Scan the lasers `due` [(robot, laser index)]: lasers of one model and table together
        (laser_batch) when `batch_scans` is on, the others one by one; the same scans either
        way."""
        crowded = bool(self.people) or len(self.robots) > 1
        groups: dict[tuple, list[tuple[Robot, int]]] = {}
        for robot, j in due:
            key = batch_key(robot.lasers[j]) if self.batch_scans else None
            groups.setdefault(key if key is not None else (id(robot), j), []).append((robot, j))
        circles: np.ndarray | None = None
        owners: dict[int, int] = {}   # id(robot) -> its row in `circles`
        for members in groups.values():
            scans = None
            if len(members) > 1:
                if circles is None and crowded:
                    circles = np.array(self._obstacle_circles(None), dtype=float)
                    owners = {id(r): len(self.people) + i for i, r in enumerate(self.robots)}
                scans = scan_many([robot.lasers[j] for robot, j in members],
                                  [robot.state.pose for robot, _ in members], circles,
                                  [owners[id(robot)] for robot, _ in members] if crowded
                                  else None, self.closed_boxes)
            for k, (robot, j) in enumerate(members):
                ranges = scans[k] if scans is not None else robot.lasers[j].scan(
                    robot.state.pose, self._obstacle_circles(robot) if crowded else (),
                    self.closed_boxes)
                count = 1 if robot.scans[j] is None else robot.scans[j].count + 1
                robot.scans[j] = Scan(self.time, ranges, count)
                robot.next_scan[j] += robot.lasers[j].model.scan_time

    # --- camera ---------------------------------------------------------------------------
    def camera_frame(self, name: str) -> CameraFrame:
        """Detections of robot `name`'s camera at the current time (CameraFrame)."""
        robot = self.robot(name)
        camera = robot.camera
        if camera is None:
            raise KeyError(f"robot {name!r} has no camera")
        pose = robot.state.pose
        width, height = camera.frame_size
        frame = CameraFrame(width, height)
        people = list(self.people)
        objects = list(self.objects.values())
        targets = [p.pose[:2] for p in people] + [o.pose[:2] for o in objects]
        seen = camera.in_line_of_sight(pose, targets)
        ideal = camera.model.name == "ideal"
        blockers = [] if ideal else [(o.pose[0], o.pose[1], o.pose[2], o.elevation, o.size)
                                     for o in objects if not o.held_by]
        for person, visible in zip(people, seen[:len(people)]):
            if not visible:
                continue
            look = self.objects[person.looking_at].centre() if person.looking_at else None
            keypoints, _ = person_keypoints(person.posture, person.pose,
                                            holding=bool(person.holding), look_target=look,
                                            surface=self._surface(person))
            lighting = self.config.lighting_at(*person.pose[:2])
            hidden = list(hidden_face(keypoints, pose))
            behind = (hidden_by_boxes(keypoints, camera.eye(pose), blockers) if blockers
                      else np.zeros(len(keypoints), dtype=bool))
            share = float(behind.mean())
            if camera.person_missed(keypoints, pose, share, lighting):
                continue
            skeleton, box = camera.detect_person(
                person.name, keypoints, person.shirt_colour, pose,
                hidden=sorted(set(hidden) | set(np.flatnonzero(behind).tolist())),
                lighting=lighting, hidden_fraction=share)
            if skeleton is not None:
                frame.skeletons.append(skeleton)
            if box is not None and (skeleton is not None or not ideal):
                frame.objects.append(box)
        if ideal:
            candidates = [(o.name, o.label, o.corners(), o.centre())
                          for o, visible in zip(objects, seen[len(people):])
                          if visible and not camera.missed()]
            frame.objects.extend(camera.detect_objects(candidates, pose))
            return frame
        shown = [o for o, visible in zip(objects, seen[len(people):]) if visible]
        labels = sorted({o.label for o in objects})
        frame.objects.extend(camera.detect_objects(
            [(o.name, o.label, o.corners(), o.centre()) for o in shown], pose,
            lighting=[self.config.lighting_at(*o.pose[:2]) for o in shown], labels=labels))
        frame.objects.extend(camera.false_detections(self.config.lighting_at(*pose[:2]), labels))
        return frame
