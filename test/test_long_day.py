"""The long day as a user runs it (`scripts/run_scenario config/scenarios/household_long_day.yaml`,
10x): human_db starts without a shirt, and the run's human_db shows every resident's colours
written by the robot's own meetings and Carol's shirt changed after she put on her pyjamas
(thesis 000 §3.2.3: Initialization, and Recall updated "once the human changes his/her clothes").

Needs the workspace environment (source scripts/env.sh); about 12 minutes on 2 cores.
"""
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from human_db.colour import mean_shirt_distance
from tamp_bringup.scenario import load_scenario, residents

ROOT = Path(__file__).resolve().parent.parent
SCENARIO = ROOT / "config" / "scenarios" / "household_long_day.yaml"
HUMANS_DB = "social_household_humans.sqlite"   # in the run folder (social_household.launch)
RUN_LIMIT_S = 2400   # [s] wall clock: 6,700 simulated seconds at 10x take about 12 minutes


def shirt_rows(db_path):
    """(name, time [s], (3, 3) colours, source) of every shirt row, in time order."""
    with sqlite3.connect(f"file:{db_path}?mode=ro", uri=True) as db:
        rows = db.execute("SELECT h.name, s.time, s.r1, s.g1, s.b1, s.r2, s.g2, s.b2, s.r5, "
                          "s.g5, s.b5, s.source FROM shirts s JOIN humans h "
                          "ON h.id = s.human_id ORDER BY s.time").fetchall()
    return [(r[0], r[1], np.array(r[2:11]).reshape(3, 3), r[11]) for r in rows]


@pytest.mark.long      # the two-hour day at 10x, about 12 minutes: `make test-long`
def test_the_long_day_registers_everyone_and_carols_change_of_clothes(tmp_path):
    scenario = load_scenario(SCENARIO)
    changes = [m for m in scenario.moves if m.clothes]
    assert changes, "the long day's world changes nobody's clothes"
    run = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_scenario"), str(SCENARIO),
                          "--speed", "10", "--out-dir", str(tmp_path)],
                         capture_output=True, text=True, timeout=RUN_LIMIT_S)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    rows = shirt_rows(tmp_path / "run" / HUMANS_DB)
    # every resident's colours came from a meeting during the run (none were imported)
    assert {source for _, _, _, source in rows} <= {"register", "recall"}, rows
    met = {name for name, _, _, source in rows if source in ("register", "recall")}
    assert set(residents(scenario)) <= met, f"not registered by the robot: {rows}"
    for move in changes:
        after = [(time, colours) for name, time, colours, source in rows
                 if name == move.person and time > move.time_s and source == "recall"]
        assert after, f"{move.person}'s shirt after {move.time_s:.0f} s was never registered"
        before = [colours for name, time, colours, _ in rows
                  if name == move.person and time <= move.time_s]
        assert before, f"{move.person}'s first shirt was not kept"
        # the new row is the new clothes: nearer the shirt put on than the one taken off
        new = np.array(move.shirt)
        old = np.array(scenario.shirts.get(move.person, before[-1]))
        assert mean_shirt_distance(after[0][1], new) < mean_shirt_distance(after[0][1], old)
