"""Exact fleet optimum: the label-setting DP of `exact` extended to k robots (the reference the
fleet allocators are measured against), for small sets.

A label is (every robot's time, reward, every robot's order) after serving a set S of instructions
with the robots standing on given nodes. It is extended by one instruction served next by one
robot, layer by layer (|S| = 0, 1, ...), under the fleet's timing rule (`fleet`). Within a (S,
nodes) key, a label whose robots are all free no later, whose chain heads (served instructions
with an unserved successor) were completed no later and whose reward is no lower dominates
another. A label is dropped when its reward plus an admissible bound (each remaining instruction
served as if the robot that can reach it first drove there directly next) cannot beat the best
complete assignment known, seeded by the auction. Robots with the same start are interchangeable,
so robot r takes instructions only once robot r - 1 with the same start has one. The result is
optimal over every assignment and order that respects the chains, with full knowledge of the
launches (a clairvoyant bound for online allocators).

Without chains the robots do not wait on each other, so the optimum splits the set: each robot's
best reward for every subset (a single-robot label-setting DP over (subset, last instruction),
labels (time, reward) Pareto-pruned), combined over the robots subset by subset. Staggered
launches defeat the joint labels' dominance (a robot early for a launch waits), not these.
"""
import time
from collections.abc import Sequence

import numpy as np

from task_planner.baselines import PlannerTooLarge
from task_planner.exact import SolverTimeout
from task_planner.fleet import RobotStart, check_starts, fleet_reward, run_fleet, service_end
from task_planner.fleet_auction import SequentialAuction
from task_planner.problem import Problem
from task_planner.reward import decayed_reward

_TOLERANCE = 1e-12
# (every robot's time [s], reward, every robot's order, chain head -> its completion time [s])
Label = tuple[tuple[float, ...], float, tuple[tuple[int, ...], ...], dict[int, float]]
Key = tuple[int, tuple[int, ...]]   # (served set's bit mask, the robots' nodes)


def fleet_exact_optimum(problem: Problem, starts: Sequence[RobotStart], max_instructions: int = 12,
                        time_limit_s: float | None = None) -> tuple[list[list[int]], float]:
    """(orders per robot, reward) of the best assignment and order of every instruction.

    Raises PlannerTooLarge above `max_instructions` and SolverTimeout past `time_limit_s`.
    """
    check_starts(problem, starts)
    p, k = problem, len(starts)
    if p.count > max_instructions:
        raise PlannerTooLarge(f"fleet exact optimum: {p.count} instructions exceed the limit "
                              f"of {max_instructions}")
    if not (p.predecessor >= 0).any():
        return _split_optimum(p, starts)
    seed = run_fleet(p, starts, SequentialAuction()).orders
    best_orders, best_reward = [list(o) for o in seed], fleet_reward(p, seed, starts)
    deadline = None if time_limit_s is None else time.perf_counter() + time_limit_s
    twin = [r > 0 and starts[r] == starts[r - 1] for r in range(k)]
    heads: dict[int, int] = {}         # chain head -> bit mask of its successors
    for s, b in enumerate(p.predecessor):
        if b >= 0:
            heads[int(b)] = heads.get(int(b), 0) | 1 << s
    empty: tuple[tuple[int, ...], ...] = tuple(() for _ in range(k))
    start: Label = (tuple(float(s.free_at) for s in starts), 0.0, empty, {})
    layer: dict[Key, list[Label]] = {(0, tuple(s.node for s in starts)): [start]}
    for _ in range(p.count):
        following: dict[Key, list[Label]] = {}
        for (served, nodes), labels in layer.items():
            if deadline is not None and time.perf_counter() > deadline:
                raise SolverTimeout(f"fleet exact optimum: {p.count} instructions, {k} robots: "
                                    f"time limit exceeded")
            for label in labels:
                if label[1] + _bound(p, served, nodes, label) < best_reward - _TOLERANCE:
                    continue
                _extend(p, served, nodes, label, twin, heads, following)
        layer = following
    return _best_complete(layer, best_orders, best_reward)


def _best_complete(layer: dict[Key, list[Label]], best_orders: list[list[int]],
                   best_reward: float) -> tuple[list[list[int]], float]:
    """(orders, reward) of the best complete label, if it beats the best known."""
    for labels in layer.values():
        for clocks, reward, orders, _ in labels:
            if reward > best_reward + _TOLERANCE:
                best_reward, best_orders = reward, [list(o) for o in orders]
    return best_orders, best_reward


def _extend(p: Problem, served: int, nodes: tuple[int, ...], label: Label, twin: Sequence[bool],
            heads: dict[int, int], following: dict[Key, list[Label]]) -> None:
    """Every label with one more instruction served by one robot, added without dominated ones."""
    clocks, reward, orders, done = label
    for i in range(p.count):
        before = int(p.predecessor[i])
        if served >> i & 1 or (before >= 0 and not served >> before & 1):
            continue
        after = done.get(before, 0.0)
        for r in range(len(nodes)):
            if twin[r] and not orders[r - 1]:
                continue
            finish = service_end(p, nodes[r], clocks[r], i, after)
            gain = p.gamma[i] * p.beta[i] ** (finish - p.launch[i])   # Eq. 4-2: hot loop
            new_done = done
            if i in heads:
                new_done = dict(done)
                new_done[i] = finish
            key: Key = (served | 1 << i, nodes[:r] + (int(p.node[i]),) + nodes[r + 1:])
            new: Label = (clocks[:r] + (finish,) + clocks[r + 1:], reward + gain,
                   orders[:r] + (orders[r] + (i,),) + orders[r + 1:], new_done)
            _insert(following.setdefault(key, []), new, _open_heads(key[0], heads))


def _open_heads(served: int, heads: dict[int, int]) -> list[int]:
    """The served chain heads (`heads`: head -> its successors' bits) with a successor not
    served yet."""
    return [h for h, successors in heads.items()
            if served >> h & 1 and served & successors != successors]


def _dominates(a: Label, b: Label, open_heads: Sequence[int]) -> bool:
    """Label a is free no later on every robot, has its open chain heads done no later, and
    earned no less than label b."""
    return a[1] >= b[1] and all(x <= y for x, y in zip(a[0], b[0])) and all(
        a[3][h] <= b[3][h] for h in open_heads)


def _insert(labels: list[Label], label: Label, open_heads: Sequence[int]) -> None:
    """Keep `labels` (of one key) free of dominated labels."""
    if any(_dominates(other, label, open_heads) for other in labels):
        return
    labels[:] = [o for o in labels if not _dominates(label, o, open_heads)]
    labels.append(label)


def _bound(p: Problem, served: int, nodes: tuple[int, ...], label: Label) -> float:
    """Admissible bound on the reward still to come: each remaining instruction finished when
    the first robot able to reach it could, driving there directly next."""
    remaining = np.array([i for i in range(p.count) if not served >> i & 1], dtype=int)
    if not len(remaining):
        return 0.0
    clocks, _, _, done = label
    arrive = (np.array(clocks)[:, None] + p.travel_s[list(nodes)][:, p.node[remaining]]).min(0)
    after = np.array([done.get(int(p.predecessor[i]), 0.0) for i in remaining])
    finish = np.maximum(np.maximum(arrive, p.launch[remaining]), after) + p.duration[remaining]
    return float(decayed_reward(p.gamma[remaining], p.beta[remaining],
                                finish - p.launch[remaining]).sum())


def _split_optimum(p: Problem,
                   starts: Sequence[RobotStart]) -> tuple[list[list[int]], float]:
    """(orders, reward) of the best split of a chain-free set over the robots."""
    full = (1 << p.count) - 1
    combined: dict[int, tuple[float, tuple[tuple[int, ...], ...]]] | None = None
    # subset -> (reward, the robots' orders so far)
    for start in starts:
        alone = _alone(p, start)                 # subset -> (reward, order) of this robot
        if combined is None:
            combined = {mask: (reward, (order,)) for mask, (reward, order) in alone.items()}
            continue
        merged: dict[int, tuple[float, tuple[tuple[int, ...], ...]]] = {}
        for mask in range(full + 1):
            top: tuple[float, tuple[tuple[int, ...], ...]] | None = None
            part = mask                           # every subset `part` of `mask` for this robot
            while True:
                rest = combined[mask ^ part]
                reward = rest[0] + alone[part][0]
                if top is None or reward > top[0] + _TOLERANCE:
                    top = (reward, rest[1] + (alone[part][1],))
                if not part:
                    break
                part = (part - 1) & mask
            assert top is not None   # part = mask ran at least once
            merged[mask] = top
        combined = merged
    if combined is None:
        raise ValueError("fleet exact optimum: no robot to serve the instructions")
    reward, orders = combined[full]
    return [list(order) for order in orders], reward


def _alone(p: Problem, start: RobotStart) -> dict[int, tuple[float, tuple[int, ...]]]:
    """{subset mask: (best reward, order)} of one robot serving exactly that subset."""
    count = p.count
    labels: dict[tuple[int, int], list[tuple[float, float, tuple[int, ...]]]] = {
        (0, -1): [(float(start.free_at), 0.0, ())]}
    best: dict[int, tuple[float, tuple[int, ...]]] = {0: (0.0, ())}
    for mask in range(1 << count):
        for last in [-1, *range(count)]:
            for clock, reward, order in labels.pop((mask, last), ()):
                node = start.node if last < 0 else int(p.node[last])
                if reward > best.get(mask, (-1.0,))[0]:
                    best[mask] = (reward, order)
                for i in range(count):
                    if mask >> i & 1:
                        continue
                    finish = service_end(p, node, clock, i)
                    gain = p.gamma[i] * p.beta[i] ** (finish - p.launch[i])   # hot loop
                    _insert_alone(labels.setdefault((mask | 1 << i, i), []),
                                  (finish, reward + gain, order + (i,)))
    return best


def _insert_alone(labels: list[tuple[float, float, tuple[int, ...]]],
                  label: tuple[float, float, tuple[int, ...]]) -> None:
    """Keep one (subset, last) key's labels free of those later and earning no more."""
    if any(o[0] <= label[0] and o[1] >= label[1] for o in labels):
        return
    labels[:] = [o for o in labels if not (label[0] <= o[0] and label[1] >= o[1])]
    labels.append(label)
