"""Command-line tool `records`: export a recorder bag to the seed's text format, or check a file.

    records export BAG OUT.txt [--velocity-source odom|cmd_vel]
    records check RECORDS.txt
"""
import argparse
import sys

from penguin_base.record_format import RecordFormatError, read_records, write_records
from penguin_base.recording import VELOCITY_SOURCES
from penguin_base.ros_record_bag import DEFAULT_TOPICS, BagExportError, sequences_from_bag


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="records", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = parser.add_subparsers(dest="command", required=True)
    export = commands.add_parser("export", help="bag -> text records (Fig. 3.3.1)")
    export.add_argument("bag")
    export.add_argument("output")
    export.add_argument("--velocity-source", choices=VELOCITY_SOURCES, default="odom",
                        help="velocity of each sample: measured (odom) or commanded (cmd_vel)")
    for name, default in DEFAULT_TOPICS.items():
        export.add_argument(f"--{name.replace('_', '-')}-topic", default=default)
    check = commands.add_parser("check", help="import a text record file and summarise it")
    check.add_argument("records")
    return parser.parse_args(argv)


def export(args):
    topics = {name: getattr(args, f"{name}_topic") for name in DEFAULT_TOPICS}
    try:
        sequences, builder = sequences_from_bag(args.bag, args.velocity_source, topics)
    except BagExportError as error:
        print(f"records export: {error}", file=sys.stderr)
        return 1
    write_records(args.output, sequences)
    samples = sum(len(s.samples) for s in sequences)
    print(f"wrote {len(sequences)} sequence(s), {samples} sample(s) to {args.output}")
    if builder.skipped_scans:
        print(f"note: {builder.skipped_scans} scan(s) before the first {args.velocity_source} "
              "message were skipped")
    if builder.unfinished:
        print(f"note: {builder.unfinished} sequence(s) had no end event; closed at the bag's end")
    return 0


def check(args):
    try:
        sequences = read_records(args.records)
    except (OSError, RecordFormatError) as error:
        print(f"records check: {error}", file=sys.stderr)
        return 1
    for index, sequence in enumerate(sequences, start=1):
        beams = len(sequence.samples[0].ranges) if sequence.samples else 0
        print(f"sequence {index}: class {sequence.instruction_class}, "
              f"{len(sequence.samples)} samples, {beams} ranges each")
    return 0


def main(argv=None):
    args = parse_args(argv)
    return export(args) if args.command == "export" else check(args)
