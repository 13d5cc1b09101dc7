"""Paths and numbers shared by the verbal perception tests (imported by conftest and tests)."""
from pathlib import Path

from perception.verbal_instructions import Priority

WS = Path(__file__).resolve().parents[3]
KEYWORDS = WS / "config" / "keywords.yaml"
GRAPH = WS / "maps" / "household.graph.yaml"
CORPUS = WS / "src" / "perception" / "data" / "verbal_corpus.yaml"

# Thesis 000 Table 5-5 (verbal levels; self-generated 1/0.90 is never produced from speech).
TABLE_5_5 = {"physical": Priority(8, 0.98), "negative": Priority(5, 0.96),
             "neutral": Priority(3, 0.94), "positive": Priority(2, 0.92)}
