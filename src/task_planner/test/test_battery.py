"""Low-battery model and the executor's self-generated 'go charge' instruction."""
import pytest
from planner_factories import make_instruction
from test_executor import FUNCTIONS, NavigationModel, make_executor, run_executor

from task_planner.baselines import PriorityFirst
from task_planner.battery import BatteryConfig, BatteryModel
from task_planner.executor import Charging, Executor, ExecutorConfig
from task_planner.people_belief import PeopleAtPlaces
from task_planner.instruction import ROBOT
from task_planner.reward import Priority
from task_planner.task_buffer import DONE, BufferConfig, TaskBuffer


def test_drain_and_charge_in_watt_hours():
    battery = BatteryModel(BatteryConfig(capacity_wh=300.0, idle_w=40.0, moving_w=90.0,
                                         charge_w=150.0))
    battery.drain("idle", 3600.0)       # 40 W for an hour
    assert battery.level_wh == pytest.approx(260.0)
    battery.drain("moving", 3600.0 + 1800.0)  # 90 W for half an hour
    assert battery.level_wh == pytest.approx(215.0)
    battery.drain("charging", 9000.0)   # the gain is added when the function ends
    assert battery.level_wh == pytest.approx(215.0)
    assert battery.seconds_to_full() == pytest.approx(85.0 * 3600.0 / 150.0)
    battery.charge(3600.0)
    assert battery.level_wh == 300.0 and not battery.is_low()


def test_low_battery_sends_the_robot_to_charge(line_graph, tmp_path):
    A, D = 0, 3
    config = BatteryConfig(capacity_wh=0.1, idle_w=0.0, moving_w=36.0, executing_w=0.0,
                           charge_w=36.0, low_fraction=0.5)
    battery = BatteryModel(config)
    executor = make_executor(line_graph, PriorityFirst(), tmp_path)
    executor.state.charging = Charging(battery, A, 8, Priority("self_generated", 1.0, 0.9))
    far = make_instruction(1, D, gamma=3.0, beta=0.94, duration=0, function=1)
    trace = run_executor(executor, [(0.0, far)], NavigationModel(line_graph, 0.5))
    # A->B 2 s, B->C 4 s at 36 W: 0.06 Wh spent, 0.04 left (40 % < 50 %) at C at 6 s:
    # charge for 0.06 Wh at 36 W = 6 s at A. PF serves 1 at D first (12 s), D->A 12 s: charge
    # runs 24-30 s.
    charge = executor.buffer.get(2)   # the buffer's next id after instruction 1
    assert charge.instruction.type == ROBOT and charge.instruction.destination == A
    assert (charge.instruction.start_time, charge.instruction.duration) == (6.0, 6)
    assert charge.state == DONE and charge.completion_time == pytest.approx(30.0)
    assert charge.reward_earned == pytest.approx(0.9 ** 24)
    assert trace.executed == [(12.0, 1, "chat"), (24.0, 2, "charge")]
    assert (24.0, "I am charging my battery at the A.") in trace.said
    assert battery.level_wh == pytest.approx(0.06)  # drained to 0 by 12 s, then 6 s at 36 W
    assert FUNCTIONS[8].name == "charge"


def test_battery_level_survives_an_executor_restart(line_graph, tmp_path):
    """The level is journalled with the instructions; a restarted executor resumes it."""
    config = BatteryConfig(capacity_wh=10.0, idle_w=0.0, moving_w=3600.0, executing_w=0.0,
                           charge_w=36.0, low_fraction=0.05)
    priority = Priority("self_generated", 1.0, 0.9)

    def start(battery):
        buffer = TaskBuffer(tmp_path / "buffer.sqlite", BufferConfig(node_count=line_graph.size))
        return Executor(buffer, line_graph, PriorityFirst(), PeopleAtPlaces(), FUNCTIONS,
                        ExecutorConfig(speed_mps=0.5), start_node=0,
                        charging=Charging(battery, 0, 8, priority))

    first = start(BatteryModel(config))
    # A->B is 2 s at 3,600 W = 2 Wh; the robot is killed at B (no close, no final save)
    run_executor(first, [(0.0, make_instruction(1, 1, gamma=3.0, beta=0.94, duration=0,
                                                function=1))],
                 NavigationModel(line_graph, 0.5))
    assert first.charging.battery.level_wh == pytest.approx(8.0)
    restarted = start(BatteryModel(config))   # a fresh model would say full (10 Wh)
    assert restarted.charging.battery.level_wh == pytest.approx(8.0)
