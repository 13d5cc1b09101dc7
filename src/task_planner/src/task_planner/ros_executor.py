"""The task_planner node: the TAMP executor (task_planner.executor) behind ROS.

Callbacks only cache under a lock (instructions, the human table, move_base results); a timer feeds
them to the executor and carries out its commands: `Navigate` -> move_base goal at the node's pose,
`Execute` -> timed by the executor itself, `Say` -> /robot/say. The submit service journals before
it answers, so its acknowledgement is durable; a request with id 0 gets the next id of the journal
(TaskBuffer.next_id), or of the fleet with `~fleet_pool`, returned in the answer; a refusal answers
with the reason (a broken Table 4-1 field, a function not in `~robot_functions`, a place not in
the graph, more than `~max_open_instructions` open). With `~fleet_pool`
the robot is one of a fleet sharing that pool (task_planner.fleet_link); a pool that cannot be
reached (PoolUnavailable) is an ERROR on /diagnostics, refuses what would need it, and the robot
rejoins once it is back. /task_planner/state carries
the open instructions and the `~state_recent` most recently finished ones; /task_planner/get_buffer
every instruction.
"""
import dataclasses
import math
import os
import queue
import sqlite3
import threading
import time
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import actionlib
import rospy
from actionlib_msgs.msg import GoalStatus
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from geometry_msgs.msg import PoseWithCovarianceStamped
from move_base_msgs.msg import MoveBaseAction, MoveBaseGoal
from std_msgs.msg import String, UInt32
from tamp_msgs.msg import AskWho, HumanArray, ObservedHumanArray, TaskBufferState
from tamp_msgs.msg import Instruction as InstructionMsg
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor, run_node
from visualization_msgs.msg import MarkerArray
from tamp_msgs.srv import (CancelInstruction, CancelInstructionResponse, GetTaskBuffer,
                           GetTaskBufferResponse, SubmitInstruction, SubmitInstructionResponse)

from task_planner.battery import BatteryConfig, BatteryModel
from task_planner.conversions import (buffer_to_msg, instruction_from_msg, people_from_msg,
                                      sightings_from_observed)
from task_planner.executor import (OVERDUE_ORDERS, Charging, Executor, ExecutorConfig,
                                   latency_ms, nearest_node)
from task_planner.executor_commands import Ask, Execute, Navigate, Say, StopMotion, Verify, Wait
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool, PoolUnavailable
from task_planner.fleet_registry import FLEET_ALLOCATORS
from task_planner.graph import load_graph
from task_planner.people_belief import PeopleAtPlaces
from task_planner.instruction import InvalidInstruction
from task_planner.plan_view import plan_view
from task_planner.planner_registry import EXECUTOR, make_planner
from task_planner.ros_markers import plan_markers
from task_planner.reward import load_priorities
from task_planner.robot_functions import load_robot_functions
from task_planner.settings import BATTERY, REQUIRED, load_settings
from task_planner.task_buffer import (JOURNAL_FAILED, PENDING, STATE_NAMES, BufferConfig,
                                      TaskBuffer, TaskBufferError)
from task_planner.waypoint_watch import WaypointWatch
from tamp_resources import resource

ROOT = resource()
QUARANTINE_SHOWN = 20   # quarantined rows listed on /diagnostics (their count always is)
OBSERVED_KEPT = 100     # analysed frames cached between two ticks (the oldest are dropped)


@dataclass(frozen=True)
class NodeParams:
    planner: str = "seed"          # a planner_registry name that runs in the EXECUTOR
    graph: str = str(ROOT / "maps/household.graph.yaml")
    settings: str = str(ROOT / "config/task_planner.yaml")
    robot_functions: str = str(ROOT / "config/robot_functions.yaml")
    journal: str = ""              # SQLite task buffer journal; "" = $ROS_HOME/task_buffer.sqlite
    start_node: str = ""           # place the robot starts on; "" = nearest to /amcl_pose
    max_goal_attempts: int = 3     # move_base attempts per goal before the instruction fails
    tick_period: float = 0.05      # executor step [s]
    frame_id: str = "map"          # frame of the move_base goals
    battery: bool = True           # low-battery model: the robot sends itself to charge
    charging_place: str = "charging_place"  # graph node name of the charger
    priorities: str = str(ROOT / "config/priorities.yaml")  # Table 5-5 (self_generated row)
    latency_warn_ms: float = 10.0  # diagnostics WARN when the median decision takes longer [ms]
    verify_wait: float = 2.0       # without look_headings: stand and look this long [s]
    look_headings: int = 6         # turns in place to look around a place: 6 steps of 51°, each
                                   # within the camera's 57° field of view
    look_dwell: float = 0.6        # stay on each heading this long (3 camera frames) [s]
    look_frames: int = 3           # and until visual perception analysed this many frames
                                   # taken there (/humans/observed); 0 = the dwell alone
    look_frames_wait: float = 10.0  # but turn on after this long on one heading [s]
    ask_wait: float = 0.0          # a person faced and watched whom perception still cannot
                                   # tell is asked on ~ask_who whether they are the one looked
                                   # for (perception's introduction node says it and writes a
                                   # yes to human_db); wait this long for it [s]; 0 = never ask
    look_again: float = 20.0       # a place looked all around this recently is not looked
                                   # around again for another person [s]; 0 = look every time
    fresh: float = 5.0             # a sighting this old still counts as "the person is here" [s]
    stranger_fresh: float = 10.0   # meet a stranger once perception saw someone it cannot tell
                                   # at the place this recently, else look around for
                                   # them [s]; 0 = greet on arrival
    search_all_places: bool = True  # search every place (else only the last known ones)
    follow_belief: bool = True     # serve people where perception last saw them (or their
                                   # schedule puts them), not where the request said
    search_miss: float = 40.0      # following the belief, what finding a person not there costs
                                   # (a look around, a call, the drive on): the planner adds
                                   # the chance of a miss times this to their instruction [s];
                                   # 0 = the planner ignores misses (the seed)
    stay: float = 600.0            # the mean time a person stays at a place, for that chance
                                   # (a sighting ages exponentially) [s]
    pass_wait: float = 4.0         # after an abort ask to pass and wait this long [s]; 0 = no
    patrol: bool = False           # look at stale places while idle
    own_yields: bool = True        # a person's request interrupts the robot's own instruction
    meetings_inherit: bool = True  # a stranger's meeting is planned with the priority of the
                                   # strongest request waiting to know who its person is
    serve_within: float = 120.0    # an instruction launched this long ago is served before any
                                   # newer one [s]; 0 = Eq. 4-2's reward alone decides (the
                                   # seed: an old request may wait for ever)
    overdue_order: str = "smith"   # among the overdue ones: "smith" (the most priority per
                                   # second) or "oldest" first (the least maximum lateness)
    patrol_interval: float = 60.0  # a place looked at this recently is not patrolled [s]
    pass_through: tuple = ()       # places people only pass through: patrolled only while the
                                   # belief or a schedule puts someone there, searched last
    utc_offset: float = 0.0        # added to ROS time for the time of day of the schedules'
                                   # predicted places [s] (simulated time: the day's start)
    marker_period: float = 0.5     # least time between two /task_planner/markers updates [s]
    plan_view_max: int = 40        # markers show the plan only up to this many open instructions
    state_recent: int = 50         # /task_planner/state carries this many finished instructions
                                   # (the most recent) besides the open ones
    pass_radius: float = 0.6       # a waypoint (a graph node on the way to the place a move is
                                   # for) counts as reached once move_base reports the robot
                                   # this near it, and the robot drives on without stopping,
                                   # facing the node after it [m]; 0 = stop at every node,
                                   # facing its own yaw (the seed's node-by-node moves)
    goal_silence: float = 5.0      # no feedback from move_base this long on an active goal: the
                                   # server is taken as gone and the goal as lost [s of wall
                                   # time: a restarting server is no faster in a faster sim]
    max_preemptions: int = 3       # a goal preempted by another sender (rviz "2D Nav Goal") is
                                   # sent again this often, then handled as aborted
    event_hold: float = 10.0       # diagnostics keep a navigation or journal event this long [s]
    fleet_pool: str = ""           # the pool the executors of a fleet share: an SQLite file
                                   # (or sqlite:///abs/path; one host) or
                                   # postgresql://[user@]host[:port]/database (several hosts);
                                   # "" = a robot on its own
    robot_name: str = ""           # this robot's name in the fleet; "" = the node's namespace
    fleet_allocator: str = "auction"  # a fleet_registry allocator: `auction` decides over the
                                   # whole fleet; `seed`, `rollout`: each robot runs ~planner on
                                   # the instructions no other robot holds
    fleet_lease: float = 10.0      # a claim lapses this long after its robot last renewed it
                                   # [s of ROS time]; another robot may then serve it
    corridors: tuple = ()          # places one robot of the fleet at a time drives through
    corridor_wait: float = 60.0    # wait this long for a corridor, then drive on [s]
    max_handbacks: int = 2         # an instruction of the fleet's pool whose place the robot
                                   # cannot reach goes back to the pool this many times
    one_robot_per_place: bool = False  # leave a place's instructions to the robot there
    log_decisions: bool = True     # log the executor's reasons (move, look, search, serve, fail)
    max_open_instructions: int = 2000  # a new instruction beyond this many open ones is refused
                                   # ("the task buffer is full"): each open one costs every
                                   # decision and every state message; 0 = no cap

    @classmethod
    def from_ros(cls):
        """Read every field from the private parameter of the same name (default if unset)."""
        params = config_from_params(cls)   # check() is run there
        if params.journal:
            return params
        return dataclasses.replace(params, journal=str(
            Path(os.environ.get("ROS_HOME", Path.home() / ".ros")) / "task_buffer.sqlite"))

    def check(self):
        """ValueError naming the parameter when a number cannot work (a tick period of 0 would
        spin, a goal silence of 0 would drop every goal)."""
        positive = ("tick_period", "goal_silence", "event_hold", "fresh", "fleet_lease", "stay",
                    "corridor_wait", "look_frames_wait")
        at_least_zero = ("max_goal_attempts", "latency_warn_ms", "verify_wait", "look_headings",
                         "look_dwell", "look_frames", "look_again", "stranger_fresh", "pass_wait",
                         "ask_wait", "pass_radius", "search_miss",
                         "patrol_interval", "serve_within",
                         "marker_period", "plan_view_max", "state_recent", "max_preemptions",
                         "max_open_instructions", "max_handbacks")
        if self.overdue_order not in OVERDUE_ORDERS:
            raise ValueError(f"parameter ~overdue_order: '{self.overdue_order}' (choose one of "
                             f"{', '.join(OVERDUE_ORDERS)})")
        if self.fleet_allocator not in FLEET_ALLOCATORS:
            raise ValueError(f"parameter ~fleet_allocator: unknown fleet allocator "
                             f"'{self.fleet_allocator}' (choose one of "
                             f"{', '.join(FLEET_ALLOCATORS)})")
        for name in positive + at_least_zero:
            value = getattr(self, name)
            low_ok = value > 0 if name in positive else value >= 0
            if not (math.isfinite(value) and low_ok):
                raise ValueError(f"parameter ~{name} must be a finite number "
                                 f"{'> 0' if name in positive else '>= 0'}; got {value}")


class ExecutorNode:
    def __init__(self, params):
        self.params = params
        settings = load_settings(params.settings, REQUIRED + (BATTERY if params.battery else ()))
        self.graph = load_graph(params.graph, float(settings["robot_radius_m"]))
        Path(params.journal).parent.mkdir(parents=True, exist_ok=True)
        self.executor_functions = load_robot_functions(params.robot_functions)
        buffer = TaskBuffer(params.journal, BufferConfig(
            node_count=self.graph.size, place_names=tuple(self.graph.names),
            recent_finished=params.state_recent,
            functions=tuple((f.code, f.name) for f in self.executor_functions.values())))
        self.people = PeopleAtPlaces()
        self.executor = Executor(
            buffer, self.graph, make_planner(params.planner, settings, use=EXECUTOR), self.people,
            self.executor_functions,
            ExecutorConfig(float(settings["speed_mps"]), params.max_goal_attempts,
                           verify_wait_s=params.verify_wait, look_headings=params.look_headings,
                           look_dwell_s=params.look_dwell, look_frames=params.look_frames,
                           look_frames_wait_s=params.look_frames_wait,
                           ask_wait_s=params.ask_wait,
                           look_again_s=params.look_again,
                           fresh_s=params.fresh, stranger_fresh_s=params.stranger_fresh,
                           search_all_places=params.search_all_places,
                           follow_belief=params.follow_belief,
                           search_miss_s=params.search_miss, stay_s=params.stay,
                           pass_wait_s=params.pass_wait, patrol=params.patrol,
                           own_yields=params.own_yields,
                           meetings_inherit=params.meetings_inherit,
                           serve_within_s=params.serve_within,
                           overdue_order=params.overdue_order,
                           patrol_interval_s=params.patrol_interval,
                           pass_through=tuple(self.graph.index(n) for n in params.pass_through),
                           corridors=tuple(self.graph.index(name) for name in params.corridors),
                           corridor_wait_s=params.corridor_wait,
                           max_handbacks=params.max_handbacks,
                           one_robot_per_place=params.one_robot_per_place,
                           max_open=params.max_open_instructions,
                           fleet_allocator=params.fleet_allocator),
            start_node=self.graph.index(params.start_node) if params.start_node else 0,
            charging=self._charging(params, settings) if params.battery else None,
            fleet=self._fleet(params))
        self.lock = threading.Lock()  # guards the caches below and the executor
        self.inbox, self.humans, self.observed = [], None, deque(maxlen=OBSERVED_KEPT)
        self.functions_over = []   # ids from ~function_over: functions that ended early
        self.answers = []          # (name, place) of introduction/asked: a question not answered
        #                            yes
        # move_base results: a lock-free queue, because actionlib calls done callbacks holding
        # its goal mutex, which _cancel_goal (called under self.lock) takes too
        self.results = queue.SimpleQueue()
        self._schedules, self._predicted_at = {}, -float("inf")  # schedules, last prediction
        self.refused, self.nav_goal, self.goal_seq = 0, None, 0
        self._goal_heard = 0.0      # wall time of the last feedback on the goal we follow [s]
        self._last_goal = None      # (node, heading, through) of the goal we follow, to send
        #                             it again
        self.waypoint = WaypointWatch(params.pass_radius)  # the waypoint goal not yet passed
        self._preemptions = 0       # times another sender preempted the goal we follow
        self.events = deque(maxlen=20)  # (wall time, text): shown on diagnostics for event_hold
        self.sup = None
        self._quarantine_seen = 0   # quarantined rows already announced (_announce_quarantine)
        self._logged = 0            # executor log entries already written (_log_decisions)
        self.step_s = deque(maxlen=1000)  # wall time of the latest busy executor steps [s]
        self.settings = settings
        self.view_planner = make_planner(params.planner, settings,  # plays the plan forward
                                         use=EXECUTOR)
        self._view_key, self._view_time = None, -float("inf")
        self._tree_text, self._tree_time = "", -float("inf")   # /task_planner/tree, published
        self._activity = ""                                      # /task_planner/activity, published

    @staticmethod
    def _fleet(params):
        """The robot's FleetLink with `~fleet_pool`, else None; ValueError names a problem."""
        if not params.fleet_pool:
            return None
        robot = params.robot_name or rospy.get_namespace().strip("/")
        if not robot:
            raise ValueError("parameter ~robot_name: a robot of a fleet needs a name (or a "
                             "namespace)")
        return FleetLink(FleetPool(params.fleet_pool, lease_s=params.fleet_lease), robot)

    def _charging(self, params, settings):
        functions = {f.name: f for f in self.executor_functions.values()}
        if "charge" not in functions:
            raise ValueError(f"{params.robot_functions}: no 'charge' function for the battery")
        config = BatteryConfig(**{name: float(settings[f"battery_{name}"]) for name in (
            "capacity_wh", "idle_w", "moving_w", "executing_w", "charge_w", "low_fraction")})
        return Charging(BatteryModel(config, now=rospy.get_time()),
                        self.graph.index(params.charging_place), functions["charge"].code,
                        load_priorities(params.priorities)["self_generated"])

    def setup(self, timeout):
        """Publishers, subscribers, services and the move_base client; False if it is not up."""
        self.sup = Supervisor("task_planner: executor", hardware_id="task_planner")
        self.say_pub = rospy.Publisher("robot/say", String, queue_size=10)
        self.ask_pub = rospy.Publisher("~ask_who", AskWho, queue_size=5)
        self.state_pub = rospy.Publisher("~state", TaskBufferState, queue_size=1,
                                         latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        self.marker_pub = rospy.Publisher("~markers", MarkerArray, queue_size=1,
                                          latch=True)
        self.tree_pub = rospy.Publisher("~tree", String, queue_size=1, latch=True)
        self.activity_pub = rospy.Publisher("~activity", String, queue_size=10, latch=True)
        # the plain ActionClient: the executor follows one goal at a time itself (goal_seq), so
        # a late transition of a goal it replaced is ignored quietly (SimpleActionClient logs
        # each as an ERROR, "a goal handle that we're not tracking")
        self.move_base = actionlib.ActionClient("move_base", MoveBaseAction)
        self.goal_handle = None
        if not self.move_base.wait_for_server(rospy.Duration(timeout)):
            rospy.logerr("task_planner: move_base is not up after %.0f s", timeout)
            return False
        if not self.params.start_node:
            try:
                pose = rospy.wait_for_message("amcl_pose", PoseWithCovarianceStamped,
                                              timeout).pose.pose.position
            except rospy.ROSException:
                rospy.logerr("task_planner: no /amcl_pose after %.0f s to find the start place "
                             "(or set ~start_node)", timeout)
                return False
            self.executor.node = nearest_node(self.graph, pose.x, pose.y)
        rospy.loginfo("task_planner: starting at %s; %d open instruction(s) in the journal "
                      "(%d resumed)", self.graph.names[self.executor.node],
                      len(self.executor.buffer.open_records()), self.executor.buffer.resumed)
        sup = self.sup
        sup.subscriber("~instructions", InstructionMsg, self._on_instruction,
                       queue_size=1000)
        sup.subscriber("humans/known", HumanArray, self._on_humans, queue_size=1)
        sup.subscriber("humans/observed", ObservedHumanArray, self._on_observed, queue_size=10)
        sup.subscriber("~function_over", UInt32, self._on_function_over, queue_size=10)
        sup.subscriber("introduction/asked", AskWho, self._on_asked, queue_size=5)
        sup.service("~submit", SubmitInstruction, self._submit)
        sup.service("~cancel", CancelInstruction, self._cancel)
        sup.service("~get_buffer", GetTaskBuffer, self._get_buffer)
        sup.timer(self.params.tick_period, self._tick, worker="tick", on_error=self._tick_fault)
        sup.timer(1.0, self._diagnose, worker="diagnostics")
        with self.lock:
            self._publish_state()
        return True

    # ---- callbacks: cache only ----

    def _on_instruction(self, msg):
        with self.lock:
            self.inbox.append(msg)

    def _on_function_over(self, msg):
        with self.lock:
            self.functions_over.append(int(msg.data))

    def _on_asked(self, msg):
        if msg.answer != "yes":   # a yes reaches the belief through human_db's table
            with self.lock:
                self.answers.append((msg.name, msg.place))

    def _on_humans(self, msg):
        with self.lock:
            self.humans = msg

    def _on_observed(self, msg):
        with self.lock:
            self.observed.append(msg)

    def _on_goal_transition(self, goal_seq, handle):
        """Goal `goal_seq` moved on (accepted, active, ended): heard from move_base; its end is
        queued with the status and the server's text."""
        self._goal_heard = time.monotonic()  # one float: no lock needed
        if handle.get_comm_state() == actionlib.CommState.DONE:
            self.results.put((goal_seq, handle.get_goal_status(),
                              handle.get_goal_status_text()))

    def _on_goal_feedback(self, goal_seq, feedback):
        """move_base's feedback on goal `goal_seq`: it is alive; near enough a waypoint, the
        waypoint is passed (queued as reached; the goal that follows replaces it on the move)."""
        self._goal_heard = time.monotonic()
        here = feedback.base_position.pose.position
        distance = self.waypoint.passed(goal_seq, here.x, here.y)
        if distance is not None:
            self.results.put((goal_seq, GoalStatus.SUCCEEDED,
                              f"waypoint passed {distance:.2f} m from it"))

    # ---- services: journal before answering ----

    def _submit(self, request):
        msg = request.instruction
        allocate = msg.id == 0   # the buffer chooses the id (under the lock: no other submit
        with self.lock:          # or tick can journal in between)
            if allocate:
                msg.id = self.executor.new_id(msg.previous_id)
            try:
                instruction = instruction_from_msg(msg)
            except InvalidInstruction as error:
                return self._refused(msg, allocate, str(error))
            try:
                results, commands = self.executor.receive([instruction], rospy.get_time())
            except Exception as exc:
                if self.executor.buffer.holds(instruction.id):
                    # journalled (acknowledged), then a later write or step raised
                    self._step_fault(exc)
                    results, commands = [(self.executor.buffer.get(instruction.id), "")], []
                elif isinstance(exc, sqlite3.Error):   # a write before it failed (full disk)
                    results, commands = [(None, f"instruction {instruction.id}: "
                                                f"{JOURNAL_FAILED}: writing "
                                                f"{self.params.journal} failed: {exc}")], []
                elif isinstance(exc, PoolUnavailable):   # checked with the fleet first
                    self._event(str(exc), DiagnosticStatus.ERROR)
                    results, commands = [(None, f"instruction {instruction.id}: {exc}")], []
                else:
                    raise   # not journalled: the caller gets the error
            self._carry_out(commands)
            self._publish_state()
        record, error = results[0]
        if record is None:
            self._journal_trouble(error)
            return self._refused(msg, allocate, error)
        return SubmitInstructionResponse(True, instruction.id, "")

    @staticmethod
    def _refused(msg, allocated, reason):
        rospy.logwarn("task_planner: refused submitted instruction: %s", reason)
        return SubmitInstructionResponse(False, 0 if allocated else msg.id, reason)

    def _cancel(self, request):
        with self.lock:
            try:
                _, commands = self.executor.cancel(request.id, rospy.get_time())
            except TaskBufferError as error:
                return CancelInstructionResponse(False, str(error))
            self._carry_out(commands)
            self._publish_state()
        return CancelInstructionResponse(True, "")

    def _get_buffer(self, _request):
        with self.lock:
            return GetTaskBufferResponse(buffer_to_msg(self.executor.buffer, rospy.Time.now(),
                                                       complete=True))

    # ---- the executor step ----

    def _tick_fault(self, exc):
        """A tick raised (the supervisor logged it): see _step_fault."""
        with self.lock:
            self._step_fault(exc)

    def _step_fault(self, exc):
        """A step of the executor raised (the caller holds the lock): fail the instruction being
        served with the reason, so neither this run nor a restart runs it again, and stop; a
        fleet pool out of reach fails nothing: the robot stops, the instruction waits open and
        the robot rejoins the fleet once the pool answers again. A
        journal write that failed (a full disk) or a fleet pool that cannot be reached is an
        ERROR on diagnostics; when even the failure cannot be written, the robot still stops."""
        now = rospy.get_time()
        instruction_id = self.executor.serving()
        level = (DiagnosticStatus.ERROR if isinstance(exc, (sqlite3.Error, PoolUnavailable))
                 else DiagnosticStatus.WARN)
        lost_pool = isinstance(exc, PoolUnavailable)   # not the instruction's fault: it waits
        try:
            commands = self.executor.fault(now, fault_text(exc), fail=not lost_pool,
                                           rejoin=lost_pool)
            failed = (f"; instruction {instruction_id} {'waits' if lost_pool else 'failed'}"
                      if instruction_id else "")
        except sqlite3.Error as error:
            commands, failed = [StopMotion()], f"; writing {self.params.journal} failed: {error}"
            level = DiagnosticStatus.ERROR
        except PoolUnavailable as error:   # journalled; the pool learns of it at the rejoin
            commands, failed = [StopMotion()], f"; {error}"
            level = DiagnosticStatus.ERROR
        self._event(f"fault in the executor step: {fault_text(exc)}{failed}", level)
        self._carry_out(commands)
        self._publish_state()

    def _tick(self, _event):
        with self.lock:
            now = rospy.get_time()
            self._update_people(now)
            version, decisions = self.executor.buffer.version, len(self.executor.decision_s)
            started = time.perf_counter()
            commands = self._receive(now) + self._navigation_results(now)
            over, self.functions_over = self.functions_over, []
            for instruction_id in over:
                self.executor.function_over(instruction_id, now)
            answers, self.answers = self.answers, []
            for name, place in answers:
                self.executor.not_answered(name, place, now)
            commands += self.executor.tick(now)
            self._log_decisions()
            busy = (self.executor.buffer.version != version or commands
                    or len(self.executor.decision_s) != decisions)
            if busy:  # journal + decide + write back, without the ROS publishing below
                self.step_s.append(time.perf_counter() - started)
            self._carry_out(commands)
            if self.executor.buffer.version != version:
                self._publish_state()
            self._publish_view()
            self._publish_tree()
            self._publish_activity()

    def _log_decisions(self):
        """The executor's new reasons (move, look, search, serve, fail) to the node's log, so a
        run's launch log tells why the robot went where it went (`~log_decisions`)."""
        log = self.executor.log
        if self.params.log_decisions:
            for stamp, text in log[self._logged:]:
                rospy.loginfo("task_planner: [%.1f s] %s", stamp, text)
        self._logged = len(log)

    def _receive(self, now):
        inbox, self.inbox = self.inbox, []
        instructions = []
        for msg in inbox:
            try:
                instructions.append(instruction_from_msg(msg))
            except InvalidInstruction as error:
                self.refused += 1
                rospy.logwarn("task_planner: refused instruction: %s", error)
        if not instructions:
            return []
        results, commands = self.executor.receive(instructions, now)
        for _, error in results:
            if error:
                self.refused += 1
                rospy.logwarn("task_planner: refused instruction: %s", error)
                self._journal_trouble(error)
        return commands

    def _navigation_results(self, now):
        results = []
        while not self.results.empty():
            results.append(self.results.get())
        commands = []
        following = self.executor.mode in ("moving", "looking")
        for goal_seq, state, text in results:
            if goal_seq != self.nav_goal or not following:
                continue  # a goal we replaced (preempted) or no longer follow
            self.nav_goal = None
            if state == GoalStatus.SUCCEEDED:
                commands += self.executor.arrived(now)
            elif state == GoalStatus.PREEMPTED and self._preemptions < self.params.max_preemptions:
                # we only ever cancel goals we stopped following: another sender took move_base
                self._preemptions += 1
                self._event(f"move_base goal to {self.graph.names[self._last_goal[0]]} preempted "
                            f"by another sender (rviz 2D Nav Goal?); sent again "
                            f"({self._preemptions}/{self.params.max_preemptions})")
                self._send_goal(*self._last_goal, again=True)
            else:  # aborted, rejected, recalled, lost, or preempted once too often
                reason = text or GoalStatus.to_string(state)
                if state != GoalStatus.ABORTED:  # not move_base's own "no path": say so
                    self._event(f"move_base goal to {self.graph.names[self._last_goal[0]]} "
                                f"ended {GoalStatus.to_string(state)}: {reason}")
                commands += self.executor.aborted(now, reason)
        silent = time.monotonic() - self._goal_heard
        if self.nav_goal is not None and following and silent > self.params.goal_silence:
            self.nav_goal = None       # results of this goal, should it ever end, are ignored
            self._cancel_goal()
            reason = (f"move_base silent for {silent:.1f} s (wall clock) on the goal to "
                      f"{self.graph.names[self._last_goal[0]]} (server gone?)")
            self._event(reason)
            commands += self.executor.aborted(now, reason)
        return commands

    def _journal_trouble(self, error):
        """A refusal because the journal could not be written (disk full) degrades the node."""
        if JOURNAL_FAILED in error:
            self._event(error, DiagnosticStatus.ERROR)

    def _event(self, text, level=DiagnosticStatus.WARN):
        """Log `text` (not again while it repeats) and show it on diagnostics for event_hold."""
        if not self.events or self.events[-1][2] != text:
            rospy.logwarn("task_planner: %s", text)
        else:
            self.events.pop()
        self.events.append((time.monotonic(), level, text))

    def _update_people(self, now):
        """Belief from the frames visual perception analysed (who it saw where, and how far it
        got: a look waits for it) and from human_db's table (places perception wrote) when a
        new one came; the schedules' predicted places once a second (they change by the
        minute)."""
        day_s = self.params.utc_offset + now
        while self.observed:
            self.people.take_frame(*sightings_from_observed(self.observed.popleft(),
                                                            self.graph.names))
        if self.humans is not None:
            sightings, self._schedules = people_from_msg(self.humans, self.graph.names)
            self.humans = None
            self.people.take_table(sightings, self._schedules, day_s)
            self._predicted_at = now
        elif now - self._predicted_at >= 1.0:
            self.people.predict(self._schedules, day_s)
            self._predicted_at = now

    def _carry_out(self, commands):
        for command in commands:
            if isinstance(command, Navigate):
                self._send_goal(command.node, command.yaw, command.through)
            elif isinstance(command, StopMotion):
                self.nav_goal = None
                self._cancel_goal()   # this goal only: a new one may follow at once
            elif isinstance(command, Wait):
                rospy.logdebug("task_planner: waiting until %.1f s", command.until_s)
            elif isinstance(command, Say):
                self.say_pub.publish(String(command.text))
                rospy.loginfo("task_planner says: %s", command.text)
            elif isinstance(command, Ask):
                msg = AskWho(name=command.name, place=command.place, call=command.call)
                msg.header.stamp = rospy.Time.now()
                self.ask_pub.publish(msg)
                rospy.loginfo("task_planner: %s", f"calling {command.name} at {command.place}"
                              if command.call else f"asking whether the person at "
                              f"{command.place} is {command.name}")
            elif isinstance(command, Verify):
                rospy.loginfo("task_planner: looking for %s for instruction %d until %.1f s",
                              command.target, command.instruction_id, command.until_s)
            elif isinstance(command, Execute):
                rospy.loginfo("task_planner: %s for instruction %d (%.0f s)", command.function,
                              command.instruction_id, command.duration_s)

    def _cancel_goal(self):
        """Cancel our move_base goal unless it has ended: cancelling an ended goal would take
        its handle back to waiting for the cancel's answer."""
        handle = self.goal_handle
        if handle is None:
            return
        with handle.comm_state_machine.mutex:   # its result cannot end it between check and cancel
            if handle.get_comm_state() != actionlib.CommState.DONE:
                handle.cancel()

    def _send_goal(self, node, heading=None, through=None, again=False):
        """A move_base goal to graph node `node`: facing `heading` (a turn of a look around),
        else, for a waypoint passed on the way (`through` with `~pass_radius`), facing on to
        the node after it, else facing the node's own yaw."""
        x, y, yaw = self.graph.poses[node]
        passing = self.waypoint.passing(through)
        yaw = heading if heading is not None else through if passing else yaw
        goal = MoveBaseGoal()
        goal.target_pose.header.frame_id = self.params.frame_id
        goal.target_pose.header.stamp = rospy.Time.now()
        goal.target_pose.pose.position.x, goal.target_pose.pose.position.y = x, y
        goal.target_pose.pose.orientation.z = math.sin(yaw / 2.0)
        goal.target_pose.pose.orientation.w = math.cos(yaw / 2.0)
        self.goal_seq += 1
        self.nav_goal = self.goal_seq   # results of earlier (replaced) goals are ignored
        self._last_goal, self._goal_heard = (node, heading, through), time.monotonic()
        self.waypoint.sent(self.goal_seq, x, y, passing)
        if not again:
            self._preemptions = 0
        self.goal_handle = self.move_base.send_goal(
            goal, transition_cb=lambda handle, n=self.goal_seq: self._on_goal_transition(n, handle),
            feedback_cb=lambda _, feedback, n=self.goal_seq: self._on_goal_feedback(n, feedback))
        rospy.loginfo("task_planner: move_base goal %s%s", self.graph.names[node],
                      f" (look, heading {heading:.2f} rad)" if heading is not None else
                      f" (waypoint, passed within {self.params.pass_radius:.2f} m)" if passing
                      else "")

    def _publish_view(self):
        """Markers of the ripple, next node and plan, when something they show has changed."""
        executor = self.executor
        key = (executor.buffer.version, executor.node, executor.goal, executor.mode)
        wall = time.monotonic()
        if key == self._view_key or wall - self._view_time < self.params.marker_period:
            return
        self._view_key, self._view_time = key, wall
        pending = tuple(r.instruction for r in executor.buffer.open_records()
                        if r.state == PENDING)
        view = plan_view(self.graph, pending, self.view_planner, float(self.settings["speed_mps"]),
                         float(self.settings["step_s"]), executor.node,
                         -1 if executor.goal is None else executor.goal,
                         plan_max=self.params.plan_view_max)
        self.marker_pub.publish(plan_markers(view, self.graph, self.params.frame_id))

    def _publish_activity(self):
        """What the robot does now (travel, look around, searching, ...), when it changed."""
        label = self.executor.activity()
        if label != self._activity:
            self._activity = label
            self.activity_pub.publish(String(label))

    def _publish_tree(self):
        """The behaviour tree with each node's status of the last tick, when it changed (at
        most every marker_period)."""
        wall = time.monotonic()
        if wall - self._tree_time < self.params.marker_period:
            return
        self._tree_time = wall
        text = self.executor.drawing()
        if text != self._tree_text:
            self._tree_text = text
            self.tree_pub.publish(String(text))

    def _publish_state(self):
        self.state_pub.publish(buffer_to_msg(self.executor.buffer, rospy.Time.now()))

    def _quarantined(self):
        """[(file, row id, reason)] of the journal's and the fleet pool's rows that did not load
        (TaskBuffer and FleetPool quarantine)."""
        rows = [(f"journal {self.params.journal}", i, reason)
                for i, reason in self.executor.buffer.quarantined]
        fleet = self.executor.fleet
        if fleet:
            rows += [(f"fleet pool {fleet.pool.path}", i, reason)
                     for i, reason in fleet.pool.quarantined.items()]
        return rows

    def _announce_quarantine(self, quarantined):
        """Log each newly quarantined row; a WARN event per file names them for event_hold."""
        new = quarantined[self._quarantine_seen:]
        self._quarantine_seen = len(quarantined)
        by_file = {}
        for where, row, reason in new:
            rospy.logwarn("task_planner: %s row %d: %s", where, row, reason)
            by_file.setdefault(where, []).append(str(row))
        for where, rows in by_file.items():
            self._event(f"{where}: {len(rows)} row(s) that do not load quarantined (rows "
                        f"{', '.join(rows[:10])}{', ...' if len(rows) > 10 else ''}; reasons in "
                        "the values)")

    def _diagnose(self, _event):
        with self.lock:
            quarantined = self._quarantined()
            self._announce_quarantine(quarantined)
            counts = dict(zip(STATE_NAMES, self.executor.buffer.counts()))
            decision = latency_ms(self.executor.decision_s)
            step = latency_ms(self.step_s)
            slow = decision[0] > self.params.latency_warn_ms
            hold = time.monotonic() - self.params.event_hold
            events = [(level, text) for at, level, text in self.events if at >= hold]
            level = max([DiagnosticStatus.WARN if self.refused or slow else DiagnosticStatus.OK]
                        + [level for level, _ in events])
            message = f"{self.executor.mode} at {self.graph.names[self.executor.node]}"
            if self.refused:
                message += f"; {self.refused} instruction(s) refused"
            if events:
                message += "; " + "; ".join(text for _, text in events[-3:])
            if slow:
                message += f"; median decision {decision[0]:.1f} ms"
            values = [KeyValue(k, str(v)) for k, v in counts.items()]
            # over the last 1,000 decisions / busy steps: median, 95th percentile, max [ms]
            cpu = latency_ms(self.executor.decision_cpu_s)
            for name, figures in (("decision", decision), ("decision_cpu", cpu), ("step", step)):
                values += [KeyValue(f"{name}_ms_{stat}", f"{value:.3f}")
                           for stat, value in zip(("median", "p95", "max"), figures)]
            values.append(KeyValue("decisions_timed", str(len(self.executor.decision_s))))
            values.append(KeyValue("total_reward", f"{self.executor.buffer.total_reward():.3f}"))
            values.append(KeyValue("quarantined_rows", str(len(quarantined))))
            values += [KeyValue(f"{where} row {row}", reason)
                       for where, row, reason in quarantined[:QUARANTINE_SHOWN]]
            fleet = self.executor.fleet
            if fleet:
                values += [KeyValue("fleet_robot", fleet.robot),
                           KeyValue("fleet_holds", str(fleet.held))]
            if self.executor.charging:
                values.append(KeyValue("battery_percent",
                                       f"{100 * self.executor.charging.battery.fraction:.1f}"))
            self.refused = 0
        fleet = self.executor.fleet
        status = DiagnosticStatus(level=level, name="task_planner: executor" + (
            f" ({fleet.robot})" if fleet else ""),
                                  message=message, hardware_id="task_planner", values=values)
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diag_pub.publish(array)


def main():
    """The node; whatever stops it (a ValueError: a parameter, settings, journal or graph file
    that cannot be used) is said on /diagnostics before it exits 1 (supervision.run_node)."""
    rospy.init_node("task_planner")
    return run_node("task_planner: executor", _run, hardware_id="task_planner",
                    log_name="task_planner")


def _run():
    node = ExecutorNode(NodeParams.from_ros())
    if not node.setup(timeout=60.0):
        return 1
    rospy.spin()
    return 0
