"""Labelled sentences for verbal perception and their scoring (accuracy of function, priority
level, target and chain, or of the refusal)."""
from dataclasses import dataclass
from pathlib import Path

import yaml

from perception.requests import RejectedUtterance
from perception.verbal_instructions import Person, VerbalPipeline


@dataclass(frozen=True)
class CorpusCase:
    text: str
    ip: str                  # phone IP of the speaker
    function: str = ""       # expected robot function name ("" when rejected)
    level: str = ""          # expected priority level
    target: str = ""         # expected target of the first instruction
    chain: tuple = ()        # expected follow-up function names
    rejected: str = ""       # expected fragment of the refusal reason; "" = accepted
    ambiguous: bool = False  # a careful reader could disagree with the expectation
    why: str = ""            # why it is ambiguous


@dataclass(frozen=True)
class Outcome:
    function: str = ""   # robot function name of the first instruction
    level: str = ""      # priority level
    target: str = ""     # target of the first instruction
    chain: tuple = ()    # function names of the follow-ups
    rejected: str = ""   # refusal reason; "" = accepted


def load_corpus(path: str | Path) -> tuple[list[Person], list[CorpusCase]]:
    """(people, cases) of a corpus YAML file (see src/perception/data/verbal_corpus.yaml)."""
    data = yaml.safe_load(Path(path).read_text())
    people = [Person(name=p["name"], ip=str(p["ip"]), location=p["location"])
              for p in data["people"]]
    ip_of = {p.name: p.ip for p in people}
    cases: list[CorpusCase] = []
    for entry in data["cases"]:
        speaker_ip = str(entry["ip"]) if "ip" in entry else ip_of[entry["from"]]
        fields = {k: v for k, v in entry.items() if k not in ("from", "ip")}
        fields["chain"] = tuple(fields.get("chain", ()))
        cases.append(CorpusCase(ip=speaker_ip, **fields))
    return people, cases


def outcome_of(pipeline: VerbalPipeline, text: str, ip: str, start_time: float = 0.0) -> Outcome:
    """What the pipeline makes of one sentence, in the corpus's terms."""
    try:
        interpretation, result = pipeline.process(text, ip, start_time)
    except RejectedUtterance as error:
        return Outcome(rejected=str(error))
    names = {f.code: f.name for f in pipeline.keywords.functions.values()}
    first, follow_ups = result.instructions[0], result.instructions[1:]
    return Outcome(function=names[first.function], level=interpretation.level,
                   target=first.target, chain=tuple(names[i.function] for i in follow_ups))


def case_passes(case: CorpusCase, outcome: Outcome) -> bool:
    """True when the outcome matches every expectation of the case."""
    if case.rejected or outcome.rejected:
        return bool(case.rejected) and case.rejected in outcome.rejected
    return (outcome.function, outcome.level, outcome.target, outcome.chain) == \
        (case.function, case.level, case.target, case.chain)


def function_matches(case: CorpusCase, outcome: Outcome) -> bool:
    """True when the requested function (or the refusal) is right, whatever the priority."""
    if case.rejected or outcome.rejected:
        return bool(case.rejected) and bool(outcome.rejected)
    return outcome.function == case.function
