"""Post-processing layer (§2.2.5): Eq. 2.2-12 on its boundary values and the halting counter."""
import pytest

from semantic_nav.postprocess import HaltingCounter, PostprocessConfig, adjust_speed, apply_stop


@pytest.mark.parametrize("v, expected", [
    (0.0, 0.0), (1e-3, 0.0), (-1e-3, 0.0), (9.99e-4, 0.0),        # |v| <= v_min -> 0
    (1.0001e-3, 2e-2), (-1.0001e-3, -2e-2), (0.015, 2e-2),        # v_min < |v| <= v_move
    (2e-2, 2e-2), (-2e-2, -2e-2),                                 # |v| = v_move stays v_move
    (0.020001, 0.020001), (-0.3, -0.3), (0.8, 0.8),               # otherwise unchanged
])
def test_speed_adjusting_boundaries(v, expected):
    assert adjust_speed(v) == pytest.approx(expected, abs=1e-12)


def test_speed_adjusting_uses_config():
    config = PostprocessConfig(v_min=0.01, v_move=0.05)
    assert adjust_speed(0.01, config) == 0.0
    assert adjust_speed(-0.011, config) == -0.05
    assert adjust_speed(0.06, config) == 0.06


def test_halting_counter_fires_on_the_fiftieth_zero_and_restarts():
    counter = HaltingCounter()
    fired = [counter.update(0.0, 0.0) for _ in range(49)]
    assert not any(fired) and counter.count == 49
    assert counter.update(0.0, 0.0)          # 50th consecutive zero output
    assert counter.count == 0
    assert not any(counter.update(0.0, 0.0) for _ in range(49))
    assert counter.update(0.0, 0.0)


def test_halting_counter_needs_consecutive_zeros():
    counter = HaltingCounter(PostprocessConfig(halt_steps=3))
    assert [counter.update(*c) for c in [(0, 0), (0, 0), (0.02, 0), (0, 0), (0, 0), (0, -0.02),
                                         (0, 0), (0, 0), (0, 0)]] == \
        [False, False, False, False, False, False, False, False, True]


@pytest.mark.parametrize("p, expected", [
    (None, (0.04, 0.01)),       # no stop head: unchanged (the seed's path)
    (0.5, (0.04, 0.01)),        # at the threshold: still moving
    (0.500001, (0.0, 0.0)),     # above it: stop
    (0.99, (0.0, 0.0)),
])
def test_stop_head_boundary(p, expected):
    assert apply_stop(0.04, 0.01, p) == expected
