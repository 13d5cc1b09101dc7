"""COCO-18 body keypoints in OpenPose order (thesis 000 Fig. 3-4) and the joint groups the
visual heuristics read.

A skeleton is an (18, 2) float array of image coordinates [px] (x right, y down) with NaN rows
for joints the pose detector did not find.
"""
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

NOSE, NECK, R_SHOULDER, R_ELBOW, R_WRIST, L_SHOULDER, L_ELBOW, L_WRIST = range(8)
R_HIP, R_KNEE, R_ANKLE, L_HIP, L_KNEE, L_ANKLE, R_EYE, L_EYE, R_EAR, L_EAR = range(8, 18)
NUM_KEYPOINTS = 18
Skeleton = NDArray[np.float64]   # (18, 2) [px], NaN rows for joints not found

HANDS = (R_WRIST, L_WRIST)                               # Algorithm 3-2: joints 4, 7
FOREARMS = ((R_ELBOW, R_WRIST), (L_ELBOW, L_WRIST))      # Algorithm 3-2 line 13: (3,4), (6,7)
EARS = (R_EAR, L_EAR)                                    # Algorithm 3-2: joints 16, 17
EYES = (R_EYE, L_EYE)                                    # Algorithm 3-2: joints 14, 15
HIPS = (R_HIP, L_HIP)
KNEES = (R_KNEE, L_KNEE)
ANKLES = (R_ANKLE, L_ANKLE)


def as_skeleton(points: ArrayLike, confidence: ArrayLike | None = None) -> Skeleton:
    """Validate (18, 2) keypoints; joints with confidence 0 (or non-finite) become NaN rows."""
    pts = np.array(points, dtype=float)
    if pts.shape != (NUM_KEYPOINTS, 2):
        raise ValueError(f"skeleton needs shape ({NUM_KEYPOINTS}, 2), got {pts.shape}")
    if confidence is not None:
        conf = np.asarray(confidence, dtype=float)
        if conf.shape != (NUM_KEYPOINTS,):
            raise ValueError(f"skeleton confidence needs shape ({NUM_KEYPOINTS},), "
                             f"got {conf.shape}")
        pts[~(conf > 0)] = np.nan
    pts[~np.isfinite(pts).all(axis=1)] = np.nan
    return pts


def present(skeleton: Skeleton, joints: Sequence[int]) -> list[int]:
    """The subset of `joints` that were detected."""
    return [j for j in joints if np.isfinite(skeleton[j]).all()]


def mean_of(skeleton: Skeleton, joints: Sequence[int]) -> NDArray[np.float64] | None:
    """Mean position of the detected joints among `joints`, or None if none was detected."""
    found = present(skeleton, joints)
    return skeleton[found].mean(axis=0) if found else None
