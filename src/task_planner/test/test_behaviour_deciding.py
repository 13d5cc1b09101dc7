"""task_planner.behaviours.deciding: the planner's decision, serve here or drive, turn back."""
from dataclasses import replace

import numpy as np
import pytest
from behaviour_factories import A, B, C, D, make_context, journal
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.baselines import PriorityFirst, ShortestTimeFirst
from task_planner.battery import BatteryConfig, BatteryModel
from task_planner.behaviours.context import Charging, ExecutorConfig
from task_planner.behaviours.deciding import (Deciding, decide, fetch_and_decode, heading,
                                              redecide, seen_elsewhere, waiting_for_a_meeting)
from task_planner.executor_commands import EXECUTING, IDLE, MOVING, Navigate, StopMotion
from task_planner.instruction import ROBOT
from task_planner.people_belief import PeopleAtPlaces
from task_planner.problem import Problem
from task_planner.reward import Priority
from task_planner.ripple_planner import RipplePlanner


def test_an_instruction_here_is_served_and_one_elsewhere_driven_to(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=B)
    journal(ctx, make_instruction(1, B, duration=5, function=1),
            make_instruction(2, D, duration=5, function=1))
    assert decide(ctx, 0.0)[0].function == "chat" and ctx.mode == EXECUTING
    ctx.mode = IDLE
    ctx.buffer.finish(1, 5.0)
    assert decide(ctx, 5.0) == [Navigate(C, 2)]
    assert ctx.log[-1] == (5.0, "move B -> C for 2")
    assert len(ctx.decision_s) == len(ctx.decision_cpu_s) == 2


def test_a_successor_waits_for_its_predecessor(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    journal(ctx, make_instruction(2, B, function=1, previous_id=1))
    assert decide(ctx, 0.0) == [] and ctx.mode == IDLE


def test_a_new_instruction_can_turn_the_robot_back_mid_edge(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst())
    journal(ctx, make_instruction(1, D, gamma=1.0, function=1))
    decide(ctx, 0.0)
    assert (ctx.mode, ctx.goal) == (MOVING, C)
    journal(ctx, make_instruction(2, A, gamma=9.0, function=1), now=1.0)
    assert redecide(ctx, 1.0) == [Navigate(B, 2)]     # back through the node just left
    assert (ctx.node, ctx.goal, ctx.goal_for) == (C, B, 2)


def test_a_robot_nearer_the_node_it_left_decides_from_there(line_graph, tmp_path):
    """Driving B -> C (2 m: 4 s), 0.5 s after leaving B, instructions at B and at C arrive:
    the nearest (SF) from B is the one at B: the robot turns back, 0.5 s from B."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=ShortestTimeFirst())
    journal(ctx, make_instruction(1, D, function=1))
    decide(ctx, 0.0)
    journal(ctx, make_instruction(2, B, function=1), make_instruction(3, C, function=1), now=0.5)
    assert redecide(ctx, 0.5) == [Navigate(B, 2)]
    assert (ctx.node, ctx.goal) == (C, B)
    assert ctx.where_on_leg(0.5) == pytest.approx((3.5, 0.5))   # from C, to B
    assert ctx.where_on_leg(9.0) == pytest.approx((4.0, 0.0))   # never past the goal


def test_a_robot_nearly_at_the_next_node_decides_from_it(line_graph, tmp_path):
    """The same instructions 0.5 s short of C: the nearest from C is the one at C, so the
    robot drives on. Deciding from B, which it left 3.5 s before, turned it back, and the
    next request, decided from C, which it never reached, sent it on again."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=ShortestTimeFirst())
    journal(ctx, make_instruction(1, D, function=1))
    decide(ctx, 0.0)
    journal(ctx, make_instruction(2, B, function=1), make_instruction(3, C, function=1), now=3.5)
    assert redecide(ctx, 3.5) == []
    assert (ctx.node, ctx.goal, ctx.mode) == (B, C, MOVING)


def test_the_person_driven_for_seen_elsewhere_turns_the_robot_back(line_graph, tmp_path):
    """Driving to serve Bob where he was seen (D), the robot hears that he is at A (a camera
    frame, or the introduction registering him where it met him): it decides again at once,
    once."""
    people = PeopleAtPlaces()
    people.seen("Bob", D, 0.0)
    ctx = make_context(line_graph, tmp_path, node=B, people=people, follow_belief=True)
    journal(ctx, make_instruction(1, D, function=1, target="Bob"))
    assert decide(ctx, 0.0) == [Navigate(C, 1)] and ctx.serve_at == D
    assert seen_elsewhere(ctx, 1.0) == []            # still believed at D: drive on
    people.seen("Bob", A, 2.0)
    assert seen_elsewhere(ctx, 2.0) == [Navigate(B, 1)]   # back through the node just left
    assert ctx.log[-2] == (2.0, "Bob seen at A; decide again") and ctx.serve_at == A
    assert seen_elsewhere(ctx, 3.0) == []            # the same news decides once


def test_a_person_seen_by_turns_in_two_places_decides_again_once_per_leg(line_graph,
                                                                        tmp_path):
    """Bob, believed at D, is seen at C (where the robot drives: it drives on) and then at D
    again while the robot is on the same leg: no second decision on that leg."""
    people = PeopleAtPlaces()
    people.seen("Bob", D, 0.0)
    ctx = make_context(line_graph, tmp_path, node=B, people=people, follow_belief=True)
    journal(ctx, make_instruction(1, D, function=1, target="Bob"))
    decide(ctx, 0.0)
    people.seen("Bob", C, 1.0)
    assert seen_elsewhere(ctx, 1.0) == [] and ctx.serve_at == C      # drive on to C
    people.seen("Bob", D, 2.0)
    logged = len(ctx.log)
    assert seen_elsewhere(ctx, 2.0) == [] and len(ctx.log) == logged  # same leg: nothing


def test_a_patrol_gives_way_at_once(posed_line_graph, tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=2)
    ctx.mode, ctx.looking = "looking", [0, [], 0.0, None, None, None]   # looking (patrol)
    journal(ctx, make_instruction(1, D, function=1))
    assert redecide(ctx, 1.0) == [StopMotion(), Navigate(C, 1, through=0.0)]


def test_heading_picks_the_strongest_eq_4_2_term_through_the_neighbour(star_graph):
    instructions = (make_instruction(1, 1, gamma=3.0, beta=0.9),
                    make_instruction(2, 2, gamma=5.0, beta=0.9),
                    make_instruction(3, 2, gamma=4.0, beta=0.99))
    problem = Problem(star_graph, instructions, 0.5, 0)
    available = np.arange(3)
    # from the hub every leaf is 8 s away: 5 * 0.9 ** 8 = 2.15 < 4 * 0.99 ** 8 = 3.69
    assert heading(problem, 0, 2, available) == 2


def test_the_decide_leaf_runs_only_when_idle(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, planner=RipplePlanner())
    journal(ctx, make_instruction(1, C, function=1))
    leaf = Deciding(ctx)
    ctx.mode, ctx.now, ctx.out = MOVING, 0.0, []
    leaf.tick_once()
    assert leaf.status == Status.FAILURE and ctx.out == []
    ctx.mode = IDLE
    leaf.tick_once()
    assert leaf.status == Status.SUCCESS and ctx.out == [Navigate(B, 1)]


def test_a_request_for_someone_never_seen_waits_while_a_stranger_is_to_be_met(line_graph,
                                                                             tmp_path):
    """Carol has never been seen (not met: the camera cannot tell who she is), so her chat
    waits while the robot has a stranger to meet; Bob's, seen in A, does not. Met, or with no
    stranger, her request is eligible again."""
    people = PeopleAtPlaces()
    people.seen("Bob", A, 1.0)
    ctx = make_context(line_graph, tmp_path, node=B, people=people, planner=PriorityFirst())
    carol, bob, meet = journal(
        ctx, make_instruction(1, C, gamma=8.0, function=1, source="Carol", target="Carol"),
        make_instruction(2, A, gamma=5.0, function=1, source="Bob", target="Bob"),
        make_instruction(3, D, gamma=1.0, function=9, type=ROBOT, source="robot"))
    pending = [carol, bob, meet]
    assert waiting_for_a_meeting(ctx, pending) == {1}
    assert decide(ctx, 2.0) == [Navigate(A, 2)]          # Bob's, not Carol's stronger one
    assert waiting_for_a_meeting(ctx, [carol, bob]) == set()
    people.seen("Carol", D, 3.0)
    assert waiting_for_a_meeting(ctx, pending) == set()
    ctx.searched[2] = [A]          # Bob was not where the robot looked: maybe in new clothes
    people.missed("Bob", A)
    assert waiting_for_a_meeting(ctx, pending) == {2}
    people.seen("Bob", C, 4.0)     # seen since (met in his new clothes): his request goes on
    assert waiting_for_a_meeting(ctx, pending) == set()


def test_a_meeting_is_planned_with_the_priority_of_the_request_waiting_for_it(line_graph,
                                                                              tmp_path):
    """Carol, never seen, asks with gamma 8: the stranger the robot is to meet may be her, so
    with meetings_inherit the planner sees the meeting (gamma 1) at Carol's priority, and the
    journal keeps its own; without it, or with nobody waiting, the meeting keeps its own."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       meetings_inherit=True)
    journal(
        ctx, make_instruction(1, C, gamma=8.0, beta=0.98, function=1, source="Carol",
                              target="Carol"),
        make_instruction(2, D, gamma=1.0, beta=0.9, function=9, type=ROBOT, source="robot"))
    problem, available = fetch_and_decode(ctx, 0.0)
    planned = {i.id: i for i in problem.instructions}
    assert (planned[2].gamma, planned[2].beta) == (8.0, 0.98) and list(available) == [1]
    assert ctx.buffer.get(2).instruction.gamma == 1.0
    ctx.config = replace(ctx.config, meetings_inherit=False)
    problem, _ = fetch_and_decode(ctx, 1.0)
    assert {i.id: i.gamma for i in problem.instructions}[2] == 1.0
    ctx.config = replace(ctx.config, meetings_inherit=True)
    ctx.people.seen("Carol", C, 2.0)               # seen: her request no longer waits
    problem, available = fetch_and_decode(ctx, 2.0)
    assert {i.id: i.gamma for i in problem.instructions}[2] == 1.0 and len(available) == 2


def test_an_overdue_request_goes_before_newer_ones(line_graph, tmp_path):
    """Bob asked at 0 s, Carol at 100 s with the same priority: by Eq. 4-2 Bob's request is
    worth 5 * 0.96 ** 130 = 0.03 at 130 s against Carol's 2.0, so the reward alone serves
    Carol first. With serve_within_s 120 Bob's request, 130 s old, goes first."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst())
    journal(ctx, make_instruction(1, A, gamma=5.0, beta=0.96, function=1, start_time=0.0))
    journal(ctx, make_instruction(2, C, gamma=5.0, beta=0.96, function=1, start_time=100.0),
            now=100.0)
    _, available = fetch_and_decode(ctx, 130.0)
    assert list(available) == [0, 1]                    # the seed's rule: both, by reward
    ctx.config = replace(ctx.config, serve_within_s=120.0)
    _, available = fetch_and_decode(ctx, 110.0)
    assert list(available) == [0, 1]                    # nothing overdue yet
    problem, available = fetch_and_decode(ctx, 130.0)
    assert [int(problem.ids[k]) for k in available] == [1]


def test_the_robots_own_overdue_instruction_never_goes_before_a_persons_request(line_graph,
                                                                              tmp_path):
    """The robot's music recommendation (function 6), 200 s old, is overdue; Frank's request
    of 190 s is not, and still goes first: the robot serves itself only when no person needs
    it. Alone, the overdue recommendation is served."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0)
    journal(ctx, make_instruction(1, A, gamma=1.0, beta=0.9, function=6, type=ROBOT,
                                  source="robot", start_time=0.0))
    journal(ctx, make_instruction(2, C, gamma=3.0, beta=0.94, function=6, start_time=190.0),
            now=190.0)
    problem, available = fetch_and_decode(ctx, 200.0)
    assert sorted(int(problem.ids[k]) for k in available) == [1, 2]
    (tmp_path / "alone").mkdir()
    alone = make_context(line_graph, tmp_path / "alone", node=B, planner=PriorityFirst(),
                         serve_within_s=120.0)
    journal(alone, make_instruction(1, A, gamma=1.0, beta=0.9, function=6, type=ROBOT,
                                    source="robot", start_time=0.0))
    problem, available = fetch_and_decode(alone, 200.0)
    assert [int(problem.ids[k]) for k in available] == [1]


def test_by_smiths_rule_the_nearer_overdue_request_goes_first_and_of_equals_the_older(
        line_graph, tmp_path):
    """Two requests of one priority overdue at 400 s: by reward the newer (at D, launched at
    250 s) would go first; by Smith's rule from B the older (at A, 2 s away against 10 s) does,
    from D the one there. From C, where both are 6 s away, the older."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0, overdue_order="smith")
    journal(ctx, make_instruction(1, A, gamma=5.0, beta=0.96, function=1, start_time=0.0))
    journal(ctx, make_instruction(2, D, gamma=5.0, beta=0.96, function=1, start_time=250.0),
            now=250.0)
    problem, available = fetch_and_decode(ctx, 400.0)
    assert [int(problem.ids[k]) for k in available] == [1]
    ctx.node = D
    problem, available = fetch_and_decode(ctx, 400.0)
    assert [int(problem.ids[k]) for k in available] == [2]
    ctx.node = C
    problem, available = fetch_and_decode(ctx, 400.0)
    assert [int(problem.ids[k]) for k in available] == [1]


def test_overdue_instructions_go_by_priority_per_second_of_the_robots_time(line_graph,
                                                                          tmp_path):
    """Smith's rule at 400 s, robot at B (0.5 m/s; B to D is 5 m, 10 s): David's call for
    physical help at D (gamma 8, 30 s) is worth 8 / (10 + 30) = 0.2 per second, Bob's chat
    here (gamma 5, 60 s) 5 / 60 = 0.08: the call goes first, though the chat is here. A check
    here (gamma 3, 10 s), 3 / 10 = 0.3, goes before both."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0, overdue_order="smith")
    journal(ctx, make_instruction(1, D, gamma=8.0, beta=0.98, duration=30, function=1,
                                  start_time=0.0))
    journal(ctx, make_instruction(2, B, gamma=5.0, beta=0.96, duration=60, function=1,
                                  start_time=100.0), now=100.0)
    problem, available = fetch_and_decode(ctx, 400.0)
    assert [int(problem.ids[k]) for k in available] == [1]
    journal(ctx, make_instruction(3, B, gamma=3.0, beta=0.94, duration=10, function=1,
                                  start_time=200.0), now=200.0)
    problem, available = fetch_and_decode(ctx, 400.0)
    assert [int(problem.ids[k]) for k in available] == [3]


def test_the_oldest_overdue_request_goes_first_so_a_long_chat_is_not_passed_over(line_graph,
                                                                                tmp_path):
    """Oldest first (Jackson's rule), the set of the test above launched in another order:
    Bob's chat here (gamma 5, 60 s) at 0 s goes before the call for physical help at D (100 s)
    and the check here (200 s), which Smith's rule serves first; of two launched together, the
    one with the more priority per second."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0)
    launches = {2: 0.0, 1: 100.0, 3: 200.0}     # the chat, the call, the check
    for k, (place, gamma, beta, duration) in {2: (B, 5.0, 0.96, 60), 1: (D, 8.0, 0.98, 30),
                                               3: (B, 3.0, 0.94, 10)}.items():
        journal(ctx, make_instruction(k, place, gamma=gamma, beta=beta, duration=duration,
                                      function=1, start_time=launches[k]), now=launches[k])
    orders = {}
    for order in ("smith", "oldest"):
        ctx.config = replace(ctx.config, overdue_order=order)
        problem, available = fetch_and_decode(ctx, 400.0)
        orders[order] = [int(problem.ids[k]) for k in available]
    assert orders == {"smith": [3], "oldest": [2]}
    (tmp_path / "together").mkdir()
    together = make_context(line_graph, tmp_path / "together", node=B, planner=PriorityFirst(),
                            serve_within_s=120.0, overdue_order="oldest")
    journal(together, make_instruction(1, B, gamma=5.0, beta=0.96, duration=60, function=1,
                                       start_time=0.0),
            make_instruction(2, B, gamma=3.0, beta=0.94, duration=10, function=1,
                             start_time=0.0))
    problem, available = fetch_and_decode(together, 400.0)
    assert [int(problem.ids[k]) for k in available] == [2]     # 3 / 10 against 5 / 60


def test_an_unknown_overdue_order_is_refused_with_the_choices():
    with pytest.raises(ValueError, match="overdue_order must be one of .*smith.*oldest"):
        ExecutorConfig(overdue_order="fifo")


def test_the_charge_never_sets_the_place_of_overdue_requests(line_graph, tmp_path):
    """The robot's charge (function 8, at A) pending since 0 s is the oldest; an overdue request
    at D goes with it, not after it. Overdue alone, the charge goes first."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0)
    ctx.charging = Charging(BatteryModel(BatteryConfig()), A, 8,
                            Priority("self_generated", 1.0, 0.9))
    journal(ctx, make_instruction(1, A, function=8, type=ROBOT, source="robot", start_time=0.0),
            make_instruction(2, C, function=1, start_time=250.0), now=250.0)
    problem, available = fetch_and_decode(ctx, 300.0)
    assert [int(problem.ids[k]) for k in available] == [1]          # only the charge is late
    journal(ctx, make_instruction(3, D, function=1, start_time=100.0), now=300.0)
    problem, available = fetch_and_decode(ctx, 300.0)
    assert sorted(int(problem.ids[k]) for k in available) == [1, 3]


def test_a_meeting_is_overdue_while_an_overdue_request_waits_for_it(line_graph, tmp_path):
    """Carol, never seen, asked 150 s ago; a newer request of Bob's and a meeting are open:
    the meeting (Carol may be the stranger) goes before Bob's."""
    ctx = make_context(line_graph, tmp_path, node=B, planner=PriorityFirst(),
                       serve_within_s=120.0)
    ctx.people.seen("Bob", C, 1.0)
    journal(ctx, make_instruction(1, C, function=1, source="Carol", target="Carol",
                                  start_time=0.0))
    journal(ctx, make_instruction(2, C, function=1, source="Bob", target="Bob", start_time=140.0),
            make_instruction(3, D, gamma=1.0, beta=0.9, function=9, type=ROBOT, source="robot",
                             start_time=145.0), now=145.0)
    problem, available = fetch_and_decode(ctx, 150.0)
    assert [int(problem.ids[k]) for k in available] == [3]
    ctx.buffer.start(3, 150.0)
    ctx.buffer.finish(3, 151.0)     # met someone else: Carol's request is searched for
    problem, available = fetch_and_decode(ctx, 152.0)
    assert [int(problem.ids[k]) for k in available] == [1]
