"""task_planner.behaviours.searching: where to serve, and the next place to search."""
from behaviour_factories import A, B, C, D, make_context, journal
from planner_factories import make_instruction

from task_planner.behaviours.searching import search_next, served_where, where
from task_planner.executor_commands import Say
from task_planner.people_belief import PeopleAtPlaces
from task_planner.task_buffer import FAILED


def test_without_the_belief_an_instruction_is_served_at_its_destination(line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", D, stamp=0.0)
    ctx = make_context(line_graph, tmp_path, people=people)
    visit = make_instruction(1, B, function=3, target="Bob")
    assert where(ctx, visit) == B and served_where(ctx, visit, 0.0) is visit


def test_following_the_belief_serves_where_the_person_was_seen(line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", D, stamp=0.0)
    ctx = make_context(line_graph, tmp_path, people=people, follow_belief=True)
    visit = make_instruction(1, B, function=3, target="Bob")
    assert where(ctx, visit) == D and served_where(ctx, visit, 0.0).destination == D


def test_a_meeting_is_planned_with_the_time_its_dialogue_is_expected_to_take(line_graph,
                                                                             tmp_path):
    ctx = make_context(line_graph, tmp_path)
    meeting = make_instruction(1, B, function=9, duration=60)   # introduce: expected_s 10
    planned = served_where(ctx, meeting, 0.0)
    assert (planned.destination, planned.duration, meeting.duration) == (B, 10, 60)
    short = make_instruction(2, B, function=9, duration=5)
    assert served_where(ctx, short, 0.0) is short                   # never longer than its own


def test_the_planner_weighs_the_expected_cost_of_a_miss(line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", D, stamp=0.0)
    ctx = make_context(line_graph, tmp_path, people=people, follow_belief=True,
                       search_miss_s=40.0, stay_s=600.0)
    visit = make_instruction(1, B, function=3, target="Bob", duration=20)
    assert served_where(ctx, visit, 0.0).duration == 20        # just seen there
    # seen 300 s ago: 1 - exp(-0.5) = 0.39 of a 40 s miss, 15.7 s, planned as 15 s
    assert served_where(ctx, visit, 300.0).duration == 35
    people.missed("Bob", D)                                     # not where he was believed:
    assert served_where(ctx, visit, 300.0).duration == 40       # UNSEEN_MISS 0.5 of 40 s
    (tmp_path / "off").mkdir()
    off = make_context(line_graph, tmp_path / "off", people=people, follow_belief=True)
    assert served_where(off, visit, 300.0).duration == 20       # search_miss_s 0: the seed


def test_a_miss_searches_the_last_known_places_then_fails(line_graph, tmp_path):
    people = PeopleAtPlaces()
    people.seen("Bob", C, stamp=0.0)
    people.seen("Bob", B, stamp=1.0)              # last seen at B, before that at C
    ctx = make_context(line_graph, tmp_path, node=B, people=people)
    record, = journal(ctx, make_instruction(1, B, function=3, target="Bob"))
    assert search_next(ctx, record.instruction, 5.0) == []
    assert ctx.search[1] == [C] and ctx.searched[1] == [B]
    assert where(ctx, record.instruction) == C
    ctx.node = C
    assert search_next(ctx, record.instruction, 9.0) == [
        Say("Sorry, I could not complete request 1.")]
    failed = ctx.buffer.get(1)
    assert failed.state == FAILED and failed.reason == "Bob not found (searched B, C)"
    assert ctx.buffer.searches() == [(1, "Bob", 5.0, 9.0, False, ["B", "C"])]


def test_searching_all_places_goes_on_to_places_never_looked_at(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path, node=B, search_all_places=True)
    ctx.looked_s.update({A: 0.0, B: 0.0})
    record, = journal(ctx, make_instruction(1, B, function=3, target="Zoe"))
    search_next(ctx, record.instruction, 5.0)
    assert ctx.search[1][0] in (C, D) and B not in ctx.search[1]


def test_a_miss_counts_for_every_search_for_that_person(line_graph, tmp_path):
    """Two instructions for Zoe search at once: a look at B that misses her takes B out of the
    other one's search too, so the robot does not come back to look there again; a search for
    someone else keeps B."""
    ctx = make_context(line_graph, tmp_path, node=B, search_all_places=True, follow_belief=True)
    first, second, other = journal(ctx, make_instruction(1, B, function=3, target="Zoe"),
                                   make_instruction(2, B, function=4, target="Zoe"),
                                   make_instruction(3, B, function=3, target="Yan"))
    for record in (first, second, other):
        where(ctx, record.instruction)             # each plans its search
    assert all(B in ctx.search[i] for i in (1, 2, 3))
    search_next(ctx, first.instruction, 5.0)
    assert B not in ctx.search[2] and ctx.searched[2] == [B]
    assert B in ctx.search[3] and 3 not in ctx.searched
