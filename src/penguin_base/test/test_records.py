"""Navigating records (thesis 002 §3.3.1, Fig. 3.3.1): text format, errors, bag round trip."""
import math
import random

import pytest

from penguin_base.record_format import (RecordFormatError, RecordSequence, Sample,
                                        format_records, parse_records, read_records,
                                        write_records)
from penguin_base.recording import SequenceBuilder


def random_sequences(seed=1):
    rng = random.Random(seed)
    sequences = []
    for instruction_class in (1, 5, 10):
        samples = [Sample(rng.uniform(-0.4, 0.4), rng.uniform(-1, 1),
                          tuple(rng.uniform(0.1, 30.0) for _ in range(24)) + (math.inf,))
                   for _ in range(rng.randint(5, 40))]
        sequences.append(RecordSequence(instruction_class, samples))
    return sequences


def test_text_round_trip_is_exact(tmp_path):
    sequences = random_sequences()
    path = tmp_path / "records.txt"
    write_records(path, sequences)
    assert read_records(path) == sequences


def test_file_layout_follows_fig_3_3_1():
    sample = Sample(3.12608e-05, 9.45645e-05, (3.57306, 3.56535))
    text = format_records([RecordSequence(5, [sample])])
    assert text == "R;5\n3.12608e-05;9.45645e-05;3.57306;3.56535\nSTOP\n"


def test_parser_accepts_the_spacing_of_fig_3_3_1():
    text = ("R; 5\n"
            "0.205536; -0.00150286; 0.0827481; 2.70479;\n"
            "3.2488e-05;-8.69685e-05;2.71135;2.69437;\n"
            "\n"
            "STOP\n")
    [sequence] = parse_records(text)
    assert sequence.instruction_class == 5
    assert sequence.samples[0] == Sample(0.205536, -0.00150286, (0.0827481, 2.70479))
    assert sequence.samples[1].ranges == (2.71135, 2.69437)


@pytest.mark.parametrize("text, line, message", [
    ("R;3\n0.1;0.0;1.0\n0.1;abc;1.0\nSTOP\n", 3, "field 2 is not a number: 'abc'"),
    ("0.1;0.0;1.0\n", 1, "sample outside a sequence"),
    ("R;11\nSTOP\n", 1, "bad instruction class '11'"),
    ("R;two\nSTOP\n", 1, "bad instruction class 'two'"),
    ("R;1\n0.1;0.0;1.0\nR;2\n", 3, "inside the sequence started at line 1"),
    ("R;1\n0.1;0.0;1.0\n", 1, "sequence never ended"),
    ("STOP\n", 1, "STOP without a start indicator"),
    ("R;4\n0.1;0.0\nSTOP\n", 2, "at least one range"),
    ("R;4\nnan;0.0;1.0\nSTOP\n", 2, "velocity must be finite"),
    ("R;4\n0.1;0.0;1.0;2.0\n0.1;0.0;1.0\nSTOP\n", 3, "1 ranges, but this sequence's first"),
    ("R;4\n0.1;0.0;-1.0\nSTOP\n", 2, "negative laser range"),
])
def test_malformed_records_name_the_line(text, line, message):
    with pytest.raises(RecordFormatError) as caught:
        parse_records(text, source="bad.txt")
    assert caught.value.line_number == line
    assert str(caught.value).startswith(f"bad.txt:{line}: ")
    assert message in str(caught.value)


def test_sequence_builder_pairs_each_scan_with_the_latest_velocity():
    builder = SequenceBuilder("odom")
    builder.on_scan((9.0,))                     # before any sequence: not recorded
    builder.on_instruction_class(2)
    builder.on_scan((1.0,))                     # no odometry yet: skipped
    builder.on_velocity("odom", 0.1, 0.0)
    builder.on_velocity("cmd_vel", 0.3, 0.5)    # other source: ignored
    builder.on_scan((2.0,))
    builder.on_velocity("odom", 0.2, -0.1)
    builder.on_scan((3.0,))
    builder.on_instruction_class(0)
    builder.on_scan((4.0,))                     # after the end: not recorded
    assert builder.finish() == [RecordSequence(2, [Sample(0.1, 0.0, (2.0,)),
                                                   Sample(0.2, -0.1, (3.0,))])]
    assert builder.skipped_scans == 1
    with pytest.raises(ValueError, match="instruction class must be 1..10"):
        builder.on_instruction_class(12)
