
import numpy as np
import pytest

from task_planner.reward import PriorityError, decayed_reward, load_priorities
from tamp_resources import resource

CONFIG = resource("config") / "priorities.yaml"


def test_eq_4_2_on_hand_numbers():
    # 8 * 0.98^10 = 8 * 0.8170728068875467; 3 * 0.94^0 = 3; 1 * 0.9^2.5 = 0.7684334714209162
    assert decayed_reward(8, 0.98, 10) == pytest.approx(6.536582455100374)
    assert decayed_reward(3, 0.94, 0) == pytest.approx(3.0)
    assert decayed_reward(1, 0.9, 2.5) == pytest.approx(0.7684334714209162)
    both = decayed_reward(np.array([8.0, 1.0]), np.array([0.98, 0.9]), np.array([10, 2.5]))
    assert both == pytest.approx([6.536582455100374, 0.7684334714209162])


def test_priority_table_is_table_5_5():
    table = load_priorities(CONFIG)
    assert [(p.name, p.gamma, p.beta) for p in table.values()] == [
        ("physical", 8.0, 0.98), ("negative", 5.0, 0.96), ("neutral", 3.0, 0.94),
        ("positive", 2.0, 0.92), ("self_generated", 1.0, 0.90)]


@pytest.mark.parametrize("text, message", [
    ("priorities: {x: {gamma: 0, beta: 0.9}}", "priority 'x'"),
    ("priorities: {x: {gamma: 2, beta: 1.0}}", "0 < beta < 1"),
    ("priorities: {x: {gamma: 2}}", "numeric gamma and beta"),
    ("other: 1", "non-empty mapping"),
])
def test_bad_priority_file_is_named(tmp_path, text, message):
    path = tmp_path / "p.yaml"
    path.write_text(text)
    with pytest.raises(PriorityError, match=message):
        load_priorities(path)
