"""Benchmark human_db: identify observed people against a large household (thesis 000 §3.2.3)
and the store's write and query speed. Prints the figures (latencies as p50, p95, p99); nothing
is asserted.

    source scripts/env.sh && scripts/bench_human_db [--people 1000] [--observed 10]
"""
import argparse
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
from supervision.latency import summarise, time_calls_ms

from human_db.colour import ColourIndex, best_matches, mean_shirt_distance, shirt_distance_matrix
from human_db.model import Human
from human_db.store import HumanStore

NOISE = 12        # [RGB units] camera noise added to the observed copies of stored shirts
THRESHOLD = 200.0  # identification threshold of Algorithm 3-1 [RGB distance]
WRITERS = 4       # concurrent writer threads


def positive(text):
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer; got {text!r}")
    return int(text)


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="bench_human_db", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--people", type=positive, default=1000, help="stored household members")
    parser.add_argument("--observed", type=positive, default=10, help="people seen in one frame")
    parser.add_argument("--repeats", type=positive, default=200, help="timed repetitions")
    parser.add_argument("--updates", type=positive, default=1000,
                        help="updates per writer thread")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    if args.observed > args.people:
        parser.error(f"--observed ({args.observed}) cannot exceed --people ({args.people})")
    if args.people < 2:
        parser.error("--people must be at least 2 (the query bench reads two people)")
    return args


def timed(function, repeats):
    """LatencySummary [ms] of `repeats` calls of `function()`."""
    return summarise(time_calls_ms(function, repeats))


def python_loop(observed, names, stored, threshold):
    """Algorithm 3-1 with best match, scalar Eq. 3-10 in plain Python (the unvectorised way)."""
    results = []
    for colours in observed:
        distances = [mean_shirt_distance(colours, s) for s in stored]
        results.append(best_matches([distances], names, threshold)[0])
    return results


def observe(stored, count, rng):
    """(indices, noisy shirt colours) of `count` distinct stored people seen by the camera."""
    picked = rng.choice(len(stored), size=count, replace=False)
    noise = rng.integers(-NOISE, NOISE + 1, stored[picked].shape)
    return picked, np.clip(stored[picked] + noise, 0, 255)


def bench_identification(args, store, names, stored, rng):
    picked, observed = observe(stored, args.observed, rng)
    index = ColourIndex(names, stored)
    matches = index.identify_many(observed)
    hits = sum(m is not None and m.name == names[p] for m, p in zip(matches, picked))
    lists = stored.tolist()
    rows = [
        ("numpy, colours cached in memory (node's hot path)",
         timed(lambda: index.identify_many(observed), args.repeats)),
        ("numpy, distance matrix only", timed(lambda: shirt_distance_matrix(observed, stored),
                                              args.repeats)),
        ("numpy + read colour table from SQLite (after a write)",
         timed(lambda: ColourIndex(*store.shirt_colour_table()).identify_many(observed),
               max(10, args.repeats // 10))),
        ("plain Python loop (Algorithm 3-1, scalar Eq. 3-10)",
         timed(lambda: python_loop(observed.tolist(), names, lists, THRESHOLD), 3)),
    ]
    print(f"\nidentification: {args.observed} observed people vs {len(names)} stored "
          f"(threshold {THRESHOLD:.0f}, noise ±{NOISE})")
    print(f"  correct matches: {hits}/{args.observed}")
    print(f"  {'method':58s} {'p50 ms':>10s} {'p95 ms':>9s} {'p99 ms':>9s}")
    for label, figures in rows:
        print(f"  {label:58s} {figures.p50:10.3f} {figures.p95:9.3f} {figures.p99:9.3f}")
    return hits


def bench_writes(args, path, names):
    store = HumanStore(path)

    def write(k):
        for i in range(args.updates):
            store.update(names[k % len(names)], now=float(i), location="office",
                         activity=f"step {i}", source=f"bench {k}")

    start = time.perf_counter()
    write(0)
    single = time.perf_counter() - start
    threads = [threading.Thread(target=write, args=(k,)) for k in range(WRITERS)]
    start = time.perf_counter()
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    parallel = time.perf_counter() - start
    where = timed(lambda: store.where_was(names[0], args.updates / 2), args.repeats)
    get = timed(lambda: store.get(names[1]), args.repeats)
    print(f"\nstore ({store.config.synchronous} sync, WAL): {path}")
    print(f"  1 writer  x {args.updates} updates: {single:6.2f} s = "
          f"{args.updates / single:7.0f} updates/s")
    print(f"  {WRITERS} writers x {args.updates} updates: {parallel:6.2f} s = "
          f"{WRITERS * args.updates / parallel:7.0f} updates/s (busy retries: "
          f"{store.busy_retries})")
    print(f"  where_was over {len(store.history(names[0]))} history rows: "
          f"{where.describe(digits=3)}")
    print(f"  get one person with schedules: {get.describe(digits=3)}")
    store.close()


def main(argv=None):
    args = parse_args(argv)
    rng = np.random.default_rng(args.seed)
    stored = rng.integers(0, 256, size=(args.people, 3, 3))
    names = [f"person{i:04d}" for i in range(args.people)]
    with tempfile.TemporaryDirectory() as work:
        path = Path(work) / "bench.sqlite"
        store = HumanStore(path)
        humans = [Human(name=n, gender="female", age=30, shirt_colour=c.tolist())
                  for n, c in zip(names, stored)]
        start = time.perf_counter()
        store.register_all(humans, now=0.0)
        print(f"registered {args.people} people in one transaction: "
              f"{time.perf_counter() - start:.3f} s")
        bench_identification(args, store, names, stored, rng)
        store.close()
        bench_writes(args, path, names)
    return 0
