"""Framewise hierarchical human activity recognition (thesis 000 Sec. 3.2.4).

Detailed activities come from objects near the hands (O_h), objects in the eyesight (O_e) and
whether the person looks at their hands (E_h,e), scored through an affordance table
(Algorithm 3-2, Eqs. 3-11 ... 3-13); when no detailed activity is probable enough the result falls
back to the posture read from the skeleton (sitting, standing, lying).

Beyond the seed (each switchable in ActivityConfig, documented in docs/perception/visual.md):
reach and gaze are measured to an object's box rather than its centre (a hand on a fridge door, a
face at the top of a person's box); the furniture a sitting or lying person rests on (O_s: boxes
containing the hips) adds a posture-conditioned term w_s P_s(a|o, posture) P(o) (§2: a sofa "can
be a sitting tool for human to watch television ... a furniture for people to take a nap", so
lying on a bed is sleeping); the top of the torso falls back from the neck to the shoulders and
head so a lying person whose neck is out of the frame still has a posture; another person's
skeleton standing near the person and facing them is a person in the eyesight (a chat partner,
Table 5-4) even when no 'person' box lies in the gaze cone, e.g. when the person faces the camera
or turns away from it (the body's heading is read from the shoulders' depths); with the joints in
the map (an RGB-D camera at a known pose), the posture comes from the body in 3-D -- the torso's
slope and the height of the neck above the floor -- so a person lying seen from the feet, or
sitting behind a table that hides the hips, still has a posture; and an activity the affordance
table allows only in some postures (`postures:`: putting things in the fridge or going out is
done standing) scores nothing in another one; and what a hand holds (a hand within
`hold_distance` of a hand-held thing's box in the map: the cup at the lips, the bowl in the
hands) is what the hands are doing, so when a frame shows one, the things that only lie within
reach (the bottle beside the plate) leave the hand term (Eq. 3-12 over O_h, held).
"""
import math
from collections.abc import Collection, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray

from perception.keypoints import (
    ANKLES, EARS, EYES, FOREARMS, HANDS, HIPS, KNEES, L_SHOULDER, NECK, NOSE, R_SHOULDER, Skeleton,
    mean_of, present)

POSTURES = ("sitting", "standing", "lying")
UNKNOWN_POSTURE = "unknown"
SHOULDERS = (R_SHOULDER, L_SHOULDER)
HEAD = (NOSE,) + EYES + EARS
BOX_GRID = 7   # points per side where the angle to a box is sampled


@dataclass
class ActivityConfig:
    """Hyper-parameters of Algorithm 3-2 / 3-3."""

    range_factor: float = 1.0          # [-] alpha_hand: object near a hand within this x forearm
    eyesight_angle: float = 0.35       # [rad] delta_eye: half-angle of the eyesight cone
    weight_hands: float = 1.0          # [-] w_h
    weight_eyes: float = 1.0           # [-] w_e
    weight_looking: float = 1.0        # [-] w_E
    probability_threshold: float = 0.4  # [-] P_th: below it the posture is reported
    lying_ratio: float = 1.0           # [-] torso |dx|/|dy| above this -> lying
    sitting_thigh_ratio: float = 0.5   # [-] hip->knee drop / torso length below this -> sitting
    sitting_leg_ratio: float = 1.1     # [-] hip->ankle drop / torso length below this -> sitting
    to_box: bool = True                # reach and gaze to the object's box (False: box centre)
    weight_support: float = 0.5        # [-] w_s of the furniture the person rests on (0: off)
    support_margin: float = 0.25       # [-] hips within this x torso length of the box: on it
    # Chat partners from skeletons (False: only 'person' boxes in the gaze cone, as in the seed).
    partners_from_skeletons: bool = True
    torso_length: float = 0.5          # [m] neck to hip midpoint of an adult: metres per pixel
    partner_distance: float = 2.1      # [m] farther apart is no conversation (Hall's social
    #                                    distance, near phase, ends at 2.1 m)
    partner_facing_angle: float = 0.785  # [rad] partner's body within this of the person (45 deg:
    #                                      Kendon's L-shaped F-formation)
    hand_depth_gap: float = 0.6        # [m] an object whose depth is this much beyond or before
    #                                    the hands' is not near them, whatever the image says
    #                                    (0: image distance only, as the seed)
    # Posture from the joints in the map (False: from the image alone, as the seed). Heights of
    # the neck above the floor: an adult's is about 1.45 m standing, 1.0-1.1 m sitting on a chair
    # or sofa, about 0.6 m lying on a bed.
    posture_3d: bool = True
    # With the joints and the object's box in the map, "near the hands" is measured in metres:
    # a hand within range_factor x the longest forearm (elbow -> wrist, in 3-D) of the box
    # (False: in the image, as the seed; a forearm pointing at the camera is short there).
    reach_3d: bool = True
    forearm_length: float = 0.26       # [m] an adult's forearm, for reach_3d when no elbow with
    #                                    its wrist is seen (hidden behind what the hands hold)
    standing_height: float = 1.25      # [m] neck (else mid-shoulders) at least this high: standing
    lying_height: float = 0.8          # [m] below this: lying
    # What the hands hold decides over what only lies within their reach: a hand within this
    # of the box in the map of a thing the table lists as `handheld` holds it, and when a frame
    # shows something held, only the held things enter the hand term (0: every object within
    # reach does, as the seed). A held cup or fork is 0-0.05 m from a hand; a bottle, a laptop
    # or an umbrella standing within reach 0.1-0.4 m (docs/perception/visual.md).
    hold_distance: float = 0.08


@dataclass
class AffordanceTable:
    """P_h(a|o), P_e(a|o) per object class and P_E(a|E_h,e), with the activity categories."""

    activities: tuple
    hands: dict = field(default_factory=dict)     # label -> {activity: P_h(a|o)}
    eyes: dict = field(default_factory=dict)      # label -> {activity: P_e(a|o)}
    looking_at_hands: dict = field(default_factory=dict)   # {activity: P_E(a|E)}
    support: dict = field(default_factory=dict)   # posture -> label -> {activity: P_s(a|o,pose)}
    no_affordance: frozenset = frozenset()        # labels known to say nothing of the activity
    postures: dict = field(default_factory=dict)  # activity -> postures it is done in (absent: any)
    handheld: frozenset = frozenset()   # labels of things a hand holds or works (a cup, a mouse;
    #                                     not a chair or a fridge): held within hold_distance

    def known(self, label: str) -> bool:
        """True for a class the table has an entry for (or knows to carry no affordance)."""
        return (label in self.hands or label in self.eyes or label in self.no_affordance
                or any(label in row for row in self.support.values()))


@dataclass
class SeenObject:
    """A detected object as the heuristics need it: class, confidence P(o), box centre [px]."""

    label: str
    confidence: float
    cx: float
    cy: float
    width: float = 0.0   # [px] box size; 0 = a point at the centre
    height: float = 0.0
    depth: float = math.nan   # [m] at the box (NaN: unknown)
    extent: tuple | None = None   # (low, high) corners (3,) [m] of its box in the map (None:
    #                               unknown): the image box back-projected at its depth

    @property
    def in_image(self) -> bool:
        """False for an object with no box in this image (remembered: object_memory)."""
        return math.isfinite(self.cx) and math.isfinite(self.cy)

    def box_points(self) -> NDArray[np.float64]:
        """A BOX_GRID x BOX_GRID grid over the box, (n, 2) [px]; the centre for a point."""
        if self.width <= 0 and self.height <= 0:
            return np.array([[self.cx, self.cy]])
        u = np.linspace(self.cx - self.width / 2, self.cx + self.width / 2, BOX_GRID)
        v = np.linspace(self.cy - self.height / 2, self.cy + self.height / 2, BOX_GRID)
        return np.stack(np.meshgrid(u, v), axis=-1).reshape(-1, 2)

    def distance_to(self, point: Sequence[float] | NDArray[np.float64]) -> float:
        """[px] from `point` to the nearest point of the box (0 inside)."""
        dx = max(abs(point[0] - self.cx) - self.width / 2, 0.0)
        dy = max(abs(point[1] - self.cy) - self.height / 2, 0.0)
        return math.hypot(dx, dy)


@dataclass
class BodyView:
    """Another person in the frame, as the chat-partner test needs them."""

    skeleton: np.ndarray      # (18, 2) [px], NaN rows for missing joints
    depth: np.ndarray         # (18,) [m], NaN where unknown
    confidence: float         # [-] P(o) of the person detection


@dataclass
class ActivityResult:
    activity: str                 # detailed activity, or the posture when none is probable
    probabilities: dict           # activity -> P(a) (empty when no object gave a score)
    posture: str
    near_hands: list              # labels in O_h
    in_eyesight: list             # labels in O_e
    looking_at_hands: bool
    resting_on: list = field(default_factory=list)   # labels in O_s (furniture under the hips)
    holding: list = field(default_factory=list)   # labels of O_h held (hold_distance)


def _check_probabilities(where: str, table: Mapping[str, Mapping[str, float]],
                         activities: Collection[str]) -> None:
    for label, row in table.items():
        for activity, p in row.items():
            if activity not in activities:
                raise ValueError(f"{where}: '{label}' names unknown activity '{activity}'")
            if not 0.0 <= float(p) <= 1.0:
                raise ValueError(f"{where}: '{label}' -> '{activity}' probability {p} "
                                 "not in [0, 1]")


def load_affordances(path: str | Path) -> AffordanceTable:
    """Read config/affordances.yaml into an AffordanceTable, validating every entry."""
    with open(path) as f:
        doc = yaml.safe_load(f)
    for key in ("activities", "hands", "eyes", "looking_at_hands"):
        if key not in doc:
            raise ValueError(f"{path}: missing '{key}'")
    activities = tuple(doc["activities"])
    hands = {k: {a: float(p) for a, p in v.items()} for k, v in doc["hands"].items()}
    eyes = {k: {a: float(p) for a, p in v.items()} for k, v in doc["eyes"].items()}
    looking = {a: float(p) for a, p in doc["looking_at_hands"].items()}
    support = {posture: {k: {a: float(p) for a, p in v.items()} for k, v in rows.items()}
               for posture, rows in (doc.get("support") or {}).items()}
    _check_probabilities(f"{path} hands", hands, activities)
    _check_probabilities(f"{path} eyes", eyes, activities)
    _check_probabilities(f"{path} looking_at_hands", {"E": looking}, activities)
    for posture, rows in support.items():
        if posture not in POSTURES:
            raise ValueError(f"{path} support: unknown posture '{posture}' (one of {POSTURES})")
        _check_probabilities(f"{path} support.{posture}", rows, activities)
    no_affordance = frozenset(doc.get("no_affordance") or ())
    postures = {a: tuple(v) for a, v in (doc.get("postures") or {}).items()}
    for activity, allowed in postures.items():
        if activity not in activities:
            raise ValueError(f"{path} postures: unknown activity '{activity}'")
        wrong = [x for x in allowed if x not in POSTURES]
        if wrong or not allowed:
            raise ValueError(f"{path} postures.{activity}: {wrong or 'no posture'} "
                             f"(each one of {POSTURES})")
    handheld = frozenset(doc.get("handheld") or ())
    unknown = sorted(handheld - set(hands))
    if unknown:
        raise ValueError(f"{path} handheld: {unknown} not in 'hands' (a held thing needs P_h)")
    return AffordanceTable(activities, hands, eyes, looking, support, no_affordance, postures,
                           handheld)


def _min_angle(skeleton: Skeleton, targets: ArrayLike) -> float:
    """Smallest angle [rad] between ear->eye and ear->target over the detected ears and eyes and
    the target points (one point, shape (2,), or several, shape (n, 2))."""
    best = math.inf
    gaze = present(skeleton, EYES) or present(skeleton, (NOSE,))
    points = np.atleast_2d(np.asarray(targets, dtype=float))
    for ear in present(skeleton, EARS):
        origin = skeleton[ear]
        to_targets = points - origin
        for eye in gaze:
            to_eye = skeleton[eye] - origin
            norms = np.linalg.norm(to_eye) * np.linalg.norm(to_targets, axis=1)
            ok = norms > 0
            if ok.any():
                cos = np.clip(to_targets[ok] @ to_eye / norms[ok], -1.0, 1.0)
                best = min(best, float(np.arccos(cos).min()))
    return best


def forearm_length(skeleton: Skeleton) -> float:
    """Longest detected forearm (elbow -> wrist) [px], 0 if none (Algorithm 3-2 line 13)."""
    lengths = [float(np.linalg.norm(skeleton[e] - skeleton[w]))
               for e, w in FOREARMS if len(present(skeleton, (e, w))) == 2]
    return max(lengths, default=0.0)


def faces_camera(skeleton: Skeleton) -> bool:
    """Fig. 3-12 (a): both ears and both eyes visible with the nose between the ears."""
    if len(present(skeleton, EARS)) < 2 or len(present(skeleton, EYES)) < 2:
        return False
    if not present(skeleton, (NOSE,)):
        return False
    lo, hi = sorted(skeleton[list(EARS), 0])
    return lo < skeleton[NOSE, 0] < hi


def forearm_length_3d(body: NDArray[np.float64]) -> float:
    """Longest forearm (elbow -> wrist) [m] of the joints in the map, 0 if none."""
    lengths = [float(np.linalg.norm(body[e] - body[w])) for e, w in FOREARMS
               if np.isfinite(body[[e, w]]).all()]
    return max(lengths, default=0.0)


def distance_to_extent(point: NDArray[np.float64], extent: tuple) -> float:
    """[m] from a map point to an axis-aligned box (low, high) of the map (0 inside)."""
    low, high = np.asarray(extent[0], dtype=float), np.asarray(extent[1], dtype=float)
    return float(np.linalg.norm(np.maximum(np.maximum(low - point, 0.0), point - high)))


def hands_in_map(joints: NDArray[np.float64]) -> list[NDArray[np.float64]]:
    """The wrists of the joints in the map (18, 3) [m] that are known."""
    return [joints[h] for h in HANDS if np.isfinite(joints[h]).all()]


def near_hands_3d(body: ArrayLike | None, objects: Sequence[SeenObject],
                  config: ActivityConfig) -> list[bool | None] | None:
    """Per object, whether a hand is within range_factor x the longest 3-D forearm (else
    `forearm_length`) of its box in the map; None for an object without an extent, or for all
    when no hand is known in 3-D (the image test decides then)."""
    if not config.reach_3d or body is None:
        return None
    joints = np.asarray(body, dtype=float)
    hands = hands_in_map(joints)
    reach = config.range_factor * (forearm_length_3d(joints) or config.forearm_length)
    if not hands or reach <= 0.0:
        return None
    return [None if obj.extent is None else
            min(distance_to_extent(h, obj.extent) for h in hands) < reach for obj in objects]


def held_objects(body: ArrayLike | None, near: Sequence[SeenObject], table: AffordanceTable,
                 config: ActivityConfig) -> list[SeenObject]:
    """The objects of O_h a hand holds (beyond the seed): hand-held things (`table.handheld`)
    whose box in the map a hand is within `config.hold_distance` of; none without the joints
    or boxes in the map, or with hold_distance 0."""
    if config.hold_distance <= 0.0 or body is None:
        return []
    hands = hands_in_map(np.asarray(body, dtype=float))
    return [obj for obj in near if obj.label in table.handheld and obj.extent is not None
            and min((distance_to_extent(h, obj.extent) for h in hands), default=math.inf)
            <= config.hold_distance]


def hand_object_eyesight_sets(
        skeleton: Skeleton, objects: Iterable[SeenObject], config: ActivityConfig,
        depth: ArrayLike | None = None,
        body: ArrayLike | None = None) -> tuple[list[SeenObject], list[SeenObject], bool]:
    """Algorithm 3-2: objects near the hands O_h, in the eyesight O_e, and E_h,e.

    Beyond the seed (`config.hand_depth_gap`): with the joints' and the objects' depths, an
    object near a hand in the image but `hand_depth_gap` farther or nearer than the hands is
    behind or before them (a fridge across the room), not in them; and a person looking at
    their hands looks at what is at the hands' depth, not at what lies that far behind them in
    the image.

    Args:
        skeleton: (18, 2) keypoints [px], NaN rows for missing joints.
        objects: [SeenObject].
        depth: (18,) joint depths [m] (None: the image alone decides).
        body: (18, 3) the joints in the map [m] (None: the image decides what is near the
            hands; near_hands_3d).
    Returns:
        (O_h, O_e, E_h,e) as ([SeenObject], [SeenObject], bool).
    """
    hands = present(skeleton, HANDS)
    watching = not faces_camera(skeleton)
    looking = watching and any(
        abs(_min_angle(skeleton, skeleton[h])) < config.eyesight_angle for h in hands)
    reach = config.range_factor * forearm_length(skeleton)
    hands_at = (joints_depth(skeleton, depth, HANDS)
                if depth is not None and config.hand_depth_gap > 0 else None)
    near: list[SeenObject] = []
    seen: list[SeenObject] = []
    objects = list(objects)
    in_reach = near_hands_3d(body, objects, config) or [None] * len(objects)
    for obj, metric in zip(objects, in_reach):
        shape = obj if config.to_box else SeenObject(obj.label, obj.confidence, obj.cx, obj.cy)
        apart = (hands_at is not None   # False, too, for an object without a depth (NaN)
                 and abs(obj.depth - hands_at) > config.hand_depth_gap)
        if not obj.in_image:            # remembered (object_memory): the 3-D reach alone
            if metric:
                near.append(obj)
            continue
        if metric is None:              # no 3-D reach for it: the image decides
            metric = not apart and min((shape.distance_to(skeleton[h]) for h in hands),
                                       default=math.inf) < reach
        if metric:
            near.append(obj)
        if watching and abs(_min_angle(skeleton, shape.box_points())) < config.eyesight_angle \
                and not (looking and apart):
            seen.append(obj)
    return near, seen, looking


def torso_top(skeleton: Skeleton) -> NDArray[np.float64] | None:
    """Top of the torso [px]: the neck, else the mid-shoulders, else the head joints; or None."""
    for joints in ((NECK,), SHOULDERS, HEAD):
        point = mean_of(skeleton, joints)
        if point is not None:
            return point
    return None


def support_objects(skeleton: Skeleton, objects: Iterable[SeenObject], posture: str,
                    table: AffordanceTable, config: ActivityConfig) -> list[SeenObject]:
    """O_s: furniture a sitting or lying person rests on -- boxes of the posture's support table
    that hold the hip midpoint, within support_margin x torso length."""
    rows = table.support.get(posture, {})
    hip, top = mean_of(skeleton, HIPS), torso_top(skeleton)
    if not rows or hip is None:
        return []
    margin = config.support_margin * (float(np.linalg.norm(hip - top)) if top is not None else 0.0)
    return [obj for obj in objects
            if obj.label in rows and obj.width > 0 and obj.distance_to(hip) <= margin]


def metres_per_pixel(skeleton: Skeleton, config: ActivityConfig) -> float | None:
    """Image scale at a body [m/px]: torso_length over the torso's length in pixels, or None."""
    top, hip = torso_top(skeleton), mean_of(skeleton, HIPS)
    if top is None or hip is None:
        return None
    torso = float(np.linalg.norm(hip - top))
    return config.torso_length / torso if torso > 0.0 else None


def joints_depth(skeleton: Skeleton, depth: ArrayLike, joints: Sequence[int]) -> float | None:
    """Median depth [m] of those of `joints` that were detected with a depth, or None."""
    seen = present(skeleton, joints)
    d = np.asarray(depth, dtype=float)[seen] if seen else np.zeros(0)
    d = d[np.isfinite(d)]
    return float(np.median(d)) if d.size else None


def body_depth_of(skeleton: Skeleton, depth: ArrayLike) -> float | None:
    """Median depth [m] of the detected torso joints (neck, shoulders, hips), or None."""
    return joints_depth(skeleton, depth, (NECK,) + SHOULDERS + HIPS)


def body_heading(skeleton: Skeleton, depth: ArrayLike,
                 scale: float) -> NDArray[np.float64] | None:
    """Unit vector (x right, z away from the camera) the body faces, from the shoulders: the
    right-to-left-shoulder line turned by 90 deg; None without both shoulders and their depths."""
    if len(present(skeleton, SHOULDERS)) < 2:
        return None
    d = np.asarray(depth, dtype=float)[list(SHOULDERS)]
    if not np.isfinite(d).all():
        return None
    right_x = (skeleton[R_SHOULDER, 0] - skeleton[L_SHOULDER, 0]) * scale
    right_z = d[0] - d[1]
    norm = math.hypot(right_x, right_z)
    return None if norm == 0.0 else np.array([-right_z, right_x]) / norm


def chat_partners(skeleton: Skeleton, depth: ArrayLike, others: Iterable[BodyView],
                  config: ActivityConfig) -> list[BodyView]:
    """Table 5-4's person in the eyesight, read from skeletons: the other bodies (BodyView) within
    partner_distance of the person whose heading points at the person within
    partner_facing_angle (distances in the ground plane: pixels x metres_per_pixel across,
    depth along the optical axis)."""
    scale, z = metres_per_pixel(skeleton, config), body_depth_of(skeleton, depth)
    top = torso_top(skeleton)
    if scale is None or z is None or top is None:
        return []
    partners: list[BodyView] = []
    for other in others:
        o_scale, o_z = metres_per_pixel(other.skeleton, config), body_depth_of(other.skeleton,
                                                                               other.depth)
        o_top = torso_top(other.skeleton)
        if o_scale is None or o_z is None or o_top is None:
            continue
        to_person = np.array([(top[0] - o_top[0]) * (scale + o_scale) / 2.0, z - o_z])
        gap = float(np.linalg.norm(to_person))
        heading = body_heading(other.skeleton, other.depth, o_scale)
        if heading is None or gap == 0.0 or gap > config.partner_distance:
            continue
        if math.acos(max(-1.0, min(1.0, float(heading @ to_person) / gap))) <= \
                config.partner_facing_angle:
            partners.append(other)
    return partners


def partner_objects(partners: Iterable[BodyView],
                    seen: Sequence[SeenObject]) -> list[SeenObject]:
    """SeenObject 'person' boxes (around the detected joints) of the chat partners that O_e does
    not already hold as a 'person' box around their torso."""
    added: list[SeenObject] = []
    for partner in partners:
        top = torso_top(partner.skeleton)
        if top is not None and any(o.label == "person" and o.width > 0
                                   and o.distance_to(top) == 0.0 for o in seen):
            continue
        pts = partner.skeleton[np.isfinite(partner.skeleton).all(axis=1)]
        (u0, v0), (u1, v1) = pts.min(axis=0), pts.max(axis=0)
        added.append(SeenObject("person", partner.confidence, (u0 + u1) / 2.0, (v0 + v1) / 2.0,
                                float(u1 - u0), float(v1 - v0)))
    return added


def activity_scores(near: Iterable[SeenObject], seen: Iterable[SeenObject], looking: bool,
                    table: AffordanceTable, config: ActivityConfig,
                    resting_on: Iterable[SeenObject] = (), posture: str = "") -> dict[str, float]:
    """Eqs. 3-11 ... 3-13: Score(a) = w_h sum_Oh P_h(a|o)P(o) + w_e sum_Oe P_e(a|o)P(o) + w_E P_E,
    plus our support term w_s sum_Os P_s(a|o, posture)P(o) for the furniture rested on; 0 for an
    activity the table's `postures` does not allow in a known `posture`.
    """
    score = dict.fromkeys(table.activities, 0.0)
    for obj in resting_on:
        for a, p in table.support.get(posture, {}).get(obj.label, {}).items():
            score[a] += config.weight_support * p * obj.confidence
    for obj in near:                                           # Eq. 3-12
        for a, p in table.hands.get(obj.label, {}).items():
            score[a] += config.weight_hands * p * obj.confidence
    for obj in seen:                                           # Eq. 3-13
        for a, p in table.eyes.get(obj.label, {}).items():
            score[a] += config.weight_eyes * p * obj.confidence
    if looking:
        for a, p in table.looking_at_hands.items():
            score[a] += config.weight_looking * p
    if posture in POSTURES:      # beyond the seed: not done in this posture
        for a, allowed in table.postures.items():
            if posture not in allowed:
                score[a] = 0.0
    return score


def activity_probabilities(score: Mapping[str, float]) -> dict[str, float]:
    """Normalise the scores to P(a) (Eqs. 3-14, 3-15); empty when every score is zero."""
    total = sum(score.values())
    if total <= 0.0:
        return {}
    return {a: s / total for a, s in score.items() if s > 0.0}


def posture_from_skeleton(skeleton: Skeleton, config: ActivityConfig) -> str:
    """General activity from the skeleton geometry: lying, sitting or standing (Sec. 3.2.4)."""
    neck = torso_top(skeleton)
    hip = mean_of(skeleton, HIPS)
    if neck is None or hip is None:
        return UNKNOWN_POSTURE
    dx, dy = abs(hip[0] - neck[0]), hip[1] - neck[1]
    torso = math.hypot(dx, dy)
    if torso <= 0.0 or dx > config.lying_ratio * abs(dy) or dy <= 0.0:
        return "lying"
    knee = mean_of(skeleton, KNEES)
    if knee is not None:
        return "sitting" if (knee[1] - hip[1]) < config.sitting_thigh_ratio * torso else "standing"
    ankle = mean_of(skeleton, ANKLES)
    if ankle is not None:
        return "sitting" if (ankle[1] - hip[1]) < config.sitting_leg_ratio * torso else "standing"
    return UNKNOWN_POSTURE


def posture_from_body(points: ArrayLike, config: ActivityConfig) -> str:
    """General activity from the joints in the map (18, 3) [m], z up, NaN rows unknown (beyond
    the seed): lying when the torso (neck, else mid-shoulders, to mid-hips) runs more across than
    up (`lying_ratio`) or the neck is below `lying_height`; standing from `standing_height`;
    else sitting; unknown without a neck or both shoulders."""
    body = np.asarray(points, dtype=float)
    top = body[NECK] if np.isfinite(body[NECK]).all() else (
        body[list(SHOULDERS)].mean(axis=0) if np.isfinite(body[list(SHOULDERS)]).all() else None)
    if top is None:
        return UNKNOWN_POSTURE
    hips = body[list(HIPS)]
    hips = hips[np.isfinite(hips).all(axis=1)]
    if len(hips):
        hip = hips.mean(axis=0)
        across, up = top[:2] - hip[:2], top[2] - hip[2]
        if up <= 0.0 or float(np.hypot(*across)) > config.lying_ratio * up:
            return "lying"
    if top[2] < config.lying_height:
        return "lying"
    return "standing" if top[2] >= config.standing_height else "sitting"


def recognise_activity(skeleton: Skeleton, objects: Sequence[SeenObject], table: AffordanceTable,
                       config: ActivityConfig, depth: ArrayLike | None = None,
                       others: Sequence[BodyView] = (),
                       body: ArrayLike | None = None) -> ActivityResult:
    """Algorithm 3-3 with the hierarchical fallback: detailed activity or posture.

    Args:
        depth: (18,) joint depths [m] of the person (None: no chat partners from skeletons).
        others: [BodyView] the other people of the frame.
        body: (18, 3) the joints in the map [m], NaN rows unknown (None: the posture is read
            from the image alone).
    """
    near, seen, looking = hand_object_eyesight_sets(skeleton, objects, config, depth, body)
    if config.partners_from_skeletons and depth is not None and others:
        seen = seen + partner_objects(chat_partners(skeleton, depth, others, config), seen)
    posture = (posture_from_body(body, config) if config.posture_3d and body is not None
               else UNKNOWN_POSTURE)
    if posture == UNKNOWN_POSTURE:
        posture = posture_from_skeleton(skeleton, config)
    resting = (support_objects(skeleton, objects, posture, table, config)
               if config.weight_support > 0 else [])
    held = held_objects(body, near, table, config)
    probabilities = activity_probabilities(
        activity_scores(held or near, seen, looking, table, config, resting, posture))
    activity = posture
    if probabilities:
        best = max(probabilities, key=probabilities.__getitem__)
        if probabilities[best] >= config.probability_threshold:
            activity = best
    return ActivityResult(activity, probabilities, posture, [o.label for o in near],
                          [o.label for o in seen], looking, [o.label for o in resting],
                          [o.label for o in held])
