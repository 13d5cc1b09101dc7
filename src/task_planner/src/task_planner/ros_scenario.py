"""Node `scenario`: plays a scenario file (task_planner.scenario) against the running household and
records what happened.

It tells the robot nothing about the people: the world moves them (sim2d) and the robot finds
them with its own perception. On simulated time each request is sent as the phone app does
(`tamp_msgs/Utterance` on /voice_message: the text and the phone's address, never where the
speaker is), or, when `spoken`, synthesised with espeak-ng and sent as audio on /audio_utterance
for the STT node; the world's timed moves are only noted in the record. For grading alone it
keeps ground truth (the robot's trajectory, the people's true places from sim2d's markers) next
to what the robot believed (/humans/known), and what the robot said. It ends when every request
has produced an instruction and the task buffer holds no open instruction (or after the
scenario's timeout), writing the record JSON (`~record`) read by scenario_report. Exit status 0
when the scenario finished, 1 on timeout.
"""
import datetime
import json
import tempfile
import threading
import time
import wave
from pathlib import Path

import numpy as np
import rospy
import yaml
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from tamp_msgs.msg import AudioUtterance, HumanArray, TaskBufferState, Utterance
from visualization_msgs.msg import MarkerArray

from task_planner.scenario import load_scenario, place_of, timeline

OPEN = (0, 1)  # tamp_msgs/InstructionState PENDING, ACTIVE


def _changed(changes, now, place):
    """Append (now, place) to a person's [[t, place], ...] when the place differs from the last."""
    if not changes or changes[-1][1] != place:
        changes.append([now, place])


def _wav_samples(path):
    with wave.open(str(path), "rb") as stream:
        return stream.getframerate(), np.frombuffer(stream.readframes(stream.getnframes()),
                                                    dtype="<i2")


class ScenarioNode:
    def __init__(self, scenario, record_path, trajectory_period, command):
        self.scenario, self.record_path = scenario, Path(record_path)
        self.trajectory_period = trajectory_period  # [s of simulated time]
        self.command = command
        self.lock = threading.Lock()
        self.trajectory, self.said, self.state, self.events = [], [], None, []
        self.pose = None
        self.truth, self.belief = {}, {}   # name -> [[t, place], ...] when the place changed
        self.graph_spec = yaml.safe_load(Path(scenario.graph).read_text())

    # ---- callbacks: cache only ----

    def _on_pose(self, msg):
        with self.lock:
            self.pose = (msg.header.stamp.to_sec(), msg.pose.pose.position.x,
                         msg.pose.pose.position.y)

    def _on_say(self, msg):
        with self.lock:
            self.said.append((rospy.get_time(), msg.data))

    def _on_state(self, msg):
        with self.lock:
            self.state = msg

    def _on_markers(self, msg):
        """Ground truth of the people's places (sim2d's labels), for grading only."""
        now = rospy.get_time()
        with self.lock:
            for marker in msg.markers:
                if marker.ns == "people_labels":
                    name = marker.text.split(":")[0]
                    place = place_of(self.graph_spec, marker.pose.position.x,
                                     marker.pose.position.y)
                    _changed(self.truth.setdefault(name, []), now, place)

    def _on_known(self, msg):
        """What the robot believes (human_db's table), to grade it against the truth."""
        now = rospy.get_time()
        with self.lock:
            for human in msg.humans:
                _changed(self.belief.setdefault(human.name, []), now, human.location)

    # ---- the run ----

    def setup(self, timeout):
        rospy.Subscriber("/base_pose_ground_truth", Odometry, self._on_pose, queue_size=1)
        rospy.Subscriber("/robot/say", String, self._on_say, queue_size=20)
        rospy.Subscriber("/task_planner/state", TaskBufferState, self._on_state, queue_size=5)
        rospy.Subscriber("/sim2d/markers", MarkerArray, self._on_markers, queue_size=2)
        rospy.Subscriber("/humans/known", HumanArray, self._on_known, queue_size=5)
        self.voice = rospy.Publisher("/voice_message", Utterance, queue_size=10)
        self.audio = rospy.Publisher("/audio_utterance", AudioUtterance, queue_size=2)
        rospy.wait_for_service("/task_planner/get_buffer", timeout)
        self.spoken = {}
        workdir = Path(tempfile.mkdtemp(prefix="scenario_audio_"))
        if any(r.spoken for r in self.scenario.requests):
            from perception.speech_synthesis import synthesise
            for k, request in enumerate(self.scenario.requests):
                if request.spoken:
                    self.spoken[k] = _wav_samples(synthesise(request.text, workdir / f"{k}.wav"))
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown() and (
                self.voice.get_num_connections() == 0
                or (self.spoken and self.audio.get_num_connections() == 0)):
            time.sleep(0.1)
        # verbal perception identifies speakers from the latched table: wait until it is there
        table_deadline = time.monotonic() + timeout
        speakers = {r.person for r in self.scenario.requests}
        while time.monotonic() < table_deadline:
            table = rospy.wait_for_message("/humans/known", HumanArray, timeout)
            if speakers <= {h.name for h in table.humans}:
                return True
            time.sleep(0.2)
        rospy.logerr("scenario: human_db never listed %s", ", ".join(sorted(speakers)))
        return False

    def _send(self, index, request):
        stamp = rospy.Time.now()
        if request.spoken:
            rate, samples = self.spoken[index]
            msg = AudioUtterance(ip=request.ip, sample_rate=rate, samples=samples.tolist())
            msg.header.stamp = stamp
            self.audio.publish(msg)
            what = (f"{request.person} (phone {request.ip}) speaks: \"{request.text}\" "
                    f"(audio -> STT)")
        else:
            msg = Utterance(text=request.text, ip=request.ip)
            msg.header.stamp = stamp
            self.voice.publish(msg)
            what = f"{request.person} (phone {request.ip}) sends: \"{request.text}\""
        self._event(stamp.to_sec(), what)

    def _move(self, move):
        self._event(rospy.get_time(), f"{move.person} sets off to the {move.place} "
                                      f"({move.activity}), unannounced")

    def _event(self, now, what):
        self.events.append(dict(time=now - self.t0, what=what))
        rospy.loginfo("scenario %.1f s: %s", now - self.t0, what)

    def _record_pose(self, last):
        with self.lock:
            pose = self.pose
        if pose is not None and (not self.trajectory or pose[0] - last >= self.trajectory_period):
            self.trajectory.append([pose[0] - self.t0, pose[1], pose[2]])
            return pose[0]
        return last

    def _finished(self):
        """Every request answered by an instruction from its person and nothing open."""
        with self.lock:
            state = self.state
        if state is None:
            return False
        records = list(state.instructions)
        unmatched = list(records)
        for request in self.scenario.requests:
            match = next((r for r in unmatched if r.instruction.source == request.person
                          and r.instruction.start_time >= self.t0 + request.time_s - 0.5), None)
            if match is None:
                return False
            unmatched.remove(match)
        return not any(r.state in OPEN for r in records)

    def run(self, start_place):
        while rospy.get_time() <= 0 and not rospy.is_shutdown():
            time.sleep(0.05)  # sim time has not started
        self.t0 = 0.0  # the world's schedules count from the simulator's start
        wall_start = time.monotonic()
        events = timeline(self.scenario)
        last_request = max(r.time_s for r in self.scenario.requests)
        rate = rospy.Rate(20)
        last_pose, finished, index = -1e9, False, {id(r): k for k, r in
                                                   enumerate(self.scenario.requests)}
        while not rospy.is_shutdown():
            now = rospy.get_time() - self.t0
            while events and events[0][0] <= now:
                _, kind, event = events.pop(0)
                if kind == "request":
                    self._send(index[id(event)], event)
                else:
                    self._move(event)
            last_pose = self._record_pose(last_pose)
            if now > last_request and self._finished():
                finished = True
                break
            if now > last_request + self.scenario.timeout_s:
                rospy.logerr("scenario: timed out %.0f s after the last request",
                             self.scenario.timeout_s)
                break
            rate.sleep()
        self._write(start_place, finished, time.monotonic() - wall_start)
        return finished

    def _write(self, start_place, finished, wall_s):
        record = dict(
            scenario=self.scenario.name, command=self.command,
            date=datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
            speed=rospy.get_param("/sim2d/speed", 1.0),
            planner=rospy.get_param("/task_planner/planner", "seed"),
            start_place=start_place, t0=self.t0, sim_s=rospy.get_time() - self.t0,
            wall_s=wall_s, finished=finished, events=self.events, trajectory=self.trajectory,
            requests=[dict(time=r.time_s, person=r.person, text=r.text, spoken=r.spoken)
                      for r in self.scenario.requests],
            said=[[t - self.t0, text] for t, text in self.said],
            truth={n: [[t - self.t0, p] for t, p in c] for n, c in self.truth.items()},
            belief={n: [[t - self.t0, p] for t, p in c] for n, c in self.belief.items()})
        self.record_path.parent.mkdir(parents=True, exist_ok=True)
        self.record_path.write_text(json.dumps(record, indent=1))
        rospy.loginfo("scenario: record written to %s", self.record_path)


def main():
    rospy.init_node("scenario")
    scenario = load_scenario(rospy.get_param("~scenario"))
    node = ScenarioNode(scenario, rospy.get_param("~record"),
                        float(rospy.get_param("~trajectory_period", 0.5)),
                        rospy.get_param("~command", "roslaunch launch/social_household.launch"))
    if not node.setup(timeout=float(rospy.get_param("~setup_timeout", 120.0))):
        return 1
    finished = node.run(rospy.get_param("~start_place", "charging_place"))
    return 0 if finished else 1
