"""The five-key teleoperation scheme of thesis 002 §3.3.2 / Fig. 3.3.3 and its terminal loop."""
import curses

import pytest

from penguin_base import teleop_terminal
from penguin_base.config import ConfigError, TeleopConfig
from penguin_base.teleop import DOWN, LEFT, RIGHT, STOP, UP, TeleopState


@pytest.fixture
def state():
    return TeleopState(TeleopConfig())  # steps 0.02 m/s, 0.2 rad/s tap, +0.1 rad/s, hold 0.55 s


def test_up_accelerates_gradually_and_keeps_moving_without_holding(state):
    for k in range(3):
        state.press(UP, 0.1 * k)
    assert state.command(0.3) == (pytest.approx(0.06), 0.0)
    assert state.command(60.0) == (pytest.approx(0.06), 0.0)  # a minute later: still moving


def test_up_and_down_respect_the_speed_range(state):
    for k in range(50):
        state.press(UP, 0.03 * k)
    assert state.command(2.0)[0] == pytest.approx(0.4)
    state.press(DOWN, 2.1)
    assert state.command(2.2)[0] == pytest.approx(0.38)
    for k in range(30):
        state.press(DOWN, 3.0 + 0.03 * k)
    assert state.command(5.0)[0] == 0.0


def test_a_single_left_press_turns_slightly_then_stops(state):
    state.press(UP, 0.0)
    state.press(LEFT, 1.0)
    assert state.command(1.1) == (pytest.approx(0.02), pytest.approx(0.2))
    assert state.command(1.55) == (pytest.approx(0.02), pytest.approx(0.2))
    assert state.command(1.56) == (pytest.approx(0.02), 0.0)  # released: rotation stops


def test_holding_right_rotates_faster_and_release_stops_rotation(state):
    presses = [0.0, 0.5] + [0.5 + 0.033 * k for k in range(1, 11)]  # repeat delay, then 30 Hz
    for t in presses:
        state.press(RIGHT, t)
    # first press 0.2 rad/s, then +0.1 per repeat: 0.2 + 11 * 0.1 capped at 1.0
    assert state.command(presses[-1]) == (0.0, pytest.approx(-1.0))
    after_four = TeleopState(TeleopConfig())
    for t in presses[:4]:
        after_four.press(RIGHT, t)
    assert after_four.command(presses[3])[1] == pytest.approx(-0.5)
    assert state.command(presses[-1] + 0.6) == (0.0, 0.0)


def test_switching_direction_starts_again_from_a_slight_turn(state):
    for t in (0.0, 0.1, 0.2):
        state.press(LEFT, t)
    state.press(RIGHT, 0.25)
    assert state.command(0.3)[1] == pytest.approx(-0.2)


def test_one_key_stops_everything(state):
    for t in (0.0, 0.1):
        state.press(UP, t)
        state.press(LEFT, t)
    state.press(STOP, 0.2)
    assert state.command(0.2) == (0.0, 0.0)


def test_unknown_key_is_an_error(state):
    with pytest.raises(ValueError, match="unknown teleop key 'jump'"):
        state.press("jump", 0.0)


def test_config_rejects_a_positive_minimum_speed():
    with pytest.raises(ConfigError, match="min_linear_speed"):
        TeleopConfig(min_linear_speed=0.1)


class FakeScreen:
    """Stands in for a curses window: returns scripted keys, one per getch()."""

    def __init__(self, keys):
        self.keys = list(keys)

    def getch(self):
        return self.keys.pop(0) if self.keys else -1

    def keypad(self, _flag):
        pass

    def timeout(self, _ms):
        pass

    def erase(self):
        pass

    def refresh(self):
        pass

    def getmaxyx(self):
        return 24, 80

    def addnstr(self, *_args):
        pass


def test_terminal_loop_maps_arrow_keys_and_quits_on_q(monkeypatch):
    monkeypatch.setattr(curses, "curs_set", lambda _v: None)
    clock = iter(0.1 * k for k in range(1000))
    published, classes = [], []
    keys = [curses.KEY_UP, curses.KEY_UP, ord("3"), curses.KEY_LEFT, -1, ord(" "), ord("e"),
            ord("q"), curses.KEY_UP]
    teleop_terminal._loop(FakeScreen(keys), TeleopState(TeleopConfig()),
                          lambda v, w: published.append((v, w)), lambda: next(clock),
                          lambda: True, classes.append)
    assert classes == [3, 0]
    assert (pytest.approx(0.04), pytest.approx(0.2)) in published  # Up, Up, Left
    assert published[-1] == (0.0, 0.0)                              # Space stopped it
    assert max(v for v, _ in published) == pytest.approx(0.04)     # the Up after q never ran


def test_run_teleop_publishes_zero_even_when_interrupted(monkeypatch):
    def interrupted(*_args):
        raise KeyboardInterrupt

    monkeypatch.setattr(curses, "wrapper", interrupted)
    published = []
    teleop_terminal.run_teleop(TeleopState(TeleopConfig()), lambda v, w: published.append((v, w)),
                               lambda: 0.0, lambda: True)
    assert published == [(0.0, 0.0)]
