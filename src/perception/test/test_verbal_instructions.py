"""Utterances to Table 4-1 instructions: priorities of Table 5-5, destinations, chains (§4.2.1)."""
import pytest
from verbal_test_support import TABLE_5_5, WS

from perception.id_counter import IdCounter
from perception.requests import RejectedUtterance
from perception.verbal_instructions import (DictPeopleDirectory, InstructionBuilder, Person,
                                            priority_level)
from task_planner.instruction import HUMAN
from task_planner.reward import Priority
from task_planner.robot_functions import function_for, load_robot_functions

ALEX, ALICE, BOB, DAVID = "192.168.1.110", "192.168.1.101", "192.168.1.102", "192.168.1.104"
LIVING_ROOM, WELCOME, DINING_ROOM, OFFICE, BEDROOM = 2, 3, 4, 5, 6  # maps/household.graph.yaml


def test_seed_example_chat_with_me_i_feel_bad(pipeline):
    """§3.3 / Fig. 3-15: Alex's "Chat with me, I feel bad." -> chat, negative priority, at Alex."""
    interpretation, result = pipeline.process("Chat with me, I feel bad.", ALEX, 12.5)
    assert interpretation.sentiment == "negative" and interpretation.level == "negative"
    (chat,) = result.instructions
    assert (chat.function, chat.gamma, chat.beta) == (1, 5, 0.96)
    assert (chat.destination, chat.destination_name) == (LIVING_ROOM, "living_room")
    assert (chat.source, chat.target, chat.status) == ("Alex", "Alex", 2)
    assert (chat.type, chat.start_time, chat.duration, chat.previous_id) == (HUMAN, 12.5, 60, 0)
    assert chat.text == "Chat with me, I feel bad."
    assert result.notes == ()


def test_seed_chain_check_bob_status(pipeline):
    """§4.2.1: the caregiver's "check Bob status" -> check Bob, then report to the caregiver."""
    _, result = pipeline.process("check Bob status", ALICE, 0.0)
    check, report = result.instructions
    assert (check.function, check.target, check.destination, check.previous_id) == \
        (3, "Bob", BEDROOM, 0)
    assert (report.function, report.target, report.destination, report.previous_id) == \
        (7, "Alice", OFFICE, check.id)
    assert {check.source, report.source} == {"Alice"}
    assert (check.gamma, check.beta) == (report.gamma, report.beta) == (3, 0.94)  # neutral
    assert (check.text, report.text) == ("check Bob status", "[about Bob] check Bob status")


def test_report_after_a_check_names_the_person_checked_on(pipeline):
    """Issue 32: David's "Please check on Alice" ended in "David, here is my report on David."."""
    _, result = pipeline.process("Please check on Alice", DAVID, 0.0)
    check, report = result.instructions
    assert (check.target, report.source, report.target) == ("Alice", "David", "David")
    functions = load_robot_functions(WS / "config" / "robot_functions.yaml")
    assert function_for(functions, check).speech(check, "office") == \
        "Alice, how are you feeling right now?"
    assert function_for(functions, report).speech(report, "dining_room") == \
        "David, here is my report on Alice."


def test_checking_oneself_is_not_chained(pipeline):
    _, result = pipeline.process("Check my temperature, I think I have a fever.", BOB, 0.0)
    (check,) = result.instructions
    assert (check.function, check.target, check.gamma, check.beta, check.status) == \
        (3, "Bob", 8, 0.98, 1)


def test_physical_terms_outrank_vader_neutral(pipeline):
    interpretation, result = pipeline.process("I have a headache and fever", BOB, 0.0)
    assert interpretation.compound == 0.0 and interpretation.sentiment == "neutral"
    (help_,) = result.instructions
    assert (help_.function, help_.gamma, help_.beta, help_.status, help_.destination) == \
        (4, 8, 0.98, 1, BEDROOM)


def test_negated_physical_term_is_not_a_physical_request(pipeline):
    """Issue 32: YAML read the negation `no` as False, so this became priority physical (8)."""
    with pytest.raises(RejectedUtterance, match="no robot function requested"):
        pipeline.process("I have no headache", BOB, 0.0)
    interpretation, result = pipeline.process("I have no headache, chat with me", BOB, 0.0)
    # VADER reads "no headache" as negative: the negative level of Table 5-5, not physical (8).
    assert interpretation.physical_terms == () and interpretation.level == "negative"
    (chat,) = result.instructions
    assert (chat.function, chat.status, chat.gamma, chat.beta) == (1, 2, 5, 0.96)


def test_positive_request_gets_positive_priority(pipeline):
    _, result = pipeline.process("I love piano music, please play some.", DAVID, 0.0)
    (music,) = result.instructions
    assert (music.function, music.gamma, music.beta, music.destination) == \
        (6, 2, 0.92, DINING_ROOM)


def test_report_to_caregiver_goes_to_the_caregiver(pipeline):
    _, result = pipeline.process("Tell the nurse I fell in the kitchen.", ALEX, 0.0)
    (report,) = result.instructions
    assert (report.function, report.source, report.target, report.destination, report.gamma) == \
        (7, "Alex", "Alice", OFFICE, 8)


def test_unknown_ip_is_served_anonymously_at_the_default_place(pipeline):
    _, result = pipeline.process("Chat with me", "192.168.1.77", 0.0)
    (chat,) = result.instructions
    assert (chat.source, chat.target, chat.destination) == \
        ("anonymous@192.168.1.77", "anonymous@192.168.1.77", WELCOME)
    assert any("unknown phone IP '192.168.1.77'" in note for note in result.notes)


def test_unknown_ip_chain_reports_at_the_default_place(pipeline):
    _, result = pipeline.process("Check Bob status", "", 0.0)
    check, report = result.instructions
    assert (check.destination, report.destination, report.target) == \
        (BEDROOM, WELCOME, "anonymous")


@pytest.mark.parametrize("location, why", [("", "location unknown"),
                                           ("garage", "unknown place 'garage'")])
def test_person_without_known_place_is_served_at_default(keywords, analyser, place_ids,
                                                         location, why):
    from perception.verbal_instructions import VerbalPipeline
    people = DictPeopleDirectory([Person("Eve", "10.0.0.20", location)])
    builder = InstructionBuilder(keywords, TABLE_5_5, place_ids, people)
    _, result = VerbalPipeline(keywords, analyser, builder, people).process(
        "Remind me to eat", "10.0.0.20", 0.0)
    assert result.instructions[0].destination == WELCOME
    assert any(why in note for note in result.notes)


def test_ids_are_unique_and_consecutive(pipeline):
    ids = [i.id for text in ("check Bob status", "Chat with me", "Play a song")
           for i in pipeline.process(text, ALEX, 0.0)[1].instructions]
    assert ids == [1, 2, 3, 4]


def test_restarted_node_does_not_reuse_ids(keywords, analyser, directory, place_ids, tmp_path):
    """A node started again with the same ~first_id goes on after its last id (issue 12)."""
    from perception.verbal_instructions import VerbalPipeline

    def start_node():
        ids = IdCounter(first_id=1, path=tmp_path / "perception_verbal_last_id")
        builder = InstructionBuilder(keywords, TABLE_5_5, place_ids, directory, ids=ids)
        return VerbalPipeline(keywords, analyser, builder, directory)

    before = [i.id for i in start_node().process("check Bob status", ALEX, 0.0)[1].instructions]
    after = [i.id for i in start_node().process("Chat with me", ALEX, 1.0)[1].instructions]
    assert (before, after) == ([1, 2], [3])


@pytest.mark.parametrize("text, reason", [
    ("", "empty text"),
    ("Help me " * 1250, "10000 characters"),
    ("Ich habe Kopfschmerzen und Fieber.", "does not look English"),
    ("Check Zed status.", "unknown target name 'Zed'"),
    ("The weather is nice today.", "no robot function requested"),
])
def test_bad_input_yields_no_instruction(pipeline, text, reason):
    with pytest.raises(RejectedUtterance, match=reason):
        pipeline.process(text, ALEX, 0.0)
    # Nothing was built: the next accepted request still gets the first id.
    assert pipeline.process("Chat with me", ALEX, 0.0)[1].instructions[0].id == 1


@pytest.mark.parametrize("terms, sentiment, level", [
    (("fever",), "positive", "physical"), ((), "negative", "negative"),
    ((), "neutral", "neutral"), ((), "positive", "positive")])
def test_priority_order_physical_first(terms, sentiment, level):
    assert priority_level(terms, sentiment) == level


def test_builder_refuses_incomplete_priority_table(keywords, place_ids, directory):
    partial = {"physical": Priority("physical", 8, 0.98)}
    with pytest.raises(ValueError, match="lacks levels"):
        InstructionBuilder(keywords, partial, place_ids, directory)


def test_builder_refuses_default_place_outside_graph(keywords, directory):
    with pytest.raises(ValueError, match="default_place 'welcome'"):
        InstructionBuilder(keywords, TABLE_5_5, {"kitchen": 0}, directory)
