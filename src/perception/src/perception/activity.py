"""Framewise hierarchical human activity recognition (thesis 000 Sec. 3.2.4).

Detailed activities come from objects near the hands (O_h), objects in the eyesight (O_e) and
whether the person looks at their hands (E_h,e), scored through an affordance table
(Algorithm 3-2, Eqs. 3-11 ... 3-13); when no detailed activity is probable enough the result falls
back to the posture read from the skeleton (sitting, standing, lying).
"""
import math
from dataclasses import dataclass, field

import numpy as np
import yaml

from perception.keypoints import (
    ANKLES, EARS, EYES, FOREARMS, HANDS, HIPS, KNEES, NECK, NOSE, mean_of, present)

POSTURES = ("sitting", "standing", "lying")
UNKNOWN_POSTURE = "unknown"


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


@dataclass
class AffordanceTable:
    """P_h(a|o), P_e(a|o) per object class and P_E(a|E_h,e), with the activity categories."""

    activities: tuple
    hands: dict = field(default_factory=dict)     # label -> {activity: P_h(a|o)}
    eyes: dict = field(default_factory=dict)      # label -> {activity: P_e(a|o)}
    looking_at_hands: dict = field(default_factory=dict)   # {activity: P_E(a|E)}

    def known(self, label):
        return label in self.hands or label in self.eyes


@dataclass
class SeenObject:
    """A detected object as the heuristics need it: class, confidence P(o), box centre [px]."""

    label: str
    confidence: float
    cx: float
    cy: float


@dataclass
class ActivityResult:
    activity: str                 # detailed activity, or the posture when none is probable
    probabilities: dict           # activity -> P(a) (empty when no object gave a score)
    posture: str
    near_hands: list              # labels in O_h
    in_eyesight: list             # labels in O_e
    looking_at_hands: bool


def _check_probabilities(where, table, activities):
    for label, row in table.items():
        for activity, p in row.items():
            if activity not in activities:
                raise ValueError(f"{where}: '{label}' names unknown activity '{activity}'")
            if not 0.0 <= float(p) <= 1.0:
                raise ValueError(f"{where}: '{label}' -> '{activity}' probability {p} "
                                 "not in [0, 1]")


def load_affordances(path):
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
    _check_probabilities(f"{path} hands", hands, activities)
    _check_probabilities(f"{path} eyes", eyes, activities)
    _check_probabilities(f"{path} looking_at_hands", {"E": looking}, activities)
    return AffordanceTable(activities, hands, eyes, looking)


def _min_angle(skeleton, target):
    """Smallest angle [rad] between ear->eye and ear->target over the detected ears and eyes."""
    best = math.inf
    gaze = present(skeleton, EYES) or present(skeleton, (NOSE,))
    for ear in present(skeleton, EARS):
        origin = skeleton[ear]
        to_target = np.asarray(target, dtype=float) - origin
        for eye in gaze:
            to_eye = skeleton[eye] - origin
            norm = np.linalg.norm(to_eye) * np.linalg.norm(to_target)
            if norm > 0:
                cos = float(np.clip(np.dot(to_eye, to_target) / norm, -1.0, 1.0))
                best = min(best, math.acos(cos))
    return best


def forearm_length(skeleton):
    """Longest detected forearm (elbow -> wrist) [px], 0 if none (Algorithm 3-2 line 13)."""
    lengths = [float(np.linalg.norm(skeleton[e] - skeleton[w]))
               for e, w in FOREARMS if len(present(skeleton, (e, w))) == 2]
    return max(lengths, default=0.0)


def faces_camera(skeleton):
    """Fig. 3-12 (a): both ears and both eyes visible with the nose between the ears."""
    if len(present(skeleton, EARS)) < 2 or len(present(skeleton, EYES)) < 2:
        return False
    if not present(skeleton, (NOSE,)):
        return False
    lo, hi = sorted(skeleton[list(EARS), 0])
    return lo < skeleton[NOSE, 0] < hi


def hand_object_eyesight_sets(skeleton, objects, config):
    """Algorithm 3-2: objects near the hands O_h, in the eyesight O_e, and E_h,e.

    Args:
        skeleton: (18, 2) keypoints [px], NaN rows for missing joints.
        objects: [SeenObject].
    Returns:
        (O_h, O_e, E_h,e) as ([SeenObject], [SeenObject], bool).
    """
    hands = present(skeleton, HANDS)
    watching = not faces_camera(skeleton)
    looking = watching and any(
        abs(_min_angle(skeleton, skeleton[h])) < config.eyesight_angle for h in hands)
    reach = config.range_factor * forearm_length(skeleton)
    near, seen = [], []
    for obj in objects:
        centre = np.array([obj.cx, obj.cy])
        d_hand = min((float(np.linalg.norm(skeleton[h] - centre)) for h in hands), default=math.inf)
        if d_hand < reach:
            near.append(obj)
        if watching and abs(_min_angle(skeleton, centre)) < config.eyesight_angle:
            seen.append(obj)
    return near, seen, looking


def activity_scores(near, seen, looking, table, config):
    """Eqs. 3-11 ... 3-13: Score(a) = w_h sum_Oh P_h(a|o)P(o) + w_e sum_Oe P_e(a|o)P(o) + w_E P_E.
    """
    score = dict.fromkeys(table.activities, 0.0)
    for obj in near:                                           # Eq. 3-12
        for a, p in table.hands.get(obj.label, {}).items():
            score[a] += config.weight_hands * p * obj.confidence
    for obj in seen:                                           # Eq. 3-13
        for a, p in table.eyes.get(obj.label, {}).items():
            score[a] += config.weight_eyes * p * obj.confidence
    if looking:
        for a, p in table.looking_at_hands.items():
            score[a] += config.weight_looking * p
    return score


def activity_probabilities(score):
    """Normalise the scores to P(a) (Eqs. 3-14, 3-15); empty when every score is zero."""
    total = sum(score.values())
    if total <= 0.0:
        return {}
    return {a: s / total for a, s in score.items() if s > 0.0}


def posture_from_skeleton(skeleton, config):
    """General activity from the skeleton geometry: lying, sitting or standing (Sec. 3.2.4)."""
    neck = mean_of(skeleton, (NECK,))
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


def recognise_activity(skeleton, objects, table, config):
    """Algorithm 3-3 with the hierarchical fallback: detailed activity or posture."""
    near, seen, looking = hand_object_eyesight_sets(skeleton, objects, config)
    probabilities = activity_probabilities(activity_scores(near, seen, looking, table, config))
    posture = posture_from_skeleton(skeleton, config)
    activity = posture
    if probabilities:
        best = max(probabilities, key=probabilities.get)
        if probabilities[best] >= config.probability_threshold:
            activity = best
    return ActivityResult(activity, probabilities, posture, [o.label for o in near],
                          [o.label for o in seen], looking)
