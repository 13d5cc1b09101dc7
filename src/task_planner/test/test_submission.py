"""Chains handed to the task buffer, which allocates the ids (task_planner.submission)."""
import pytest
from planner_factories import make_instruction

from task_planner.submission import submit_chain
from task_planner.task_buffer import TaskBuffer


def buffer_service(buffer, now=0.0):
    """What /task_planner/submit does with a request of id 0 (ros_executor._submit)."""
    def submit(instruction, previous_id):
        allocated = make_instruction(buffer.next_id(previous_id), instruction.destination,
                                     previous_id=previous_id)
        buffer.submit(allocated, now)
        return True, allocated.id, ""
    return submit


def test_a_chain_gets_the_next_ids_of_the_journal_and_links_them(tmp_path):
    buffer = TaskBuffer(tmp_path / "buffer.sqlite")
    for k in (3, 8):   # ids journalled earlier, e.g. by another sender or an earlier run
        buffer.submit(make_instruction(k, 0), now=0.0)
    chain = [make_instruction(1, 2), make_instruction(2, 3, previous_id=1),
             make_instruction(3, 4, previous_id=2)]
    submission = submit_chain(chain, buffer_service(buffer))
    assert submission.complete and submission.not_sent == 0
    assert [(i.id, i.previous_id, i.destination) for i in submission.accepted] == \
        [(9, 0, 2), (10, 9, 3), (11, 10, 4)]
    assert [(r.instruction.id, r.instruction.previous_id) for r in buffer.records()][2:] == \
        [(9, 0), (10, 9), (11, 10)]


def test_the_chain_stops_at_the_first_refusal():
    answers = iter([(True, 5, ""), (False, 0, "instruction 6: destination node 9 is not in the "
                                              "graph (nodes 0..6)")])
    sent = []

    def submit(instruction, previous_id):
        sent.append(instruction.id)
        return next(answers)

    chain = [make_instruction(1, 2), make_instruction(2, 9, previous_id=1),
             make_instruction(3, 4, previous_id=2)]
    submission = submit_chain(chain, submit)
    assert sent == [1, 2]               # the third would wait for a predecessor never journalled
    assert [i.id for i in submission.accepted] == [5]
    assert (submission.complete, submission.not_sent) == (False, 2)
    assert submission.refusal.startswith("instruction 6: destination node 9")
    empty = submit_chain(chain[:1], lambda i, p: (False, 0, ""))
    assert empty.refusal == "refused without a reason"


def test_a_predecessor_outside_the_chain_is_an_error():
    with pytest.raises(ValueError, match="previous_id 7 is no earlier instruction of the chain"):
        submit_chain([make_instruction(2, 0, previous_id=7)], lambda i, p: (True, 1, ""))
