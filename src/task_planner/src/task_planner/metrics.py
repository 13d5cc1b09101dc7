"""Planner metrics of thesis 000 §5.3: reward curve, completion, time ratio, order similarity."""
from collections.abc import Sequence

import numpy as np

from task_planner.problem import Problem, Schedule

from task_planner.reward import decayed_reward


def reward_curve(problem: Problem, schedule: Schedule,
                 with_decision: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Fig. 5-6: (times [s], accumulated reward) after each served instruction, in time order."""
    served = np.array([index for index, _ in schedule.served], dtype=int)
    completion = np.asarray(schedule.completion, dtype=float)
    if with_decision:
        completion = completion + np.asarray(schedule.decision_before)
    gains = decayed_reward(problem.gamma[served], problem.beta[served],
                           completion - problem.launch[served])
    order = np.argsort(completion, kind="stable")
    return completion[order], np.cumsum(gains[order])


def completion_time(schedule: Schedule, with_decision: bool = False) -> float:
    """Time [s] when the last instruction is done (0 when nothing was served)."""
    if not schedule.served:
        return 0.0
    completion = np.asarray(schedule.completion)
    if with_decision:
        completion = completion + np.asarray(schedule.decision_before)
    return float(completion.max())


def time_ratio(task_processing_s: float, decision_s: float, navigation_s: float) -> float:
    """Eq. 5-2: task processing time / (task processing + decision + navigation time)."""
    total = task_processing_s + decision_s + navigation_s
    return task_processing_s / total if total > 0 else 0.0


def navigation_time(problem: Problem, schedule: Schedule) -> float:
    """Seconds spent driving the schedule's route."""
    route = schedule.route
    return float(sum(problem.edge_s[a, b] for a, b in zip(route, route[1:])))


def similarity_cost(order_a: Sequence[int], order_b: Sequence[int]) -> int:
    """Eq. 5-1: sum over instructions of |pos_A(i) - pos_B(i)| (positions start at 1)."""
    if sorted(order_a) != sorted(order_b):
        raise ValueError(f"orders hold different instructions: {order_a} vs {order_b}")
    position_b = {item: k for k, item in enumerate(order_b)}
    return int(sum(abs(k - position_b[item]) for k, item in enumerate(order_a)))


def average_index(samples: Sequence[Sequence[int]]) -> dict[int, float]:
    """Eq. 5-3: mean 1-based position of every instruction over the sample orders.

    Returns {instruction: mean position}.
    """
    if not samples:
        raise ValueError("average index needs at least one sample order")
    items = sorted(samples[0])
    for sample in samples:
        if sorted(sample) != items:
            raise ValueError(f"sample {sample} does not hold the instructions {items}")
    return {item: float(np.mean([list(s).index(item) + 1 for s in samples])) for item in items}


def order_by_average_index(samples: Sequence[Sequence[int]]) -> list[int]:
    """§5.3.4: the instructions sorted by their Eq. 5-3 average index (ties: smaller id first)."""
    means = average_index(samples)
    return sorted(means, key=lambda item: (means[item], item))
