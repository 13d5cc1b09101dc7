"""Where the idle robots of a fleet wait (beyond the seed; ROS-free).

An online robot learns of an instruction at its launch and must drive there; the reward it earns
decays from the launch (Eq. 4-2). Idle robots therefore wait at the places from which the fleet
reaches a new instruction soonest on average: the k-median of the graph's nodes (the p-median
problem, S. L. Hakimi, "Optimum locations of switching centers and the absolute centers and
medians of a graph", Operations Research 12(3), 1964), solved exactly over every set of k nodes
for small graphs, else by greedy addition and single swaps (M. B. Teitz and P. Bart, Operations
Research 16(5), 1968). Each idle robot heads for one of them: the idle robots are matched to the
places by least total travel (scipy's linear_sum_assignment).
"""
import itertools
import math
from collections.abc import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

EXACT_SETS = 20000   # at most this many k-sets of nodes are enumerated (else greedy + swaps)


def median_cost(travel_s: np.ndarray, places: Sequence[int], weights: np.ndarray) -> float:
    """Mean travel [s] to a node (weighted) from the nearest of `places`."""
    return float(weights @ travel_s[list(places)].min(axis=0))


def waiting_places(travel_s: np.ndarray, k: int, weights: np.ndarray | None = None,
                   candidates: Sequence[int] | None = None) -> tuple[int, ...]:
    """The k nodes (sorted) among `candidates` (default every node) that minimise the weighted
    mean travel [s] from the nearest of them to a node (`weights`: how likely an instruction is
    at each node; default uniform)."""
    n = travel_s.shape[0]
    if k < 1:
        raise ValueError(f"waiting places for {k} robots: need at least one")
    w = np.full(n, 1.0 / n) if weights is None else np.asarray(weights, dtype=float)
    nodes = list(range(n)) if candidates is None else sorted(set(candidates))
    if k >= len(nodes):
        return tuple(nodes)
    if math.comb(len(nodes), k) <= EXACT_SETS:
        best = min(itertools.combinations(nodes, k),
                   key=lambda c: (median_cost(travel_s, c, w), c))
        return tuple(best)
    places: list[int] = []
    for _ in range(k):                       # greedy: add the node that helps most
        places.append(min((v for v in nodes if v not in places),
                          key=lambda v: median_cost(travel_s, places + [v], w)))
    improved = True
    while improved:                          # Teitz-Bart: swap while a swap helps
        improved = False
        cost = median_cost(travel_s, places, w)
        for i, v in itertools.product(range(k), nodes):
            if v in places:
                continue
            trial = places[:i] + [v] + places[i + 1:]
            if median_cost(travel_s, trial, w) < cost - 1e-12:
                places, cost, improved = trial, median_cost(travel_s, trial, w), True
    return tuple(sorted(places))


def waiting_place_of(robot: int, nodes: Sequence[int], idle: Sequence[int],
                     places: Sequence[int], travel_s: np.ndarray) -> int | None:
    """The waiting place of idle robot `robot` (an index into `nodes`, the robots' nodes) when
    the robots `idle` are matched to `places` by least total travel; None when it is not idle."""
    if robot not in idle or not places:
        return None
    cost = travel_s[np.ix_([nodes[r] for r in idle], list(places))]
    rows, cols = linear_sum_assignment(cost)
    match = dict(zip(rows.tolist(), cols.tolist()))
    column = match.get(list(idle).index(robot))
    return None if column is None else int(places[column])


def online_ceiling(travel_s: np.ndarray, k: int, priorities: Sequence[tuple[float, float]],
                   durations: Sequence[float]) -> float:
    """What an online fleet can expect to earn of what an optimum that knows every launch, with
    a robot already waiting at each destination, earns: instructions launched one at a time
    at a uniformly drawn node, with a uniformly drawn priority (gamma, beta) and duration [s],
    reached from the k places the fleet waits at best for that priority
    (Eq. 4-2: gamma beta ** (travel + duration) against gamma beta ** duration). An upper
    bound when the robots are idle at each launch, as when launches are far apart."""
    n = travel_s.shape[0]
    earned = known = 0.0
    for gamma, beta in priorities:
        served = np.mean([beta ** d for d in durations]) * gamma
        reach = max(float(np.mean(beta ** travel_s[list(c)].min(axis=0)))
                    for c in itertools.combinations(range(n), min(k, n)))
        earned += served * reach
        known += served
    return earned / known
