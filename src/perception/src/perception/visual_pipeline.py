"""One camera frame -> per-person results: activity (Sec. 3.2.4), map position and semantic
place (Sec. 3.2.2), shirt colours for identification (Sec. 3.2.3).

Input is camera-level: object boxes and COCO-18 skeletons of the stitched frame with depth at
every joint and shirt colour at joints 1, 2, 5 -- what the simulator publishes and what the image
front end (YOLO + mediapipe + depth image) produces. Problems with one person (missing joints,
no valid depth) are reported in that person's `problems` instead of raising.
"""
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from floorplan.semantic_graph import SemanticGraph

from perception.activity import (ActivityConfig, ActivityResult, AffordanceTable, BodyView,
                                 SeenObject, recognise_activity, torso_top)
from perception.keypoints import (HIPS, L_SHOULDER, NECK, R_SHOULDER, Skeleton, as_skeleton,
                                  present)
from perception.localisation import (DepthWindowConfig, pixel_to_camera, semantic_place,
                                     stitched_rows, transform_point)
from perception.object_memory import ObjectMemory

DEPTH_JOINTS = (NECK, R_SHOULDER, L_SHOULDER) + HIPS   # torso joints: depth of the body
MIN_DEPTH = DepthWindowConfig.min_depth   # [m] nearer depth readings are invalid


@dataclass
class ObjectBox:
    label: str
    confidence: float
    x: float            # box top-left [px]
    y: float
    width: float        # [px]
    height: float
    depth: float = float("nan")   # [m]


@dataclass
class PersonView:
    points: np.ndarray        # (18, 2) [px]
    confidence: np.ndarray    # (18,)
    depth: np.ndarray         # (18,) [m], NaN when unknown
    shirt: np.ndarray         # (3, 3) uint8 RGB at joints 1, 2, 5; zeros where unseen


@dataclass
class FrameView:
    width: int
    height: int               # stitched height [px]
    objects: list = field(default_factory=list)   # [ObjectBox]
    people: list = field(default_factory=list)    # [PersonView]


@dataclass
class StackedCameras:
    """Intrinsics and map <- optical transforms of the stitched top/bottom cameras."""

    top_height: int            # [px] rows of the top image in the stitched frame
    intrinsics: dict           # 'top'/'bottom' -> Intrinsics
    to_map: dict               # 'top'/'bottom' -> 4x4 transform


@dataclass
class PersonResult:
    activity: ActivityResult
    position: tuple[float, float] | None = None   # (x, y) [m] in the map, None: not localised
    place: str = ""
    shirt: np.ndarray | None = None   # (3, 3) when all three colour joints were seen
    problems: list = field(default_factory=list)


def body_depth(person: PersonView, min_depth: float) -> float | None:
    """Median depth [m] over the detected torso joints with valid depth, or None."""
    d = np.asarray(person.depth, dtype=float)[list(DEPTH_JOINTS)]
    seen = np.asarray(person.confidence)[list(DEPTH_JOINTS)] > 0
    valid = d[seen & np.isfinite(d) & (d >= min_depth)]
    return float(np.median(valid)) if valid.size else None


def objects_for(skeleton: Skeleton, objects: Iterable[ObjectBox],
                extents: Sequence[tuple | None] | None = None) -> list[SeenObject]:
    """Candidate objects for one person: everything except the person box around their neck (else
    the top of their torso: shoulders or head); `extents`: each object's box in the map
    (object_extent), None where unknown."""
    keep: list[SeenObject] = []
    neck = torso_top(skeleton)
    objects = list(objects)
    for obj, extent in zip(objects, extents if extents is not None else [None] * len(objects)):
        own = obj.label == "person" and neck is not None and (
            obj.x <= neck[0] <= obj.x + obj.width and obj.y <= neck[1] <= obj.y + obj.height)
        if not own:
            keep.append(SeenObject(obj.label, float(obj.confidence), obj.x + obj.width / 2.0,
                                   obj.y + obj.height / 2.0, float(obj.width), float(obj.height),
                                   float(obj.depth), extent))
    return keep


def object_extent(obj: ObjectBox, cameras: StackedCameras,
                  min_depth: float) -> tuple | None:
    """(low, high) corners (3,) [m] of an object's box in the map: the image box's corners
    back-projected at the object's depth and that far again as deep as the box's smaller side
    (the depth is the front surface's); None without a valid depth."""
    d = float(obj.depth)
    if not (np.isfinite(d) and d >= min_depth):
        return None
    top = cameras.intrinsics["top"]
    thickness = min(obj.width / top.fx, obj.height / top.fy) * d
    u = np.array([obj.x, obj.x + obj.width, obj.x, obj.x + obj.width]).repeat(2)
    v = np.array([obj.y, obj.y, obj.y + obj.height, obj.y + obj.height]).repeat(2)
    block = stitched_points_to_map(u, v, np.tile([d, d + thickness], 4), cameras)
    return block.min(axis=0), block.max(axis=0)


def body_view(person: PersonView, objects: Iterable[ObjectBox]) -> BodyView:
    """A PersonView as another body of the frame: P(o) of the 'person' box around its torso top,
    else the mean confidence of its detected joints."""
    skeleton = as_skeleton(person.points, person.confidence)
    top = torso_top(skeleton)
    conf = np.asarray(person.confidence, dtype=float)
    confidence = float(conf[conf > 0].mean()) if (conf > 0).any() else 0.0
    if top is not None:
        for obj in objects:
            if obj.label == "person" and (obj.x <= top[0] <= obj.x + obj.width
                                          and obj.y <= top[1] <= obj.y + obj.height):
                confidence = float(obj.confidence)
                break
    return BodyView(skeleton, np.asarray(person.depth, dtype=float), confidence)


def unknown_classes(objects: Iterable[ObjectBox], table: AffordanceTable) -> list[str]:
    """Sorted labels of the objects the affordance table has no entry for (people excepted)."""
    return sorted({o.label for o in objects if o.label != "person" and not table.known(o.label)})


def stitched_to_map(u: float, v: float, depth: float,
                    cameras: StackedCameras) -> np.ndarray:
    """Map (x, y, z) [m] of stitched-frame pixel (u, v) at `depth` (Eqs. 3-3..3-5 in the camera
    that saw it, then that camera's pose)."""
    return stitched_points_to_map(np.array([u], dtype=float), np.array([v], dtype=float),
                                  np.array([depth], dtype=float), cameras)[0]


def stitched_points_to_map(u: NDArray[np.float64], v: NDArray[np.float64],
                           depth: NDArray[np.float64], cameras: StackedCameras) -> np.ndarray:
    """Map points (n, 3) [m] of n stitched-frame pixels at their depths: Eqs. 3-3..3-5 in the
    camera that saw each, then that camera's pose, one matrix product per camera (an object's
    box in the map is made for every object of every frame)."""
    out = np.empty((len(u), 3))
    in_top, rows = stitched_rows(v, cameras.top_height)
    for which, mask in (("top", in_top), ("bottom", ~in_top)):
        if mask.any():
            camera = pixel_to_camera(u[mask], rows[mask], depth[mask],
                                     cameras.intrinsics[which])      # (3, m), Eqs. 3-3..3-5
            out[mask] = transform_point(cameras.to_map[which], camera.T)
    return out


def locate(skeleton: Skeleton, depth: float | None,
           cameras: StackedCameras) -> tuple[float, float] | None:
    """Map (x, y) [m] of the body from the neck (else hips) pixel and the body depth."""
    anchor = present(skeleton, (NECK,)) or present(skeleton, HIPS)
    if not anchor or depth is None:
        return None
    u, v = skeleton[anchor].mean(axis=0)
    x, y = stitched_to_map(u, v, depth, cameras)[:2]
    return float(x), float(y)


def joints_in_map(person: PersonView, cameras: StackedCameras,
                  min_depth: float) -> np.ndarray:
    """(18, 3) map position [m] of every joint detected with a valid depth; NaN rows else."""
    points = np.asarray(person.points, dtype=float)
    depth = np.asarray(person.depth, dtype=float)
    body = np.full((len(points), 3), np.nan)
    valid = ((np.asarray(person.confidence) > 0) & np.isfinite(depth)
             & np.isfinite(points).all(axis=1))
    valid[valid] = depth[valid] >= min_depth
    if valid.any():
        body[valid] = stitched_points_to_map(points[valid, 0], points[valid, 1], depth[valid],
                                             cameras)
    return body


def analyse_person(person: PersonView, objects: Sequence[ObjectBox], table: AffordanceTable,
                   config: ActivityConfig, cameras: StackedCameras | None,
                   graph: SemanticGraph | None, min_depth: float = MIN_DEPTH,
                   others: Sequence[BodyView] = (),
                   extents: Sequence[tuple | None] | None = None,
                   remembered: Sequence[SeenObject] = ()) -> PersonResult:
    """Activity, map position, semantic place and shirt colours of one person (`others`: the
    frame's other people as BodyView, possible chat partners; `extents`: the objects' boxes in
    the map, object_extent; `remembered`: objects this frame missed, ObjectMemory.recall)."""
    skeleton = as_skeleton(person.points, person.confidence)
    body = joints_in_map(person, cameras, min_depth) if cameras is not None else None
    candidates = objects_for(skeleton, objects, extents) + list(remembered)
    result = PersonResult(recognise_activity(skeleton, candidates, table, config,
                                             np.asarray(person.depth, dtype=float), others,
                                             body))
    if len(present(skeleton, range(len(skeleton)))) < len(skeleton):
        result.problems.append("skeleton has missing joints")
    if cameras is not None:
        result.position = locate(skeleton, body_depth(person, min_depth), cameras)
        if result.position is None:
            result.problems.append("no valid depth at the torso: not localised")
        elif graph is not None:
            result.place = semantic_place(graph, *result.position)
    shirt = np.asarray(person.shirt, dtype=np.uint8).reshape(3, 3)
    if shirt.any(axis=1).all():
        result.shirt = shirt
    return result


def analyse_frame(frame: FrameView, table: AffordanceTable, config: ActivityConfig,
                  cameras: StackedCameras | None = None,
                  graph: SemanticGraph | None = None, memory: ObjectMemory | None = None,
                  stamp: float = 0.0) -> list[PersonResult]:
    """Every person of a frame -> [PersonResult] in the frame's order; with a `memory`, the
    frame's fixed objects are remembered at `stamp` [s] and those it missed are offered to the
    people within reach of them."""
    bodies = [body_view(p, frame.objects) for p in frame.people]
    remembering = memory if memory is not None and memory.config.keep_s > 0 else None
    extents = ([object_extent(o, cameras, MIN_DEPTH) for o in frame.objects]
               if cameras is not None and (frame.people or remembering) else None)
    remembered: list[SeenObject] = []
    if remembering is not None and extents is not None:
        remembering.update(stamp, [(o.label, o.confidence, e)
                                   for o, e in zip(frame.objects, extents)])
        remembered = remembering.recall(stamp)
    return [analyse_person(p, frame.objects, table, config, cameras, graph,
                           others=bodies[:i] + bodies[i + 1:], extents=extents,
                           remembered=remembered)
            for i, p in enumerate(frame.people)]
