"""The robot's belief about people: search order, idle patrol, looking around, asking to pass."""
import math

import pytest
from planner_factories import make_instruction

from task_planner.baselines import FirstComeFirstServe, PriorityFirst
from task_planner.behaviours.searching import where
from task_planner.executor import Executor, ExecutorConfig
from task_planner.executor_commands import Execute, Navigate, Say, StopMotion, Wait
from task_planner.executor_sim import NavigationModel, run_executor
from task_planner.graph import graph_from_edges
from task_planner.people_belief import (UPCOMING_S, PeopleAtPlaces, patrol_target,
                                        scheduled_place, search_order)
from task_planner.robot_functions import load_robot_functions
from task_planner.instruction import ROBOT
from task_planner.task_buffer import FAILED, PENDING, BufferConfig, TaskBuffer
from tamp_resources import resource

FUNCTIONS = load_robot_functions(
    resource("config") / "robot_functions.yaml")
A, B, C, D = range(4)


@pytest.fixture
def graph():
    """A -1- B -2- C -3- D (metres), every place facing east."""
    return graph_from_edges("ABCD", [("A", "B", 1.0), ("B", "C", 2.0), ("C", "D", 3.0)],
                            poses=[(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (3.0, 0.0, 0.0),
                                   (6.0, 0.0, 0.0)])


def executor_for(graph, tmp_path, people, start=A, planner=FirstComeFirstServe, **config):
    buffer = TaskBuffer(tmp_path / "buffer.sqlite", BufferConfig(node_count=graph.size))
    settings = dict(speed_mps=0.5, look_headings=3, search_all_places=True)
    settings.update(config)
    return Executor(buffer, graph, planner(), people, FUNCTIONS, ExecutorConfig(**settings),
                    start_node=start)


def test_search_order_is_last_seen_then_schedule_then_stalest():
    people = PeopleAtPlaces()
    people.seen("Bob", C, stamp=5.0)
    people.predicted["Bob"] = A
    looked = {B: 50.0, D: 10.0}              # A and C never looked at; D before B
    assert search_order("Bob", people, looked, range(4), searched=[]) == [C, A, D, B]
    assert search_order("Bob", people, looked, range(4), searched=[C]) == [A, D, B]
    # equally stale places: the nearest first (distances from the robot at D)
    assert search_order("Zoe", PeopleAtPlaces(), {}, range(4), [],
                        distance_m=[6, 5, 3, 0]) == [D, C, B, A]


def test_for_someone_never_seen_a_place_their_schedule_names_counts_as_twice_as_likely():
    """Bob, never seen, has nothing scheduled now; at other times of day his schedule puts him
    at D (TV in the evening). Among places not looked at, the order is distance over
    likelihood: D at 4 m (2 m) before C at 3 m, but after C at 1 m (he may be anywhere, and
    a look there is cheap); a place looked at stays behind the unlooked ones. Once seen
    (and missed there), the nearest first again after the place he was seen at."""
    people = PeopleAtPlaces()
    people.predict({"Bob": [(68400.0, 75600.0, D)]}, day_s=45000.0)
    assert people.predicted["Bob"] is None and people.habitual["Bob"] == {D}
    assert search_order("Bob", people, {}, range(4), [],
                        distance_m=[6, 5, 3, 4]) == [D, C, B, A]
    assert search_order("Bob", people, {}, range(4), [],
                        distance_m=[6, 5, 1, 4]) == [C, D, B, A]
    assert search_order("Bob", people, {D: 30.0}, range(4), [],
                        distance_m=[6, 5, 3, 4]) == [C, B, A, D]
    people.seen("Bob", A, stamp=40.0)
    people.missed("Bob", A)
    assert search_order("Bob", people, {A: 41.0}, range(4), [],
                        distance_m=[6, 5, 3, 4]) == [A, C, D, B]   # A: seen there before


def test_places_people_only_pass_through_are_searched_last_unless_pointed_at():
    """D is a passage: Zoe, never seen, is looked for in it after every other place even though
    it is the nearest; Bob, last seen in D, is looked for there first."""
    assert search_order("Zoe", PeopleAtPlaces(), {}, range(4), [],
                        distance_m=[6, 5, 3, 0], last=(D,)) == [C, B, A, D]
    people = PeopleAtPlaces()
    people.seen("Bob", D, stamp=5.0)
    assert search_order("Bob", people, {}, range(4), [], distance_m=[6, 5, 3, 0],
                        last=(D,))[0] == D


def test_search_looks_where_they_were_seen_before_the_stalest_places():
    people = PeopleAtPlaces()
    people.seen("David", B, stamp=10.0)      # met in B
    people.seen("David", C, stamp=20.0)      # then taken for someone in C
    people.predicted["David"] = A
    looked = {B: 15.0, C: 30.0}              # D never looked at: the stalest
    assert search_order("David", people, looked, range(4), searched=[]) == [C, A, B, D]
    # C looked all around after the sighting there and missed him: C ranks by staleness
    swept = {C: (25.0, 30.0), B: (12.0, 15.0)}
    assert search_order("David", people, looked, range(4), [], swept=swept) == [A, B, D, C]
    # the schedule's place stays second even when looked around since (he may have come)
    swept[A] = (40.0, 45.0)
    assert search_order("David", people, looked, range(4), [], swept=swept)[:2] == [A, B]



def test_a_person_the_belief_says_nothing_of_is_looked_for_where_others_are_expected():
    """Carol was never seen and her schedule is empty now; Bob's puts him at C: C first (the
    household gathers there; a stranger seen there is met), then the stalest places. Once
    she was seen, others' schedules say nothing of her."""
    people = PeopleAtPlaces()
    people.predicted.update({"Bob": C, "Carol": None})
    looked = {C: 50.0, D: 10.0}
    assert search_order("Carol", people, looked, range(4), searched=[]) == [C, A, B, D]
    people.seen("Carol", B, 60.0)
    people.missed("Carol", B)                # seen once: as for anyone; the looks at C and D
    #                                          came before her sighting and tell nothing
    assert search_order("Carol", people, looked, range(4), searched=[B]) == [A, C, D]


def test_a_look_before_the_last_sighting_does_not_make_a_place_stale():
    """Alice was last seen in B at 179 s. D was looked at 151 s, before: she may have gone
    there since, as to A or C; the nearest of them goes first. C, looked at 190 s, after her
    sighting, comes last."""
    people = PeopleAtPlaces()
    people.seen("Alice", B, stamp=179.0)
    people.missed("Alice", B)
    looked = {A: 1.0, C: 190.0, D: 151.0}
    assert search_order("Alice", people, looked, range(4), searched=[B],
                        distance_m=[5.0, 3.0, 4.0, 1.0]) == [D, A, C]


def test_an_older_sighting_does_not_undo_a_missed_look():
    people = PeopleAtPlaces()
    people.seen("Bob", C, stamp=5.0)
    people.missed("Bob", C)                  # the robot looked at C and did not see him
    people.seen("Bob", C, stamp=5.0)         # the same database row published again
    assert people.now["Bob"] is None and people.last_known_places("Bob") == [C]
    people.seen("Bob", C, stamp=9.0)         # a new sighting counts
    assert people.is_at("Bob", C) and not people.is_at("Bob", C, since=9.5)


def test_scheduled_place_wraps_past_midnight():
    entries = [(8 * 3600.0, 9 * 3600.0, "kitchen"), (22 * 3600.0, 6 * 3600.0, "bedroom")]
    assert [scheduled_place(entries, h * 3600.0) for h in (8.5, 23, 3, 12)] == \
        ["kitchen", "bedroom", "bedroom", None]


def test_patrol_prefers_stale_occupied_places_and_rests_when_all_are_fresh():
    people = PeopleAtPlaces()
    people.predicted["Carol"] = D
    looked = {A: 90.0, B: 0.0, C: 0.0, D: 0.0}
    # B, C, D are equally stale (100 s); D's expected person doubles its score
    assert patrol_target(range(4), people, looked, 100.0, min_interval_s=30.0) == D
    assert patrol_target(range(4), people, {n: 90.0 for n in range(4)}, 100.0, 30.0) is None
    # never looked at, nobody expected: the nearest first (the robot at C)
    assert patrol_target(range(4), PeopleAtPlaces(), {}, 100.0, 30.0, [3, 2, 0, 3]) == C


def test_person_moved_unseen_is_found_by_search_and_served_there(graph, tmp_path):
    """Bob was last seen at B and has moved to D: the robot looks around B, then C (never
    looked at; A was looked at after his sighting), then finds him at D."""
    people = PeopleAtPlaces()
    people.seen("Bob", B, stamp=0.0)
    executor = executor_for(graph, tmp_path, people, fresh_s=1.0)
    executor.state.looked_s[A] = 0.5
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    assert executor.receive([visit], 0.0)[1] == [Navigate(B, 1)]
    # A->B 2 s; three 1 s turns at B; B->C 4 s; three turns at C; C->D 6 s
    commands = executor.arrived(2.0)
    for clock in (3.0, 4.0, 5.0):
        assert commands[0].yaw is not None
        commands = executor.arrived(clock)
    assert commands == [Navigate(C, 1)] and executor.state.searched[1] == [B]
    commands = executor.arrived(9.0)
    for clock in (10.0, 11.0, 12.0):
        commands = executor.arrived(clock)
    assert commands == [Navigate(D, 1)]
    people.seen("Bob", D, stamp=17.5)        # perception sees him as the robot comes in
    commands = executor.arrived(18.0)
    assert commands[0] == Execute(1, "check_status", 4.0)
    assert executor.buffer.searches() == [(1, "Bob", 5.0, 18.0, True, ["B", "C", "D"])]


def test_search_fails_only_when_every_place_was_looked_at(graph, tmp_path):
    executor = executor_for(graph, tmp_path, PeopleAtPlaces())
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Zoe")
    run_executor(executor, [(0.0, visit)], NavigationModel(graph, 0.5, turn_s=1.0))
    record = executor.buffer.get(1)
    assert record.state == FAILED
    assert record.reason.startswith("Zoe not found (searched B, ")
    (_, _, _, _, found, places), = executor.buffer.searches()
    assert not found and sorted(places) == ["A", "B", "C", "D"]


def test_a_place_with_someone_perception_could_not_tell_is_looked_at_again(graph, tmp_path):
    """Zoe is nowhere perception could tell her; at C it saw someone it could not tell (half
    hidden) during the search. With every place searched, the robot looks at C once more
    before it gives up; without anybody such, C is looked at once."""
    def search(people, folder):
        (tmp_path / folder).mkdir()
        executor = executor_for(graph, tmp_path / folder, people)
        visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3,
                                 target="Zoe")
        run_executor(executor, [(0.0, visit)], NavigationModel(graph, 0.5, turn_s=1.0))
        assert executor.buffer.get(1).state == FAILED
        (_, _, _, _, _, places), = executor.buffer.searches()
        return places, [text for _, text in executor.state.log if "look again" in text]

    places, said = search(PeopleAtPlaces(), "nobody")
    assert sorted(places) == ["A", "B", "C", "D"] and not said
    people = PeopleAtPlaces()
    people.someone_unidentified(C, 3.0, 0.0, stamp=5.0)   # after the first miss (at 5 s)
    places, said = search(people, "someone")
    assert places.count("C") == 2 and places[-1] == "C"
    assert said == ["Zoe not seen anywhere; look again at C, where someone perception could "
                    "not tell was"]
    people = PeopleAtPlaces()                      # two such places: both looked at again
    people.someone_unidentified(B, 1.0, 0.0, stamp=5.0)
    people.someone_unidentified(C, 3.0, 0.0, stamp=5.0)
    places, said = search(people, "two")
    assert places == ["B", "A", "C", "D", "C", "B"] and len(said) == 2
    people = PeopleAtPlaces()                      # seen during the first look (2-5 s) at B
    people.someone_unidentified(B, 1.0, 0.0, stamp=3.0)
    places, said = search(people, "first")
    assert places.count("B") == 2 and len(said) == 1


def test_look_stops_as_soon_as_the_person_is_seen(graph, tmp_path):
    people = PeopleAtPlaces()
    executor = executor_for(graph, tmp_path, people, start=B)
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    _, commands = executor.receive([visit], 0.0)
    assert commands == [Navigate(B, 1, yaw=math.pi / 2)] and executor.mode == "looking"
    assert executor.arrived(1.0) == [Navigate(B, 1, yaw=math.pi)]
    people.seen("Bob", B, stamp=1.5)
    commands = executor.tick(1.6)
    assert commands[:2] == [StopMotion(), Execute(1, "check_status", 4.0)]


def test_idle_robot_patrols_and_drops_the_patrol_for_an_instruction(graph, tmp_path):
    people = PeopleAtPlaces()
    people.predicted["Carol"] = C
    executor = executor_for(graph, tmp_path, people, patrol=True, patrol_interval_s=30.0)
    executor.state.looked_s.update({A: 0.0, B: 0.0, C: 0.0, D: 0.0})
    assert executor.tick(100.0) == [Navigate(B, 0, through=0.0)]  # on the way to C
    assert executor.arrived(102.0) == [Navigate(C, 0)]
    assert executor.arrived(106.0) == [Navigate(C, 0, yaw=math.pi / 2)]
    visit = make_instruction(1, A, gamma=2.0, beta=0.9, duration=4, function=1,
                             start_time=107.0)
    _, commands = executor.receive([visit], 107.0)
    assert commands == [StopMotion(), Navigate(B, 1, through=math.pi)] and executor.mode == "moving"


def test_blocked_robot_asks_to_pass_waits_then_retries(graph, tmp_path):
    executor = executor_for(graph, tmp_path, PeopleAtPlaces(), pass_wait_s=5.0)
    visit = make_instruction(1, C, gamma=2.0, beta=0.9, duration=4, function=1)
    assert executor.receive([visit], 0.0)[1] == [Navigate(B, 1, through=0.0)]
    assert executor.aborted(1.0, "blocked") == [Say("Excuse me, may I pass?"), Wait(6.0)]
    assert executor.tick(5.9) == []
    assert executor.tick(6.0) == [Navigate(B, 1, through=0.0)]


def test_following_the_belief_serves_where_the_person_was_seen(graph, tmp_path):
    people = PeopleAtPlaces()
    executor = executor_for(graph, tmp_path, people, follow_belief=True)
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=1, target="Bob")
    executor.state.looked_s.update({A: 0.0, B: 0.0, C: 0.0})
    # never seen, no schedule: his search is planned once, stalest place first (D)
    assert executor.receive([visit], 0.0)[1] == [Navigate(B, 1, through=0.0)]  # on the way to D
    assert executor.state.search[1] == [D, A, B, C]
    executor.node = B                          # the plan does not change as the robot moves
    assert where(executor.state, visit) == D
    people.seen("Bob", C, stamp=0.5)           # perception sees him at C
    assert where(executor.state, visit) == C
    people.missed("Bob", C)                    # a look at C misses him: the search again
    assert where(executor.state, visit) == D
    chat = make_instruction(2, B, gamma=2.0, beta=0.9, duration=4, function=1, target="Ann")
    people.predicted["Ann"] = C                # her schedule's place comes first
    assert where(executor.state, chat) == C
    people.predicted["Bob"] = B                # his schedule turns to B: B goes first
    assert where(executor.state, visit) == B and executor.state.search[1] == [B, D, A, C]


def test_look_dwells_on_each_heading_before_it_turns_on(graph, tmp_path):
    people = PeopleAtPlaces()
    executor = executor_for(graph, tmp_path, people, start=B, look_headings=2, look_dwell_s=2.0)
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    assert executor.receive([visit], 0.0)[1] == [Navigate(B, 1, yaw=2 * math.pi / 3)]
    assert executor.arrived(1.0) == [Wait(3.0)]
    assert executor.tick(2.9) == [] and executor.mode == "looking"
    assert executor.tick(3.0) == [Navigate(B, 1, yaw=4 * math.pi / 3)]
    assert executor.arrived(4.0) == [Wait(6.0)]
    people.seen("Bob", B, stamp=5.5)          # perception catches up while it dwells
    assert executor.tick(5.6)[:2] == [StopMotion(), Execute(1, "check_status", 4.0)]


def test_a_look_that_sees_nobody_ends_after_the_last_dwell(graph, tmp_path):
    executor = executor_for(graph, tmp_path, PeopleAtPlaces(), start=B, look_headings=1,
                            look_dwell_s=2.0)
    visit = make_instruction(1, B, gamma=2.0, beta=0.9, duration=4, function=3, target="Bob")
    executor.receive([visit], 0.0)
    assert executor.arrived(1.0) == [Wait(3.0)]
    assert executor.tick(3.0) == [Navigate(A, 1)]       # on to the next place of the search
    assert executor.state.searched[1] == [B] and executor.state.looked_s[B] == 3.0


def own_then_chat(graph, tmp_path, function, name, duration):
    """The robot starts an instruction of its own at A; at 10 s Bob asks for a chat at B.
    Returns the executor and the commands of the chat's arrival."""
    executor = executor_for(graph, tmp_path, PeopleAtPlaces(), planner=PriorityFirst,
                            own_yields=True)
    own = make_instruction(100000, A, gamma=1.0, beta=0.9, duration=duration, function=function,
                           type=ROBOT)
    assert executor.receive([own], 0.0)[1][0] == Execute(100000, name, float(duration))
    chat = make_instruction(1, B, gamma=5.0, beta=0.9, duration=60, function=1, start_time=10.0)
    return executor, executor.receive([chat], 10.0)[1]


def test_a_persons_request_interrupts_the_robots_own_instruction(graph, tmp_path):
    executor, commands = own_then_chat(graph, tmp_path, 6, "play_music", 120)
    assert commands[:2] == [StopMotion(), Say("Excuse me, I am needed elsewhere. I will be back.")]
    assert commands[2] == Navigate(B, 1)
    assert executor.buffer.get(100000).state == PENDING     # served later


def test_introductions_are_not_interrupted(graph, tmp_path):
    executor, commands = own_then_chat(graph, tmp_path, 9, "introduce", 60)
    assert commands == [] and executor.mode == "executing"


def test_an_interrupted_own_instruction_waits_until_people_are_served(graph, tmp_path):
    """FCFS would pick the interrupted music again (it came first): it waits for the chat."""
    executor = executor_for(graph, tmp_path, PeopleAtPlaces(), own_yields=True)
    music = make_instruction(100000, A, gamma=1.0, beta=0.9, duration=120, function=6,
                             type=ROBOT)
    executor.receive([music], 0.0)
    chat = make_instruction(1, B, gamma=5.0, beta=0.9, duration=60, function=1, start_time=10.0)
    assert executor.receive([chat], 10.0)[1][2] == Navigate(B, 1)
    assert executor.arrived(12.0)[0] == Execute(1, "chat", 60.0)
    executor.tick(72.0)                        # the chat is done: the music comes back
    assert executor.goal == A and executor.state.goal_for == 100000


def test_the_table_gives_sightings_and_the_schedules_predictions():
    people = PeopleAtPlaces()
    schedules = {"Bob": [(18.5 * 3600, 19 * 3600, C)], "Zoe": []}
    people.take_table({"Bob": (B, 10.0)}, schedules, 18 * 3600)
    assert people.now == {"Bob": B} and people.predicted == {"Bob": None, "Zoe": None}
    people.predict(schedules, 18.6 * 3600)
    assert people.predicted["Bob"] == C


def test_a_schedule_entry_starting_within_ten_minutes_is_searched_after_the_current_one():
    """Carol's bedtime is at 14:00. At 13:58 nothing is scheduled, and she was last seen at B
    (missed there now) and before at D; her bed at C comes next, before D: people go to bed
    a few minutes early. At 13:40 the entry is 20 minutes off and C is only the nearest of
    the rest. An entry that runs now is not upcoming; the next one wraps past midnight."""
    schedules = {"Carol": [(14 * 3600, 15 * 3600, C)]}
    people = PeopleAtPlaces()
    people.seen("Carol", D, stamp=1.0)
    people.seen("Carol", B, stamp=2.0)
    people.predict(schedules, 13 * 3600 + 58 * 60)
    assert (people.predicted["Carol"], people.upcoming["Carol"]) == (None, C)
    assert search_order("Carol", people, {}, range(4), searched=[B]) == [C, D, A]
    people.predict(schedules, 13 * 3600 + 40 * 60)
    assert people.upcoming["Carol"] is None
    assert search_order("Carol", people, {}, range(4), searched=[B],
                        distance_m=[1, 0, 2, 5]) == [D, A, C]
    people.predict(schedules, 14 * 3600 + 60)
    assert (people.predicted["Carol"], people.upcoming["Carol"]) == (C, None)
    assert scheduled_place([(0.0, 3600.0, A)], 86400.0 - 300.0 + UPCOMING_S,
                           starting_after=86400.0 - 300.0) == A


def test_the_latest_person_not_told_apart_from_those_already_faced():
    """unidentified_at gives the latest sighting at a place since a time, or with away_from the
    latest of someone more than APART_M from each position given (another person)."""
    people = PeopleAtPlaces()
    people.someone_unidentified(2, 1.0, 1.0, stamp=1.0)
    people.someone_unidentified(2, 4.0, 1.0, stamp=2.0)
    people.someone_unidentified(2, 1.2, 1.1, stamp=3.0)   # the first one again, moved a little
    assert people.unidentified_at(2, 0.0) == (1.2, 1.1)
    assert people.unidentified_at(2, 0.0, away_from=[(1.0, 1.0)]) == (4.0, 1.0)
    assert people.unidentified_at(2, 2.5, away_from=[(1.0, 1.0)]) is None   # seen too early
    assert people.unidentified_at(2, 0.0, away_from=[(1.0, 1.0), (4.0, 1.5)]) is None
    assert people.unidentified_at(3, 0.0) is None
