"""Eq. 3-6 ... 3-10 and Algorithm 3-1 against the seed's own numbers (thesis 000 §5.2.3)."""
import math

import numpy as np
import pytest

from human_db.colour import (ColourIndex, IdentificationConfig, Match, approximate_colour_distance,
                             best_matches, identifies, identify_first_below_threshold,
                             mean_shirt_distance, shirt_colours, shirt_distance_matrix)
from human_db.errors import InvalidColour

# Table 5-1: shirt colours at joints 1, 2, 5 of the query image (a) and the test image (b).
TABLE_5_1_QUERY = ((215, 250, 220), (32, 77, 238), (29, 74, 219))
TABLE_5_1_TEST = ((253, 255, 199), (172, 190, 168), (87, 100, 142))


def test_table_5_1_colour_metric_is_189_43():
    distance = mean_shirt_distance(TABLE_5_1_QUERY, TABLE_5_1_TEST)
    # Independent per-joint values (Eq. 3-10 by hand): 72.2916, 332.8872, 163.1401.
    assert distance == pytest.approx((72.291646 + 332.887204 + 163.140145) / 3, abs=1e-5)
    # The thesis prints 189.43: the exact mean is 189.4397, cut (not rounded) to two decimals.
    assert math.floor(distance * 100) / 100 == 189.43


def test_eq_3_10_by_hand():
    # r̄ = 105, ΔR = -10, ΔG = 10, ΔB = 30:
    # sqrt((2 + 105/256)·100 + 4·100 + (2 + 150/256)·900) = sqrt(2968.359375)
    assert approximate_colour_distance((100, 150, 200), (110, 140, 170)) == \
        pytest.approx(math.sqrt(2968.359375), abs=1e-12)
    # pure red against black: r̄ = 127.5, only ΔR = 255 counts
    assert approximate_colour_distance((255, 0, 0), (0, 0, 0)) == \
        pytest.approx(255 * math.sqrt(2 + 127.5 / 256), abs=1e-9)
    assert approximate_colour_distance((10, 20, 30), (10, 20, 30)) == 0.0


def test_red_weighting_makes_blue_differences_cost_more_on_dark_red():
    # With a small r̄ the blue weight 2 + (255 - r̄)/256 is near 3, the red weight near 2.
    blue_step = approximate_colour_distance((0, 0, 0), (0, 0, 100))   # r̄ = 0
    red_step = approximate_colour_distance((0, 0, 0), (100, 0, 0))    # r̄ = 50
    assert blue_step == pytest.approx(100 * math.sqrt(2 + 255 / 256))
    assert red_step == pytest.approx(100 * math.sqrt(2 + 50 / 256))
    assert blue_step > red_step


def test_vectorised_matrix_equals_the_scalar_equations():
    rng = np.random.default_rng(3)
    observed = rng.integers(0, 256, size=(5, 3, 3))
    stored = rng.integers(0, 256, size=(7, 3, 3))
    matrix = shirt_distance_matrix(observed, stored)
    assert matrix.shape == (5, 7)
    for n in range(5):
        for m in range(7):
            assert matrix[n, m] == pytest.approx(mean_shirt_distance(observed[n], stored[m]),
                                                 abs=1e-9)
    table = shirt_distance_matrix(np.array([TABLE_5_1_QUERY]), np.array([TABLE_5_1_TEST]))
    assert table[0, 0] == pytest.approx(189.43966, abs=1e-5)


def test_table_5_2_classification_with_threshold_200():
    # Table 5-2: distances of query people A, B (rows) to six test images (columns).
    distances = np.array([[124.4, 172.4, 422.4, 387.2, 301.1, 300.2],
                          [387.8, 417.5, 34.5, 186.1, 295.1, 390.7]])
    matches = best_matches(distances.T, ["A", "B"], threshold=200.0)
    assert [m.name if m else None for m in matches] == ["A", "A", "B", "B", None, None]
    assert [m.distance for m in matches if m] == [124.4, 172.4, 34.5, 186.1]


def test_threshold_is_strict_and_configurable():
    assert best_matches([[200.0]], ["A"], threshold=200.0) == [None]
    assert best_matches([[199.9]], ["A"], threshold=200.0) == [Match("A", 199.9)]
    assert best_matches([[250.0]], ["A"], threshold=300.0) == [Match("A", 250.0)]


def test_best_match_is_the_closest_of_two_under_threshold_where_algorithm_3_1_takes_first():
    observed = np.array([[200, 30, 40]] * 3)
    far = np.array([[200, 60, 40]] * 3)     # ΔG = 30 -> 60.0 per joint
    near = np.array([[200, 40, 40]] * 3)    # ΔG = 10 -> 20.0 per joint
    names, stored = ["Far", "Near"], np.stack([far, near])
    assert mean_shirt_distance(observed, far) == pytest.approx(60.0)
    assert mean_shirt_distance(observed, near) == pytest.approx(20.0)
    assert identify_first_below_threshold(observed, names, stored, 200.0) == "Far"
    index = ColourIndex(names, stored, IdentificationConfig(threshold=200.0))
    match = index.identify(observed.ravel().tolist())
    assert match.name == "Near"
    assert match.distance == pytest.approx(20.0)


def test_nobody_below_threshold_and_empty_database_give_none():
    index = ColourIndex(["A"], [[[0, 0, 0]] * 3])
    assert index.identify([[255, 255, 255]] * 3) is None
    assert ColourIndex([], np.zeros((0, 3, 3))).identify([[1, 2, 3]] * 3) is None
    assert identify_first_below_threshold(np.zeros((3, 3)), [], [], 200.0) is None


def test_identify_many_scores_every_observation():
    index = ColourIndex(["Red", "Blue"], [[[200, 30, 40]] * 3, [[30, 60, 200]] * 3])
    matches = index.identify_many([[[205, 35, 45]] * 3, [[255, 255, 255]] * 3,
                                   [[25, 55, 190]] * 3])
    assert [m.name if m else None for m in matches] == ["Red", None, "Blue"]


def test_shirt_colours_accepts_flat_and_nested():
    flat = shirt_colours([1, 2, 3, 4, 5, 6, 7, 8, 9])
    assert flat.tolist() == [[1, 2, 3], [4, 5, 6], [7, 8, 9]]
    assert shirt_colours(((1, 2, 3), (4, 5, 6), (7, 8, 9))).tolist() == flat.tolist()
    assert shirt_colours(bytes([0, 255, 0, 0, 255, 0, 0, 255, 0]))[0].tolist() == [0, 255, 0]


@pytest.mark.parametrize("bad, needle", [
    ([1, 2, 3, 4, 5, 6, 7, 8], "9 values"),
    ([[1, 2, 3], [4, 5, 6]], "9 values"),
    ([[1, 2, 3], [4, 5, 6], [7, 8]], "9 values"),
    ([0, 0, 0, 0, 0, 0, 0, 0, 256], "outside 0-255"),
    ([0, 0, 0, 0, -1, 0, 0, 0, 0], "outside 0-255"),
    ([0, 0, 0, 0, 0, 0, 0, 0, 3.5], "not an integer"),
    ([0, 0, 0, 0, 0, 0, 0, 0, True], "not an integer"),
    (["red", "green", "blue"], "9 values, got 3"),
    (["x"] * 9, "not an integer"),
    ("red", "the text"),
    (None, "3 joints x RGB"),
    (42, "3 joints x RGB"),
])
def test_malformed_colours_are_refused_with_the_reason(bad, needle):
    with pytest.raises(InvalidColour, match=needle):
        shirt_colours(bad, "test colour")


def test_two_similar_shirts_under_threshold_identify_nobody_with_a_margin():
    """Never a silent guess between two people in similar shirts: with a margin the sighting of
    the test above (20 from Near, 60 from Far) is ambiguous; a clear winner stays identified."""
    observed = np.array([[200, 30, 40]] * 3)
    far, near = np.array([[200, 60, 40]] * 3), np.array([[200, 40, 40]] * 3)
    index = ColourIndex(["Far", "Near"], np.stack([far, near]),
                        IdentificationConfig(threshold=200.0, margin=60.0))
    assert index.identify(observed) is None
    assert not identifies(observed, [far, near], IdentificationConfig(200.0, 60.0))
    blue = np.array([[30, 60, 200]] * 3)
    index = ColourIndex(["Near", "Blue"], np.stack([near, blue]),
                        IdentificationConfig(threshold=200.0, margin=60.0))
    assert index.identify(observed).name == "Near"           # Blue is far above the threshold
    assert identifies(observed, [near, blue], IdentificationConfig(200.0, 60.0))
    assert not identifies(observed, [], IdentificationConfig())
