"""Utterances to Table 4-1 instructions: priorities of Table 5-5, destinations, chains (§4.2.1)."""
import pytest
from verbal_test_support import TABLE_5_5, WS

from perception.requests import RejectedUtterance
from perception.verbal_instructions import (PHONE_MAX_CHARS, DictPeopleDirectory,
                                            InstructionBuilder, Person, priority_level,
                                            refusal_sentence, rejection_sentence)
from task_planner.instruction import HUMAN
from task_planner.reward import Priority
from task_planner.robot_functions import function_for, load_robot_functions
from task_planner.submission import Submission, submit_chain

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


def test_ids_are_provisional_positions_in_the_chain(pipeline):
    """The task buffer allocates the ids: a request's instructions are numbered 1, 2, ... in
    chain order, the successor naming its predecessor's number."""
    chains = [[(i.id, i.previous_id) for i in pipeline.process(text, ALEX, 0.0)[1].instructions]
              for text in ("check Bob status", "Chat with me", "Play a song")]
    assert chains == [[(1, 0), (2, 1)], [(1, 0)], [(1, 0)]]


def test_a_chain_is_submitted_with_the_ids_the_task_buffer_allocates(pipeline):
    _, result = pipeline.process("check Bob status", ALEX, 0.0)
    requests = []

    def task_buffer(instruction, previous_id):   # allocates 41, 42, ...
        requests.append((instruction.function, previous_id))
        return True, 40 + len(requests), ""

    submission = submit_chain(result.instructions, task_buffer)
    assert requests == [(3, 0), (7, 41)]          # the report names the check's allocated id
    assert [(i.id, i.previous_id) for i in submission.accepted] == [(41, 0), (42, 41)]
    assert submission.complete and refusal_sentence(submission) == ""


def test_a_request_not_taken_is_said_with_the_reason(pipeline):
    _, result = pipeline.process("check Bob status", ALEX, 0.0)
    refused = submit_chain(result.instructions, lambda i, p: (False, 0, "the buffer is full"))
    assert (refused.accepted, refused.not_sent) == ((), 2)
    assert refusal_sentence(refused) == "Sorry, I cannot take your request: the buffer is full"
    answers = iter([(True, 7, ""), (False, 0, "instruction 8: destination node 9 is not in "
                                              "the graph (nodes 0..6)")])
    half = submit_chain(result.instructions, lambda i, p: next(answers))
    assert ([i.id for i in half.accepted], half.not_sent) == ([7], 1)
    assert refusal_sentence(half) == (
        "Sorry, I could only take part of your request (as request 7): instruction 8: "
        "destination node 9 is not in the graph (nodes 0..6)")
    assert refusal_sentence(Submission((), "", 0)) == ""


@pytest.mark.parametrize("text, reason", [
    ("", "empty text"),
    ("Help me " * 1250, "10000 characters"),
    ("Ich habe Kopfschmerzen und Fieber.", "does not look English"),
    ("Check Zed status.", "unknown target name 'Zed'"),
    ("The weather is nice today.", "no robot function requested"),
    ("Please check on Zoe.", "unknown target name 'Zoe'"),
])
def test_bad_input_yields_no_instruction_and_a_spoken_reason(pipeline, text, reason):
    with pytest.raises(RejectedUtterance, match=reason) as caught:
        pipeline.process(text, ALEX, 0.0)
    assert rejection_sentence(caught.value) == f"Sorry, I cannot take your request: {caught.value}"
    assert pipeline.process("Chat with me", ALEX, 0.0)[1].instructions   # still working


@pytest.mark.parametrize("ip, reason", [
    ("1" * 91, "the phone address has 91 characters, more than the 90 a phone address may have"),
    ("10.0.0.1 x", "the phone address '10.0.0.1 x' holds spaces or control characters"),
    ("10.0.0.1\n", r"the phone address '10.0.0.1\\n' holds spaces or control characters"),
])
def test_a_bad_phone_address_is_refused_not_a_fault(pipeline, ip, reason):
    with pytest.raises(RejectedUtterance, match=f"^{reason}$"):
        pipeline.process("Play a song", ip, 0.0)


def test_the_longest_phone_address_fits_an_anonymous_source(pipeline):
    ip = "1" * PHONE_MAX_CHARS
    (music,) = pipeline.process("Play a song", ip, 0.0)[1].instructions
    assert music.source == f"anonymous@{ip}" and len(music.source) == 100


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
