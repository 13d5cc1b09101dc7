"""Turn a time-ordered stream of recorded messages into recording sequences (thesis 002 §3.3.1).

Each laser scan inside a sequence becomes one sample, paired with the latest velocity seen before
it. The velocity comes from the odometry (the robot's measured velocity, as Fig. 3.3.1 shows) or
from /cmd_vel (what the driver commanded). A sequence runs from an instruction-class event 1..10 to
the next event 0 (or the next class).
"""
from penguin_base.record_format import RecordSequence, Sample, check_class

VELOCITY_SOURCES = ("odom", "cmd_vel")


class SequenceBuilder:
    """Feed events in time order; `finish()` returns the completed RecordSequences."""

    def __init__(self, velocity_source="odom"):
        if velocity_source not in VELOCITY_SOURCES:
            raise ValueError(f"velocity source must be one of {VELOCITY_SOURCES}, "
                             f"got {velocity_source!r}")
        self.velocity_source = velocity_source
        self.sequences = []
        self._current = None
        self._velocity = None
        self.skipped_scans = 0   # scans inside a sequence before any velocity was known
        self.unfinished = 0      # sequences still open at finish()

    def on_instruction_class(self, instruction_class):
        """1..10 starts a sequence of that class (closing an open one); 0 ends the sequence."""
        if instruction_class != 0:
            check_class(instruction_class)
        if self._current is not None:
            self.sequences.append(self._current)
            self._current = None
        if instruction_class != 0:
            self._current = RecordSequence(instruction_class, [])

    def on_velocity(self, source, v, omega):
        if source == self.velocity_source:
            self._velocity = (float(v), float(omega))

    def on_scan(self, ranges):
        if self._current is None:
            return
        if self._velocity is None:
            self.skipped_scans += 1
            return
        self._current.samples.append(Sample(*self._velocity, tuple(float(r) for r in ranges)))

    @property
    def recording(self):
        return self._current is not None

    def finish(self):
        """Close an open sequence (the recording stopped without an end event) and return all."""
        if self._current is not None:
            self.unfinished += 1
            self.sequences.append(self._current)
            self._current = None
        return self.sequences
