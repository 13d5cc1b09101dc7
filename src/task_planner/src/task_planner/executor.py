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
- on arrival the target person must have been seen at the place (`people.is_at`, a sighting
  at most `fresh_s` old): if not, the robot looks around (`look_headings` turns in place; or,
  with none, stands for `verify_wait_s`) while perception updates the people, then searches on
  (`people_belief.search_order`: last seen place, the schedule's place, then every other place
  stalest first; with `search_all_places` off only their last known places) and serves the
  instruction where they are found; it fails when no place is left ("<name> not found");
- a navigation abort may be a person in the way: with `pass_wait_s` the robot asks to pass,
  waits, and only then retries;
- a successor whose predecessor has not arrived `predecessor_wait_s` (task buffer) after it
  fails with a reason naming the predecessor, and the robot says it could not complete it;
- with `patrol` on, an idle robot looks at the stalest, most likely occupied place
  (`people_belief.patrol_target`) and drops the patrol as soon as an instruction arrives;
- with a `fleet` (fleet_link.FleetLink) the robot shares what it receives, takes in what the
  other robots received, decides among the instructions no other robot holds, claims its choice
  before it drives for it, and closes in its journal what another robot closed; a robot holds
  a corridor (`corridors`, narrow places) before it drives into it and waits while another
  robot is in it, at most `corridor_wait_s`, then drives on (its move_base passes the other);
  with `one_robot_per_place` it leaves the instructions at a place to the robot that holds one
  there. At its first event, and after a fault or a failed pool write, it rejoins the fleet
  from its journal (FleetLink.rejoin), keeping what it serves; its charging instructions stay
  its own.
"""
import math
import time
from collections import deque
from dataclasses import dataclass, replace

import numpy as np

from task_planner.battery import charge_instruction
from task_planner import fleet_pool
from task_planner.executor_commands import (EXECUTING, IDLE, LOOKING, MOVING, VERIFYING, Execute,
                                            Navigate, Say, StopMotion, Verify, Wait)
from task_planner.finding_people import FindingPeople
from task_planner.instruction import HUMAN, ROBOT
from task_planner.planner_api import NODE, STEP, kind_of
from task_planner.problem import Problem
from task_planner.robot_functions import RobotFunctionError, function_for
from task_planner.task_buffer import ACTIVE, PENDING

BATTERY_KEY = "battery_level_wh"   # robot_state entry of the journal


@dataclass(frozen=True)
class ExecutorConfig:
    speed_mps: float = 0.5        # robot speed along graph edges, for the planners [m/s]
    max_goal_attempts: int = 3    # navigation attempts per goal before its instruction fails
    latency_window: int = 1000    # decisions whose wall time is kept (decision_s)
    battery_save_wh: float = 0.5  # journal the battery level when it moved this much [Wh]
    verify_wait_s: float = 0.0    # look for an absent target person this long on arrival [s]
    look_headings: int = 0        # turns in place to look around a place (0: stand, as above)
    look_dwell_s: float = 0.0     # stay on each heading this long, perception catching up [s]
    fresh_s: float = math.inf     # a sighting this old counts as "the person is here" [s]
    search_all_places: bool = False  # search every place, not only the last known ones
    follow_belief: bool = False   # serve a person where the robot believes them (else: where
                                  # the instruction says, until a search begins)
    pass_wait_s: float = 0.0      # after an abort ask to pass and wait this long [s] (0: no)
    pass_request: str = "Excuse me, may I pass?"
    patrol: bool = False          # look at stale places while idle
    own_yields: bool = False      # a person's request interrupts the robot's own instruction
    own_kept: tuple = ("charge", "introduce")  # own functions that are never interrupted
    yield_notice: str = "Excuse me, I am needed elsewhere. I will be back."
    patrol_interval_s: float = 60.0  # a place looked at this recently is not patrolled [s]
    never_looked_s: float = 600.0  # how stale the patrol takes a place never looked at [s]
    corridors: tuple = ()         # graph nodes one robot of a fleet at a time drives through
    corridor_wait_s: float = 60.0  # wait this long for a corridor, then drive on [s]
    corridor_poll_s: float = 1.0  # look again whether the corridor is free this often [s]
    one_robot_per_place: bool = False  # in a fleet, leave the instructions at a place to the
                                  # robot that holds one there (small rooms fit one robot)


@dataclass(frozen=True)
class Charging:
    """The low-battery rule: where to charge, with which function code and priority."""

    battery: object        # battery.BatteryModel
    place: int             # charging place (graph node)
    function_code: int     # robot function `charge`
    priority: object       # reward.Priority of self-generated instructions (Table 5-5)


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


class Executor(FindingPeople):
    """Fetch → decode → decide → navigate → verify → execute → write back (Fig. 4-14)."""

    def __init__(self, buffer, graph, planner, people, functions, config=None, start_node=0,
                 charging=None, fleet=None):
        self.buffer, self.graph, self.planner = buffer, graph, planner
        self.fleet = fleet               # FleetLink, or None for a robot on its own
        self._lost_claims = set()        # ids another robot held when this one claimed them
        if kind_of(planner) == STEP:
            raise ValueError(f"planner {planner.name!r} decides every step along an edge; the "
                             f"executor drives whole edges and runs node or target planners")
        self._node_planner = kind_of(planner) == NODE  # else a target planner (planner_api)
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
        self.looking = None              # [instruction id (0: patrol), headings left, since,
                                         #  end of the last heading's dwell (None: turning)]
        self.looked_s = {}               # node -> when the robot last looked around it [s]
        self.retry_at = None             # when to retry an aborted goal after asking to pass, or
                                         # to look again whether a corridor is free
        self._corridor_wait = None       # since when the robot waits for a corridor [s]
        self._search_start = {}          # instruction id -> when its search began [s]
        self._deferred = set()           # own instructions waiting while people's are open
        self.log = []                    # (time [s], event text): why each move was made
        self._problem_key, self._problem = None, None
        self._target = None              # (problem, index) a target planner is driving to
        # wall and thread CPU time [s] of the latest decisions (fetch + decode + decide, no
        # journal writes); CPU time leaves out waiting for a core on a loaded machine
        self.decision_s = deque(maxlen=self.config.latency_window)
        self.decision_cpu_s = deque(maxlen=self.config.latency_window)
        self._saved_wh = None            # battery level last journalled [Wh]
        self._patrol_goal = None         # place an idle patrol is driving to
        if charging is not None:         # a restarted executor resumes the journalled level
            battery = charging.battery
            battery.level_wh = min(battery.config.capacity_wh,
                                   buffer.robot_value(BATTERY_KEY, battery.level_wh))
            self._save_battery(force=True)
        self._in_fleet = False           # rejoined the fleet (at the first event with a time)
        self._owed = []                  # commands of an event that raised afterwards

    # ---- events ----

    def new_id(self, previous_id=0):
        """The id for an instruction whose sender lets the robot choose (its fleet's, if any)."""
        own = self.buffer.next_id(previous_id)
        return self.fleet.next_id(own - 1) if self.fleet else own

    def receive(self, instructions, now):
        """Journal new instructions (one transaction), share them with the fleet and re-decide;
        returns (results, commands)."""
        self._drain(now)
        if self.fleet is None:
            return self._take_in(self.buffer.submit_many(instructions, now), now)
        commands = self._fleet_sync(now)
        try:
            # under the pool's write lock from the id check to the share: an id the pool holds
            # for another instruction is refused before it is journalled
            with self.fleet.transaction():
                refused = self.fleet.conflicts(instructions)
                journalled = iter(self.buffer.submit_many(
                    [i for i in instructions if i.id not in refused], now))
                results = [(None, refused[i.id]) if i.id in refused else next(journalled)
                           for i in instructions]
                self.fleet.share([record.instruction for record, _ in results if record])
        except Exception:
            self._in_fleet = False   # rolled back: the next event rejoins from the journal
            self._owed = commands    # the rejoin's stop goes out with the next tick
            raise
        results, decided = self._take_in(results, now)   # claims as at a tick, each committed
        return results, commands + decided

    def _fleet_sync(self, now):
        """At every event of a robot in a fleet: the commands an earlier event owes (it raised
        after ordering them), and those of a rejoin when one is due (_rejoin_fleet)."""
        if self.fleet is None:
            return []
        commands, self._owed = self._owed, []
        return commands + self._rejoin_fleet(now)

    def _rejoin_fleet(self, now):
        """After a start, a fault or a failed pool write: FleetLink.rejoin from the journal,
        claiming again the instruction the robot serves, where it serves it (its charging
        instructions stay its own), and hold again, one by one, the corridors it stands in or
        drives into. An open instruction whose id the fleet knows as another instruction fails
        here with the reason (serving it would serve the other: the robot stops); one another
        robot took meanwhile the robot stops serving and leaves open. Returns the commands."""
        if self._in_fleet:
            return []
        charge = self.charging.function_code if self.charging else None
        serving = self.serving()
        place = self._where(self.buffer.get(serving).instruction) if serving else -1
        clashes = self.fleet.rejoin(self.buffer.records(), lambda instruction: (
            instruction.type == ROBOT and instruction.function == charge),
            keep=serving, now=now, place=place)
        self._in_fleet = True
        commands = []
        if serving in clashes:
            commands = self.fault(now, clashes[serving], fail=False)
        elif serving and self.fleet.held != serving and serving not in self.fleet.local:
            self.log.append((now, f"lost {serving} to another robot"))
            commands = self.fault(now, f"instruction {serving} is another robot's now",
                                  fail=False)
        for instruction_id, reason in clashes.items():
            if self.buffer.get(instruction_id).is_open:
                self.buffer.fail(instruction_id, now, f"not served: {reason}")
                self.log.append((now, f"failed {instruction_id}: {reason}"))
        here = self._corridors_of((self.node,))
        ahead = self._corridors_of((self.goal,)) - here if self.mode == MOVING else set()
        for name in sorted(here) + sorted(ahead):   # one by one: each is held or not
            self.fleet.enter({name}, now)   # "" or another robot came in meanwhile: it leaves
        return commands

    def _take_in(self, results, now):
        """Log what was journalled or refused; a person's request interrupts the robot's own
        instruction; re-decide. Returns (results, commands)."""
        for record, error in results:
            self.log.append((now, f"refused: {error}" if error else
                             f"received {record.instruction.id}"))
        if not any(record is not None for record, _ in results):
            return results, []
        from_people = any(r is not None and r.instruction.type == HUMAN for r, _ in results)
        commands = self._yield_own(now) if from_people else []
        return results, commands + self._redecide(now)

    def tick(self, now):
        """Periodic step: finish an execution whose time is up, or decide when idle."""
        commands = self._fleet_news(now) if self.fleet else []
        commands += self._check_battery(now) + self._give_up_waiting(now)
        if self.mode == EXECUTING and now >= self.executing[1]:
            instruction_id = self.executing[0]
            record = self.buffer.finish(instruction_id, now)
            self._close_in_fleet(instruction_id, now, fleet_pool.DONE)
            if self.charging and record.instruction.function == self.charging.function_code:
                self.charging.battery.charge(record.instruction.duration)
                self._save_battery(force=True)
            self.search.pop(instruction_id, None)
            self.searched.pop(instruction_id, None)
            self.log.append((now, f"done {instruction_id}: reward {record.reward_earned:.3f}"))
            self.mode, self.executing = IDLE, None
        if self.mode == VERIFYING:
            commands += self._verify(now)
        if self.mode == LOOKING:
            commands += self._look_found(now)
        if self.mode == LOOKING and self.looking[3] is not None and now >= self.looking[3]:
            commands += self._look_step(now)
        if self.mode == MOVING and self.retry_at is not None and now >= self.retry_at:
            self.retry_at = None
            commands += self._drive(now)
        if self.mode == IDLE:
            return commands + self._decide(now)
        return commands

    def _fleet_news(self, now):
        """Take in what the other robots received, close what the pool holds closed, then
        decide on the news; renew the lease."""
        commands = self._fleet_sync(now)
        news = [i for i in self.fleet.news() if not self.buffer.holds(i.id)]
        results = self.buffer.submit_many(news, now) if news else []
        open_ids = [r.instruction.id for r in self.buffer.open_records()]
        for instruction_id, state, reason in self.fleet.closed_in_pool(open_ids):
            if self.buffer.get(instruction_id).is_open:   # not closed with its predecessor
                commands += self._drop(instruction_id, now, reason, lambda i, t, why, s=state:
                                       self.buffer.close_elsewhere(i, t, s, why))
        if results:
            commands += self._take_in(results, now)[1]
        self.fleet.renew(now)
        return commands

    def _close_in_fleet(self, instruction_id, now, state):
        if self.fleet is not None:
            trouble = self.fleet.close(instruction_id, now, state)
            if trouble:
                self.log.append((now, f"fleet: {trouble}"))

    def _give_up_waiting(self, now):
        """Fail successors whose predecessor never arrived (BufferConfig.predecessor_wait_s)."""
        commands = []
        for record in self.buffer.fail_missing_predecessors(now):
            self.log.append((now, f"failed {record.instruction.id}: {record.reason}"))
            commands.append(Say(f"Sorry, I could not complete request {record.instruction.id}."))
        return commands

    def _drain(self, now):
        """Spend the battery energy of the mode the robot was in until `now`."""
        if self.charging is None:
            return
        busy_charging = self.mode == EXECUTING and self.buffer.get(
            self.executing[0]).instruction.function == self.charging.function_code
        mode = IDLE if self.mode in (VERIFYING, LOOKING) else self.mode  # about on the spot
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
        instruction = charge_instruction(self.new_id(), now, charging.place,
                                         self.graph.names[charging.place], charging.priority,
                                         battery, charging.function_code)
        if self.fleet:   # the robot's own body: never another robot's to serve
            self.fleet.keep_local(instruction.id)
        self.log.append((now, f"battery low ({100 * battery.fraction:.0f} %): charge"))
        return self.receive([instruction], now)[1]

    def arrived(self, now):
        """The navigation goal was reached (or, while looking around, the heading)."""
        self._drain(now)
        stop = self._fleet_sync(now)
        if stop:
            return stop   # what it drove for is no longer its own: it stopped
        if self.mode == LOOKING:
            return self._look_step(now)
        if self.mode != MOVING:
            raise RuntimeError(f"arrival reported while {self.mode}")
        self.node, self.mode, self.goal = self.goal, IDLE, None
        self.log.append((now, f"at {self.graph.names[self.node]}"))
        if self.fleet:   # out of a corridor once the robot stands outside it
            self.fleet.leave(keep=self._corridors_of((self.node,)))
        commands = self._check_battery(now)
        if self.mode == IDLE and self.goal_for == 0 and self._patrol_goal == self.node:
            return commands + self._start_look(0, now)
        return commands + (self._decide(now) if self.mode == IDLE else [])

    def aborted(self, now, reason):
        """Navigation gave up on the goal: ask to pass and retry it, then fail the instruction
        it was for (a turn of a look around is skipped)."""
        self._drain(now)
        stop = self._fleet_sync(now)
        if stop:
            return stop   # what it drove for is no longer its own: it stopped
        if self.mode == LOOKING:
            return self._look_step(now)
        if self.mode != MOVING:
            raise RuntimeError(f"abort reported while {self.mode}")
        if self.attempts < self.config.max_goal_attempts:
            self.attempts += 1
            self.log.append((now, f"retry {self.attempts} to {self.graph.names[self.goal]}"))
            if self.config.pass_wait_s > 0:  # perhaps someone stands in the way
                self.retry_at = now + self.config.pass_wait_s
                return [Say(self.config.pass_request), Wait(self.retry_at)]
            return [Navigate(self.goal, self.goal_for)]
        goal, self.mode, self.goal = self.goal, IDLE, None
        if not self.goal_for and self._patrol_goal is not None:  # patrol elsewhere for now
            self.looked_s[self._patrol_goal], self._patrol_goal = now, None
        if self.goal_for and self.buffer.get(self.goal_for).is_open:
            self._fail(self.goal_for, now,
                       f"navigation to {self.graph.names[goal]} aborted "
                       f"{self.config.max_goal_attempts} times: {reason}")
        return self._decide(now)

    def cancel(self, instruction_id, now):
        """Withdraw an instruction (for the whole fleet); the robot stops its function if it was
        executing it. Returns (record, commands)."""
        self._drain(now)
        record = self.buffer.get(instruction_id)   # an unknown id is refused before anything
        rejoined = self._fleet_sync(now)
        if record.is_open:   # else buffer.cancel below refuses it
            # closed in the pool first: deciding anew gives back what the robot held, and no
            # other robot may claim it meanwhile
            self._close_in_fleet(instruction_id, now, fleet_pool.CANCELLED)
        commands = self._drop(instruction_id, now, "cancelled by request",
                              lambda i, t, why: self.buffer.cancel(i, t, why))
        return self.buffer.get(instruction_id), rejoined + commands

    def _drop(self, instruction_id, now, reason, close):
        """Close an open instruction with `close(id, now, reason)` and stop serving it."""
        close(instruction_id, now, reason)
        if self.mode == EXECUTING and self.executing[0] == instruction_id:
            self.mode, self.executing = IDLE, None
        if self.mode == VERIFYING and self.verifying[0] == instruction_id:
            self.mode, self.verifying = IDLE, None
        stop = []
        if self.mode == LOOKING and self.looking[0] == instruction_id:
            self.mode, self.looking, stop = IDLE, None, [StopMotion()]
        self.search.pop(instruction_id, None)
        self.searched.pop(instruction_id, None)
        self.log.append((now, f"closed {instruction_id}: {reason}"))
        return stop + self._redecide(now)

    def serving(self):
        """Id of the instruction the robot is moving for, looking for, verifying or executing
        (0 when idle or patrolling)."""
        if self.mode == MOVING:
            return self.goal_for
        if self.mode == LOOKING:
            return self.looking[0]
        if self.mode == VERIFYING:
            return self.verifying[0]
        if self.mode == EXECUTING:
            return self.executing[0]
        return 0

    def fault(self, now, reason, fail=True):
        """A step of the executor raised: fail the instruction being served with `reason` (it is
        journalled FAILED, so a restart never re-runs it), stop, and go idle. With `fail` off
        (another robot of the fleet holds it now) it is left open, not failed. Returns the
        commands; the next tick decides afresh."""
        instruction_id = self.serving()
        self.mode, self.goal, self.goal_for, self.attempts = IDLE, None, 0, 0
        self.executing = self.verifying = self.looking = self.retry_at = None
        self._corridor_wait = None
        self._patrol_goal = self._target = None
        self._problem_key = self._problem = None
        commands = [StopMotion()]
        if not fail:
            if instruction_id and self.buffer.get(instruction_id).state == ACTIVE:
                self.buffer.requeue(instruction_id)   # its function was cut short here
            self.log.append((now, f"stop: {reason}"))
            return commands
        self._in_fleet = False   # a pool write may have failed: the next event rejoins
        if instruction_id and self.buffer.get(instruction_id).is_open:
            commands += self._fail(instruction_id, now, f"fault while serving it: {reason}")
        else:
            self.log.append((now, f"fault: {reason}"))
        return commands

    # ---- decision ----

    def _redecide(self, now):
        if self.mode == LOOKING and self.looking[0] == 0:  # a patrol gives way at once
            self.mode, self.looking = IDLE, None
            return [StopMotion()] + self._decide(now)
        if self.mode == IDLE:
            return self._decide(now)
        if self.mode != MOVING or self.retry_at is not None:
            return []  # a robot function, the look for its person, a wait to pass go on
        self._lost_claims.clear()
        decision = self._timed_decision(now)
        if decision is None:
            return []
        problem, index, step = decision
        if self.fleet and not self.fleet.claim(int(problem.ids[index]), now,
                                               int(problem.node[index])):
            return []  # another robot took it first: drive on, the next event decides again
        if step == self.goal:
            # a patrol's move now serves the instruction; in a fleet the move serves the one
            # the robot claimed (the one before went back to the pool)
            if not self.goal_for or self.fleet:
                self.goal_for, self._patrol_goal = int(problem.ids[index]), None
            return []
        # Any other decision goes through the node just left: turn back to it mid-edge.
        self._patrol_goal = None
        self.node, self.goal = self.goal, self.node
        self.goal_for, self.attempts = int(problem.ids[index]), 1
        self.log.append((now, f"turn back to {self.graph.names[self.goal]} for {self.goal_for}"))
        return [Navigate(self.goal, self.goal_for)]

    def _decide(self, now):
        """Fetch, decode, decide at the robot's node; returns the commands of the decision."""
        commands = []
        self._lost_claims.clear()
        while True:
            decision = self._timed_decision(now)
            if decision is None:
                if self.fleet:
                    self.fleet.release()
                return commands + (self._patrol(now) if self.config.patrol else [])
            problem, index, step = decision
            instruction_id = int(problem.ids[index])
            if self.fleet and not self.fleet.claim(instruction_id, now, int(problem.node[index])):
                self._lost_claims.add(instruction_id)
                continue  # another robot took it first: choose among the rest
            if step is None:
                commands += self._serve(instruction_id, now)
                if self.mode in (EXECUTING, VERIFYING, LOOKING):
                    return commands
                continue  # failed, or the person is searched elsewhere: decide again
            self.mode, self.goal, self.goal_for, self.attempts = MOVING, step, instruction_id, 1
            self._patrol_goal = None
            self.log.append((now, f"move {self.graph.names[self.node]} -> "
                                  f"{self.graph.names[step]} for {instruction_id}"))
            return commands + self._drive(now)

    def _corridors_of(self, nodes):
        return {self.graph.names[n] for n in nodes if n in self.config.corridors}

    def _drive(self, now):
        """Navigate to the goal, once the robot holds the corridor it drives into (in a fleet);
        while another robot is in it, wait and look again, at most corridor_wait_s. A robot
        never waits for the corridor it stands in."""
        here = self._corridors_of((self.node,)) if self.fleet else set()
        needed = self._corridors_of((self.goal,)) - here if self.fleet else set()
        holder = self.fleet.enter(needed, now) if needed else ""
        if here:
            self.fleet.enter(here, now)   # kept while it leaves (unless another robot has it)
        if holder:
            since = self._corridor_wait if self._corridor_wait is not None else now
            if now - since < self.config.corridor_wait_s:
                if self._corridor_wait is None:
                    self.log.append((now, f"wait: {holder} is in {', '.join(sorted(needed))}"))
                self._corridor_wait = since
                self.retry_at = now + self.config.corridor_poll_s
                return [Wait(self.retry_at)]
            self.log.append((now, f"drive on after {now - since:.0f} s: {holder} stays in "
                                  f"{', '.join(sorted(needed))}"))
        self._corridor_wait = None
        return [Navigate(self.goal, self.goal_for)]

    def _timed_decision(self, now):
        """Fetch, decode and decide at the robot's node, timed: (problem, index, next node), or
        None when nothing is eligible."""
        started, started_cpu = time.perf_counter(), time.thread_time()
        problem, available = self._fetch_and_decode(now)
        decision = None
        if len(available):
            index, step = self._ask_planner(problem, self.node, now, available)
            decision = problem, index, step
        self.decision_s.append(time.perf_counter() - started)
        self.decision_cpu_s.append(time.thread_time() - started_cpu)
        return decision

    def _fetch_and_decode(self, now):
        """Fig. 4-14 fetch + decode: the open instructions as a Problem, and the eligible indices.

        A searched instruction's destination is the place being searched. The planner is reset
        only when the instruction set changes, so its per-set memory (the loop guard) holds. An
        own instruction that gave way to a person waits until no person's instruction is open.
        In a fleet, an instruction another robot holds is not eligible.
        """
        pending = [r for r in self.buffer.open_records() if r.state == PENDING]
        if not any(r.instruction.type == HUMAN for r in pending):
            self._deferred.clear()
        instructions = tuple(self._served_where(r.instruction) for r in pending)
        if instructions != self._problem_key:
            self._problem = Problem(self.graph, instructions, self.config.speed_mps, self.node)
            self._problem_key = instructions
            self.planner.reset(self._problem)
        done = self.buffer.done_ids()  # a successor waits for its predecessor (task_buffer)
        skipped, busy_places = self._deferred, ()
        if self.fleet:
            taken = self.fleet.taken(now)
            skipped = skipped | self._lost_claims | taken
            if self.config.one_robot_per_place:
                busy_places = self.fleet.busy_places(now)
        available = np.array([k for k, r in enumerate(pending)
                              if (r.instruction.previous_id == 0
                                  or r.instruction.previous_id in done)
                              and r.instruction.id not in skipped
                              and instructions[k].destination not in busy_places], dtype=int)
        return self._problem, available

    def _served_where(self, instruction):
        """The instruction with the destination it is served at (copied only when that differs:
        a flood of instructions is decoded at every decision)."""
        where = self._where(instruction)
        return instruction if where == instruction.destination else \
            replace(instruction, destination=where)

    def _ask_planner(self, problem, node, now, available):
        """(instruction index, next node), next node None when the decision is to serve here."""
        if self._node_planner:  # node planner (the seed's, Algorithm 4-2)
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
        if target and not self.people.is_at(target, self.node, now - self.config.fresh_s):
            if self.config.look_headings > 0:
                return self._start_look(instruction_id, now)
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
        """Start the robot function of `instruction` here (PENDING -> ACTIVE); not when the
        robot's fleet lease ran out meanwhile (another robot may serve it)."""
        instruction_id = instruction.id
        if self.fleet and not self.fleet.holds(instruction_id, now):
            self._lost_claims.add(instruction_id)
            self.log.append((now, f"lost {instruction_id} to another robot"))
            return []
        self._end_search(instruction, now, found=True)
        self.buffer.start(instruction_id, now)
        self.mode, self.executing = EXECUTING, (instruction_id, now + instruction.duration)
        place = self.graph.names[self.node]
        self.log.append((now, f"execute {function.name} for {instruction_id} at {place}"))
        return [Execute(instruction_id, function.name, float(instruction.duration)),
                Say(function.speech(instruction, place))]

    def _fail(self, instruction_id, now, reason):
        self.buffer.fail(instruction_id, now, reason)
        self._close_in_fleet(instruction_id, now, fleet_pool.FAILED)
        self.search.pop(instruction_id, None)
        self.searched.pop(instruction_id, None)
        self.log.append((now, f"failed {instruction_id}: {reason}"))
        return [Say(f"Sorry, I could not complete request {instruction_id}.")]
