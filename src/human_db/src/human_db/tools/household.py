"""Command line: import a household YAML into a database file, or export one to YAML.

Run it while no human_db node writes to the same file: the node caches the colour table.
"""
import argparse
import sys

from human_db.errors import HumanDbError
from human_db.household import export_household, import_household, load_household
from human_db.store import HumanStore


def parse_args(argv):
    parser = argparse.ArgumentParser(prog="household", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    load = sub.add_parser("import", help="register every person of a YAML file")
    load.add_argument("yaml", help="household file, e.g. config/household.yaml")
    load.add_argument("--db", required=True, help="SQLite file (created when missing)")
    load.add_argument("--replace", action="store_true",
                      help="overwrite people already registered (their history stays)")
    dump = sub.add_parser("export", help="write the database's household to a YAML file")
    dump.add_argument("yaml", help="output file")
    dump.add_argument("--db", required=True, help="SQLite file")
    dump.add_argument("--places-from", default="",
                      help="copy the `places` list from this household file")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        store = HumanStore(args.db, on_retry=lambda message: print(f"household: {message}",
                                                                   file=sys.stderr))
        if args.command == "import":
            names = import_household(store, args.yaml, replace=args.replace)
            print(f"imported {len(names)} people into {store.path}: {', '.join(names)}")
        else:
            places = load_household(args.places_from)[0] if args.places_from else ()
            export_household(store, args.yaml, places)
            print(f"exported {store.count()} people from {store.path} to {args.yaml}")
        store.close()
    except HumanDbError as error:
        print(f"household: {error}", file=sys.stderr)
        return 1
    return 0
