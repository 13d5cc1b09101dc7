"""scripts/eval_activity's library: the confusion figures, arguments, a tiny split run."""
from collections import Counter, defaultdict

import pytest

from tamp_bringup.tools import eval_activity as evaluation
from tamp_bringup.sim_activity_set import SCENES

LABELS = [s.label for s in SCENES]


def test_confusion_counts_accuracy_and_the_missed_column():
    counts = defaultdict(Counter, {label: Counter({label: 2}) for label in LABELS})
    counts["eat"] = Counter({"eat": 1, "drink": 2, "missed": 1})
    labels, predicted, matrix, accuracy, total = evaluation.confusion(counts)
    assert labels == LABELS and predicted == LABELS + ["missed"]
    assert accuracy["eat"] == 0.25 and accuracy["drink"] == 1.0
    assert matrix[0].tolist() == [1, 2] + [0] * (len(LABELS) - 2) + [1]
    assert total == pytest.approx((2 * (len(LABELS) - 1) + 1) / (2 * (len(LABELS) - 1) + 4))


@pytest.mark.parametrize("argv, message", [
    (["--miss", "1.5"], "--miss: must be a probability in [0, 1]; got '1.5'"),
    (["--repeats", "0"], "--repeats must be at least 1"),
    (["--keypoint-noise", "-1"], "--keypoint-noise must not be negative"),
    (["--split", "test"], "--split: invalid choice: 'test'"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit):
        evaluation.parse_args(argv)
    assert message in capsys.readouterr().err


def test_a_tiny_split_writes_the_table_and_the_matrix(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(evaluation.SPLITS, "held-out", ((2.0,), (0.0,), (0.0,), 100))
    assert evaluation.main(["--split", "held-out", "--repeats", "1", "--miss", "0",
                            "--out", str(tmp_path), "--note", "A remark."]) == 0
    table = (tmp_path / "activity_accuracy_held_out.md").read_text().splitlines()
    assert table[0] == "# Activity recognition on simulator-labelled frames (held-out split)"
    assert table[2] == ("Written by `scripts/eval_activity --split held-out --miss 0.0 "
                        "--keypoint-noise 2.0 --repeats 1` (scripts/eval_activity). A remark.")
    rows = [line for line in table if line.startswith("| ") and not line.startswith("| class")]
    assert [row.split(" | ")[0][2:] for row in rows] == LABELS
    assert all(row.split(" | ")[1] == "1" for row in rows)     # one frame per class
    assert (tmp_path / "activity_confusion_held_out.png").read_bytes()[:4] == b"\x89PNG"
    printed = capsys.readouterr().out.splitlines()
    assert printed[-1].startswith("overall    ") and "(held-out split)" in printed[-1]
