"""Instruction ids survive a restart of the node that hands them out."""
import pytest

from perception.id_counter import IdCounter


def test_restarted_counter_continues_after_the_last_id_handed_out(tmp_path):
    path = tmp_path / "last_id"
    first = IdCounter(first_id=1, path=path)
    assert [first.take() for _ in range(3)] == [1, 2, 3]
    assert path.read_text() == "3\n"
    restarted = IdCounter(first_id=1, path=path)   # the node started again, same ~first_id
    assert restarted.take() == 4


def test_first_id_above_the_recorded_one_wins(tmp_path):
    path = tmp_path / "last_id"
    path.write_text("41\n")
    assert IdCounter(first_id=100, path=path).take() == 100
    assert IdCounter(first_id=10, path=path).take() == 101


def test_in_memory_counter_and_bad_state_file(tmp_path):
    counter = IdCounter(first_id=7)
    assert (counter.take(), counter.take(), counter.next_id) == (7, 8, 9)
    bad = tmp_path / "last_id"
    bad.write_text("seven")
    with pytest.raises(ValueError, match="last_id: expected the last instruction id"):
        IdCounter(path=bad)
    with pytest.raises(ValueError, match="first_id must be >= 1"):
        IdCounter(first_id=0)
