"""Calibration of a simulated camera against the real detectors (YOLOv3-tiny, mediapipe pose and
the shirt-colour sampling of thesis 000 Sec. 3.2.3 at joints 1, 2, 5).

Each real photo is fitted into the top camera's 640 x 480 image of the robot's stitched 640 x 960
frame (Sec. 3.2.1; the bottom camera's half is grey), as the image front end runs YOLO on the
stitched frame: the reference frame. The detector and the pose model are run on the reference
frame and on the same frame under the conditions a home produces, one factor at a time:

- distance: the frame shrunk by a factor onto a grey 640 x 480 canvas (a farther person is fewer
  pixels in the same image);
- occlusion: a grey band over the lower or the side part of each reference person's box (a sofa
  back, a door frame);
- lighting: less light with the camera's auto-exposure (sensor read noise amplified by the gain)
  and colour casts that auto white balance leaves (tungsten, cool fluorescent).

What the detectors find on the reference frame is the reference (a self-consistency measure: a
person the detector misses in the clear photo is not counted, so the miss rates are those *added*
by each condition). Per condition the table gives the person miss rate, the pose miss rate, the
box and keypoint error as a share of the person's height, the colour factor and residual at the
colour joints, the object-label confusions and the false detections per image. An occluded
person is matched against the visible part of their box (what a detector can box). The miss
rate against apparent height is also fitted with a logistic curve (`fit_miss_curve`), which the
simulator uses between and beyond the measured heights.
"""
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from perception.detector_registry import Detector, PoseEstimator
from perception.image_frontend import joint_colours, person_crop

FRAME = (640, 480)              # [px] width, height of one robot camera image
STITCHED_ROWS = 2               # top and bottom camera stacked
CANVAS_GREY = 114               # [0-255] the letterbox grey detectors are trained with
MATCH_IOU = 0.5                 # [-] a detection matches a reference box at this IoU or more
FALSE_IOU = 0.1                 # [-] a detection overlapping no reference box more is false
COLOUR_PATCH = 5                # [px] as perception.image_frontend.FrontEndConfig.colour_patch
CROP_PADDING = 0.15             # [-] as FrontEndConfig.crop_padding
MIN_JOINTS = 4                  # [-] a skeleton with fewer seen joints counts as a pose miss

Box = tuple[float, float, float, float]          # (x, y, w, h) [px]
Transform = tuple[float, float, float]           # (s, x0, y0): reference px -> frame px
Pose = tuple[NDArray[np.float64], NDArray[np.float64]]   # points (18, 2) [px], confidence (18,)


@dataclass(frozen=True)
class Lighting:
    """A room's light as the camera renders it (auto-exposure and auto white balance on)."""

    name: str
    light: float = 1.0                          # [-] scene light relative to daylight
    white_balance: tuple = (1.0, 1.0, 1.0)      # [-] R, G, B cast left after auto white balance
    read_noise: float = 1.5                     # [0-255] sensor noise at the sensor's own gain

    def render(self, image_bgr: np.ndarray, rng: np.random.Generator) -> NDArray[np.uint8]:
        """The frame as the camera gives it: exposure quantised at the sensor, read noise, then
        auto-exposure's gain 1 / light, then the colour cast (BGR order)."""
        sensor = np.round(image_bgr.astype(float) * self.light)
        sensor = sensor + rng.normal(0.0, self.read_noise, sensor.shape)
        out = sensor / self.light * np.array(self.white_balance[::-1])
        return np.clip(np.round(out), 0, 255).astype(np.uint8)


LIGHTINGS = (
    Lighting("daylight"),
    Lighting("indoor", light=0.5),
    Lighting("dim", light=0.2),
    Lighting("dark", light=0.08),
    Lighting("tungsten", light=0.5, white_balance=(1.0, 0.88, 0.70)),
    Lighting("fluorescent", light=0.5, white_balance=(0.92, 1.0, 1.06)),
)
SCALES = (1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.13, 0.09)   # [-] of the reference frame's size
OCCLUSIONS = (("bottom", 0.25), ("bottom", 0.5), ("bottom", 0.75),
              ("side", 0.25), ("side", 0.5))             # (which part, share of the box hidden)


@dataclass(frozen=True)
class Condition:
    kind: str                   # "scale", "occlusion" or "lighting"
    name: str                   # row name in the table
    scale: float = 1.0
    occlusion: tuple = ()       # (side, fraction) or ()
    lighting: Lighting = Lighting("daylight")


def conditions() -> list[Condition]:
    """Every condition of the table, one factor changed at a time."""
    out = [Condition("scale", f"scale {s:g}", scale=s) for s in SCALES]
    out += [Condition("occlusion", f"{side} {f:g}", occlusion=(side, f)) for side, f in OCCLUSIONS]
    out += [Condition("lighting", light.name, lighting=light) for light in LIGHTINGS]
    return out


def fit_frame(image: np.ndarray, frame: tuple[int, int] = FRAME) -> np.ndarray:
    """The photo shrunk (never enlarged) to fit the top camera's image, centred on grey, above
    a grey bottom image: the reference (stitched) frame."""
    import cv2
    width, height = frame
    h, w = image.shape[:2]
    s = min(1.0, width / w, height / h)
    resized = cv2.resize(image, (round(w * s), round(h * s)), interpolation=cv2.INTER_AREA) \
        if s < 1.0 else image
    top = on_canvas(resized, frame)[0]
    return np.vstack([top, np.full_like(top, CANVAS_GREY)])


def on_canvas(image: np.ndarray,
              frame: tuple[int, int] = FRAME) -> tuple[NDArray[np.uint8], Transform]:
    """`image` centred on a grey canvas of `frame` (width, height): (canvas, (1, x0, y0))."""
    width, height = frame
    canvas = np.full((height, width, 3), CANVAS_GREY, np.uint8)
    h, w = image.shape[:2]
    x0, y0 = (width - w) // 2, (height - h) // 2
    canvas[y0:y0 + h, x0:x0 + w] = image
    return canvas, (1.0, float(x0), float(y0))


def shrink(reference: np.ndarray, scale: float,
           frame: tuple[int, int] = FRAME) -> tuple[np.ndarray, Transform]:
    """The reference frame's top image shrunk by `scale` about its centre on grey (the scene
    farther away), and the (s, x0, y0) that maps reference pixels into it."""
    import cv2
    if scale >= 1.0:
        return reference.copy(), (1.0, 0.0, 0.0)
    width, height = frame
    top = reference[:height]
    small = cv2.resize(top, (max(1, round(width * scale)), max(1, round(height * scale))),
                       interpolation=cv2.INTER_AREA)
    canvas, (_, x0, y0) = on_canvas(small, frame)
    return np.vstack([canvas, reference[height:]]), (scale, x0, y0)


def visible_part(box: Sequence[float], side: str, fraction: float) -> Box:
    """The (x, y, w, h) part of a box left in view when its lower (`bottom`) or right (`side`)
    `fraction` is hidden."""
    x, y, w, h = box
    return (x, y, w, h * (1 - fraction)) if side == "bottom" else (x, y, w * (1 - fraction), h)


def occlude(reference: np.ndarray, boxes: Iterable[Sequence[float]], side: str,
            fraction: float) -> np.ndarray:
    """Grey over the lower (`bottom`) or right (`side`) `fraction` of each (x, y, w, h) box."""
    out = reference.copy()
    for box in boxes:
        x, y, w, h = visible_part(box, side, fraction)
        x0, y0 = (int(x), int(np.ceil(y + h))) if side == "bottom" else (int(np.ceil(x + w)),
                                                                          int(y))
        x1, y1 = int(np.ceil(box[0] + box[2])), int(np.ceil(box[1] + box[3]))
        out[max(0, y0):max(0, y1), max(0, x0):max(0, x1)] = CANVAS_GREY
    return out


def iou(a: Sequence[float], b: Sequence[float]) -> float:
    """Intersection over union of two (x, y, w, h) boxes."""
    ax1, ay1, bx1, by1 = a[0] + a[2], a[1] + a[3], b[0] + b[2], b[1] + b[3]
    iw = max(0.0, min(ax1, bx1) - max(a[0], b[0]))
    ih = max(0.0, min(ay1, by1) - max(a[1], b[1]))
    inter = iw * ih
    union = a[2] * a[3] + b[2] * b[3] - inter
    return inter / union if union > 0 else 0.0


def to_reference(box: Sequence[float], transform: Transform) -> Box:
    """A (x, y, w, h) box of a transformed frame in reference-frame pixels."""
    s, x0, y0 = transform
    return ((box[0] - x0) / s, (box[1] - y0) / s, box[2] / s, box[3] / s)


def best_match(box: Sequence[float],
               candidates: Sequence[Sequence[float]]) -> tuple[int, float]:
    """Index and IoU of the candidate box overlapping `box` most (-1, 0.0 when none)."""
    if not candidates:
        return -1, 0.0
    overlaps = [iou(box, c) for c in candidates]
    k = int(np.argmax(overlaps))
    return k, overlaps[k]


def box_error(reference: Sequence[float], found: Sequence[float]) -> float:
    """Mean absolute edge displacement of `found` against `reference`, over its height."""
    ref = np.array([reference[0], reference[1], reference[0] + reference[2],
                    reference[1] + reference[3]])
    got = np.array([found[0], found[1], found[0] + found[2], found[1] + found[3]])
    return float(np.abs(got - ref).mean() / max(reference[3], 1.0))


def keypoint_error(reference: Pose, found: Pose, height: float) -> float:
    """RMS distance of the joints both skeletons see, over the person's height (NaN if none)."""
    (rp, rc), (fp, fc) = reference, found
    both = (rc > 0) & (fc > 0)
    if not both.any():
        return float("nan")
    d = np.linalg.norm(rp[both] - fp[both], axis=1)
    return float(np.sqrt((d ** 2).mean()) / max(height, 1.0))


@dataclass
class PersonSeen:
    box: tuple                  # (x, y, w, h) in reference-frame pixels
    skeleton: Pose | None = None   # (points in reference-frame px, confidence) or None
    colours: np.ndarray | None = None  # (3, 3) RGB at joints 1, 2, 5 (zeros where unseen)


@dataclass
class FrameSeen:
    people: list = field(default_factory=list)
    objects: list = field(default_factory=list)    # [(label, (x, y, w, h))] reference pixels


def observe(image: np.ndarray, transform: Transform, detector: Detector,
            pose: PoseEstimator) -> FrameSeen:
    """Run the real detectors on one frame; boxes and joints mapped to reference pixels."""
    seen = FrameSeen()
    for det in detector.detect(image):
        box = to_reference((det.x, det.y, det.width, det.height), transform)
        if det.label != "person":
            seen.objects.append((det.label, box))
            continue
        person = PersonSeen(box)
        x0, y0, x1, y1 = person_crop((det.x, det.y, det.width, det.height), image.shape,
                                     CROP_PADDING)
        found = pose.skeletons(np.ascontiguousarray(image[y0:y1, x0:x1])) \
            if x1 - x0 >= 8 and y1 - y0 >= 8 else []
        if found:
            points, confidence = found[0]
            points = points + np.array([x0, y0], dtype=float)
            if int((confidence > 0).sum()) >= MIN_JOINTS:
                s, ox, oy = transform
                person.skeleton = ((points - [ox, oy]) / s, confidence)
                person.colours = joint_colours(image, points, confidence, COLOUR_PATCH)
        seen.people.append(person)
    return seen


@dataclass
class Tally:
    """Counts and errors of one condition over every photo."""

    people: int = 0             # reference people (person boxes)
    missed: int = 0             # ... no person box matched
    posed: int = 0              # matched reference people with a reference skeleton
    pose_missed: int = 0        # ... with no skeleton under the condition
    box_errors: list = field(default_factory=list)
    keypoint_errors: list = field(default_factory=list)
    colours: list = field(default_factory=list)  # (reference RGB, found RGB) per seen joint
    objects: int = 0            # reference objects (not people)
    objects_missed: int = 0
    confusions: dict = field(default_factory=dict)         # "true -> found": count
    false_people: int = 0
    false_objects: int = 0
    images: int = 0
    missed_heights: list = field(default_factory=list)   # reference heights [px] of the missed
    object_sizes: list = field(default_factory=list)     # sqrt(area) [px] of reference objects
    missed_sizes: list = field(default_factory=list)     # ... of the missed ones


def tally_frame(tally: Tally, reference: FrameSeen, seen: FrameSeen,
                occlusion: tuple[str, float] | tuple[()] = (), scale: float = 1.0) -> None:
    """Add one condition frame's detections, compared with the reference frame's, to `tally`;
    `occlusion` (side, fraction) says which part of each reference person is hidden, `scale`
    how much smaller than in the reference frame everything is."""
    tally.images += 1
    used: set[int] = set()
    for person in reference.people:
        tally.people += 1
        box = visible_part(person.box, *occlusion) if occlusion else person.box
        k, overlap = best_match(box, [p.box for p in seen.people])
        if overlap < MATCH_IOU:
            tally.missed += 1
            tally.missed_heights.append(person.box[3] * scale)
            continue
        used.add(k)
        found = seen.people[k]
        tally.box_errors.append(box_error(box, found.box))
        if person.skeleton is None:
            continue
        tally.posed += 1
        if found.skeleton is None:
            tally.pose_missed += 1
            continue
        error = keypoint_error(person.skeleton, found.skeleton, person.box[3])
        if np.isfinite(error):
            tally.keypoint_errors.append(error)
        if person.colours is None or found.colours is None:
            raise ValueError("a person seen with a skeleton but without its joint colours")
        tally.colours += [(ref, got) for ref, got in zip(person.colours.astype(float),
                                                         found.colours.astype(float))
                          if ref.any() and got.any()]
    tally.false_people += sum(1 for k, p in enumerate(seen.people) if k not in used and
                              best_match(p.box, [q.box for q in reference.people])[1] < FALSE_IOU
                              and best_match(p.box, [b for _, b in reference.objects])[1]
                              < FALSE_IOU)
    claimed: set[int] = set()
    for label, box in reference.objects:
        tally.objects += 1
        size = float(np.sqrt(box[2] * box[3])) * scale
        tally.object_sizes.append(size)
        k, overlap = best_match(box, [b for _, b in seen.objects])
        if overlap < MATCH_IOU:
            tally.objects_missed += 1
            tally.missed_sizes.append(size)
            continue
        claimed.add(k)
        if seen.objects[k][0] != label:
            key = f"{label} -> {seen.objects[k][0]}"
            tally.confusions[key] = tally.confusions.get(key, 0) + 1
    every_reference = [p.box for p in reference.people] + [b for _, b in reference.objects]
    tally.false_objects += sum(1 for k, (_, box) in enumerate(seen.objects) if k not in claimed
                               and best_match(box, every_reference)[1] < FALSE_IOU)


def transformed(reference_image: np.ndarray, reference: FrameSeen, condition: Condition,
                rng: np.random.Generator) -> tuple[NDArray[np.uint8], Transform]:
    """The condition's frame and its transform to reference pixels."""
    image, transform = reference_image, (1.0, 0.0, 0.0)
    if condition.scale < 1.0:
        image, transform = shrink(reference_image, condition.scale)
    if condition.occlusion:
        side, fraction = condition.occlusion
        image = occlude(image, [p.box for p in reference.people], side, fraction)
    return condition.lighting.render(image, rng), transform


def person_heights(reference: FrameSeen, condition: Condition) -> list[float]:
    """Apparent heights [px] of the reference people under `condition`."""
    return [p.box[3] * condition.scale for p in reference.people]


def _mean(values: Sequence[float], digits: int = 3) -> float | None:
    return round(float(np.mean(values)), digits) if len(values) else None


def summarise(condition: Condition, tally: Tally, heights: Sequence[float]) -> dict[str, Any]:
    """One table row (plain types for YAML)."""
    row: dict[str, Any] = {"name": condition.name, "people": tally.people,
           "miss_rate": round(tally.missed / tally.people, 3) if tally.people else None,
           "missed": tally.missed,
           "pose_miss_rate": (round(tally.pose_missed / tally.posed, 3)
                              if tally.posed else None),
           "box_error": _mean(tally.box_errors),
           "keypoint_error": _mean(tally.keypoint_errors),
           "false_people_per_image": round(tally.false_people / max(tally.images, 1), 3),
           "false_objects_per_image": round(tally.false_objects / max(tally.images, 1), 3),
           "objects": tally.objects,
           "object_miss_rate": (round(tally.objects_missed / tally.objects, 3)
                                if tally.objects else None),
           "label_confusion_rate": (round(sum(tally.confusions.values())
                                          / (tally.objects - tally.objects_missed), 3)
                                    if tally.objects > tally.objects_missed else None),
           "confusions": dict(sorted(tally.confusions.items()))}
    if condition.kind == "scale":
        row["scale"] = condition.scale
        row["person_height_px"] = _mean(heights, 1)
        row["heights"] = [round(float(h), 1) for h in heights]
        row["missed_heights"] = [round(float(h), 1) for h in tally.missed_heights]
        row["object_sizes"] = [round(h, 1) for h in tally.object_sizes]
        row["missed_object_sizes"] = [round(h, 1) for h in tally.missed_sizes]
    if condition.kind == "occlusion":
        row["side"], row["hidden_fraction"] = condition.occlusion
    if condition.kind == "lighting":
        light = condition.lighting
        row.update(light=light.light, white_balance=list(light.white_balance),
                   read_noise=light.read_noise)
    if tally.colours:
        factor, residual = colour_model(tally.colours)
        row["colour_factor"] = [round(float(v), 3) for v in factor]
        row["colour_residual"] = round(residual, 2)
        row["colour_joints"] = len(tally.colours)
    return row


def colour_model(
        pairs: Sequence[tuple[NDArray[np.float64], NDArray[np.float64]]]
) -> tuple[NDArray[np.float64], float]:
    """Per-channel factor (least squares through the origin) from reference to found RGB, and
    the RMS per-channel residual [0-255] left after it."""
    ref = np.array([r for r, _ in pairs])
    got = np.array([g for _, g in pairs])
    factor = (ref * got).sum(axis=0) / np.maximum((ref * ref).sum(axis=0), 1e-9)
    residual = got - ref * factor
    return factor, float(np.sqrt(np.mean(np.square(residual))))


def calibrate(photos: Iterable[tuple[str, np.ndarray]], detector: Detector, pose: PoseEstimator,
              seed: int = 0,
              progress: Callable[[int, int], None] | None = None) -> dict[str, Any]:
    """The calibration table: {"scale": [...], "occlusion": [...], "lighting": [...]} rows.

    `photos` is [(name, BGR image)]; `progress(done, total)` is called after each frame.
    """
    rng = np.random.default_rng(seed)
    references: list[tuple[np.ndarray, FrameSeen]] = []
    for _, photo in photos:
        image = fit_frame(photo)
        references.append((image, observe(image, (1.0, 0.0, 0.0), detector, pose)))
    table: dict[str, Any] = {"scale": [], "occlusion": [], "lighting": []}
    every = conditions()
    total, done = len(every) * len(references), 0
    for condition in every:
        tally, heights = Tally(), []
        for image, reference in references:
            frame, transform = transformed(image, reference, condition, rng)
            tally_frame(tally, reference, observe(frame, transform, detector, pose),
                        condition.occlusion, condition.scale)
            heights += person_heights(reference, condition)
            done += 1
            if progress:
                progress(done, total)
        table[condition.kind].append(summarise(condition, tally, heights))
    table["miss_curve"] = fit_miss_curve(table["scale"], "heights", "missed_heights")
    table["object_miss_curve"] = fit_miss_curve(table["scale"], "object_sizes",
                                                "missed_object_sizes")
    return table


def fit_miss_curve(rows: Sequence[Mapping[str, Any]], sizes: str = "heights",
                   missed_sizes: str = "missed_heights") -> dict[str, float]:
    """Logistic miss rate against apparent size h [px] (a person's height, an object's square
    root of area), fitted by maximum likelihood to every reference person or object of every
    scale row: miss(h) = 1 / (1 + exp((h - h50) / width)). Returns {"h50": px, "width": px}."""
    from scipy.optimize import minimize
    heights = np.array([h for row in rows for h in row[sizes]])
    missed_pool = [h for row in rows for h in row[missed_sizes]]
    missed = np.zeros(len(heights), dtype=bool)
    for h in missed_pool:        # mark one not-yet-marked person of that height as missed
        k = np.flatnonzero((heights == h) & ~missed)[0]
        missed[k] = True

    def negative_log_likelihood(params: NDArray[np.float64]) -> float:
        h50, log_width = params
        p = 1.0 / (1.0 + np.exp(np.clip((heights - h50) / np.exp(log_width), -50, 50)))
        p = np.clip(p, 1e-9, 1 - 1e-9)
        return -float(np.sum(np.where(missed, np.log(p), np.log(1 - p))))

    best = minimize(negative_log_likelihood, x0=[float(np.median(heights)), np.log(20.0)],
                    method="Nelder-Mead")
    return {"h50": round(float(best.x[0]), 1), "width": round(float(np.exp(best.x[1])), 1),
            "samples": int(len(heights)), "missed": int(missed.sum())}
