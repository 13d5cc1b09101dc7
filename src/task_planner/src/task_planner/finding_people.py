"""How the executor finds people (ROS-free): it looks around a place (turns in place while
perception watches), searches for a person who is not where it believed them, serves people where
its belief puts them, patrols when idle, and lets a person's request interrupt what it does for
itself (thesis 000 §4.2.1: the robot wanders and observes the household when it is unoccupied).

A mixin of task_planner.executor.Executor: it works on the executor's state (buffer, graph,
people, mode, looking, search, searched, looked_s, config) and returns commands.
"""
import math

from task_planner.executor_commands import (EXECUTING, IDLE, LOOKING, MOVING, Navigate, Say,
                                            Search, StopMotion, Wait)
from task_planner.instruction import ROBOT
from task_planner.people_belief import patrol_target, search_order
from task_planner.robot_functions import function_for


class FindingPeople:
    """Looks, searches, patrol and giving way, for the Executor."""

    def _yield_own(self, now):
        """With `own_yields`, a person's request interrupts what the robot does for an
        instruction it gave itself (unless its function is in `own_kept`): back to pending,
        served later."""
        if not self.config.own_yields or self.mode not in (EXECUTING, LOOKING):
            return []
        instruction_id = self.executing[0] if self.mode == EXECUTING else self.looking[0]
        if not instruction_id:
            return []
        instruction = self.buffer.get(instruction_id).instruction
        function = self.functions.get(instruction.function)
        if instruction.type != ROBOT or function is None or function.name in self.config.own_kept:
            return []
        if self.mode == EXECUTING:
            self.buffer.requeue(instruction_id)
        self._deferred.add(instruction_id)
        self.mode, self.executing, self.looking = IDLE, None, None
        self.log.append((now, f"{instruction_id} waits: a person asked for something"))
        return [StopMotion(), Say(self.config.yield_notice)]

    def _where(self, instruction):
        """Where to serve an instruction. Following the belief: where its person was last seen,
        else the next place of their search (planned once, from where the robot is, so the goal
        does not change as the robot moves). Otherwise: the place being searched, else its
        destination."""
        target, key = instruction.target, instruction.id
        if self.config.follow_belief and target:
            seen = self.people.now.get(target)
            if seen is not None:
                return seen
            if key not in self.search and self.config.search_all_places:
                self.search[key] = search_order(target, self.people, self.looked_s,
                                                range(self.graph.size),
                                                self.searched.get(key, ()),
                                                self.graph.shortest[self.node])
        queue = self.search.get(key)
        return queue[0] if queue else instruction.destination

    def _search_next(self, instruction, now):
        """Person not here: go on to their next last known place, or fail having searched all."""
        searched = self.searched.setdefault(instruction.id, [])
        if not searched:
            self._search_start[instruction.id] = now
        searched.append(self.node)
        self.people.missed(instruction.target, self.node)
        if self.config.search_all_places:
            queue = search_order(instruction.target, self.people, self.looked_s,
                                 range(self.graph.size), searched, self.graph.shortest[self.node])
        else:
            queue = self.search.get(instruction.id)
            if queue is None:  # first miss, at the instruction's own destination
                queue = self.people.last_known_places(instruction.target)
            queue = [p for p in queue if p not in searched]
        if queue:
            self.search[instruction.id] = queue
            self.log.append((now, f"{instruction.target} not at {self.graph.names[self.node]}; "
                                  f"search {self.graph.names[queue[0]]}"))
            return []
        looked = ", ".join(self.graph.names[n] for n in searched)
        self._end_search(instruction, now, found=False)
        return self._fail(instruction.id, now,
                          f"{instruction.target} not found (searched {looked})")

    def _end_search(self, instruction, now, found):
        """Keep a finished search (one that missed the person at least once) for the report."""
        places = self.searched.get(instruction.id)
        if not places:
            return
        names = [self.graph.names[n] for n in places]
        self.buffer.store_search(Search(
            instruction.id, instruction.target, self._search_start.pop(instruction.id, now), now,
            found, tuple(names + [self.graph.names[self.node]] if found else names)))

    def _start_look(self, instruction_id, now):
        """Turn through `look_headings` headings on this node (evenly spaced after the one the
        robot arrived with), perception watching meanwhile."""
        count = max(1, self.config.look_headings)
        yaw = float(self.graph.poses[self.node][2])
        headings = [yaw + 2.0 * math.pi * k / (count + 1) for k in range(1, count + 1)]
        self.mode, self.looking = LOOKING, [instruction_id, headings[1:], now, None]
        what = (f"for {self.buffer.get(instruction_id).instruction.target}" if instruction_id
                else "(patrol)")
        self.log.append((now, f"look around {self.graph.names[self.node]} {what}"))
        return [Navigate(self.node, instruction_id, yaw=headings[0])]

    def _look_step(self, now):
        """A heading of the look was reached: dwell on it while perception catches up (the
        camera sees little while turning), then turn to the next one or end the look."""
        if self.config.look_dwell_s > 0 and self.looking[3] is None:
            self.looking[3] = now + self.config.look_dwell_s
            return [Wait(self.looking[3])]
        self.looking[3] = None
        instruction_id, headings = self.looking[:2]
        if headings:
            self.looking[1] = headings[1:]
            return [Navigate(self.node, instruction_id, yaw=headings[0])]
        return self._end_look(now)

    def _end_look(self, now):
        """The look is over without finding an instruction's person: search on (or decide)."""
        instruction_id = self.looking[0]
        self.looked_s[self.node] = now
        self.mode, self.looking = IDLE, None
        if not instruction_id:
            self._patrol_goal = None
            return self._decide(now)
        record = self.buffer.get(instruction_id)
        if not record.is_open:
            return self._decide(now)
        return self._search_next(record.instruction, now) + self._decide(now)

    def _look_found(self, now):
        """While looking for an instruction's person: serve them once perception sees them."""
        instruction_id, _, since, _ = self.looking
        if not instruction_id:
            return []
        instruction = self.buffer.get(instruction_id).instruction
        if not self.people.is_at(instruction.target, self.node, since):
            return []
        self.mode, self.looking = IDLE, None
        self.looked_s[self.node] = now
        return [StopMotion()] + self._execute(instruction,
                                              function_for(self.functions, instruction), now)

    def _patrol(self, now):
        """Idle: drive to the stalest, likeliest occupied place and look around it."""
        target = patrol_target(range(self.graph.size), self.people, self.looked_s, now,
                               self.config.patrol_interval_s, self.graph.shortest[self.node],
                               self.config.never_looked_s)
        if target is None:
            return []
        if target == self.node:
            return self._start_look(0, now)
        step = int(self.graph.next_hop[self.node, target])
        if self._patrol_goal != target:
            self.log.append((now, f"patrol to {self.graph.names[target]}"))
        self._patrol_goal = target
        self.mode, self.goal, self.goal_for, self.attempts = MOVING, step, 0, 1
        return [Navigate(step, 0)]
