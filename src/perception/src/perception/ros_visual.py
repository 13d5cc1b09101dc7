"""The visual perception node: camera-level frames (/camera/detections, tamp_msgs/PerceptionFrame,
from the simulator or the image front end) -> /humans/observed, human_db updates, self-generated
instructions on /task_planner/submit (the task buffer allocates their ids), /diagnostics with
latency.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor: a fault while a
frame is analysed makes that frame a refused frame with the reason (counted in the node's own
diagnostics) and raises the node's "perception: visual: supervision" status to ERROR; the next
frame is analysed as usual."""
import math
import threading
import time
from dataclasses import dataclass, field

import rospy
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from human_db.conversions import human_from_msg
from human_db.schedule import check_schedule, doubted_match, time_of_day
from floorplan.semantic_graph import load_graph
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor
from tamp_msgs.msg import HumanArray, InstructionState, ObservedHumanArray, PerceptionFrame
from tamp_msgs.msg import TaskBufferState
from tamp_msgs.srv import IdentifyHuman, UpdateHuman
from task_planner.reward import load_priorities
from task_planner.ros_submit import SubmitClient

from perception.activity import ActivityConfig, load_affordances
from perception.activity_track import ActivityTrackConfig, ActivityTracks
from perception.object_memory import ObjectMemory, ObjectMemoryConfig
from perception.localisation import Intrinsics, optical_to_map_transform
from perception.requests import keyword_config_from_dict
from perception.self_instructions import (
    Observation, SelfInstructionConfig, SelfInstructionGenerator)
from perception.conversions import frame_from_msg, observed_to_msg
from perception.visual_pipeline import StackedCameras, analyse_frame, unknown_classes

PEPPER_TOP = {"fx": 583.9, "fy": 588.5, "cx": 320.0, "cy": 240.0, "width": 640, "height": 480,
              "mount_x": 0.09, "mount_height": 1.15, "tilt": 0.1}
PEPPER_BOTTOM = dict(PEPPER_TOP, mount_height=1.05, tilt=0.8)


@dataclass
class VisualParams:
    affordances: str                      # ~affordances: config/affordances.yaml
    graph: str                            # ~graph: maps/<map>.graph.yaml
    keywords: dict                        # ~keywords: config/keywords.yaml contents (rosparam)
    priorities_file: str                  # ~priorities_file: config/priorities.yaml
    top_camera: dict = field(default_factory=lambda: dict(PEPPER_TOP))      # ~top_camera
    bottom_camera: dict = field(default_factory=lambda: dict(PEPPER_BOTTOM))  # ~bottom_camera
    map_frame: str = "map"                # ~map_frame
    base_frame: str = "base_link"         # ~base_frame
    period: float = 0.2                   # ~period: analysis timer period [s]
    recommendations: dict = field(default_factory=lambda: {"read": "play_music"})
    deviation_function: str = "remind"    # ~deviation_function on a schedule deviation (seed)
    timed_reminders: bool = True          # ~timed_reminders when schedule entries start
    repeat_after: float = 600.0           # ~repeat_after [s] between equal self-instructions
    self_instructions: bool = True        # ~self_instructions
    idle_only: bool = True                # ~idle_only: only while no human instruction is open
    submit_timeout: float = 2.0           # ~submit_timeout: wall-clock wait for
                                          # /task_planner/submit per instruction [s]
    utc_offset: float = 0.0               # ~utc_offset [s] for schedule times of day
    slow_latency: float = 0.1             # ~slow_latency [s]: diagnostics WARN above this
    activity_window: float = 8.0          # ~activity_window [s]: an identified person's
                                          # activity fused over this many seconds of frames
                                          # (activity_track; 0: framewise, the seed)
    activity_min_probability: float = 0.2  # ~activity_min_probability: mean P(a) over the
                                           # window for a detailed activity
    activity_hold: float = 600.0          # ~activity_hold [s]: a detailed activity read is kept
                                          # this long while the person stays at the place in
                                          # the same posture (0: not kept)
    hold_distance: float = 0.08           # ~hold_distance [m]: a hand this close to a hand-held
                                          # thing holds it, and what is held decides the hand
                                          # term (ActivityConfig; 0: all within reach, the seed)
    object_memory: float = 1800.0         # ~object_memory [s]: a spot of the map of detected
                                          # objects is kept this long after its last detection;
                                          # a fixed object a frame misses is offered to the
                                          # people within reach (object_memory; 0: each frame
                                          # alone, the seed)
    sure_distance: float = 80.0           # ~sure_distance: a colour match this far (mean
                                          # Eq. 3-10) or farther that the schedules contradict,
                                          # or while a resident is not met yet, is doubted:
                                          # published as a stranger, the robot asks
                                          # (human_db.schedule.doubted_match); 0: never


def read_params():
    """Node parameters; KeyError names a missing required one."""
    return config_from_params(VisualParams, hint=" (see src/perception/launch/visual.launch)")


def _camera_parts(spec, robot_pose):
    intr = Intrinsics(float(spec["fx"]), float(spec["fy"]), float(spec["cx"]), float(spec["cy"]),
                      int(spec["width"]), int(spec["height"]))
    return intr, optical_to_map_transform(robot_pose, float(spec["mount_x"]),
                                          float(spec["mount_height"]), float(spec["tilt"]))


class VisualNode:
    def __init__(self, params):
        self.params = params
        self._lock = threading.Lock()
        self._frame = None
        self._humans = {}
        self._latencies = []
        self._unknown_classes = set()   # object classes already warned about (once each)
        self._counts = {"frames": 0, "people": 0, "bad_frames": 0, "identified": 0,
                        "doubted": 0, "instructions": 0, "not_taken": 0}
        self._timers = []
        self._analysing = None   # the frame the work timer is analysing (for a fault's reason)
        self._last_bad_frame = ""   # why the last refused frame was refused
        self._busy = False   # a human instruction is pending or active (/task_planner/state)
        self._day_s = None   # time of day of the last reminder tick [s since midnight]

    def setup(self, sup):
        """Load the configuration and start the ROS API under the node's Supervisor `sup`."""
        p = self.params
        self.table = load_affordances(p.affordances)
        self.graph = load_graph(p.graph)
        keywords = keyword_config_from_dict(p.keywords)
        functions = {n: (f.code, f.duration_s) for n, f in keywords.functions.items()}
        priority = load_priorities(p.priorities_file)["self_generated"]
        codes = {a: i + 1 for i, a in enumerate(self.table.activities)}
        self.generator = SelfInstructionGenerator(
            SelfInstructionConfig(dict(p.recommendations),
                                  deviation_function=str(p.deviation_function),
                                  timed_reminders=bool(p.timed_reminders),
                                  repeat_after=float(p.repeat_after)),
            functions, priority, self.graph.place_ids(), codes)
        self.config = ActivityConfig(hold_distance=float(p.hold_distance))
        self.tracks = ActivityTracks(ActivityTrackConfig(
            float(p.activity_window), float(p.activity_min_probability),
            float(p.activity_hold)))
        self.memory = ObjectMemory(ObjectMemoryConfig(float(p.object_memory)))
        self.tf_buffer = tf2_ros.Buffer()
        self.tf_listener = tf2_ros.TransformListener(self.tf_buffer)
        self.identify = rospy.ServiceProxy("human_db/identify", IdentifyHuman)
        self.update = rospy.ServiceProxy("human_db/update", UpdateHuman)
        self.observed = rospy.Publisher("humans/observed", ObservedHumanArray, queue_size=5)
        self.submit = SubmitClient(float(p.submit_timeout))
        self.diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        sup.subscriber("camera/detections", PerceptionFrame, self._on_frame, queue_size=1)
        sup.subscriber("humans/known", HumanArray, self._on_humans, queue_size=1)
        sup.subscriber("task_planner/state", TaskBufferState, self._on_state, queue_size=1)
        self._timers = [sup.timer(float(p.period), self._on_work, worker="work",
                                  on_error=self._refuse_frame),
                        sup.timer(1.0, self._on_diagnostics, worker="diagnostics"),
                        sup.timer(1.0, self._on_clock, worker="reminders")]

    def _on_frame(self, msg):
        with self._lock:
            self._frame = msg

    def _on_state(self, msg):
        open_states = (InstructionState.PENDING, InstructionState.ACTIVE)
        busy = any(s.state in open_states and not s.instruction.type for s in msg.instructions)
        with self._lock:
            self._busy = busy

    def _on_humans(self, msg):
        table = {h.name: human_from_msg(h) for h in msg.humans}
        with self._lock:
            self._humans = table

    def _cameras(self):
        """Stacked cameras placed at the robot's map pose from tf, None when tf has none."""
        try:
            t = self.tf_buffer.lookup_transform(self.params.map_frame, self.params.base_frame,
                                                rospy.Time(0), rospy.Duration(0.05))
        except (tf2_ros.LookupException, tf2_ros.ConnectivityException,
                tf2_ros.ExtrapolationException) as error:
            rospy.logwarn_throttle(10.0, "visual: no %s -> %s transform, people not localised: %s",
                                   self.params.map_frame, self.params.base_frame, error)
            return None
        q = t.transform.rotation
        yaw = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
        pose = (t.transform.translation.x, t.transform.translation.y, yaw)
        top, bottom = (_camera_parts(self.params.top_camera, pose),
                       _camera_parts(self.params.bottom_camera, pose))
        return StackedCameras(int(self.params.top_camera["height"]),
                              {"top": top[0], "bottom": bottom[0]},
                              {"top": top[1], "bottom": bottom[1]})

    def _warn_unknown_classes(self, objects):
        """Warn once per object class that config/affordances.yaml does not know."""
        new = [label for label in unknown_classes(objects, self.table)
               if label not in self._unknown_classes]
        if new:
            self._unknown_classes.update(new)
            rospy.logwarn("visual: object classes not in the affordance table, ignored: %s", new)

    def _on_work(self, _event):
        with self._lock:
            msg, self._frame = self._frame, None
        if msg is None:
            return
        self._analysing = msg
        started = time.perf_counter()
        frame = frame_from_msg(msg)   # ValueError on a malformed frame: _refuse_frame
        stamp = msg.header.stamp.to_sec() if not msg.header.stamp.is_zero() else rospy.get_time()
        results = analyse_frame(frame, self.table, self.config, self._cameras(), self.graph,
                                self.memory, stamp)
        self._warn_unknown_classes(frame.objects)
        out = ObservedHumanArray(header=msg.header)
        for result in results:
            for problem in result.problems:
                rospy.logwarn_throttle(10.0, "visual: %s", problem)
            name, doubted_as = self._identify(result, stamp)
            if name:
                act = result.activity
                act.activity = self.tracks.update(name, stamp, result.place, act.activity,
                                                  act.probabilities, act.posture,
                                                  act.holding)
            out.humans.append(observed_to_msg(result, name, doubted_as))
            if name:
                self._record(name, result, msg.header.stamp)
        self.observed.publish(out)
        with self._lock:
            self._counts["frames"] += 1
            self._counts["people"] += len(results)
            self._latencies = (self._latencies + [time.perf_counter() - started])[-50:]
        self._analysing = None

    def _refuse_frame(self, error):
        """The work timer faulted (a malformed frame, or anything else while analysing it): the
        frame counts as refused, with the reason; the next frame is analysed as usual."""
        msg, self._analysing = self._analysing, None
        if msg is None:
            return
        reason = f"frame stamped {msg.header.stamp.to_sec():.3f}: {fault_text(error)}"
        with self._lock:
            self._counts["bad_frames"] += 1
            self._last_bad_frame = reason

    def _identify(self, result, stamp):
        """(name, "") of an identified person, ("", name) of a doubted match, else ("", "")."""
        if result.shirt is None:
            return "", ""
        try:
            reply = self.identify(shirt_color=result.shirt.reshape(-1).tolist())
        except (rospy.ServiceException, rospy.ROSException) as error:
            rospy.logwarn_throttle(10.0, "visual: /human_db/identify failed: %s", error)
            return "", ""
        if not reply.found:
            return "", ""
        with self._lock:
            humans = self._humans   # _on_humans replaces the table, never changes it
        instead = doubted_match(reply.name, reply.distance, self.params.sure_distance,
                                result.place, time_of_day(stamp, self.params.utc_offset),
                                humans.values())
        if not instead:
            return reply.name, ""
        rospy.loginfo_throttle(30.0, "visual: a shirt %.0f from %s's in the %s may be %s "
                               "(schedules, or not met yet): not taken for %s",
                               reply.distance, reply.name, result.place, instead, reply.name)
        with self._lock:
            self._counts["doubted"] += 1
        return "", reply.name

    def _record(self, name, result, stamp):
        activity = result.activity.activity
        try:
            self.update(name=name, location=result.place, activity=activity, source="perception",
                        stamp=stamp)
        except (rospy.ServiceException, rospy.ROSException) as error:
            rospy.logwarn_throttle(10.0, "visual: /human_db/update failed: %s", error)
        with self._lock:
            self._counts["identified"] += 1
            human, busy = self._humans.get(name), self._busy
        if not self.params.self_instructions or not result.place:
            return
        if busy and self.params.idle_only:
            return   # Sec. 4.2.1: the robot observes for itself only when no person needs it
        now = stamp.to_sec() if not stamp.is_zero() else rospy.get_time()
        check = None if human is None else check_schedule(
            human, time_of_day(now, self.params.utc_offset), location=result.place,
            activity=activity)
        for instruction in self.generator.generate(Observation(name, activity, result.place, now),
                                                   check):
            self._submit_instruction(instruction)

    def _on_clock(self, _event):
        """Reminders of the schedule entries that started since the last tick."""
        now = rospy.get_time()
        day_s = time_of_day(now, self.params.utc_offset)
        previous, self._day_s = self._day_s, day_s
        if previous is None or not self.params.self_instructions:
            return
        with self._lock:
            humans = list(self._humans.values())
        for instruction in self.generator.due_reminders(humans, previous, day_s, now):
            self._submit_instruction(instruction)

    def _submit_instruction(self, instruction):
        """Submit a self-generated instruction with id 0 (the task buffer allocates it)."""
        accepted, instruction_id, problem = self.submit(instruction, previous_id=0)
        if not accepted:
            rospy.logwarn("visual: self-generated instruction not taken by the task planner "
                          "(%s): %s", instruction.text, problem)
            with self._lock:
                self._counts["not_taken"] += 1
            return
        rospy.loginfo("visual: self-generated #%d: %s", instruction_id, instruction.text)
        with self._lock:
            self._counts["instructions"] += 1

    def _on_diagnostics(self, _event):
        with self._lock:
            counts, lat = dict(self._counts), list(self._latencies)
            last_bad, busy = self._last_bad_frame, self._busy
        mean = sum(lat) / len(lat) if lat else 0.0
        slow = mean > self.params.slow_latency
        status = DiagnosticStatus(
            name="perception: visual", hardware_id="camera",
            level=DiagnosticStatus.WARN if slow or not lat else DiagnosticStatus.OK,
            message=("no frames analysed yet" if not lat else
                     f"slow: mean latency {mean * 1000:.1f} ms" if slow else "ok"),
            values=[KeyValue(k, str(v)) for k, v in sorted(counts.items())]
            + [KeyValue("mean_latency_ms", f"{mean * 1000:.2f}"),
               KeyValue("last_bad_frame", last_bad or "none"),
               KeyValue("busy_with_a_request", str(busy)),
               KeyValue("object_memory_spots", str(len(self.memory.spots)))])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diagnostics.publish(array)


def main():
    rospy.init_node("visual")
    sup = Supervisor("perception: visual", hardware_id="camera")
    try:
        node = VisualNode(read_params())
        node.setup(sup)
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal("visual: cannot start: %s", error)
        return 1
    rospy.loginfo("visual: analysing /camera/detections")
    rospy.spin()
    return 0
