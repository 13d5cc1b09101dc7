"""Base controller: limits, watchdog (injected clock), e-stop latch, bumper, stall, bad input.

Deployment values (config/penguin.yaml): r = 0.075 m, b = 0.45 m, 0.4 m/s, 1 rad/s, 0.5 m/s^2,
2 rad/s^2, watchdog 0.5 s, wheel limit 5.236 rad/s (0.3927 m/s).
"""
import math

import pytest

from penguin_base.config import BaseConfig
from penguin_base.controller import ERROR, OK, WARN, BaseController
from penguin_base.safety import CommandWatchdog, InvalidCommand

DT = 0.02  # [s] 50 Hz


def run(controller, start, end, command=None, measured=None):
    """Step the controller from start to end [s], optionally re-sending a command every step."""
    wheels, t = None, start
    while t <= end + 1e-9:
        if command is not None:
            controller.command(*command, t)
        wheels = controller.update(t, measured)
        t += DT
    return wheels


@pytest.fixture
def controller():
    return BaseController(BaseConfig())


def test_acceleration_limits_shape_the_start(controller):
    controller.command(0.4, 1.0, 0.0)
    controller.update(0.0)
    wheels = controller.update(0.1)
    # 0.5 m/s^2 * 0.1 s = 0.05 m/s; 2 rad/s^2 * 0.1 s = 0.2 rad/s
    assert (wheels.v, wheels.omega) == pytest.approx((0.05, 0.2))
    assert wheels.left == pytest.approx((0.05 - 0.2 * 0.225) / 0.075)
    assert wheels.right == pytest.approx((0.05 + 0.2 * 0.225) / 0.075)


def test_absurd_speed_is_clamped_then_limited_by_the_wheels(controller):
    assert controller.command(50.0, -30.0, 0.0) == (0.4, -1.0)
    wheels = run(controller, 0.0, 2.0, command=(50.0, 0.0))
    # 0.4 m/s would need 5.333 rad/s; the wheel limit 5.236 rad/s caps it at 0.3927 m/s
    assert wheels.left == pytest.approx(5.235988, abs=1e-6)
    assert wheels.v == pytest.approx(0.392699, abs=1e-6)
    assert controller.clamped_count > 0
    level, _message, values = controller.diagnostics(2.0)
    assert level == WARN and "clamped" in values["last problem"]


@pytest.mark.parametrize("bad", [(math.nan, 0.0), (0.1, math.inf), (-math.inf, 0.0)])
def test_non_finite_command_is_rejected_and_stops_at_once(controller, bad):
    moving = run(controller, 0.0, 1.0, command=(0.2, 0.0))
    assert moving.v == pytest.approx(0.2)
    with pytest.raises(InvalidCommand, match=r"/cmd_vel (linear\.x|angular\.z) is"):
        controller.command(*bad, 1.01)
    wheels = controller.update(1.02)
    assert (wheels.left, wheels.right) == (0.0, 0.0)
    assert wheels.stop_reason == "last /cmd_vel rejected (not finite)"
    assert controller.invalid_count == 1
    assert controller.diagnostics(1.02)[0] == WARN
    assert controller.diagnostics(6.02)[0] == OK  # 5 s after the problem
    controller.command(0.2, 0.0, 1.04)             # a valid command resumes
    assert controller.update(1.06).stop_reason == ""


def test_watchdog_stops_the_wheels_after_the_timeout(controller):
    run(controller, 0.0, 1.0, command=(0.2, 0.0))       # last command at t = 1.0 s
    assert controller.update(1.5).v == pytest.approx(0.2)  # 0.5 s old: still valid
    stopped = controller.update(1.52)
    assert (stopped.left, stopped.right) == (0.0, 0.0)
    assert stopped.stop_reason == "command watchdog expired"


def test_watchdog_with_injected_clock():
    watchdog = CommandWatchdog(0.5)
    assert watchdog.expired(0.0) and watchdog.age(0.0) is None
    watchdog.feed(10.0)
    assert not watchdog.expired(10.5)
    assert watchdog.expired(10.5001)


def test_no_command_means_no_motion(controller):
    assert controller.update(0.0).stop_reason == "no /cmd_vel"


def test_estop_latches_until_released(controller):
    run(controller, 0.0, 1.0, command=(0.2, 0.3))
    controller.set_estop(True)
    wheels = run(controller, 1.02, 1.5, command=(0.2, 0.3))
    assert (wheels.left, wheels.right) == (0.0, 0.0)
    assert wheels.stop_reason == "e-stop engaged"
    assert controller.diagnostics(1.5)[0] == ERROR
    controller.set_estop(False)
    wheels = run(controller, 1.52, 1.62, command=(0.2, 0.3))
    assert wheels.v == pytest.approx(0.5 * 0.12)  # resumes from 0 at 0.5 m/s^2 (1.50 -> 1.62 s)


def test_bumper_stops_and_rearms_only_after_a_zero_command(controller):
    run(controller, 0.0, 1.0, command=(0.2, 0.0))
    controller.set_bumper(True)
    assert controller.update(1.02).stop_reason == "bumper pressed"
    controller.set_bumper(False)
    wheels = run(controller, 1.04, 1.2, command=(0.2, 0.0))
    assert wheels.v == 0.0 and wheels.stop_reason == "bumped: waiting for a zero command"
    controller.command(0.0, 0.0, 1.22)
    wheels = run(controller, 1.24, 1.5, command=(0.2, 0.0))
    assert wheels.v > 0.0 and wheels.stop_reason == ""


def test_stall_stops_the_base(controller):
    run(controller, 0.0, 1.0, command=(0.2, 0.0), measured=(2.67, 2.67))
    wheels = run(controller, 1.02, 2.1, command=(0.2, 0.0), measured=(0.0, 0.0))
    assert wheels.v == 0.0 and wheels.stop_reason.startswith("wheel stall")
    controller.command(0.0, 0.0, 2.12)
    assert run(controller, 2.14, 2.3, command=(0.1, 0.0), measured=None).v > 0.0


def test_diagnostics_ok_when_idle(controller):
    level, message, values = controller.diagnostics(0.0)
    assert (level, message, values["seconds since last command"]) == (OK, "no /cmd_vel", "never")


def test_a_halt_stops_at_once_and_motion_restarts_from_rest(controller):
    moving = run(controller, 0.0, 1.0, command=(0.2, 0.0))
    assert moving.v == pytest.approx(0.2)
    stopped = controller.halt("control step failed: RuntimeError: boom", 1.01)
    assert (stopped.left, stopped.right, stopped.stop_reason) == (
        0.0, 0.0, "control step failed: RuntimeError: boom")
    level, _message, values = controller.diagnostics(1.02)
    assert level == WARN and values["last problem"] == "control step failed: RuntimeError: boom"
    assert values["control steps failed"] == "1"
    controller.command(0.2, 0.0, 1.02)
    wheels = controller.update(1.02)   # from rest again: 0.5 m/s^2 * 0.02 s since the last step
    assert wheels.v == pytest.approx(0.01)
