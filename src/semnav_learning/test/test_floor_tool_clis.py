"""The floor tools' command lines (semnav_floor_census, plot_semnav_oracle) on the L floor: the
census rows and their total, and the oracle and structure pictures with what they print."""
import re

import pytest

from semnav_learning.tools import semnav_floor_census, plot_semnav_oracle
from semnav_l_floor import write_l_floor


@pytest.fixture(scope="module")
def workspace(tmp_path_factory):
    """A workspace whose maps/ holds the L floor."""
    root = tmp_path_factory.mktemp("ws")
    (root / "maps").mkdir()
    write_l_floor(root / "maps")
    return root


@pytest.fixture
def l_floor(workspace, monkeypatch):
    """The L floor's map YAML, the tools run in `workspace` (TAMP_WS)."""
    monkeypatch.setenv("TAMP_WS", str(workspace))
    return str(workspace / "maps" / "l_floor.yaml")


def cells(line):
    """A census row -> its name and its cells ("9" or "4/2")."""
    name, *rest = line.split()
    return name, rest


def test_census_of_the_l_floor_has_no_counted_corners(l_floor, capsys):
    assert semnav_floor_census.main(argv=[l_floor, "--candidates", "30"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ["floor", *map(str, range(1, 11))]
    name, row = cells(lines[2])
    assert name == "l_floor" and len(lines) == 3            # one floor: no total row
    applicable = [int(cell.split("/")[0]) for cell in row]
    # one corner: going straight and turning round apply from every start, the second and
    # third corners (5-8) from none; the turn classes say how many of them are at the end
    assert applicable[0] > 0 and applicable[3] > 0 and applicable[4:8] == [0, 0, 0, 0]
    assert [("/" in cell) for cell in row] == [False, True, True, False, True, True, True, True,
                                              False, False]


def test_census_total_adds_the_floors(l_floor, capsys):
    semnav_floor_census.main(argv=[l_floor, l_floor, "--candidates", "20", "--seed", "3"])
    rows = [cells(line)[1] for line in capsys.readouterr().out.splitlines()[2:]]
    assert len(rows) == 3
    for first, second, total in zip(*rows):
        parts = [[int(v) for v in cell.split("/")] for cell in (first, second, total)]
        assert [a + b for a, b in zip(parts[0], parts[1])] == parts[2]


def test_oracle_pictures_of_an_annotated_start(workspace, l_floor, tmp_path, capsys):
    starts = tmp_path / "starts.yaml"
    starts.write_text(f"{l_floor}:\n  - {{start: [1.0, 1.0, 0.0]}}\n"
                      "  - {start: [9.0, 6.0, -90.0]}\n")
    out = workspace / "docs" / "oracle"
    assert plot_semnav_oracle.main(argv=["--starts", str(starts), "--out", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":")[0] for line in lines] == [
        "docs/oracle/l_floor_1.png", "docs/oracle/l_floor_2.png",
        "docs/oracle/l_floor_structure.png"]            # inside the workspace: relative
    found = [int(re.search(r": (\d+) of 10 classes", line).group(1)) for line in lines[:2]]
    assert all(2 <= n <= 6 for n in found)   # straight, round, the one corner's turns at most
    assert re.fullmatch(r".*: \d+ junction cells, [1-9]\d* dead-end cells", lines[2])
    for name in ("l_floor_1", "l_floor_2", "l_floor_structure"):
        assert (out / f"{name}.png").stat().st_size > 1000


def test_oracle_pictures_outside_the_workspace_print_their_path(l_floor, tmp_path, capsys):
    starts = tmp_path / "starts.yaml"
    starts.write_text(f"{l_floor}:\n  - {{start: [1.0, 1.0, 0.0]}}\n")
    plot_semnav_oracle.main(argv=["--starts", str(starts), "--out", str(tmp_path)])
    assert capsys.readouterr().out.startswith(f"{tmp_path / 'l_floor_1.png'}: ")
