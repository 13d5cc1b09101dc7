"""Node `scenario`: plays a scenario file (task_planner.scenario) against the running household and
records what happened.

At start it tells human_db where everyone is (the world's initial poses, source "scenario": the
household's presence sensing, which the robot's camera cannot replace for rooms it does not see).
Then, on simulated time: each request is sent as the phone app does (`tamp_msgs/Utterance` on
/voice_message), or, when `spoken`, synthesised with espeak-ng and sent as audio on
/audio_utterance for the STT node; each of the world's timed moves (the schedule deviations) is
recorded in human_db when the person sets off. It keeps the robot's ground-truth trajectory and
what the robot said, and ends when every request has produced an instruction and the task buffer
holds no open instruction (or after the scenario's timeout), writing the record JSON
(`~record`) read by scenario_report. Exit status 0 when the scenario finished, 1 on timeout.
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
from nav_msgs.msg import Odometry
from std_msgs.msg import String
from tamp_msgs.msg import AudioUtterance, HumanArray, TaskBufferState, Utterance
from tamp_msgs.srv import UpdateHuman

from task_planner.scenario import load_scenario, timeline

OPEN = (0, 1)  # tamp_msgs/InstructionState PENDING, ACTIVE


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

    # ---- the run ----

    def setup(self, timeout):
        rospy.Subscriber("/base_pose_ground_truth", Odometry, self._on_pose, queue_size=1)
        rospy.Subscriber("/robot/say", String, self._on_say, queue_size=20)
        rospy.Subscriber("/task_planner/state", TaskBufferState, self._on_state, queue_size=5)
        self.voice = rospy.Publisher("/voice_message", Utterance, queue_size=10)
        self.audio = rospy.Publisher("/audio_utterance", AudioUtterance, queue_size=2)
        for service in ("/human_db/update", "/task_planner/get_buffer"):
            rospy.wait_for_service(service, timeout)
        self.update = rospy.ServiceProxy("/human_db/update", UpdateHuman)
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
        for name, (place, activity) in self.scenario.initial.items():
            reply = self.update(name=name, location=place, activity=activity, source="scenario")
            if not reply.success:
                rospy.logerr("scenario: human_db refused %s: %s", name, reply.message)
                return False
        # verbal perception identifies speakers from the latched table: wait until it is there
        table_deadline = time.monotonic() + timeout
        while time.monotonic() < table_deadline:
            table = rospy.wait_for_message("/humans/known", HumanArray, timeout)
            if all(any(h.name == n and h.location == p for h in table.humans)
                   for n, (p, _) in self.scenario.initial.items()):
                return True
            time.sleep(0.2)
        rospy.logerr("scenario: human_db never showed the initial places")
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
        reply = self.update(name=move.person, location=move.place, activity=move.activity,
                            source="scenario")
        self._event(rospy.get_time(), f"{move.person} sets off to the {move.place} "
                                      f"({move.activity}) - schedule deviation"
                    + ("" if reply.success else f"; human_db refused: {reply.message}"))

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
            said=[[t - self.t0, text] for t, text in self.said])
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
