"""The simulation loop's pacing: sleeps to hold the speed, slips after a stall, shortfalls."""
import pytest

from sim2d.pacing import Pacer, PacerConfig


def test_the_loop_sleeps_until_the_step_is_due():
    pacer = Pacer(PacerConfig(speed=4.0), sim=0.0, wall=100.0)
    assert pacer.delay(sim=0.4, wall=100.05) == pytest.approx(0.05)   # 0.4 s sim = 0.1 s wall
    assert pacer.delay(sim=0.4, wall=100.2) == 0.0                    # late, within the slip
    assert pacer.slips == 0


def test_a_stall_is_a_slip_not_a_race_to_catch_up():
    pacer = Pacer(PacerConfig(speed=2.0, slip=0.5), sim=0.0, wall=0.0)
    assert pacer.delay(sim=1.0, wall=1.5) == 0.0          # 1.0 s behind: a slip, re-based
    assert (pacer.slips, pacer.seconds_lost) == (1, pytest.approx(1.0))
    # after the slip the schedule runs from there: 0.2 s of sim time is 0.1 s of wall time
    assert pacer.delay(sim=1.2, wall=1.55) == pytest.approx(0.05)


def test_a_speed_the_loop_cannot_hold_is_a_shortfall_over_a_window():
    pacer = Pacer(PacerConfig(speed=8.0, window=10.0, min_ratio=0.9), sim=0.0, wall=0.0)
    assert pacer.shortfall(sim=30.0, wall=5.0) is None             # window not over yet
    assert pacer.shortfall(sim=60.0, wall=10.0) == pytest.approx(6.0)   # 6x of 8x asked
    assert pacer.shortfall(sim=140.0, wall=20.0) is None           # 8x over the next window


def test_as_fast_as_possible_never_sleeps_or_falls_short():
    pacer = Pacer(PacerConfig(speed=0.0), sim=0.0, wall=0.0)
    assert pacer.delay(sim=5.0, wall=0.1) == 0.0
    assert pacer.shortfall(sim=1.0, wall=60.0) is None and pacer.slips == 0
