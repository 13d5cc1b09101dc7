"""The TAMP executor of thesis 000 §4.2.5 (Fig. 4-14) as a ROS-free state machine.

Instruction cycle: perceptions are written into the task buffer; the executor *fetches* the open
instructions, *decodes* them into a planning problem (reward, decay factor, destination, chains),
asks the configured planner for a *decision*, hands the next neighbouring node to the motion
planner as a navigation goal (*execute*), and on completion *writes back* to the task buffer.

The executor never waits: its inputs are events with the current time (`receive`, `arrived`,
`aborted`, `tick`, `cancel`) and its outputs are commands (`Navigate`, `Execute`, `Say`) for the
node (move_base, /robot/say) or an in-process model to carry out. Rules beyond the seed:
- new instructions re-decide at once; while driving, the decision is taken from the node just left
  and may turn the robot back mid-edge (§4 "dynamic");
- a navigation abort is retried `max_goal_attempts` times, then the instruction the move was for
  fails with the reason and the robot decides again;
- on arrival the target person must be at the place (`people.is_at`): if not, the robot looks
  for them there for `verify_wait_s` (perception updates the people meanwhile), then searches
  their last known places in turn (the instruction is served where they are found) and fails
  when none is left. A person nobody has located is not at the place either: once the wait is
  over there is nowhere else to look, and the instruction fails ("<name> not found").
"""
import time
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from task_planner.battery import charge_instruction
from task_planner.problem import Problem
from task_planner.robot_functions import RobotFunctionError, function_for
from task_planner.task_buffer import PENDING

IDLE, MOVING, EXECUTING, VERIFYING = "idle", "moving", "executing", "verifying"
BATTERY_KEY = "battery_level_wh"   # robot_state entry of the journal


@dataclass(frozen=True)
class ExecutorConfig:
    speed_mps: float = 0.5        # robot speed along graph edges, for the planners [m/s]
    max_goal_attempts: int = 3    # navigation attempts per goal before its instruction fails
    latency_window: int = 1000    # decisions whose wall time is kept (decision_s)
    battery_save_wh: float = 0.5  # journal the battery level when it moved this much [Wh]
    verify_wait_s: float = 0.0    # look for an absent target person this long on arrival [s]


@dataclass(frozen=True)
class Charging:
    """The low-battery rule: where to charge, with which function code and priority."""

    battery: object        # battery.BatteryModel
    place: int             # charging place (graph node)
    function_code: int     # robot function `charge`
    priority: object       # reward.Priority of self-generated instructions (Table 5-5)


@dataclass(frozen=True)
class Navigate:
    """Send the robot to graph node `node` (a neighbour of where it is, or the node just left)."""

    node: int
    instruction_id: int  # the instruction this move is for (0 when none)


@dataclass(frozen=True)
class Execute:
    """Run robot function `function` for `instruction_id` for `duration_s` seconds."""

    instruction_id: int
    function: str
    duration_s: float


@dataclass(frozen=True)
class Verify:
    """Look for person `target` at the robot's place until `until_s` [s], then decide again."""

    instruction_id: int
    target: str
    until_s: float


@dataclass(frozen=True)
class Say:
    text: str


def latency_ms(samples_s):
    """(median, 95th percentile, max) [ms] of wall times [s]; zeros when there are none."""
    if not len(samples_s):
        return 0.0, 0.0, 0.0
    ms = 1000.0 * np.asarray(samples_s, dtype=float)
    return float(np.median(ms)), float(np.percentile(ms, 95)), float(ms.max())


def nearest_node(graph, x, y):
    """The graph node whose pose is closest to (x, y) [m]: where a restarted robot stands."""
    poses = np.asarray(graph.poses, dtype=float)  # (V, 3) x, y, yaw [m, m, rad]
    return int(np.argmin(np.hypot(poses[:, 0] - x, poses[:, 1] - y)))


class PeopleAtPlaces:
    """Where each person is now (graph node, or None when out of sight) and was before.

    The executor node fills it from human_db (/humans/known and its history); the in-process model
    fills it from its scenario.
    """

    def __init__(self, now=None, before=None):
        self.now = dict(now or {})        # name -> node the person is at now, None = not seen
        self.before = {name: list(places) for name, places in (before or {}).items()}
        # name -> earlier nodes, most recent first

    def knows(self, name):
        """True once the person has been seen anywhere (or reported out of sight)."""
        return name in self.now or bool(self.before.get(name))

    def is_at(self, name, node):
        return self.now.get(name) == node

    def last_known_places(self, name):
        """Current place first, then earlier ones, each once."""
        places = [self.now.get(name)] + self.before.get(name, [])
        return list(dict.fromkeys(p for p in places if p is not None))

    def seen(self, name, node):
        """`name` is now at `node` (None: out of sight); the previous place becomes history."""
        previous = self.now.get(name)
        if previous is not None and previous != node:
            self.before[name] = [previous] + [p for p in self.before.get(name, [])
                                              if p != previous]
        self.now[name] = node


class Executor:
    """Fetch → decode → decide → navigate → verify → execute → write back (Fig. 4-14)."""

    def __init__(self, buffer, graph, planner, people, functions, config=None, start_node=0,
                 charging=None):
        self.buffer, self.graph, self.planner = buffer, graph, planner
        self.charging = charging         # Charging, or None for a robot without a battery model
        self.people, self.functions = people, functions
        self.config = config or ExecutorConfig()
        self.node = int(start_node)      # last node reached
        self.mode = IDLE
        self.goal = None                 # node being driven to while MOVING
        self.goal_for = 0                # instruction id the current move is for
        self.attempts = 0                # navigation attempts on the current goal
        self.executing = None            # (instruction id, end time [s]) while EXECUTING
        self.verifying = None            # (instruction id, give-up time [s]) while VERIFYING
        self.search = {}                 # instruction id -> places still to search, next first
        self.searched = {}               # instruction id -> places already searched
        self.log = []                    # (time [s], event text): why each move was made
        self._problem_key, self._problem = None, None
        self._target = None              # (problem, index) a target planner is driving to
        # wall and thread CPU time [s] of the latest decisions (fetch + decode + decide, no
        # journal writes); CPU time leaves out waiting for a core on a loaded machine
        self.decision_s = deque(maxlen=self.config.latency_window)
        self.decision_cpu_s = deque(maxlen=self.config.latency_window)
        self._saved_wh = None            # battery level last journalled [Wh]
        if charging is not None:         # a restarted executor resumes the journalled level
            battery = charging.battery
            battery.level_wh = min(battery.config.capacity_wh,
                                   buffer.robot_value(BATTERY_KEY, battery.level_wh))
            self._save_battery(force=True)

    # ---- events ----

    def receive(self, instructions, now):
        """Journal new instructions (one transaction) and re-decide; returns (results, commands)."""
        self._drain(now)
        results = self.buffer.submit_many(instructions, now)
        for record, error in results:
            self.log.append((now, f"refused: {error}" if error else
                             f"received {record.instruction.id}"))
        if not any(record is not None for record, _ in results):
            return results, []
        return results, self._redecide(now)

    def tick(self, now):
        """Periodic step: finish an execution whose time is up, or decide when idle."""
        commands = self._check_battery(now)
        if self.mode == EXECUTING and now >= self.executing[1]:
            instruction_id = self.executing[0]
            record = self.buffer.finish(instruction_id, now)
            if self.charging and record.instruction.function == self.charging.function_code:
                self.charging.battery.charge(record.instruction.duration)
                self._save_battery(force=True)
            self.search.pop(instruction_id, None)
            self.searched.pop(instruction_id, None)
            self.log.append((now, f"done {instruction_id}: reward {record.reward_earned:.3f}"))
            self.mode, self.executing = IDLE, None
        if self.mode == VERIFYING:
            commands += self._verify(now)
        if self.mode == IDLE:
            return commands + self._decide(now)
        return commands

    def _drain(self, now):
        """Spend the battery energy of the mode the robot was in until `now`."""
        if self.charging is None:
            return
        busy_charging = self.mode == EXECUTING and self.buffer.get(
            self.executing[0]).instruction.function == self.charging.function_code
        mode = IDLE if self.mode == VERIFYING else self.mode   # looking around: standing still
        self.charging.battery.drain("charging" if busy_charging else mode, now)
        self._save_battery()

    def _save_battery(self, force=False):
        """Journal the battery level when it changed by battery_save_wh (or when forced)."""
        level = self.charging.battery.level_wh
        if force or self._saved_wh is None or \
                abs(level - self._saved_wh) >= self.config.battery_save_wh:
            self.buffer.store_robot_value(BATTERY_KEY, level)
            self._saved_wh = level

    def _check_battery(self, now):
        """When the battery is low, give the robot a 'go charge' instruction (once)."""
        if self.charging is None:
            return []
        self._drain(now)
        charging = self.charging
        battery = charging.battery
        open_charge = any(r.instruction.function == charging.function_code
                          for r in self.buffer.open_records())
        if not battery.is_low() or open_charge:
            return []
        base = battery.config.self_id_base
        next_id = max((r.instruction.id for r in self.buffer.records()
                       if r.instruction.id >= base), default=base - 1) + 1
        instruction = charge_instruction(next_id, now, charging.place,
                                         self.graph.names[charging.place], charging.priority,
                                         battery, charging.function_code)
        self.log.append((now, f"battery low ({100 * battery.fraction:.0f} %): charge"))
        return self.receive([instruction], now)[1]

    def arrived(self, now):
        """The navigation goal was reached."""
        if self.mode != MOVING:
            raise RuntimeError(f"arrival reported while {self.mode}")
        self._drain(now)
        self.node, self.mode, self.goal = self.goal, IDLE, None
        self.log.append((now, f"at {self.graph.names[self.node]}"))
        commands = self._check_battery(now)
        return commands + (self._decide(now) if self.mode == IDLE else [])

    def aborted(self, now, reason):
        """Navigation gave up on the goal: retry it, then fail the instruction it was for."""
        if self.mode != MOVING:
            raise RuntimeError(f"abort reported while {self.mode}")
        self._drain(now)
        if self.attempts < self.config.max_goal_attempts:
            self.attempts += 1
            self.log.append((now, f"retry {self.attempts} to {self.graph.names[self.goal]}"))
            return [Navigate(self.goal, self.goal_for)]
        goal, self.mode, self.goal = self.goal, IDLE, None
        if self.goal_for and self.buffer.get(self.goal_for).is_open:
            self._fail(self.goal_for, now,
                       f"navigation to {self.graph.names[goal]} aborted "
                       f"{self.config.max_goal_attempts} times: {reason}")
        return self._decide(now)

    def cancel(self, instruction_id, now):
        """Withdraw an instruction; the robot stops its function if it was executing it."""
        self._drain(now)
        record = self.buffer.cancel(instruction_id, now)
        if self.mode == EXECUTING and self.executing[0] == instruction_id:
            self.mode, self.executing = IDLE, None
        if self.mode == VERIFYING and self.verifying[0] == instruction_id:
            self.mode, self.verifying = IDLE, None
        self.log.append((now, f"cancelled {instruction_id}"))
        return record, self._redecide(now)

    # ---- decision ----

    def _redecide(self, now):
        if self.mode == IDLE:
            return self._decide(now)
        if self.mode != MOVING:
            return []  # a robot function (or the look for its person) is not interrupted
        decision = self._timed_decision(now)
        if decision is None:
            return []
        problem, index, step = decision
        if step == self.goal:
            return []
        # Any other decision goes through the node just left: turn back to it mid-edge.
        self.node, self.goal = self.goal, self.node
        self.goal_for, self.attempts = int(problem.ids[index]), 1
        self.log.append((now, f"turn back to {self.graph.names[self.goal]} for {self.goal_for}"))
        return [Navigate(self.goal, self.goal_for)]

    def _decide(self, now):
        """Fetch, decode, decide at the robot's node; returns the commands of the decision."""
        commands = []
        while True:
            decision = self._timed_decision(now)
            if decision is None:
                return commands
            problem, index, step = decision
            instruction_id = int(problem.ids[index])
            if step is None:
                commands += self._serve(instruction_id, now)
                if self.mode in (EXECUTING, VERIFYING):
                    return commands
                continue  # failed, or the person is searched elsewhere: decide again
            self.mode, self.goal, self.goal_for, self.attempts = MOVING, step, instruction_id, 1
            self.log.append((now, f"move {self.graph.names[self.node]} -> "
                                  f"{self.graph.names[step]} for {instruction_id}"))
            return commands + [Navigate(step, instruction_id)]

    def _timed_decision(self, now):
        """Fetch, decode and decide at the robot's node, timed: (problem, index, next node), or
        None when nothing is eligible."""
        started, started_cpu = time.perf_counter(), time.thread_time()
        problem, available = self._fetch_and_decode()
        decision = None
        if len(available):
            index, step = self._ask_planner(problem, self.node, now, available)
            decision = problem, index, step
        self.decision_s.append(time.perf_counter() - started)
        self.decision_cpu_s.append(time.thread_time() - started_cpu)
        return decision

    def _fetch_and_decode(self):
        """Fig. 4-14 fetch + decode: the open instructions as a Problem, and the eligible indices.

        A searched instruction's destination is the place being searched. The planner is reset
        only when the instruction set changes, so its per-set memory (the loop guard) holds.
        """
        pending = [r for r in self.buffer.open_records() if r.state == PENDING]
        instructions = tuple(replace(r.instruction, destination=self.search[r.instruction.id][0])
                             if r.instruction.id in self.search else r.instruction
                             for r in pending)
        if instructions != self._problem_key:
            self._problem = Problem(self.graph, instructions, self.config.speed_mps, self.node)
            self._problem_key = instructions
            self.planner.reset(self._problem)
        done = self.buffer.done_ids()  # a successor waits for its predecessor (task_buffer)
        available = np.array([k for k, r in enumerate(pending) if r.instruction.previous_id == 0
                              or r.instruction.previous_id in done], dtype=int)
        return self._problem, available

    def _ask_planner(self, problem, node, now, available):
        """(instruction index, next node), next node None when the decision is to serve here."""
        if hasattr(self.planner, "decide"):  # node planner (the seed's, Algorithm 4-2)
            action, value = self.planner.decide(node, now, available)
            if action == "serve":
                return int(value), None
            return self._heading(problem, node, value, available), int(value)
        # Target planner: ask once per target; keep driving to it until the set changes.
        kept = self._target
        if kept is not None and kept[0] is problem and kept[1] in available:
            index = kept[1]
        else:
            index = int(self.planner.choose(node, now, available))
            self._target = (problem, index)
        if problem.node[index] == node:
            return index, None
        return index, int(self.graph.next_hop[node, problem.node[index]])

    def _heading(self, problem, node, neighbour, available):
        """The instruction a node planner's move serves: strongest Eq. 4-2 term through it."""
        nodes = problem.node[available]
        through = available[self.graph.next_hop[node, nodes] == neighbour]
        candidates = through if len(through) else available
        travel_s = problem.travel_s[node, problem.node[candidates]]
        terms = problem.gamma[candidates] * np.power(problem.beta[candidates], travel_s)
        return int(candidates[int(np.argmax(terms))])

    # ---- serve (verify, execute) ----

    def _serve(self, instruction_id, now):
        """Verify the target person is here, then execute the robot function (or search/fail)."""
        instruction = self.buffer.get(instruction_id).instruction
        try:
            function = function_for(self.functions, instruction)
        except RobotFunctionError as error:
            return self._fail(instruction_id, now, str(error))
        target = instruction.target
        if target and not self.people.is_at(target, self.node):
            if self.config.verify_wait_s > 0:
                until = now + self.config.verify_wait_s
                self.mode, self.verifying = VERIFYING, (instruction_id, until)
                self.log.append((now, f"look for {target} at {self.graph.names[self.node]}"))
                return [Verify(instruction_id, target, until)]
            return self._search_next(instruction, now)
        return self._execute(instruction, function, now)

    def _verify(self, now):
        """While looking for the target person: execute once they are here, else search on."""
        instruction_id, until = self.verifying
        record = self.buffer.get(instruction_id)
        if self.people.is_at(record.instruction.target, self.node):
            self.mode, self.verifying = IDLE, None
            return self._execute(record.instruction,
                                 function_for(self.functions, record.instruction), now)
        if now < until:
            return []
        self.mode, self.verifying = IDLE, None
        return self._search_next(record.instruction, now)

    def _execute(self, instruction, function, now):
        """Start the robot function of `instruction` here (PENDING -> ACTIVE)."""
        instruction_id = instruction.id
        self.buffer.start(instruction_id, now)
        self.mode, self.executing = EXECUTING, (instruction_id, now + instruction.duration)
        place = self.graph.names[self.node]
        self.log.append((now, f"execute {function.name} for {instruction_id} at {place}"))
        return [Execute(instruction_id, function.name, float(instruction.duration)),
                Say(function.speech(instruction, place))]

    def _search_next(self, instruction, now):
        """Person not here: go on to their next last known place, or fail having searched all."""
        searched = self.searched.setdefault(instruction.id, [])
        searched.append(self.node)
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
        return self._fail(instruction.id, now,
                          f"{instruction.target} not found (searched {looked})")

    def _fail(self, instruction_id, now, reason):
        self.buffer.fail(instruction_id, now, reason)
        self.search.pop(instruction_id, None)
        self.searched.pop(instruction_id, None)
        self.log.append((now, f"failed {instruction_id}: {reason}"))
        return [Say(f"Sorry, I could not complete request {instruction_id}.")]
