"""compare_semnav's command line (compare_semnav): the McNemar table of two results of one plan, and
the errors for files that are not results or not of the same plan."""
import json

import pytest

from semnav_learning.tools.compare_semnav import main


def write_result(path, successes, labels=(1, 1, 2, 2)):
    """An eval_semnav --json result with one episode per label."""
    episodes = [{"spec": {"floor": "f", "start": [float(i), 0.0, 0.0], "labels": [label],
                          "sentence": "s", "held_out": False}, "success": success}
                for i, (label, success) in enumerate(zip(labels, successes))]
    path.write_text(json.dumps({"episodes": episodes}))
    return str(path)


def test_the_table_counts_each_side_and_the_discordant_episodes(tmp_path, capsys):
    bc = write_result(tmp_path / "bc.json", [True, True, True, False])
    dagger = write_result(tmp_path / "dagger.json", [True, False, False, False])
    assert main([bc, dagger]) == 0
    # class 1: 2 vs 1, one only bc (p = 2 * 1/2 = 1); class 2: 1 vs 0 (p 1); all: 3 vs 1 with
    # two discordant episodes both bc's, p = 2 * (1/2)^2 = 0.5
    assert capsys.readouterr().out.splitlines() == [
        "| class | bc | dagger | only bc | only dagger | p |",
        "|---|---:|---:|---:|---:|---:|",
        "| 1 | 2 | 1 | 1 | 0 | 1 |",
        "| 2 | 1 | 0 | 1 | 0 | 1 |",
        "| all | 3 | 1 | 2 | 0 | 0.5 |"]


def test_results_of_different_plans_or_no_result_are_refused(tmp_path):
    first = write_result(tmp_path / "a.json", [True] * 4)
    other = write_result(tmp_path / "b.json", [True] * 4, labels=(1, 2, 2, 2))
    with pytest.raises(SystemExit, match=r"compare_semnav: .*a.json vs .*b.json: episode 1 "):
        main([first, other])
    (tmp_path / "table.md").write_text("| not json |")
    with pytest.raises(SystemExit, match=r"table.md: not an eval_semnav --json result "
                                         r"\(JSONDecodeError"):
        main([first, str(tmp_path / "table.md")])
    with pytest.raises(SystemExit, match=r"missing.json: not an eval_semnav --json result "
                                         r"\(FileNotFoundError"):
        main([first, str(tmp_path / "missing.json")])
