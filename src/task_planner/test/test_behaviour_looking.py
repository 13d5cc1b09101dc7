"""task_planner.behaviours.looking: serve here, or look around / stand and look for the person."""
import math

from behaviour_factories import B, C, make_context, journal
from planner_factories import make_instruction
from py_trees.common import Status

from task_planner.behaviours.looking import (LookingAround, StandingToLook, end_look, look_step,
                                             not_answered, serve_here, start_look)
from task_planner.executor_commands import (EXECUTING, IDLE, LOOKING, VERIFYING, Ask, Execute,
                                            Navigate, StopMotion, Verify, Wait)
from task_planner.instruction import ROBOT
from task_planner.people_belief import PeopleAtPlaces
from task_planner.task_buffer import FAILED


def test_a_person_seen_here_is_served_at_once(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", B, stamp=0.0)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3)
    journal(ctx, make_instruction(1, B, duration=20, function=3, target="Bob"))
    assert serve_here(ctx, 1, 1.0)[0] == Execute(1, "check_status", 20.0)
    assert ctx.mode == EXECUTING


def test_an_absent_person_starts_a_look_around_of_evenly_spaced_turns(posed_line_graph,
                                                                      tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=3)
    journal(ctx, make_instruction(1, B, function=3, target="Bob"))
    assert serve_here(ctx, 1, 1.0) == [Navigate(B, 1, yaw=math.pi / 2)]
    assert ctx.mode == LOOKING and ctx.looking == [1, [math.pi, 3 * math.pi / 2], 1.0, None,
                                                   None, None]
    assert look_step(ctx, 2.0) == [Navigate(B, 1, yaw=math.pi)]


def test_a_heading_is_held_a_dwell_before_the_next_turn(posed_line_graph, tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=2, look_dwell_s=0.6)
    start_look(ctx, 0, 0.0)                        # a patrol's look
    assert look_step(ctx, 1.0) == [Wait(1.6)]
    leaf = LookingAround(ctx)
    ctx.now = 1.5
    leaf.tick_once()
    assert leaf.status == Status.RUNNING and ctx.looking[3] == 1.6
    ctx.now = 1.6
    ctx.out = []
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 0, yaw=4 * math.pi / 3)]


def test_a_heading_is_held_until_perception_analysed_frames_taken_there(posed_line_graph,
                                                                        tmp_path):
    people = PeopleAtPlaces()
    people.analysed(0.5)                           # perception reports its frames
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=2,
                       look_dwell_s=0.6, look_frames=2, look_frames_wait_s=5.0)
    start_look(ctx, 0, 0.0)
    assert look_step(ctx, 1.0) == [Wait(1.6)]      # heading reached at 1.0
    leaf = LookingAround(ctx)
    people.analysed(0.9)                           # taken before the heading was reached
    people.analysed(1.2)
    ctx.now, ctx.out = 2.0, []                     # the dwell is over, one frame of two
    leaf.tick_once()
    assert ctx.out == [] and leaf.status == Status.RUNNING
    people.analysed(1.8)
    ctx.now = 2.1
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 0, yaw=4 * math.pi / 3)]


def test_a_heading_is_left_after_the_wait_when_perception_falls_silent(posed_line_graph,
                                                                       tmp_path):
    people = PeopleAtPlaces()
    people.analysed(0.5)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=2,
                       look_dwell_s=0.6, look_frames=3, look_frames_wait_s=5.0)
    start_look(ctx, 0, 0.0)
    look_step(ctx, 1.0)
    leaf = LookingAround(ctx)
    ctx.now, ctx.out = 5.9, []
    leaf.tick_once()
    assert ctx.out == []
    ctx.now = 6.0                                  # held 5 s: turn on all the same
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 0, yaw=4 * math.pi / 3)]


def test_without_frame_reports_the_dwell_alone_counts(posed_line_graph, tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=2, look_dwell_s=0.6,
                       look_frames=3)
    start_look(ctx, 0, 0.0)
    look_step(ctx, 1.0)
    leaf = LookingAround(ctx)
    ctx.now, ctx.out = 1.6, []
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 0, yaw=4 * math.pi / 3)]


def test_someone_perception_cannot_tell_is_faced_once_and_watched(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.analysed(0.5)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3,
                       look_dwell_s=0.6, look_frames=2, look_frames_wait_s=5.0)
    journal(ctx, make_instruction(1, B, duration=20, function=3, target="Bob"))
    serve_here(ctx, 1, 1.0)                        # a look for Bob begins at 1.0
    leaf = LookingAround(ctx)
    people.someone_unidentified(B, 1.0, 1.0, 0.5)  # seen before the look: not this look's
    ctx.now, ctx.out = 1.2, []
    leaf.tick_once()
    assert ctx.out == []
    people.someone_unidentified(B, 1.0, 1.0, 1.1)  # due north of B, whose shirt named nobody
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi / 2)] and ctx.looking[5] == "facing"
    assert look_step(ctx, 2.0) == [Wait(2.6)]     # faced at 2.0
    for stamp in (2.1, 2.2, 2.3):
        people.analysed(stamp)                     # frames enough, but they are watched ...
    ctx.now, ctx.out = 6.9, []
    leaf.tick_once()
    assert ctx.out == []
    ctx.now = 7.0                                  # ... 5 s, then the look turns on
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi)] and ctx.looking[5] == "faced"
    people.someone_unidentified(B, 1.0, 1.0, 7.1)  # once per look
    ctx.now, ctx.out = 7.2, []
    leaf.tick_once()
    assert ctx.out == []


def asked_look(posed_line_graph, tmp_path, instruction=None, **config):
    """A look for Bob at B (or for `instruction`'s person) that faced someone perception
    cannot tell (faced at 2.0, watched 5 s), with ask_wait_s 8."""
    people = PeopleAtPlaces()
    people.analysed(0.5)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3,
                       look_dwell_s=0.6, look_frames=2, look_frames_wait_s=5.0,
                       **{"ask_wait_s": 8.0, **config})
    journal(ctx, instruction or make_instruction(1, B, duration=20, function=3, target="Bob"))
    serve_here(ctx, 1, 1.0)
    leaf = LookingAround(ctx)
    people.someone_unidentified(B, 1.0, 1.0, 1.1)
    ctx.now, ctx.out = 1.2, []
    leaf.tick_once()
    look_step(ctx, 2.0)
    return ctx, people, leaf


def test_someone_still_not_told_after_the_watch_is_asked_and_a_yes_serves_them(
        posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path)
    people.someone_unidentified(B, 1.0, 1.0, 4.0)  # still not told while watched
    ctx.now, ctx.out = 7.0, []
    leaf.tick_once()
    place = ctx.graph.names[B]
    assert ctx.out == [Ask(1, "Bob", place), Wait(15.0)] and ctx.looking[5] == "asking"
    assert ctx.log[-1] == (7.0, f"ask whether the person at {place} is Bob")
    ctx.now, ctx.out = 14.0, []
    leaf.tick_once()
    assert ctx.out == []                           # waiting for the answer
    people.seen("Bob", B, stamp=14.5)              # "yes": human_db puts Bob here
    ctx.now = 14.6
    leaf.tick_once()
    assert ctx.out[:2] == [StopMotion(), Execute(1, "check_status", 20.0)]


def test_without_a_yes_the_look_turns_on_after_the_wait_and_asks_each_person_once(
        posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path)
    people.someone_unidentified(B, 1.0, 1.0, 4.0)
    ctx.now, ctx.out = 7.0, []
    leaf.tick_once()
    ctx.now, ctx.out = 15.0, []                    # "no", or nobody answered
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi)] and ctx.looking[5] is None
    people.someone_unidentified(B, 1.3, 1.2, 15.1)  # the one asked, seen again
    ctx.now, ctx.out = 15.2, []
    leaf.tick_once()
    assert ctx.out == []
    x, y, _ = ctx.graph.pose(B)
    people.someone_unidentified(B, x - 1.0, y, 15.3)  # someone else, due west of B
    ctx.now, ctx.out = 15.4, []
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi)] and ctx.looking[5] == "facing"
    assert ctx.faced == [(1.0, 1.0), (x - 1.0, y)]


def test_a_no_ends_the_wait_for_a_yes(posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path)
    people.someone_unidentified(B, 1.0, 1.0, 4.0)
    ctx.now, ctx.out = 7.0, []
    leaf.tick_once()                               # asked at 7.0, waits until 15.0
    place = ctx.graph.names[B]
    assert not not_answered(ctx, "Carol", place, 9.0)      # not the question asked
    assert not_answered(ctx, "Bob", place, 9.0)
    ctx.now, ctx.out = 9.0, []
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi)] and ctx.looking[5] is None
    assert not not_answered(ctx, "Bob", place, 9.5)        # no longer waiting


def test_someone_faced_whom_perception_then_tells_as_another_is_asked_at_once(
        posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path)    # faced (1.0, 1.0) at 2.0
    people.take_frame(1.5, [("Carol", B, 1.0, 1.0)], [])          # told while turning: not yet
    ctx.now, ctx.out = 2.6, []
    leaf.tick_once()
    assert ctx.out == [] and ctx.looking[5] == "facing"           # watched (up to 7.0)
    people.take_frame(2.7, [("Carol", B, 1.2, 0.8)], [])          # her shirt seen at last
    ctx.now = 2.8
    leaf.tick_once()
    place = ctx.graph.names[B]     # Carol, or Bob in new clothes that match hers: asked
    assert ctx.out == [Ask(1, "Bob", place), Wait(10.8)] and ctx.looking[5] == "asking"
    assert (2.8, f"perception tells the person faced at {place} as someone other than "
                 f"Bob") in ctx.log


def test_without_questions_someone_told_as_another_ends_the_watch(posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path, ask_wait_s=0.0)
    people.take_frame(2.7, [("Carol", B, 1.2, 0.8)], [])
    ctx.now, ctx.out = 2.8, []
    leaf.tick_once()
    assert ctx.out == [Navigate(B, 1, yaw=math.pi)] and ctx.looking[5] is None


def test_someone_faced_whom_perception_then_tells_as_the_one_looked_for_is_served(
        posed_line_graph, tmp_path):
    ctx, people, leaf = asked_look(posed_line_graph, tmp_path)
    people.take_frame(2.7, [("Bob", B, 1.0, 1.1)], [])
    ctx.now, ctx.out = 2.8, []
    leaf.tick_once()
    assert ctx.out[:2] == [StopMotion(), Execute(1, "check_status", 20.0)]


def called_look(posed_line_graph, tmp_path, seen_at):
    """A one-heading look for Bob at B (Bob last seen at `seen_at` long ago), ask_wait_s 8,
    at the end of its dwell at 2.6."""
    people = PeopleAtPlaces()
    people.seen("Bob", seen_at, stamp=-100.0)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=1,
                       look_dwell_s=0.6, fresh_s=5.0, ask_wait_s=8.0)
    journal(ctx, make_instruction(1, C, duration=20, function=3, target="Bob"))
    ctx.people.seen("Bob", seen_at, stamp=-100.0)
    start_look(ctx, 1, 1.0)
    look_step(ctx, 2.0)                            # the heading reached: dwell until 2.6
    return ctx, people, LookingAround(ctx)


def test_a_look_that_misses_the_person_where_expected_calls_them(posed_line_graph, tmp_path):
    ctx, people, leaf = called_look(posed_line_graph, tmp_path, B)
    ctx.now, ctx.out = 2.6, []
    leaf.tick_once()
    place = ctx.graph.names[B]
    assert ctx.out == [Ask(1, "Bob", place, call=True), Wait(10.6)]
    assert ctx.looking[5] == "calling" and ctx.log[-1] == (2.6, f"call Bob at {place}")
    people.seen("Bob", B, stamp=5.0)               # "yes": human_db puts Bob here
    ctx.now, ctx.out = 5.1, []
    leaf.tick_once()
    assert ctx.out[:2] == [StopMotion(), Execute(1, "check_status", 20.0)]


def test_a_call_unanswered_lets_the_search_go_on(posed_line_graph, tmp_path):
    ctx, _, leaf = called_look(posed_line_graph, tmp_path, B)
    ctx.now, ctx.out = 2.6, []
    leaf.tick_once()
    assert not_answered(ctx, "Bob", ctx.graph.names[B], 6.0)   # nobody said yes
    ctx.now, ctx.out = 6.0, []
    leaf.tick_once()
    assert ctx.looking is None and not any(isinstance(c, Ask) for c in ctx.out)
    assert ctx.log[-1] == (6.0, "failed 1: Bob not found (searched B)")   # searched on: B was
    #                                                     the only place he was ever seen


def test_nobody_is_called_where_they_are_not_expected(posed_line_graph, tmp_path):
    ctx, _, leaf = called_look(posed_line_graph, tmp_path, C)   # believed at C, looked for at B
    ctx.now, ctx.out = 2.6, []
    leaf.tick_once()
    assert not any(isinstance(c, Ask) for c in ctx.out) and ctx.searched[1] == [B]


def test_a_stranger_to_meet_is_asked_nothing(posed_line_graph, tmp_path):
    """A meeting's look has no target: the greeting asks the stranger's name."""
    meeting = make_instruction(1, B, function=9, type=ROBOT, source="robot")
    ctx, _, leaf = asked_look(posed_line_graph, tmp_path, meeting, stranger_fresh_s=10.0)
    ctx.now, ctx.out = 7.0, []
    leaf.tick_once()
    assert not any(isinstance(command, Ask) for command in ctx.out)


def test_the_look_leaf_serves_the_person_once_perception_sees_them(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3)
    journal(ctx, make_instruction(1, B, duration=20, function=3, target="Bob"))
    serve_here(ctx, 1, 1.0)
    people.seen("Bob", B, stamp=1.5)
    leaf = LookingAround(ctx)
    ctx.now, ctx.out = 1.6, []
    leaf.tick_once()
    assert ctx.out[:2] == [StopMotion(), Execute(1, "check_status", 20.0)]
    assert ctx.mode == EXECUTING       # the look is over: the leaf hands on (execute runs)
    assert leaf.status == Status.FAILURE


def test_standing_to_look_searches_on_when_the_wait_is_over(line_graph, tmp_path):
    """Bob was never seen anywhere: B was the only place to look, so the search ends there."""
    ctx = make_context(line_graph, tmp_path, node=B, verify_wait_s=2.0)
    journal(ctx, make_instruction(1, B, function=3, target="Bob"))
    assert serve_here(ctx, 1, 1.0) == [Verify(1, "Bob", 3.0)]
    assert ctx.mode == VERIFYING
    leaf = StandingToLook(ctx)
    ctx.now = 2.0
    leaf.tick_once()
    assert leaf.status == Status.RUNNING
    ctx.now = 3.0
    leaf.tick_once()
    assert ctx.mode == IDLE and leaf.status == Status.FAILURE
    assert ctx.buffer.get(1).reason == "Bob not found (searched B)"


def swept_b(posed_line_graph, tmp_path, people, look_again_s):
    """The robot at B has looked all around it (0-4 s, a patrol's look); Ann's instruction at B
    comes next."""
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=1,
                       fresh_s=1.0, look_again_s=look_again_s)
    start_look(ctx, 0, 0.0)
    assert end_look(ctx, 4.0) == [] and ctx.mode == IDLE
    journal(ctx, make_instruction(1, B, duration=20, function=3, target="Ann"), now=5.0)
    return ctx


def test_a_place_just_looked_all_around_is_not_looked_around_again(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Ann", C, stamp=0.0)                 # Ann was last seen at C
    ctx = swept_b(posed_line_graph, tmp_path, people, look_again_s=20.0)
    assert ctx.swept[B] == (0.0, 4.0)
    assert serve_here(ctx, 1, 6.0) == [] and ctx.mode == IDLE   # no second look: search on
    assert ctx.search[1] == [C]
    assert ctx.log[-2] == (6.0, "Ann not seen in the look around B 2 s ago")
    (tmp_path / "always").mkdir()
    again = swept_b(posed_line_graph, tmp_path / "always", people, look_again_s=0.0)
    assert serve_here(again, 1, 6.0) == [Navigate(B, 1, yaw=math.pi)]   # looks again


def test_whoever_that_look_saw_counts_as_here(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Ann", B, stamp=2.0)                 # seen during the look, 4 s before
    ctx = swept_b(posed_line_graph, tmp_path, people, look_again_s=20.0)
    assert serve_here(ctx, 1, 6.0)[0] == Execute(1, "check_status", 20.0)


def test_a_look_long_ago_is_looked_again(posed_line_graph, tmp_path):
    ctx = swept_b(posed_line_graph, tmp_path, PeopleAtPlaces(), look_again_s=20.0)
    assert serve_here(ctx, 1, 30.0) == [Navigate(B, 1, yaw=math.pi)]


def test_a_stranger_seen_here_lately_is_met_at_once(posed_line_graph, tmp_path):
    """An introduce instruction (function 9, no target) is served on arrival when perception
    saw someone at the place it cannot tell within stranger_fresh_s."""
    people = PeopleAtPlaces()
    people.someone_unidentified(B, 1.0, 2.0, stamp=5.0, shirt=True)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3,
                       stranger_fresh_s=10.0)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 12.0)[0] == Execute(1, "introduce", 60.0)


def test_someone_half_seen_is_not_greeted_as_the_stranger(posed_line_graph, tmp_path):
    """Perception saw someone it cannot tell but not their whole shirt (a resident from behind):
    the introduction node cannot take them for its stranger, so the robot looks around."""
    people = PeopleAtPlaces()
    people.someone_unidentified(B, 1.0, 2.0, stamp=5.0)
    people.analysed(5.0)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3,
                       stranger_fresh_s=10.0)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 12.0) == [Navigate(B, 1, yaw=math.pi / 2)]
    assert ctx.mode == LOOKING


def test_a_stranger_not_seen_lately_is_looked_for_then_met(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.someone_unidentified(B, 1.0, 2.0, stamp=0.0, shirt=True)   # too long ago
    people.analysed(0.0)                                     # perception reports its frames
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=3,
                       stranger_fresh_s=10.0)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 20.0) == [Navigate(B, 1, yaw=math.pi / 2)]
    assert ctx.mode == LOOKING
    people.someone_unidentified(B, 1.5, 2.5, stamp=21.0, shirt=True)   # on the first heading
    leaf = LookingAround(ctx)
    ctx.now = 21.5
    leaf.tick_once()
    assert ctx.out[:2] == [StopMotion(), Execute(1, "introduce", 60.0)] and ctx.mode == EXECUTING


def test_a_look_that_sees_no_stranger_gives_the_meeting_up(posed_line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.analysed(0.0)
    ctx = make_context(posed_line_graph, tmp_path, node=B, people=people, look_headings=1,
                       stranger_fresh_s=10.0)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 20.0) == [Navigate(B, 1, yaw=math.pi)]
    end_look(ctx, 25.0)
    record = ctx.buffer.get(1)
    assert record.state == FAILED and "nobody unknown seen in a whole shirt" in record.reason


def test_without_stranger_fresh_s_a_stranger_is_greeted_on_arrival(posed_line_graph, tmp_path):
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=3)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 20.0)[0] == Execute(1, "introduce", 60.0)


def test_without_frames_from_perception_a_stranger_is_greeted_on_arrival(posed_line_graph,
                                                                          tmp_path):
    """Perception reports no frames to this robot: it cannot look for the stranger."""
    ctx = make_context(posed_line_graph, tmp_path, node=B, look_headings=3,
                       stranger_fresh_s=10.0)
    journal(ctx, make_instruction(1, B, duration=60, function=9, type=ROBOT, source="robot"))
    assert serve_here(ctx, 1, 20.0)[0] == Execute(1, "introduce", 60.0)
