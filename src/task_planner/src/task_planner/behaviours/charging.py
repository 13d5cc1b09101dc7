"""The battery (ROS-free): spend the energy of the mode the robot was in, journal the level, and
give the robot a 'go charge' instruction (once) when the battery is low."""
from task_planner.battery import charge_instruction
from task_planner.behaviours.receiving import new_id, take_in
from task_planner.behaviours.context import Context
from task_planner.executor_commands import EXECUTING, IDLE, LOOKING, VERIFYING, Command

BATTERY_KEY = "battery_level_wh"   # robot_state entry of the journal


def save_battery(ctx: Context, force: bool = False) -> None:
    """Journal the battery level when it changed by battery_save_wh (or when forced)."""
    level = ctx.charging_now().battery.level_wh
    if force or ctx.saved_wh is None or \
            abs(level - ctx.saved_wh) >= ctx.config.battery_save_wh:
        ctx.buffer.store_robot_value(BATTERY_KEY, level)
        ctx.saved_wh = level


def drain(ctx: Context, now: float) -> list[Command]:
    """Spend the battery energy of the mode the robot was in until `now`. Returns no
    commands."""
    if ctx.charging is None:
        return []
    busy_charging = ctx.mode == EXECUTING and ctx.buffer.get(
        ctx.executing_now()[0]).instruction.function == ctx.charging.function_code
    mode = IDLE if ctx.mode in (VERIFYING, LOOKING) else ctx.mode  # about on the spot
    ctx.charging.battery.drain("charging" if busy_charging else mode, now)
    save_battery(ctx)
    return []


def check_battery(ctx: Context, now: float) -> list[Command]:
    """When the battery is low, give the robot a 'go charge' instruction (once)."""
    if ctx.charging is None:
        return []
    drain(ctx, now)
    charging = ctx.charging
    battery = charging.battery
    open_charge = any(r.instruction.function == charging.function_code
                      for r in ctx.buffer.open_records())
    if not battery.is_low() or open_charge:
        return []
    instruction = charge_instruction(new_id(ctx), now, charging.place,
                                     ctx.graph.names[charging.place], charging.priority, battery,
                                     charging.function_code)
    if ctx.fleet:   # the robot's own body: never another robot's to serve
        ctx.fleet.keep_local(instruction.id)
    ctx.log.append((now, f"battery low ({100 * battery.fraction:.0f} %): charge"))
    return take_in(ctx, [instruction], now)[1]
