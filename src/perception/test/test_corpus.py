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


def test_ambiguous_marking_is_rare_and_explained(corpus):
    # Marking a case ambiguous takes it out of the 100% requirement, so it must stay the
    # exception (at most a tenth of the corpus) and say why; docs/perception/verbal.md reports
    # accuracy over all cases, ambiguous ones included.
    _, cases = corpus
    ambiguous = [c for c in cases if c.ambiguous]
    assert len(ambiguous) <= len(cases) // 10
    assert all(c.why for c in ambiguous)
