"""World description files (config/worlds/*.yaml): parsing and validation with clear errors.

See config/worlds/README.md for the format. Every error names the file and the offending entry.
"""
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn, TypeVar

from sim2d.camera import CameraConfig
from sim2d.detection_model import DetectionConfig
from sim2d.detection_model import DAYLIGHT, Calibration, CalibrationError, load_calibration
from sim2d.kinematics import DIFFERENTIAL, HOLONOMIC, DriveLimits, WheelConfig
from sim2d.laser import LaserModel, LaserModelError, find_laser_model
from floorplan.occupancy_map import load_map
from sim2d.odometry import OdometryConfig
from sim2d.passage_check import PassageCheck, PassageConfig, blockage_message, resting_poses
from sim2d.people import POSTURES, Person, ScheduleEntry
from floorplan.semantic_graph import SemanticGraph, load_graph
from supervision import config_file
from tamp_resources import resource

if TYPE_CHECKING:
    from _typeshed import DataclassInstance

D = TypeVar("D", bound="DataclassInstance")


class WorldError(config_file.ConfigError):
    """A world file that cannot be used; the message names the file and the problem."""


@dataclass
class LaserMount:
    model: LaserModel
    mount: tuple                # (x, y, yaw) in base_link [m, m, rad]
    mount_height: float = 0.3   # [m] (for the static tf only)
    frame: str = "base_laser"
    topic: str = "scan"
    raycast: str = "march"      # "march" (distance-transform ray marching) or "table" (LUT)
    seed: int = 0


@dataclass
class CameraRig:
    top: CameraConfig
    bottom: CameraConfig
    detection: DetectionConfig
    rate: float = 10.0          # [Hz] detection frames per second
    calibration: Calibration | None = None  # the calibrated model's table


@dataclass
class RobotConfig:
    name: str
    drive: str                  # "holonomic" or "differential"
    radius: float               # [m] circular footprint
    pose: tuple                 # start (x, y, yaw) [m, m, rad]
    namespace: str = ""         # ROS namespace ("" = global topics)
    limits: DriveLimits = field(default_factory=DriveLimits)
    wheels: WheelConfig | None = None   # differential drive only
    odometry: OdometryConfig = field(default_factory=OdometryConfig)
    lasers: list = field(default_factory=list)   # [LaserMount]
    camera: CameraRig | None = None


@dataclass
class ObjectConfig:
    name: str
    label: str                  # COCO class
    pose: tuple                 # (x, y, yaw) [m, m, rad]
    elevation: float            # [m] height of the object's base above the floor
    size: tuple                 # (length x, width y, height z) [m]


@dataclass
class WorldConfig:
    path: Path
    map_path: Path
    graph_path: Path | None = None
    robots: list = field(default_factory=list)
    people: list = field(default_factory=list)
    objects: list = field(default_factory=list)
    camera_transparent: list = field(default_factory=list)   # [[x0, y0, x1, y1]] [m]
    doors: list = field(default_factory=list)   # [DoorConfig]
    lighting: list = field(default_factory=list)   # [LightingZone]; daylight elsewhere

    def lighting_at(self, x: float, y: float) -> str:
        """Name of the lighting at map point (x, y): the first zone holding it, else daylight."""
        for zone in self.lighting:
            x0, y0, x1, y1 = zone.box
            if x0 <= x <= x1 and y0 <= y <= y1:
                return zone.condition
        return DAYLIGHT


@dataclass
class LightingZone:
    """A part of the home lit as one row of the camera calibration table says."""

    name: str
    box: tuple                  # (x0, y0, x1, y1) map-frame rectangle [m]
    condition: str              # a lighting row of the calibration table (dim, tungsten, ...)


@dataclass
class DoorConfig:
    """A door that can be closed at run time: a rectangle that becomes an obstacle."""

    name: str
    box: tuple                  # (x0, y0, x1, y1) map-frame rectangle of the closed leaf [m]
    closed: bool = False        # state at start


TOP_KEYS = ("base", "map", "graph", "camera_transparent", "doors", "lighting", "robots", "people",
            "objects")
LIGHTING_KEYS = ("name", "box", "condition")
ROBOT_KEYS = ("name", "namespace", "drive", "radius", "pose", "limits", "wheels", "odometry",
              "lasers", "camera")
LASER_KEYS = ("model", "mount") + tuple(k for k in LaserMount.__dataclass_fields__
                                        if k not in ("model", "mount"))
CAMERA_KEYS = ("rate", "top", "bottom", "detection")
PERSON_KEYS = ("name", "shirt_colour", "pose", "posture", "activity", "holding", "looking_at",
               "schedule", "radius", "walking_speed")
SHIRT_KEYS = ("joint1", "joint2", "joint5")
ENTRY_KEYS = ("time", "pose", "posture", "activity", "holding", "looking_at", "via",
              "shirt_colour")
OBJECT_KEYS = ("name", "label", "pose", "elevation", "size")
DOOR_KEYS = ("name", "box", "closed")
ELBOW_MARGIN = 0.05     # [m] a resting person's floor disc beyond the disc the lasers see


def check_keys(data: object, allowed: Sequence[str], where: str) -> dict[str, Any]:
    """Raise WorldError "<where>: unknown key ... (did you mean ...?)" for the first key of
    `data` not in `allowed`; `where` names the file and the field path."""
    return config_file.check_keys(data, allowed, where, WorldError)


def _dataclass_from(cls: type[D], data: Mapping[str, Any] | None, where: str) -> D:
    if data is None:
        return cls()
    check_keys(data, tuple(cls.__dataclass_fields__), where)
    return cls(**data)


def _number(value: Any, where: str) -> float:
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise WorldError(f"{where}: expected a number, got {value!r}") from None
    if not math.isfinite(number):
        raise WorldError(f"{where}: expected a finite number, got {value!r}")
    return number


class _Parser:
    def __init__(self, path: str | Path, laser_dir: str | Path | None) -> None:
        self.path = Path(path)
        self.laser_dir = Path(laser_dir) if laser_dir else resource("config", "lasers")
        self.graph: SemanticGraph | None = None

    def fail(self, message: str) -> NoReturn:
        raise WorldError(f"{self.path}: {message}")

    def pose(self, value: Any, where: str) -> tuple[float, ...]:
        if isinstance(value, str):
            if self.graph is None:
                self.fail(f"{where}: place name {value!r} needs a 'graph' file")
            try:
                return tuple(self.graph.place(value).pose)
            except KeyError as error:
                self.fail(f"{where}: {error.args[0]}")
        if not isinstance(value, (list, tuple)) or len(value) not in (2, 3):
            self.fail(f"{where}: pose must be [x, y, yaw] or a place name, got {value!r}")
        pose = [_number(v, f"{self.path}: {where}") for v in value]
        return tuple(pose + [0.0] * (3 - len(pose)))

    def keys(self, data: object, allowed: Sequence[str], where: str) -> None:
        check_keys(data, allowed, f"{self.path}: {where}")

    def laser(self, data: dict[str, Any], where: str) -> LaserMount:
        self.keys(data, LASER_KEYS, where)
        if "model" not in data:
            self.fail(f"{where}: missing 'model'")
        try:
            model = find_laser_model(data["model"], self.laser_dir)
        except LaserModelError as error:
            self.fail(f"{where}: {error}")
        extra = {k: v for k, v in data.items() if k not in ("model", "mount")}
        mount = self.pose(data.get("mount", [0.0, 0.0, 0.0]), f"{where}.mount")
        laser = _dataclass_from(LaserMount, dict(model=model, mount=mount, **extra), where)
        if laser.raycast not in ("march", "table"):
            self.fail(f"{where}: raycast must be 'march' or 'table', got {laser.raycast!r}")
        return laser

    def camera(self, data: dict[str, Any] | None, where: str) -> CameraRig | None:
        if data is None:
            return None
        check_keys(data, CAMERA_KEYS, where)
        top = _dataclass_from(CameraConfig, data.get("top"), f"{where}.top")
        bottom = _dataclass_from(CameraConfig, data.get("bottom"), f"{where}.bottom")
        detection = _dataclass_from(DetectionConfig, data.get("detection"), f"{where}.detection")
        calibration = None
        if detection.model == "calibrated":
            if not detection.calibration:
                self.fail(f"{where}.detection: the calibrated model needs 'calibration' (the "
                          "table scripts/calibrate_camera writes)")
            try:
                calibration = load_calibration(self.path.parent / detection.calibration)
            except CalibrationError as error:
                self.fail(f"{where}.detection: {error}")
        elif detection.model != "ideal":
            self.fail(f"{where}.detection: model must be 'calibrated' or 'ideal', got "
                      f"{detection.model!r}")
        return CameraRig(top, bottom, detection, _number(data.get("rate", 10.0), f"{where}.rate"),
                         calibration)

    def robot(self, data: dict[str, Any], i: int) -> RobotConfig:
        where = f"robots[{i}]"
        self.keys(data, ROBOT_KEYS, where)
        missing = [k for k in ("name", "drive", "radius", "pose") if k not in data]
        if missing:
            self.fail(f"{where}: missing key(s) {', '.join(missing)}")
        path, where = where, f"robot {data['name']!r}"
        if data["drive"] not in (HOLONOMIC, DIFFERENTIAL):
            self.fail(f"{where}: drive must be {HOLONOMIC!r} or {DIFFERENTIAL!r}, "
                      f"got {data['drive']!r}")
        wheels = None
        if data["drive"] == DIFFERENTIAL:
            wheels = _dataclass_from(WheelConfig, data.get("wheels"),
                                     f"{self.path}: {path}.wheels")
        return RobotConfig(
            name=str(data["name"]), drive=data["drive"],
            radius=_number(data["radius"], f"{self.path}: {where}.radius"),
            pose=self.pose(data["pose"], f"{where}.pose"),
            namespace=str(data.get("namespace", "")),
            limits=_dataclass_from(DriveLimits, data.get("limits"), f"{self.path}: {path}.limits"),
            wheels=wheels,
            odometry=_dataclass_from(OdometryConfig, data.get("odometry"),
                                     f"{self.path}: {path}.odometry"),
            lasers=[self.laser(laser, f"{path}.lasers[{j}]")
                    for j, laser in enumerate(data.get("lasers", []))],
            camera=self.camera(data.get("camera"), f"{self.path}: {path}.camera"))

    def schedule_entry(self, data: dict[str, Any], where: str, path: str) -> ScheduleEntry:
        self.keys(data, ENTRY_KEYS, path)
        if "time" not in data or "pose" not in data:
            self.fail(f"{where}: a schedule entry needs 'time' and 'pose'")
        entry = ScheduleEntry(time=_number(data["time"], f"{self.path}: {where}.time"),
                              pose=self.pose(data["pose"], f"{where}.pose"),
                              posture=data.get("posture", "standing"),
                              activity=data.get("activity", "standing"),
                              holding=data.get("holding", ""),
                              looking_at=data.get("looking_at", ""),
                              via=[self.pose(p, f"{where}.via")[:2] for p in data.get("via", [])],
                              shirt_colour=(self.shirt_colour(data["shirt_colour"], where,
                                                              f"{path}.shirt_colour")
                                            if "shirt_colour" in data else None))
        if entry.posture not in POSTURES:
            self.fail(f"{where}: posture must be one of {POSTURES}, got {entry.posture!r}")
        return entry

    def shirt_colour(self, value: Any, where: str, path: str) -> tuple[tuple[int, ...], ...]:
        """[r, g, b] for all three joints, or {joint1: [r, g, b], joint2: ..., joint5: ...}."""
        if isinstance(value, dict):
            self.keys(value, SHIRT_KEYS, path)
        joints: list[Any] = ([value.get(k) for k in ("joint1", "joint2", "joint5")]
                             if isinstance(value, dict) else [value] * 3)
        for rgb in joints:
            if (not isinstance(rgb, (list, tuple)) or len(rgb) != 3
                    or not all(isinstance(c, int) and 0 <= c <= 255 for c in rgb)):
                self.fail(f"{where}: shirt_colour must be [r, g, b] in 0..255 or "
                          f"{{joint1, joint2, joint5: [r, g, b]}}, got {value!r}")
        return tuple(tuple(rgb) for rgb in joints)

    def person(self, data: dict[str, Any], i: int) -> Person:
        path = f"people[{i}]"
        self.keys(data, PERSON_KEYS, path)
        missing = [k for k in ("name", "shirt_colour", "pose") if k not in data]
        if missing:
            self.fail(f"people[{i}]: missing key(s) {', '.join(missing)}")
        where = f"person {data['name']!r}"
        colour = self.shirt_colour(data["shirt_colour"], where, f"{path}.shirt_colour")
        posture = data.get("posture", "standing")
        if posture not in POSTURES:
            self.fail(f"{where}: posture must be one of {POSTURES}, got {posture!r}")
        schedule = sorted((self.schedule_entry(e, f"{where}.schedule[{j}]",
                                               f"{path}.schedule[{j}]")
                           for j, e in enumerate(data.get("schedule", []))),
                          key=lambda e: e.time)
        sizes: dict[str, Any] = {}   # Person keyword arguments: radius, walking_speed [m, m/s]
        for key in ("radius", "walking_speed"):
            if key in data:
                sizes[key] = _number(data[key], f"{self.path}: {where}.{key}")
                if sizes[key] <= 0:
                    self.fail(f"{where}.{key}: must be > 0, got {data[key]!r}")
        return Person(name=str(data["name"]), shirt_colour=colour,
                      pose=self.pose(data["pose"], f"{where}.pose"), posture=posture,
                      activity=data.get("activity", "standing"),
                      holding=data.get("holding", ""), looking_at=data.get("looking_at", ""),
                      schedule=schedule, **sizes)

    def obj(self, data: dict[str, Any], i: int) -> ObjectConfig:
        self.keys(data, OBJECT_KEYS, f"objects[{i}]")
        missing = [k for k in ("name", "label", "pose", "size") if k not in data]
        if missing:
            self.fail(f"objects[{i}]: missing key(s) {', '.join(missing)}")
        where = f"object {data['name']!r}"
        size = tuple(_number(v, f"{self.path}: {where}.size") for v in data["size"])
        if len(size) != 3 or min(size) <= 0:
            self.fail(f"{where}: size must be [x, y, z] > 0, got {data['size']!r}")
        return ObjectConfig(str(data["name"]), str(data["label"]),
                            self.pose(data["pose"], f"{where}.pose"),
                            _number(data.get("elevation", 0.0), f"{self.path}: {where}.elevation"),
                            size)

    def parse(self) -> WorldConfig:
        data = self.with_base(self.read(self.path))
        if "map" not in data:
            self.fail("expected a mapping with at least 'map'")
        for key in data:
            if key not in TOP_KEYS:
                self.fail(config_file.unknown_key_message(key, TOP_KEYS))
        map_path = (self.path.parent / data["map"]).resolve()
        graph_path = None
        if data.get("graph"):
            graph_path = (self.path.parent / data["graph"]).resolve()
            try:
                self.graph = load_graph(graph_path)
            except ValueError as error:
                self.fail(str(error))
        robots = [self.robot(r, i) for i, r in enumerate(data.get("robots", []))]
        names = [r.name for r in robots]
        if len(set(names)) != len(names):
            self.fail(f"robot names must be unique, got {names}")
        objects = [self.obj(o, i) for i, o in enumerate(data.get("objects", []))]
        people = [self.person(p, i) for i, p in enumerate(data.get("people", []))]
        object_names = {o.name for o in objects}
        for person in people:
            for entry in [person] + person.schedule:
                for ref in (entry.holding, entry.looking_at):
                    if ref and ref not in object_names:
                        self.fail(f"person {person.name!r} refers to unknown object {ref!r}")
        self.check_passages(map_path, robots, people)
        lighting = self.lighting(data.get("lighting") or [], robots)
        return WorldConfig(self.path, map_path, graph_path, robots, people, objects,
                           [list(map(float, r)) for r in data.get("camera_transparent", [])],
                           self.doors(data.get("doors", [])), lighting)

    def lighting(self, entries: Sequence[Any], robots: Sequence[RobotConfig]) -> list[LightingZone]:
        """The lighting zones; each condition must be a row of every calibrated camera's table."""
        zones = [self.lighting_zone(z, i) for i, z in enumerate(entries)]
        tables = [r.camera.calibration for r in robots
                  if r.camera is not None and r.camera.calibration is not None]
        for table in tables:
            for zone in zones:
                if zone.condition not in table.lighting:
                    self.fail(f"lighting {zone.name!r}: condition {zone.condition!r} is not a "
                              f"lighting row of {table.path} (rows: "
                              f"{', '.join(table.lighting)})")
        return zones

    def lighting_zone(self, data: dict[str, Any], index: int) -> LightingZone:
        where = f"lighting[{index}]"
        self.keys(data, LIGHTING_KEYS, where)
        missing = [k for k in LIGHTING_KEYS if k not in data]
        if missing:
            self.fail(f"{where}: missing {', '.join(missing)}")
        box = data["box"]
        if not isinstance(box, (list, tuple)) or len(box) != 4:
            self.fail(f"{where}: box must be [x0, y0, x1, y1], got {box!r}")
        box = tuple(_number(v, f"{self.path}: {where}.box") for v in box)
        if box[0] >= box[2] or box[1] >= box[3]:
            self.fail(f"{where}: box must have x0 < x1 and y0 < y1, got {list(box)}")
        return LightingZone(str(data["name"]), box, str(data["condition"]))

    def with_base(self, data: dict[str, Any]) -> dict[str, Any]:
        """`data` over the keys of its `base` world (one level; the base's map, graph and camera
        calibration paths stay relative to the base's folder)."""
        if "base" not in data:
            return data
        base_path = (self.path.parent / str(data.pop("base"))).resolve()
        base = self.read(base_path)
        if "base" in base:
            self.fail(f"base world {base_path} names a base of its own (one level only)")
        for key in ("map", "graph"):
            if base.get(key):
                base[key] = str((base_path.parent / base[key]).resolve())
        for robot in base.get("robots") or []:
            detection = ((robot or {}).get("camera") or {}).get("detection") or {}
            if detection.get("calibration"):
                detection["calibration"] = str((base_path.parent
                                                / detection["calibration"]).resolve())
        return {**base, **data}

    def read(self, path: str | Path) -> dict[str, Any]:
        data = config_file.read_yaml(path, WorldError, "world file")
        if not isinstance(data, dict):
            self.fail(f"{path}: expected a mapping with at least 'map'")
        return data

    def doors(self, entries: Sequence[Any]) -> list[DoorConfig]:
        doors = [self.door(d, i) for i, d in enumerate(entries)]
        names = [d.name for d in doors]
        if len(set(names)) != len(names):
            self.fail(f"door names must be unique, got {names}")
        return doors

    def door(self, data: Any, index: int) -> DoorConfig:
        where = f"doors[{index}]"
        if not isinstance(data, dict) or "name" not in data or "box" not in data:
            self.fail(f"{where}: expected a mapping with 'name' and 'box', got {data!r}")
        self.keys(data, DOOR_KEYS, where)
        box = data["box"]
        if not isinstance(box, (list, tuple)) or len(box) != 4:
            self.fail(f"{where}: box must be [x0, y0, x1, y1], got {box!r}")
        x0, y0, x1, y1 = (_number(v, f"{self.path}: {where}.box") for v in box)
        if not (x1 > x0 and y1 > y0):
            self.fail(f"{where}: box needs x1 > x0 and y1 > y0, got {box!r}")
        door = _dataclass_from(DoorConfig, dict(data, box=(x0, y0, x1, y1)),
                               f"{self.path}: {where}")
        if not isinstance(door.closed, bool):
            self.fail(f"{where}: closed must be true or false, got {door.closed!r}")
        return door

    def check_passages(self, map_path: Path, robots: Sequence[RobotConfig],
                       people: Sequence[Person]) -> None:
        """Refuse a resting pose that cuts two graph places apart (sim2d.passage_check)."""
        if self.graph is None or not robots or not people:
            return
        grid = load_map(map_path)
        person_radius = max([PassageConfig.person_radius]
                            + [p.radius + ELBOW_MARGIN for p in people])
        check = PassageCheck(grid, self.graph.places, self.graph.edges,
                             max(r.radius for r in robots), PassageConfig(person_radius))
        for person in people:
            for label, (x, y, _) in resting_poses(person):
                if not grid.inside(*grid.world_to_cell(x, y)):
                    self.fail(f"person {person.name!r} {label} ({x:.2f}, {y:.2f}) lies outside "
                              f"the map {map_path}")
                blockage = check.blockage(x, y)
                if blockage is not None:
                    self.fail(blockage_message(person.name, label, blockage, check))


def load_world_config(path: str | Path, laser_dir: str | Path | None = None) -> WorldConfig:
    """Parse a world YAML; laser models come from laser_dir (default: tamp_resources'
    config/lasers)."""
    return _Parser(path, laser_dir).parse()
