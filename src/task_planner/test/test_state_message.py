"""/task_planner/state stays bounded on a long-running buffer; get_buffer holds everything."""
import genpy
import pytest

from task_planner.tools.bench_task_buffer import long_running_buffer, serialised_size
from task_planner.conversions import buffer_to_msg
from task_planner.task_buffer import ACTIVE, PENDING

RECORDS, OPEN, RECENT = 20000, 10, 50
MAX_BYTES = 64 * 1024   # issue 35: under 64 KB at 20,000 records


@pytest.fixture(scope="module")
def buffer():
    return long_running_buffer(RECORDS, OPEN, recent_finished=RECENT)


def test_state_carries_every_open_instruction_and_a_bounded_window(buffer):
    msg = buffer_to_msg(buffer, genpy.Time(5))
    ids = [s.instruction.id for s in msg.instructions]
    records = buffer.records()
    open_ids = [r.instruction.id for r in records if r.is_open]
    assert len(open_ids) == OPEN and set(open_ids) <= set(ids)
    finished = sorted((r for r in records if not r.is_open),
                      key=lambda r: (r.completion_time, r.seq))
    assert sorted(set(ids) - set(open_ids)) == sorted(r.instruction.id for r in finished[-RECENT:])
    assert ids == sorted(ids)                  # oldest first (here ids arrived in order)
    assert len(ids) == OPEN + RECENT
    states = {s.instruction.id: s.state for s in msg.instructions}
    assert [states[i] for i in open_ids] == [ACTIVE] + [PENDING] * (OPEN - 1)
    assert msg.active_id == open_ids[0] and not msg.complete
    expected = [sum(r.state == k for r in records) for k in range(5)]
    assert list(msg.counts) == expected == [9, 1, 18791, 800, 399]
    assert msg.total_reward == pytest.approx(sum(r.reward_earned for r in records))
    assert msg.header.stamp == genpy.Time(5)
    assert serialised_size(msg) < MAX_BYTES


def test_get_buffer_answer_holds_every_record(buffer):
    msg = buffer_to_msg(buffer, genpy.Time(5), complete=True)
    assert msg.complete and len(msg.instructions) == RECORDS
    assert [s.instruction.id for s in msg.instructions] == list(range(1, RECORDS + 1))
    assert serialised_size(msg) > MAX_BYTES   # why the published state must not carry it
