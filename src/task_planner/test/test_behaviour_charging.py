"""task_planner.behaviours.charging: spend the battery by mode, charge when low (once)."""
import pytest
from behaviour_factories import A, B, C, make_context

from task_planner.battery import BatteryConfig, BatteryModel
from task_planner.behaviours.charging import BATTERY_KEY, check_battery, drain
from task_planner.behaviours.context import Charging
from task_planner.executor_commands import MOVING, Navigate
from task_planner.instruction import ROBOT
from task_planner.reward import Priority

CONFIG = BatteryConfig(capacity_wh=1.0, idle_w=36.0, moving_w=360.0, executing_w=0.0,
                       charge_w=36.0, low_fraction=0.5)


def with_battery(ctx):
    ctx.charging = Charging(BatteryModel(CONFIG), A, 8, Priority("self_generated", 1.0, 0.9))
    return ctx.charging.battery


def test_drain_spends_the_power_of_the_mode_the_robot_was_in(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    battery = with_battery(ctx)
    drain(ctx, 10.0)                          # idle: 36 W for 10 s = 0.1 Wh
    assert battery.level_wh == pytest.approx(0.9)
    ctx.mode = MOVING
    drain(ctx, 12.0)                          # moving: 360 W for 2 s = 0.2 Wh
    assert battery.level_wh == pytest.approx(0.7)
    assert ctx.buffer.robot_value(BATTERY_KEY, None) == pytest.approx(0.9)  # journalled
                                              # when it moved 0.5 Wh or more since


def test_a_low_battery_gives_the_robot_one_charge_instruction(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=C)
    with_battery(ctx)
    assert check_battery(ctx, 40.0) == []     # idle 36 W for 40 s: 0.6 Wh, not low
    commands = check_battery(ctx, 60.0)       # 0.4 Wh: below half, go charge at A
    charge = ctx.buffer.get(1).instruction
    assert (charge.type, charge.function, charge.destination) == (ROBOT, 8, A)
    assert charge.duration == 60              # 0.6 Wh to full at 36 W
    assert commands == [Navigate(B, 1)] and ctx.log[0] == (60.0, "battery low (40 %): charge")
    assert check_battery(ctx, 61.0) == [] and len(ctx.buffer.records()) == 1
