"""Task buffer benchmarks behind `scripts/bench_task_buffer`.

- Journal throughput (`journal_flood`): a flood of N instructions journalled one commit each, then
  in bursts of one transaction each.
- The /task_planner/state message of a long-running buffer (`state_message`): a journal of N
  records, nearly all finished and a few open; the serialised size [bytes] of the bounded message
  the executor node publishes and the wall time of building it (`conversions.buffer_to_msg`),
  next to the complete history (the answer of /task_planner/get_buffer) for comparison.
"""
import argparse
import io
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import genpy
import numpy as np

from task_planner.conversions import buffer_to_msg
from task_planner.instruction import Instruction
from task_planner.task_buffer import BufferConfig, TaskBuffer

TEXT = "I have a headache and fever, please come"  # a typical utterance (40 characters)


def flood(count):
    return [Instruction(id=k, gamma=3.0, beta=0.94, destination=k % 8, start_time=k / count)
            for k in range(1, count + 1)]


@dataclass(frozen=True)
class JournalFigures:
    elapsed_s: float     # wall time of journalling the whole flood [s]
    journalled: int      # instructions found on re-opening the journal
    call_ms: tuple       # wall time of each submit / submit_many call [ms]


def journal_flood(mode, count, burst, synchronous):
    """Journal `count` instructions one commit each (`mode` "one commit each") or in bursts of
    `burst` (one transaction each) in a fresh journal -> JournalFigures."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "buffer.sqlite"
        buffer = TaskBuffer(path, BufferConfig(synchronous=synchronous))
        instructions = flood(count)
        if mode == "one commit each":
            calls = [(buffer.submit, instruction, instruction.start_time)
                     for instruction in instructions]
        else:
            calls = [(buffer.submit_many, instructions[first:first + burst], first / count)
                     for first in range(0, count, burst)]
        times = []
        started = time.perf_counter()
        for call, what, now in calls:
            began = time.perf_counter()
            call(what, now=now)
            times.append(1000.0 * (time.perf_counter() - began))
        elapsed = time.perf_counter() - started
        buffer.close()
        journalled = len(TaskBuffer(path).records())
    return JournalFigures(elapsed, journalled, tuple(times))


def percentiles(values_ms):
    """(p50, p99, max) of the times [ms]."""
    return (float(np.percentile(values_ms, 50)), float(np.percentile(values_ms, 99)),
            float(max(values_ms)))


def long_running_buffer(records, open_count, recent_finished=50, path=":memory:"):
    """A buffer as after a long run: `records` instructions arrived in bursts of 50 and were
    served as they came (every 20th FAILED, every 50th CANCELLED, the rest DONE), except the last
    `open_count`, which are open (the first of them ACTIVE); texts of TEXT's length."""
    buffer = TaskBuffer(path, BufferConfig(synchronous="OFF", recent_finished=recent_finished))
    instructions = [Instruction(id=k, gamma=3.0, beta=0.99, destination=k % 7,
                                start_time=float(k), duration=30, source="Alice", target="Bob",
                                function=1 + k % 7, destination_name="living_room", text=TEXT)
                    for k in range(1, records + 1)]
    served = records - open_count
    for first in range(0, records, 50):
        burst = instructions[first:first + 50]
        buffer.submit_many(burst, now=burst[-1].start_time)
        for k in (i.id for i in burst if i.id <= served):
            if k % 50 == 0:
                buffer.cancel(k, now=k + 1.0)
            elif k % 20 == 0:
                buffer.fail(k, now=k + 1.0, reason="navigation to living_room aborted 3 times")
            else:
                buffer.start(k, now=k + 0.5)
                buffer.finish(k, now=k + 1.0)
    if open_count:
        buffer.start(served + 1, now=float(records))
    return buffer


def serialised_size(msg):
    """Bytes of `msg` on the wire (the ROS serialisation, without the connection header)."""
    stream = io.BytesIO()
    msg.serialize(stream)
    return len(stream.getvalue())


@dataclass(frozen=True)
class MessageFigures:
    instructions: int    # instruction states in the message
    size_bytes: int      # serialised size [bytes]
    build_ms: tuple      # wall time of each buffer_to_msg over the repeats [ms]


def message_figures(buffer, complete, repeats):
    """Build the message `repeats` times -> its size and every build time."""
    times, msg = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        msg = buffer_to_msg(buffer, genpy.Time(0), complete=complete)
        times.append(1000.0 * (time.perf_counter() - started))
    return MessageFigures(len(msg.instructions), serialised_size(msg), tuple(times))


def state_message(records=20000, open_count=10, recent_finished=50, repeats=20):
    """(bounded /task_planner/state figures, complete get_buffer figures) for a long run."""
    buffer = long_running_buffer(records, open_count, recent_finished)
    return (message_figures(buffer, False, repeats),
            message_figures(buffer, True, max(1, repeats // 10)))


def report_lines(args):
    """The lines `scripts/bench_task_buffer` prints for its parsed options."""
    lines = []
    for mode in ("one commit each", f"bursts of {args.burst}"):
        figures = journal_flood(mode, args.count, args.burst, args.synchronous)
        p50, p99, slowest = percentiles(figures.call_ms)
        lines.append(f"{mode:>18}: {args.count} instructions in {figures.elapsed_s:.3f} s "
                     f"({1000 * figures.elapsed_s / args.count:.3f} ms each), per call p50 "
                     f"{p50:.3f} ms, p99 {p99:.3f} ms, max {slowest:.3f} ms; journalled "
                     f"{figures.journalled}/{args.count} (synchronous={args.synchronous})")
    bounded, complete = state_message(args.records, args.open, args.recent, args.repeats)
    for name, figures in (("state (bounded)", bounded), ("get_buffer (all)", complete)):
        p50, p99, slowest = percentiles(figures.build_ms)
        lines.append(f"{name:>18}: {args.records} records ({args.open} open) -> "
                     f"{figures.instructions} instructions, {figures.size_bytes} bytes, built in "
                     f"p50 {p50:.2f} ms, p99 {p99:.2f} ms, max {slowest:.2f} ms "
                     f"({len(figures.build_ms)} builds)")
    return lines


def main(argv=None):
    """Parse, run both benchmarks and print their lines -> exit status 0."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1000)
    parser.add_argument("--burst", type=int, default=50)
    parser.add_argument("--synchronous", default="FULL")
    parser.add_argument("--records", type=int, default=20000)
    parser.add_argument("--open", type=int, default=10)
    parser.add_argument("--recent", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=20)
    for line in report_lines(parser.parse_args(argv)):
        print(line, flush=True)
    return 0
