"""The labelled corpus: coverage, and 100% on its unambiguous cases (issue 8 acceptance)."""
from perception.request_corpus import case_passes, outcome_of
from perception.requests import PRIORITY_LEVELS


def test_corpus_covers_every_function_level_chain_and_refusal(corpus, keywords):
    _, cases = corpus
    accepted = [c for c in cases if not c.rejected]
    assert len(cases) >= 40
    assert {c.function for c in accepted} == set(keywords.functions)
    assert {c.level for c in accepted} == set(PRIORITY_LEVELS)
    assert sum(1 for c in accepted if c.chain) >= 3
    assert sum(1 for c in cases if c.rejected) >= 5


def test_every_unambiguous_case_is_understood(corpus, pipeline):
    _, cases = corpus
    failures = []
    for case in (c for c in cases if not c.ambiguous):
        outcome = outcome_of(pipeline, case.text, case.ip)
        if not case_passes(case, outcome):
            failures.append(f"{case.text!r}: expected {case}, got {outcome}")
    assert failures == []


def test_ambiguous_cases_are_scored_not_hidden(corpus, pipeline):
    # The ambiguous cases count in the reported accuracy; at least one of them is read wrongly by
    # the keyword method, which is why they are marked (see docs/perception/verbal.md).
    _, cases = corpus
    ambiguous = [c for c in cases if c.ambiguous]
    assert ambiguous and all(c.why for c in ambiguous)
    passed = [case_passes(c, outcome_of(pipeline, c.text, c.ip)) for c in ambiguous]
    assert not all(passed)
