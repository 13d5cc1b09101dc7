"""The text format of human-controlled navigating records (thesis 002 §3.3.1, Fig. 3.3.1).

A file holds recording sequences. Each sequence is

    R;<class>                 start indicator carrying the basic instruction class (1-10)
    v;omega;r1;r2;...;rN      one line per sample: (moving, rotating) velocity, then laser ranges
    ...
    STOP                      end indicator

Numbers are written with repr(), so a float read back is bit-identical. Spaces after ';' and a
trailing ';' (both appear in Fig. 3.3.1) are accepted. Ranges may be `inf` or `nan` (LaserScan's
"no return"); velocities must be finite.
"""
import math
from dataclasses import dataclass

START, END = "R", "STOP"
NUM_CLASSES = 10  # Table 3.1-1: ten basic instruction classes


class RecordFormatError(ValueError):
    """A malformed record file; the message names the file and line."""

    def __init__(self, source, line_number, message):
        super().__init__(f"{source}:{line_number}: {message}")
        self.source, self.line_number = source, line_number


@dataclass(frozen=True)
class Sample:
    """One sampling datum: the robot's velocity and the laser ranges at that moment."""

    v: float            # [m/s] moving velocity
    omega: float        # [rad/s] rotating velocity
    ranges: tuple       # [m] laser ranges, beam order of the scan


@dataclass
class RecordSequence:
    """One recording sequence: the class of the instruction followed and its samples."""

    instruction_class: int
    samples: list


def format_sample(sample):
    """Fig. 3.3.1: `v;omega;ranges...` on one line."""
    return ";".join(repr(float(x)) for x in (sample.v, sample.omega, *sample.ranges))


def format_records(sequences):
    """Fig. 3.3.1: the whole file as text."""
    lines = []
    for sequence in sequences:
        check_class(sequence.instruction_class)
        lines.append(f"{START};{sequence.instruction_class}")
        lines.extend(format_sample(s) for s in sequence.samples)
        lines.append(END)
    return "".join(line + "\n" for line in lines)


def write_records(path, sequences):
    with open(path, "w", encoding="ascii") as stream:
        stream.write(format_records(sequences))


def read_records(path):
    """Import a record file; raises RecordFormatError naming the line of the first problem."""
    with open(path, encoding="ascii", errors="replace") as stream:
        return parse_records(stream.read(), source=str(path))


def check_class(instruction_class):
    if not 1 <= instruction_class <= NUM_CLASSES:
        raise ValueError(f"instruction class must be 1..{NUM_CLASSES}, got {instruction_class}")


def parse_records(text, source="<records>"):
    """Parse the text of a record file into RecordSequences."""
    sequences, current, start_line = [], None, 0
    for number, raw in enumerate(text.splitlines(), start=1):
        fields = _split(raw)
        if not fields:
            continue
        if fields[0] == START:
            if current is not None:
                raise RecordFormatError(source, number, f"start indicator inside the sequence "
                                        f"started at line {start_line} (missing {END})")
            current, start_line = RecordSequence(_parse_class(fields, source, number), []), number
        elif fields == [END]:
            if current is None:
                raise RecordFormatError(source, number, f"{END} without a start indicator")
            sequences.append(current)
            current = None
        elif current is None:
            raise RecordFormatError(source, number, f"sample outside a sequence (expected "
                                    f"'{START};<class>' first), got {raw.strip()[:40]!r}")
        else:
            current.samples.append(_parse_sample(fields, current, source, number))
    if current is not None:
        raise RecordFormatError(source, start_line, f"sequence never ended: no {END} before the "
                                "end of the file")
    return sequences


def _split(line):
    fields = [f.strip() for f in line.strip().split(";")]
    if fields and fields[-1] == "":
        fields.pop()
    return fields


def _parse_class(fields, source, number):
    if len(fields) != 2:
        raise RecordFormatError(source, number, f"start indicator must be '{START};<class>', "
                                f"got {';'.join(fields)!r}")
    try:
        instruction_class = int(fields[1])
        check_class(instruction_class)
    except ValueError as error:
        raise RecordFormatError(source, number, f"bad instruction class {fields[1]!r}: "
                                f"{error}") from None
    return instruction_class


def _parse_sample(fields, sequence, source, number):
    if len(fields) < 3:
        raise RecordFormatError(source, number, "a sample needs v;omega and at least one range, "
                                f"got {len(fields)} field(s)")
    values = []
    for index, field in enumerate(fields, start=1):
        try:
            values.append(float(field))
        except ValueError:
            raise RecordFormatError(source, number, f"field {index} is not a number: "
                                    f"{field!r}") from None
    v, omega, ranges = values[0], values[1], tuple(values[2:])
    if not (math.isfinite(v) and math.isfinite(omega)):
        raise RecordFormatError(source, number, f"velocity must be finite, got v={v}, "
                                f"omega={omega}")
    if any(r < 0.0 for r in ranges):
        raise RecordFormatError(source, number, "negative laser range")
    if sequence.samples and len(ranges) != len(sequence.samples[0].ranges):
        raise RecordFormatError(source, number, f"{len(ranges)} ranges, but this sequence's "
                                f"first sample has {len(sequence.samples[0].ranges)}")
    return Sample(v, omega, ranges)
