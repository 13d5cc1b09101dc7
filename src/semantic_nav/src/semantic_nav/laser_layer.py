"""Laser range finder layer (thesis 002 §2.2.2): any scan -> the canonical 220° UTM-30LX input.

Stages, in order: repair of invalid beams (NaN, ±inf, readings below range_min such as the
zeros some drivers send), linear interpolation to the canonical beam angles (Eq. 2.2-3 … 2.2-6),
the modified saturation (Eq. 2.2-7) and L2 normalisation (Eq. 2.2-9).

Beam arrays are 1-D float arrays in the order of sensor_msgs/LaserScan (angle_min first,
counter-clockwise, angle of beam j = angle_min + j * angle_increment).
"""
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml
from numpy.typing import ArrayLike, NDArray


class ScanError(ValueError):
    """A scan that cannot be turned into network input; the message says why."""


@dataclass
class LaserModel:
    """Geometry of one laser range finder as it publishes its scans."""

    name: str
    angle_min: float        # angle of beam 0 [rad], counter-clockwise from the x axis
    angle_increment: float  # angular resolution A_diff [rad], > 0
    beams: int              # number of measurement steps published
    range_min: float = 0.0  # readings below this are invalid [m]
    range_max: float = math.inf  # readings above this mean "no return" [m]

    @property
    def angle_max(self) -> float:
        return self.angle_min + (self.beams - 1) * self.angle_increment


@dataclass
class CanonicalScan:
    """The sensor B the network was trained on and the part of its scan that is used (Eq. 2.2-3)."""

    model: LaserModel       # the original sensor B (seed: UTM-30LX, B_min = -135°, B_diff = 0.25°)
    start: int              # B_start: first step used
    steps: int              # B_steps: number of steps used

    def angles(self) -> NDArray[np.float64]:
        """Eq. 2.2-3: angle_i = B_min + (B_start + i) * B_diff, 0 <= i < B_steps [rad]."""
        i = np.arange(self.steps)
        return self.model.angle_min + (self.start + i) * self.model.angle_increment


@dataclass
class PreprocessConfig:
    """Eq. 2.2-7 saturation and the policy for invalid beams."""

    saturation_threshold: float = 5.0  # readings >= this are "free space" [m]
    saturated_value: float = 10.0      # value given to them (seed: 10 m, not 5 m) [m]
    max_invalid_fraction: float = 0.25  # more invalid beams than this -> ScanError [1]


def laser_model_from_dict(name: str, entry: Mapping[str, Any]) -> LaserModel:
    """Build a LaserModel from a YAML mapping with angles in degrees; ScanError names bad keys."""
    try:
        model = LaserModel(
            name=name, angle_min=math.radians(float(entry["angle_min_deg"])),
            angle_increment=math.radians(float(entry["angle_increment_deg"])),
            beams=int(entry["beams"]), range_min=float(entry.get("range_min", 0.0)),
            range_max=float(entry.get("range_max", math.inf)))
    except (KeyError, TypeError, ValueError) as error:
        raise ScanError(f"laser model {name!r}: bad or missing field ({error})") from error
    if model.angle_increment <= 0 or model.beams < 2:
        raise ScanError(f"laser model {name!r}: needs angle_increment > 0 and beams >= 2")
    return model


def load_laser_config(path: str | os.PathLike[str]
                      ) -> tuple[dict[str, LaserModel], CanonicalScan, PreprocessConfig]:
    """Read config/semnav_laser.yaml -> (models by name, CanonicalScan, PreprocessConfig)."""
    config = yaml.safe_load(Path(path).read_text())
    models = {name: laser_model_from_dict(name, entry)
              for name, entry in config["laser_models"].items()}
    canonical = config["canonical"]
    if canonical["model"] not in models:
        raise ScanError(f"{path}: canonical model {canonical['model']!r} is not in laser_models")
    scan = CanonicalScan(models[canonical["model"]], int(canonical["start"]),
                         int(canonical["steps"]))
    return models, scan, PreprocessConfig(**config.get("preprocess", {}))


def repair_invalid_beams(ranges: ArrayLike, model: LaserModel,
                         config: PreprocessConfig) -> tuple[NDArray[np.float64], int]:
    """REP-117 readings -> finite ranges: +inf/above range_max -> no return, NaN/below range_min
    (incl. 0) -> value of the nearest valid beam; -inf (too close) -> range_min.

    Returns (repaired ranges, number of invalid beams). ScanError when too many are invalid.
    """
    ranges = np.asarray(ranges, dtype=np.float64)
    if ranges.ndim != 1 or ranges.size != model.beams:
        raise ScanError(f"{model.name}: expected {model.beams} ranges, got shape {ranges.shape}")
    out = ranges.copy()
    far = (ranges == np.inf) | (ranges > model.range_max)
    near = ranges == -np.inf
    out[far] = config.saturated_value
    out[near] = model.range_min
    invalid = np.isnan(ranges) | (~far & ~near & (ranges < max(model.range_min, 1e-9)))
    count = int(invalid.sum())
    if count > config.max_invalid_fraction * ranges.size:
        raise ScanError(f"{model.name}: {count} of {ranges.size} beams are NaN or below "
                        f"range_min {model.range_min} m (limit {config.max_invalid_fraction:.0%})")
    if count:
        valid = np.flatnonzero(~invalid)
        nearest = np.searchsorted(valid, np.flatnonzero(invalid)).clip(0, valid.size - 1)
        below = (nearest - 1).clip(0)
        idx = np.flatnonzero(invalid)
        closer = np.abs(valid[below] - idx) < np.abs(valid[nearest] - idx)
        out[invalid] = out[np.where(closer, valid[below], valid[nearest])]
    return out, count


def interpolation_indices(source: LaserModel,
                          angles: ArrayLike) -> tuple[NDArray[np.int_], NDArray[np.float64]]:
    """Eq. 2.2-4 and 2.2-5: SAMP_i = floor((angle - A_min) / A_diff) and INTER_i / A_diff.

    Returns (SAMP as int array, INTER_i / A_diff in [0, 1)). ScanError if an angle lies outside
    the source's scanning range.
    """
    steps = (np.asarray(angles) - source.angle_min) / source.angle_increment
    steps = np.where(np.abs(steps - np.round(steps)) < 1e-9, np.round(steps), steps)
    if steps.min() < 0 or steps.max() > source.beams - 1:
        raise ScanError(
            f"{source.name} covers {math.degrees(source.angle_min):.2f}° … "
            f"{math.degrees(source.angle_max):.2f}°, the canonical scan needs "
            f"{math.degrees(np.min(angles)):.2f}° … {math.degrees(np.max(angles)):.2f}°")
    samp = np.floor(steps).astype(int)
    return samp, steps - samp


def interpolate_scan(ranges: ArrayLike, source: LaserModel,
                     canonical: CanonicalScan) -> NDArray[np.float64]:
    """Eq. 2.2-6: B_i = A_SAMP + (A_SAMP+1 - A_SAMP) * INTER_i / A_diff for the canonical angles."""
    ranges = np.asarray(ranges, dtype=np.float64)
    samp, fraction = interpolation_indices(source, canonical.angles())
    upper = np.minimum(samp + 1, source.beams - 1)  # fraction is 0 wherever samp is the last beam
    return ranges[samp] + (ranges[upper] - ranges[samp]) * fraction


def saturate(ranges: ArrayLike, config: PreprocessConfig | None = None) -> NDArray[np.float64]:
    """Eq. 2.2-7: f(x) = x if x < 5 m, else 10 m."""
    config = config or PreprocessConfig()
    ranges = np.asarray(ranges, dtype=np.float64)
    return np.where(ranges < config.saturation_threshold, ranges, config.saturated_value)


def l2_normalise(values: ArrayLike) -> NDArray[np.float64]:
    """Eq. 2.2-9: x_i / sqrt(sum_k x_k^2) (sklearn's normalize(norm='l2') for one sample)."""
    values = np.asarray(values, dtype=np.float64)
    norm = math.sqrt(float(np.dot(values, values)))
    if not norm > 0:
        raise ScanError("scan has zero length after saturation (every beam reads 0 m)")
    return values / norm


def preprocess_scan(ranges: ArrayLike, source: LaserModel, canonical: CanonicalScan,
                    config: PreprocessConfig | None = None) -> tuple[NDArray[np.float32], int]:
    """The whole layer: repair, interpolate, saturate, normalise -> canonical input vector.

    Returns (float32 array of canonical.steps values, number of repaired invalid beams).
    """
    config = config or PreprocessConfig()
    repaired, invalid = repair_invalid_beams(ranges, source, config)
    interpolated = interpolate_scan(repaired, source, canonical)
    return l2_normalise(saturate(interpolated, config)).astype(np.float32), invalid


def model_from_scan(name: str, angle_min: float, angle_increment: float, beams: int,
                    range_min: float = 0.0, range_max: float = math.inf) -> LaserModel:
    """LaserModel from the fields of a sensor_msgs/LaserScan (so any laser works unannounced)."""
    if not angle_increment > 0 or beams < 2:
        raise ScanError(f"{name}: scan needs angle_increment > 0 and >= 2 beams, got "
                        f"{angle_increment} rad and {beams} beams")
    return LaserModel(name, float(angle_min), float(angle_increment), int(beams),
                      float(range_min), float(range_max))
