"""Paths and numbers shared by the verbal perception tests (imported by conftest and tests)."""
from pathlib import Path

import rospkg

from task_planner.reward import load_priorities
from tamp_resources import resource

WS = resource()
KEYWORDS = WS / "config" / "keywords.yaml"
GRAPH = WS / "maps" / "household.graph.yaml"
CORPUS = Path(rospkg.RosPack().get_path("perception")) / "data" / "verbal_corpus.yaml"
PRIORITIES = WS / "config" / "priorities.yaml"

# The deployment table; the tests assert the instructions' gamma and beta against thesis 000
# Table 5-5's own numbers (physical 8/0.98, negative 5/0.96, neutral 3/0.94, positive 2/0.92).
TABLE_5_5 = load_priorities(PRIORITIES)
