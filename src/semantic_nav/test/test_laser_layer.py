"""Laser layer (thesis 002 §2.2.2) against hand-computed values."""
import math

import numpy as np
import pytest

from semantic_nav.laser_layer import (PreprocessConfig, ScanError, interpolate_scan,
                                      interpolation_indices, l2_normalise, load_laser_config,
                                      model_from_scan, preprocess_scan, saturate)
from tamp_resources import resource

CONFIG = resource("config") / "semnav_laser.yaml"


@pytest.fixture(scope="module")
def lasers():
    return load_laser_config(CONFIG)


def test_canonical_angles_are_220_degrees_of_the_utm30lx(lasers):
    _, canonical, _ = lasers
    angles = np.degrees(canonical.angles())
    assert angles.size == 881
    assert angles[0] == pytest.approx(-110.0)
    assert angles[440] == pytest.approx(0.0)
    assert angles[-1] == pytest.approx(110.0)


def test_urg04lx_indices_by_hand(lasers):
    models, canonical, _ = lasers
    # -110°: (−110 + 119.8828125) / 0.3515625 = 28 + 1/9;  0°: 341 exactly;  110°: 653 + 8/9
    samp, fraction = interpolation_indices(models["urg04lx"], canonical.angles()[[0, 440, 880]])
    assert samp.tolist() == [28, 341, 653]
    assert fraction == pytest.approx([1 / 9, 0.0, 8 / 9])


def test_urg04lx_to_canonical_by_hand(lasers):
    models, canonical, _ = lasers
    urg = models["urg04lx"]
    ranges = 1.0 + 0.5 * (np.arange(urg.beams) % 4)   # A_j = 1, 1.5, 2, 2.5, 1, ...
    out = interpolate_scan(ranges, urg, canonical)
    assert out.shape == (881,)
    # i=0: A_28 + (A_29 - A_28) * 1/9 = 1 + 0.5/9
    assert out[0] == pytest.approx(1.0 + 0.5 / 9)
    # i=1 at -109.75°: t = 28 + 1/9 + 0.25/0.3515625 = 28 + 37/45 -> 1 + 0.5 * 37/45
    assert out[1] == pytest.approx(1.0 + 0.5 * 37 / 45)
    # i=2 at -109.5°: t = 29 + 8/15 -> A_29 + (A_30 - A_29) * 8/15 = 1.5 + 0.5 * 8/15
    assert out[2] == pytest.approx(1.5 + 0.5 * 8 / 15)
    assert out[440] == pytest.approx(1.5)                  # A_341, 341 % 4 = 1
    assert out[880] == pytest.approx(1.5 + 0.5 * 8 / 9)    # A_653 -> A_654


def test_utm30lx_to_canonical_is_a_crop(lasers):
    models, canonical, _ = lasers
    ranges = np.linspace(0.5, 4.0, 1081)
    np.testing.assert_allclose(interpolate_scan(ranges, models["utm30lx"], canonical),
                               ranges[100:981])


def test_too_narrow_laser_is_rejected(lasers):
    _, canonical, _ = lasers
    narrow = model_from_scan("front180", -math.pi / 2, math.radians(0.5), 361)
    with pytest.raises(ScanError, match="canonical scan needs"):
        interpolate_scan(np.ones(361), narrow, canonical)


def test_modified_saturation():
    np.testing.assert_array_equal(saturate([0.3, 4.99, 5.0, 7.0, 30.0]),
                                  [0.3, 4.99, 10.0, 10.0, 10.0])


def test_l2_normalisation():
    np.testing.assert_allclose(l2_normalise([3.0, 4.0]), [0.6, 0.8])
    np.testing.assert_allclose(l2_normalise([1.0, 2.0, 2.0]), [1 / 3, 2 / 3, 2 / 3])


def test_pipeline_on_urg_scan(lasers):
    models, canonical, config = lasers
    ranges = np.full(683, 2.0)
    ranges[341] = 5.5                 # 0°: below range_max 5.6 m, saturated to 10 m
    out, invalid = preprocess_scan(ranges, models["urg04lx"], canonical, config)
    assert invalid == 0
    # ±0.25° lie 0.25/0.3515625 = 32/45 of a step from beam 341: 5.5 - 3.5 * 32/45 = 3.01 m (< 5 m)
    side = 5.5 - 3.5 * 32 / 45
    norm = math.sqrt(878 * 2.0 ** 2 + 2 * side ** 2 + 10.0 ** 2)
    assert out[441] == pytest.approx(side / norm, rel=1e-6)
    assert out[440] == pytest.approx(10.0 / norm, rel=1e-6)
    assert out[0] == pytest.approx(2.0 / norm, rel=1e-6)
    assert out.dtype == np.float32


def test_nan_zero_and_inf_beams(lasers):
    models, canonical, config = lasers
    urg = models["urg04lx"]
    ranges = np.full(683, 2.0)
    ranges[339] = np.nan      # erroneous -> nearest valid beam 338 (2 m)
    ranges[340] = 0.0         # below range_min -> nearest valid beam 341 (2 m)
    ranges[342] = np.inf      # no return -> saturated 10 m
    ranges[500] = 7.0         # above range_max 5.6 m -> no return as well
    out, invalid = preprocess_scan(ranges, urg, canonical, config)
    assert invalid == 2
    assert np.all(np.isfinite(out))
    norm = np.linalg.norm(saturate(interpolate_scan(
        np.where(np.isin(np.arange(683), [342, 500]), 10.0, 2.0), urg, canonical)))
    # 0° is beam 341 exactly -> 2 m; 0.25° lies between beams 341 and 342 (fraction 0.25/0.3515625)
    assert out[440] == pytest.approx(2.0 / norm, rel=1e-6)
    assert out[441] == pytest.approx(10.0 / norm, rel=1e-6)   # 2 + 8 * 0.711 = 7.69 m >= 5 m


def test_all_zero_scan_is_a_clear_error(lasers):
    models, canonical, config = lasers
    with pytest.raises(ScanError, match="683 of 683 beams"):
        preprocess_scan(np.zeros(683), models["urg04lx"], canonical, config)


def test_all_nan_scan_is_a_clear_error(lasers):
    models, canonical, config = lasers
    with pytest.raises(ScanError, match="NaN"):
        preprocess_scan(np.full(1081, np.nan), models["utm30lx"], canonical, config)


def test_wrong_length_is_a_clear_error(lasers):
    models, canonical, config = lasers
    with pytest.raises(ScanError, match="expected 683 ranges"):
        preprocess_scan(np.ones(682), models["urg04lx"], canonical, config)


def test_everything_too_close_is_a_clear_error(lasers):
    models, canonical, _ = lasers
    zero_min = model_from_scan("z", models["urg04lx"].angle_min,
                               models["urg04lx"].angle_increment, 683, range_min=0.0)
    with pytest.raises(ScanError, match="zero length"):
        preprocess_scan(np.full(683, -np.inf), zero_min, canonical, PreprocessConfig())
