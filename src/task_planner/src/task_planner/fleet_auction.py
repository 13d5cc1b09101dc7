"""Sequential single-item auction over a fleet (S. Koenig et al., "The power of sequential
single-item auctions for agent coordination", AAAI 2006), re-run online whenever a robot is free.

Each round, every robot bids for every unallocated instruction, and the highest bid over all
robots and instructions wins. Up to `insertion_limit` open instructions a bid is the reward the
robot's plan gains by taking it (Eq. 4-2 summed over its plan, the instruction inserted where it
earns most); above it, a bid is the reward rate of appending it (its reward over the time from the
plan's end to its completion, the rollout planner's rule), which keeps a decision O(n^2 k).
Rounds go on until every instruction that can be planned is allocated. A successor is auctioned
once its predecessor is done, claimed or allocated, and starts after that predecessor's (planned)
completion. The free robot then heads for the first instruction of its plan one edge at a time
(as an executor drives, node by node); the other plans are provisional, and the auction is re-run
at every node and completion, so a new instruction can turn a robot on its way.

Beyond the auction (`AuctionConfig.wait_at_medians`): a robot that is free with nothing planned
drives to a waiting place (fleet_waiting: the k-median of the graph, k the fleet's robots), so a
new instruction finds a robot near it.
"""
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from task_planner.fleet import FleetView, RobotStart, service_end
from task_planner.fleet_waiting import waiting_place_of, waiting_places
from task_planner.problem import Problem
from task_planner.reward import decayed_reward

_TIE = 1e-12   # gains closer than this are equal (the lower robot, then instruction, wins)
_MIN_STEP_S = 1e-9   # guards the reward rate of an instruction that takes no time


@dataclass
class AuctionConfig:
    insertion_limit: int = 15   # open instructions up to which bids try every insertion point;
    #                             above it, bids append (the auction stays O(n^2 k) per decision)
    wait_at_medians: bool = False  # a free robot with nothing planned waits at one of the
    #                                graph's k-median places (False: where it finished)


class SequentialAuction:
    """Online fleet allocator: the sequential single-item auction, re-run at every decision."""

    name = "Auction"
    problem: Problem   # set by reset

    def __init__(self, config: AuctionConfig | None = None) -> None:
        self.config = config or AuctionConfig()
        self.robots = 0
        self.places: tuple[int, ...] | None = None   # waiting places, found at the first idle
        self._last: tuple[FleetView, list[list[int]]] | None = None   # allocate's last answer

    def reset(self, problem: Problem, starts: Sequence[RobotStart]) -> None:
        self.problem, self.robots = problem, len(starts)
        self.places, self._last = None, None

    def idle(self, view: FleetView) -> int | None:
        """The neighbour robot `view.robot` drives to while it waits (towards its waiting place,
        fleet_waiting), or None: it stays. The robots with nothing planned share the waiting
        places."""
        if not self.config.wait_at_medians:
            return None
        if self.places is None:
            self.places = waiting_places(self.problem.travel_s, self.robots)
        plans = self._plans(view)
        idle = [r for r, plan in enumerate(plans) if not plan]
        place = waiting_place_of(view.robot, view.nodes, idle, self.places,
                                 self.problem.travel_s)
        node = view.nodes[view.robot]
        if place is None or place == node:
            return None
        return int(self.problem.graph.next_hop[node, place])

    def decide(self, view: FleetView, available: np.ndarray) -> tuple[str, int | None]:
        """Towards the first instruction of this robot's plan; wait while it needs a
        predecessor that is claimed (done later) or while only other robots' plans can start.
        Plans whose chains wait on each other across robots (the bids see only planned times)
        are broken by serving the first startable instruction of its own plan, else the one that
        earns it most."""
        plans = self._plans(view)
        mine = plans[view.robot]
        startable = set(available.tolist())
        if mine and mine[0] in startable:
            return self._towards(view, mine[0])
        before = int(self.problem.predecessor[mine[0]]) if mine else -1
        if before in view.done:
            return "wait", None             # its predecessor is being served: done later
        if any(plan and plan[0] in startable for r, plan in enumerate(plans)
               if r != view.robot):
            return "wait", None             # the others start what they planned
        own = [i for i in mine if i in startable]
        return self._towards(view, own[0] if own else self._best_alone(view, available))

    def _towards(self, view: FleetView, index: int) -> tuple[str, int]:
        """Serve instruction `index` here, or drive one edge towards it (decide again there)."""
        node, place = view.nodes[view.robot], int(self.problem.node[index])
        if node == place:
            return "serve", index
        return "move", int(self.problem.graph.next_hop[node, place])

    def _plans(self, view: FleetView) -> list[list[int]]:
        """allocate(view), once per view: `idle` asks again for the view `decide` just had."""
        if self._last is None or self._last[0] is not view:
            self._last = (view, self.allocate(view))
        return self._last[1]

    def allocate(self, view: FleetView) -> list[list[int]]:
        """Every robot's plan (instruction indices in order) after the auction."""
        p = self.problem
        plans: list[list[int]] = [[] for _ in view.nodes]
        planned = dict(view.done)            # index -> (planned) completion time
        open_items = [int(i) for i in view.open]
        insertion = len(open_items) <= self.config.insertion_limit
        values = [0.0] * len(plans)
        while True:
            ready = [i for i in open_items if i not in planned and (
                p.predecessor[i] < 0 or int(p.predecessor[i]) in planned)]
            if not ready:
                return plans
            if insertion:
                r, plan, finish, value = self._best_insertion(view, plans, values, planned,
                                                              ready)
            else:
                r, plan, finish, value = self._best_append(view, plans, values, planned, ready)
            plans[r], values[r] = plan, value
            planned.update(zip(plan, finish))

    def _best_insertion(self, view: FleetView, plans: Sequence[list[int]], values: Sequence[float],
                        planned: dict[int, float],
                        ready: Sequence[int]) -> tuple[int, list[int], list[float], float]:
        best: tuple[float, int, list[int], list[float], float] | None = None
        for r, plan in enumerate(plans):
            for i in ready:
                before = int(self.problem.predecessor[i])
                lowest = plan.index(before) + 1 if before in plan else 0
                for at in range(lowest, len(plan) + 1):
                    trial = plan[:at] + [i] + plan[at:]
                    finish, value = self._timeline(view, r, trial, planned)
                    gain = value - values[r]
                    if best is None or gain > best[0] + _TIE:
                        best = (gain, r, trial, finish, value)
        if best is None:
            raise ValueError("auction: no robot bid for the ready instructions")
        return best[1:]

    def _best_append(self, view: FleetView, plans: Sequence[list[int]], values: Sequence[float],
                     planned: dict[int, float],
                     ready: Sequence[int]) -> tuple[int, list[int], list[float], float]:
        """Append bids of every robot for every ready instruction, as arrays."""
        p = self.problem
        items = np.array(ready)
        ends = [self._end(view, r, plan, planned) for r, plan in enumerate(plans)]
        node = np.array([e[0] for e in ends])
        clock = np.array([e[1] for e in ends])
        before = p.predecessor[items]
        after = np.array([planned.get(int(b), 0.0) if b >= 0 else 0.0 for b in before])
        finish = np.maximum(np.maximum(clock[:, None] + p.travel_s[node][:, p.node[items]],
                                       p.launch[items]), after) + p.duration[items]
        gain = decayed_reward(p.gamma[items], p.beta[items], finish - p.launch[items])
        rate = gain / np.maximum(finish - clock[:, None], _MIN_STEP_S)
        row, k = np.unravel_index(int(np.argmax(rate)), rate.shape)
        r = int(row)
        plan = plans[r] + [int(items[k])]
        finish_r, value = self._timeline(view, r, plan, planned)
        return r, plan, finish_r, value

    def _end(self, view: FleetView, r: int, plan: Sequence[int],
             planned: dict[int, float]) -> tuple[int, float]:
        if not plan:
            return view.nodes[r], view.clocks[r]
        return int(self.problem.node[plan[-1]]), planned[plan[-1]]

    def _timeline(self, view: FleetView, r: int, plan: Sequence[int],
                  planned: dict[int, float]) -> tuple[list[float], float]:
        """(completion times, reward) of robot r serving `plan` from where it is free."""
        p = self.problem
        node, clock, value = view.nodes[r], view.clocks[r], 0.0
        finish: list[float] = []
        own: dict[int, float] = {}
        for i in plan:
            before = int(p.predecessor[i])
            after = own.get(before, planned.get(before, 0.0)) if before >= 0 else 0.0
            clock = service_end(p, node, clock, i, after)
            node = int(p.node[i])
            own[i] = clock
            finish.append(clock)
            value += p.gamma[i] * p.beta[i] ** (clock - p.launch[i])   # Eq. 4-2, scalar: hot loop
        return finish, value

    def _best_alone(self, view: FleetView, available: np.ndarray) -> int:
        """The available instruction that earns robot `view.robot` most, served next."""
        p, r = self.problem, view.robot
        finish = np.maximum(view.clocks[r] + p.travel_s[view.nodes[r], p.node[available]],
                            p.launch[available]) + p.duration[available]
        gain = decayed_reward(p.gamma[available], p.beta[available], finish - p.launch[available])
        return int(available[int(np.argmax(gain))])
