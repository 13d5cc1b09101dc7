"""Task buffer: journal before acknowledgement, life cycle, chains, restart, bad input."""
import math
import multiprocessing
import os
import signal
import sqlite3
import subprocess
import sys

import pytest
from planner_factories import make_instruction

from task_planner.task_buffer import (ACTIVE, CANCELLED, DONE, FAILED, PENDING, BufferConfig,
                                      TaskBuffer, TaskBufferError)


@pytest.fixture
def journal(tmp_path):
    return tmp_path / "buffer.sqlite"


def test_submit_then_life_cycle_with_eq_4_2_reward(journal):
    buffer = TaskBuffer(journal)
    buffer.submit(make_instruction(1, 2, gamma=3.0, beta=0.94, start_time=10.0), now=11.0)
    assert buffer.get(1).state == PENDING and buffer.get(1).received_time == 11.0
    buffer.start(1, now=20.0)
    assert buffer.active_id() == 1
    done = buffer.finish(1, now=30.0)
    # Eq. 4-2: 3 * 0.94 ** (30 - 10) = 0.8703...
    assert done.state == DONE and done.completion_time == 30.0
    assert done.reward_earned == pytest.approx(3.0 * 0.94 ** 20)
    assert done.reward_earned == pytest.approx(0.87032, abs=1e-5)
    assert buffer.total_reward() == pytest.approx(done.reward_earned)


def test_submitted_instruction_is_in_the_journal_before_submit_returns(journal):
    buffer = TaskBuffer(journal)
    buffer.submit(make_instruction(7, 1, text="play some music"), now=1.0)
    other = TaskBuffer(journal)  # a second connection sees the committed row
    assert other.get(7).instruction.text == "play some music"


def test_bad_requests_are_named(journal):
    buffer = TaskBuffer(journal, BufferConfig(node_count=4))
    buffer.submit(make_instruction(1, 2), now=0.0)
    with pytest.raises(TaskBufferError, match="instruction 1: id already used"):
        buffer.submit(make_instruction(1, 3), now=0.0)
    assert buffer.submit(make_instruction(1, 2), now=5.0).received_time == 0.0  # idempotent
    with pytest.raises(TaskBufferError, match="destination node 9 is not in the graph"):
        buffer.submit(make_instruction(2, 9), now=0.0)
    with pytest.raises(TaskBufferError, match="cannot finish an instruction that is pending"):
        buffer.finish(1, now=1.0)
    with pytest.raises(TaskBufferError, match="instruction 5: not in the task buffer"):
        buffer.start(5, now=1.0)
    with pytest.raises(TaskBufferError, match="needs a reason"):
        buffer.fail(1, now=1.0, reason="")
    with pytest.raises(TaskBufferError, match="synchronous"):
        TaskBuffer(journal, BufferConfig(synchronous="SOMETIMES"))


def test_chain_cycle_through_forward_reference_is_refused(journal):
    buffer = TaskBuffer(journal)
    buffer.submit(make_instruction(2, 0, previous_id=1), now=0.0)
    with pytest.raises(TaskBufferError, match="returns to itself"):
        buffer.submit(make_instruction(1, 0, previous_id=2), now=0.0)


def test_successor_waits_for_predecessor_and_fails_with_it(journal):
    buffer = TaskBuffer(journal)
    buffer.submit(make_instruction(1, 0), now=0.0)
    buffer.submit(make_instruction(2, 1, previous_id=1), now=0.0)
    buffer.submit(make_instruction(3, 1, previous_id=2), now=0.0)
    buffer.submit(make_instruction(4, 1, previous_id=99), now=0.0)  # 99 has not arrived yet
    assert [buffer.eligible(buffer.get(i)) for i in (1, 2, 3, 4)] == [True, False, False, False]
    with pytest.raises(TaskBufferError, match="predecessor 1 is not done"):
        buffer.start(2, now=1.0)
    buffer.fail(1, now=2.0, reason="move_base aborted")
    assert buffer.get(2).state == FAILED and buffer.get(2).reason == "predecessor 1 failed"
    assert buffer.get(3).state == FAILED and buffer.get(3).reason == "predecessor 2 failed"
    assert buffer.get(4).state == PENDING
    buffer.submit(make_instruction(99, 2), now=2.5)  # the predecessor arrives after its successor
    buffer.start(99, now=2.6)
    buffer.finish(99, now=2.7)
    assert buffer.eligible(buffer.get(4))
    late = buffer.submit(make_instruction(5, 1, previous_id=1), now=3.0)
    assert late.state == FAILED and late.reason == "predecessor 1 failed"


def test_cancel_and_single_active(journal):
    buffer = TaskBuffer(journal)
    for k in (1, 2):
        buffer.submit(make_instruction(k, 0), now=0.0)
    buffer.start(1, now=1.0)
    with pytest.raises(TaskBufferError, match="instruction 1 is active"):
        buffer.start(2, now=1.0)
    cancelled = buffer.cancel(1, now=2.0)
    assert cancelled.state == CANCELLED and cancelled.reward_earned == 0.0
    buffer.start(2, now=3.0)
    assert buffer.active_id() == 2


def test_restart_resumes_active_as_pending_and_keeps_done_closed(journal):
    buffer = TaskBuffer(journal)
    for k in (1, 2, 3):
        buffer.submit(make_instruction(k, k, start_time=0.0), now=float(k))
    buffer.start(1, now=4.0)
    buffer.finish(1, now=5.0)
    buffer.start(2, now=6.0)
    buffer.close()
    again = TaskBuffer(journal)
    assert again.resumed == 1
    assert [(r.instruction.id, r.state) for r in again.records()] == \
        [(1, DONE), (2, PENDING), (3, PENDING)]
    assert again.get(1).reward_earned == pytest.approx(3.0 * 0.94 ** 5)
    again.submit(make_instruction(4, 0), now=7.0)
    assert [r.seq for r in again.records()] == [1, 2, 3, 4]


def _submit_then_die(path, count, ready):
    buffer = TaskBuffer(path)
    for k in range(1, count + 1):
        buffer.submit(make_instruction(k, k % 3, start_time=float(k)), now=float(k))
    buffer.start(1, now=float(count))
    buffer.finish(1, now=float(count) + 1)
    buffer.start(2, now=float(count) + 2)
    ready.set()
    signal.pause()  # killed here, mid-function, without closing the database


def test_crash_loses_nothing_acknowledged_and_repeats_nothing_done(journal):
    ready = multiprocessing.get_context("fork").Event()
    process = multiprocessing.get_context("fork").Process(
        target=_submit_then_die, args=(journal, 50, ready))
    process.start()
    assert ready.wait(30)
    os.kill(process.pid, signal.SIGKILL)
    process.join()
    assert process.exitcode == -signal.SIGKILL
    buffer = TaskBuffer(journal)
    states = {r.instruction.id: r.state for r in buffer.records()}
    assert len(states) == 50
    assert states[1] == DONE and states[2] == PENDING and buffer.resumed == 1
    assert sum(s == PENDING for s in states.values()) == 49
    assert buffer.get(1).reward_earned == pytest.approx(3.0 * 0.94 ** 50)
    assert not math.isclose(buffer.get(2).reward_earned, 3.0 * 0.94 ** 51)


def test_flood_of_1000_is_journalled_completely(journal):
    buffer = TaskBuffer(journal, BufferConfig(synchronous="FULL", node_count=8))
    # 1,000 in one second, journalled by a 20 Hz executor tick: 20 bursts of 50
    for burst in range(20):
        ids = range(burst * 50 + 1, burst * 50 + 51)
        results = buffer.submit_many(
            [make_instruction(k, k % 8, start_time=k / 1000) for k in ids], now=burst / 20)
        assert all(record is not None for record, _ in results)
    buffer.close()
    again = TaskBuffer(journal)
    ids = [r.instruction.id for r in again.records()]
    assert ids == list(range(1, 1001))
    assert all(r.state == PENDING and r.instruction.destination == r.instruction.id % 8
               for r in again.records())
    assert ACTIVE not in {r.state for r in again.records()}


def test_burst_in_one_transaction_refuses_only_the_bad_ones(journal):
    buffer = TaskBuffer(journal, BufferConfig(node_count=4))
    burst = [make_instruction(1, 0), make_instruction(2, 7), make_instruction(3, 3)]
    results = buffer.submit_many(burst, now=2.0)
    assert [r.instruction.id if r else None for r, _ in results] == [1, None, 3]
    assert "destination node 7 is not in the graph" in results[1][1]
    assert [r.instruction.id for r in TaskBuffer(journal).records()] == [1, 3]


def test_open_and_done_indexes_follow_every_change(journal):
    buffer = TaskBuffer(journal)
    for k in (1, 2, 3, 4):
        buffer.submit(make_instruction(k, k % 3, start_time=0.0), now=float(k))
    buffer.submit(make_instruction(5, 0, previous_id=4), now=5.0)
    buffer.start(2, now=6.0)
    buffer.finish(2, now=7.0)
    buffer.cancel(4, now=8.0)              # its successor 5 fails with it
    assert [r.instruction.id for r in buffer.open_records()] == [1, 3]
    assert buffer.done_ids() == {2}
    buffer.start(3, now=9.0)
    assert [(r.instruction.id, r.state) for r in buffer.open_records()] == \
        [(1, PENDING), (3, ACTIVE)]
    buffer.close()
    again = TaskBuffer(journal)                 # the indexes rebuilt from the journal agree
    assert [(r.instruction.id, r.state) for r in again.open_records()] == \
        [(1, PENDING), (3, PENDING)]
    assert again.done_ids() == {2} and again.get(5).state == FAILED


def test_robot_state_values_survive_reopening(journal):
    buffer = TaskBuffer(journal)
    assert buffer.robot_value("battery_level_wh", 795.0) == 795.0
    buffer.store_robot_value("battery_level_wh", 612.5)
    buffer.store_robot_value("battery_level_wh", 600.25)
    buffer.close()
    assert TaskBuffer(journal).robot_value("battery_level_wh") == 600.25


HOUSEHOLD_PLACES = ("charging_place", "alley", "living_room", "welcome", "dining_room", "office",
                    "bedroom")  # maps/household.graph.yaml, index = node id


def test_start_time_in_the_future_beyond_the_tolerance_is_refused(journal):
    buffer = TaskBuffer(journal)  # tolerance 5 s
    assert buffer.config.future_tolerance_s == 5.0
    assert buffer.submit(make_instruction(1, 0, start_time=105.0), now=100.0).state == PENDING
    with pytest.raises(TaskBufferError, match=r"instruction 2: start_time 105\.500 s is 5\.500 s "
                                              r"in the future \(received at 100\.000 s; "
                                              r"tolerance 5 s\)"):
        buffer.submit(make_instruction(2, 0, start_time=105.5), now=100.0)
    # issue 35: far in the future, the reward would never decay
    results = buffer.submit_many([make_instruction(3, 0, start_time=4.0e9),
                                  make_instruction(4, 0, start_time=99.0)], now=100.0)
    assert results[0][0] is None and "instruction 3: start_time 4000000000.000 s is " \
        "3999999900.000 s in the future" in results[0][1]
    assert results[1][0].state == PENDING and results[1][1] == ""
    assert [r.instruction.id for r in buffer.records()] == [1, 4]


def test_destination_name_of_another_node_is_refused(journal):
    buffer = TaskBuffer(journal, BufferConfig(node_count=7, place_names=HOUSEHOLD_PLACES))
    buffer.submit(make_instruction(1, 5, destination_name="office"), now=0.0)
    buffer.submit(make_instruction(2, 5), now=0.0)  # no name: nothing to contradict
    with pytest.raises(TaskBufferError, match="instruction 3: destination_name 'bedroom' names "
                                              "node 6, not destination node 5"):
        buffer.submit(make_instruction(3, 5, destination_name="bedroom"), now=0.0)
    with pytest.raises(TaskBufferError, match="instruction 4: destination_name 'kitchen' names "
                                              "no node of the graph, not destination node 5"):
        buffer.submit(make_instruction(4, 5, destination_name="kitchen"), now=0.0)
    assert [r.instruction.id for r in buffer.records()] == [1, 2]


def test_a_function_that_is_no_robot_function_is_refused_naming_the_known_ones(journal):
    buffer = TaskBuffer(journal, BufferConfig(functions=((1, "chat"), (3, "check_status"))))
    buffer.submit(make_instruction(1, 2, function=3), now=0.0)
    with pytest.raises(TaskBufferError, match=r"^instruction 2: function 99 is no robot function "
                                              r"\(known: 1 chat, 3 check_status\)$"):
        buffer.submit(make_instruction(2, 2, function=99), now=0.0)
    assert [r.instruction.id for r in buffer.records()] == [1]
    TaskBuffer(":memory:").submit(make_instruction(1, 2, function=99), now=0.0)  # no check


def test_successor_whose_predecessor_never_arrives_fails_naming_it(journal):
    buffer = TaskBuffer(journal)  # waits 300 s
    buffer.submit(make_instruction(4, 1, previous_id=99), now=10.0)
    buffer.submit(make_instruction(5, 1, previous_id=4), now=20.0)
    buffer.submit(make_instruction(7, 1, previous_id=6), now=10.0)
    buffer.submit(make_instruction(6, 2), now=200.0)  # 7's predecessor arrives in time
    assert buffer.fail_missing_predecessors(now=309.9) == []
    failed = buffer.fail_missing_predecessors(now=310.0)
    assert [r.instruction.id for r in failed] == [4]
    assert failed[0].state == FAILED and failed[0].completion_time == 310.0
    assert failed[0].reason == "predecessor 99 never arrived (300 s after instruction 4)"
    assert buffer.get(5).state == FAILED and buffer.get(5).reason == "predecessor 4 failed"
    assert buffer.get(7).state == PENDING and buffer.fail_missing_predecessors(now=1e4) == []


def test_wait_for_a_missing_predecessor_survives_a_restart(journal):
    TaskBuffer(journal, BufferConfig(predecessor_wait_s=60.0)).submit(
        make_instruction(2, 0, previous_id=1), now=0.0)
    again = TaskBuffer(journal, BufferConfig(predecessor_wait_s=60.0))
    assert again.fail_missing_predecessors(now=59.0) == []
    assert again.fail_missing_predecessors(now=60.0)[0].reason == \
        "predecessor 1 never arrived (60 s after instruction 2)"


def brute_force_snapshot(buffer, recent):
    """What `snapshot` must hold, from every record: the open ones and the `recent` most
    recently finished ones, by arrival."""
    records = buffer.records()
    finished = sorted((r for r in records if not r.is_open),
                      key=lambda r: (r.completion_time, r.seq))
    kept = {r.instruction.id for r in records if r.is_open}
    kept |= {r.instruction.id for r in finished[len(finished) - recent:]}
    return [r.instruction.id for r in records if r.instruction.id in kept]


def test_snapshot_holds_the_open_and_the_recently_finished_and_counts_every_state(journal):
    buffer = TaskBuffer(journal, BufferConfig(recent_finished=3))
    for k in range(1, 11):
        buffer.submit(make_instruction(k, 0, start_time=0.0), now=float(k))
    buffer.submit(make_instruction(11, 0, previous_id=10), now=11.0)
    # finished out of arrival order: 9, 2, 5, 1, 7; 10 cancelled, its successor 11 fails
    for k, now in ((9, 20.0), (2, 21.0), (5, 22.0), (1, 23.0), (7, 24.0)):
        buffer.start(k, now=now)
        buffer.finish(k, now=now + 0.5)
    buffer.cancel(10, now=30.0)
    buffer.start(3, now=31.0)
    snapshot = [r.instruction.id for r in buffer.snapshot()]
    assert snapshot == [3, 4, 6, 7, 8, 10, 11]   # open 3 4 6 8; the last finished 7 10 11
    assert snapshot == brute_force_snapshot(buffer, 3)
    assert buffer.counts() == (3, 1, 5, 1, 1)    # pending active done failed cancelled
    assert buffer.active_id() == 3
    assert buffer.total_reward() == pytest.approx(sum(r.reward_earned for r in buffer.records()))
    buffer.close()
    again = TaskBuffer(journal, BufferConfig(recent_finished=3))   # rebuilt from the journal
    assert [r.instruction.id for r in again.snapshot()] == snapshot
    assert again.counts() == (4, 0, 5, 1, 1) and again.active_id() == 0   # 3 back to pending


def test_next_id_follows_every_id_and_predecessor_ever_journalled(journal):
    buffer = TaskBuffer(journal)
    assert buffer.next_id() == 1
    buffer.submit(make_instruction(4, 0), now=0.0)
    buffer.submit(make_instruction(2, 0, previous_id=9), now=0.0)   # 9 has not arrived yet
    assert buffer.next_id() == 10 and buffer.next_id(previous_id=12) == 13
    buffer.start(4, now=1.0)
    buffer.finish(4, now=2.0)
    buffer.close()
    again = TaskBuffer(journal)       # read from the journal: a restart reuses no id
    assert again.next_id() == 10
    again.submit(make_instruction(again.next_id(), 0), now=3.0)
    assert again.next_id() == 11


def test_a_journal_row_that_is_no_valid_instruction_is_quarantined_not_run(journal):
    buffer = TaskBuffer(journal)
    buffer.submit(make_instruction(1, 1), 0.0)
    buffer.submit(make_instruction(2, 2), 0.0)
    buffer.start(2, 1.0)
    buffer.close()
    with sqlite3.connect(journal) as db:  # the poison pill, as an older version wrote it
        db.execute("UPDATE instructions SET gamma = ?, beta = 1e-300 WHERE id = 2", (math.inf,))
    reopened = TaskBuffer(journal)
    reason = ("quarantined: journal row 2 is no valid instruction: instruction 2: gamma must be "
              "a finite number; got gamma = inf")
    assert reopened.quarantined == [(2, reason)]
    assert [r.instruction.id for r in reopened.open_records()] == [1]
    assert reopened.next_id() == 3  # its id stays used
    reopened.close()
    with sqlite3.connect(journal) as db:
        state, why = db.execute("SELECT state, reason FROM instructions WHERE id = 2").fetchone()
    assert (state, why) == (FAILED, reason)
    again = TaskBuffer(journal)  # never re-run: still left out, nothing open but instruction 1
    assert [r.instruction.id for r in again.open_records()] == [1]
    again.close()


WRITER = """
import resource, sys
from task_planner.task_buffer import TaskBuffer
from task_planner.instruction import Instruction
limit = int(sys.argv[2])
buffer = TaskBuffer(sys.argv[1])
resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))  # a disk that fills up
accepted = refused = 0
reason = ""
for i in range(1, 3001):
    record, error = buffer.submit_many([Instruction(id=i, gamma=1.0, beta=0.9, destination=1,
                                                    text="x" * 400)], 0.0)[0]
    if record is None:
        refused += 1
        reason = reason or error
    else:
        accepted += 1
print(accepted, refused, len(buffer.records()), sum(1 for r in buffer.open_records()))
print(reason)
"""


def test_a_full_disk_refuses_with_the_reason_and_loses_nothing_accepted(journal):
    run = subprocess.run([sys.executable, "-c", WRITER, str(journal), str(256 * 1024)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    counts, reason = run.stdout.splitlines()[:2]
    accepted, refused, in_memory, open_count = map(int, counts.split())
    assert 0 < accepted < 3000 and accepted + refused == 3000
    assert in_memory == open_count == accepted  # memory holds only what the journal holds
    assert reason.startswith(f"instruction {accepted + 1}: not journalled, so not accepted: "
                             f"writing {journal} failed: ")
    reopened = TaskBuffer(journal)
    assert len(reopened.records()) == accepted  # every accepted one survived
    reopened.close()
