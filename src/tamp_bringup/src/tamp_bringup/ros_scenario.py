"""Node `scenario`: plays a scenario file (tamp_bringup.scenario) against the running household and
records what happened.

It tells the robot nothing about the people: the world moves them (sim2d) and the robot finds
them with its own perception. On simulated time each request is sent as the phone app does
(`tamp_msgs/Utterance` on /voice_message: the text and the phone's address, never where the
speaker is), or, when `spoken`, synthesised with espeak-ng and sent as audio on /audio_utterance
for the STT node; the world's timed moves are only noted in the record. For grading alone it
keeps ground truth (the robot's trajectory, the people's true places and activities from sim2d's
markers) next to what the robot believed (/humans/known) and what perception read them doing
(/humans/observed: frames per true activity and activity read), and what the robot said. It
ends when every request has produced an instruction and the task buffer holds no open
instruction (or after the scenario's timeout), writing the record JSON (`~record`) read by
scenario_report. Exit status 0 when the scenario finished, 1 on timeout. /task_planner/state
shows the open instructions; once none of a person is open, the whole buffer
(/task_planner/get_buffer) is matched against the requests, since the state carries only the
most recently finished instructions.

Its subscribers and each pass of its loop run under one supervision.ros_supervisor.Supervisor
("tamp_bringup: scenario: supervision" on /diagnostics): a request whose sending raises is
recorded as an event "request N of PERSON not sent: <reason>" (the run then times out), and any
other fault of a pass is recorded once as an event with its reason; the loop goes on.

Visitors (people of the world the household does not know) answer the robot's introduction
questions (thesis 000 §3.2.3): a sentence on /robot/say that asks them something
(scenario.visitor_answer) while the robot is in their place (ground truth, used only to drive the
scripted person) is answered with espeak-ng speech on /audio_utterance from their phone, so the
answer goes through the STT node and perception. With several robots (`~robots`, their
namespaces) it follows each robot's pose and speech, a visitor answers when any robot is in their
place, and the record holds every robot's trajectory; the task buffer it reads
(/task_planner/state, /task_planner/get_buffer, remapped by the launch file) is one robot's, which
holds every instruction of the fleet. Their requests are held until human_db lists
them (/humans/known); each registration (time, name, how long the dialogue took) is recorded.
A resident whose world move puts on a new shirt answers the robot's name question the same way,
on the robot's microphone (ip ""), while the robot is in the place the move took them; when
human_db's table shows their shirt changed, the recall is recorded. Asked "are you NAME?"
(perception.identity_question), the person a robot faces in its place (ground truth positions
from sim2d's people labels, for driving the scripted people only) answers yes or no on the
robot's microphone.
"""
import dataclasses
import datetime
import json
import math
import os
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
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor
from tamp_msgs.msg import (AudioUtterance, HumanArray, ObservedHumanArray, TaskBufferState,
                           Utterance)
from tamp_msgs.srv import GetTaskBuffer
from visualization_msgs.msg import MarkerArray

from tamp_bringup.activity_report import count_frame, parse_label
from tamp_bringup.scenario import (
    ASKED_WHO, CALLED, IDENTITY_QUESTION, INTRODUCE_TEXT, ends_dialogue, identity_answer,
    load_scenario, person_asked, place_of, resident_answer, residents, seen_shirt, timeline,
    visitor_answer, who_answers)

LOOP_HZ = 20  # [Hz of simulated time] passes of the run loop
OPEN = (0, 1)  # tamp_msgs/InstructionState PENDING, ACTIVE
ACTIVE, HUMAN = 1, 0  # tamp_msgs/InstructionState ACTIVE, tamp_msgs/Instruction HUMAN
WHO_WAIT_S = 3.0  # [s of simulated time] a question waits this long for the task buffer state
                  # that names the stranger asked, when several people could answer


@dataclasses.dataclass(frozen=True)
class ScenarioParams:
    """~parameters of the node."""

    scenario: str                     # the scenario file (required)
    record: str                       # where the record JSON goes (required)
    timeout: float = 0.0              # [s] > 0: replaces the file's timeout_s
    trajectory_period: float = 0.5    # [s of simulated time] between trajectory points
    command: str = "roslaunch tamp_bringup social_household.launch"   # shown in the report
    robots: tuple = ("",)             # namespaces of the robots ("" = the one robot's topics)
    setup_timeout: float = 300.0      # [s] wall-clock wait for the household to come up
    start_place: str = "charging_place"


def _changed(changes, now, place):
    """Append (now, place) to a person's [[t, place], ...] when the place differs from the last."""
    if not changes or changes[-1][1] != place:
        changes.append([now, place])


def _wav_samples(path):
    with wave.open(str(path), "rb") as stream:
        return stream.getframerate(), np.frombuffer(stream.readframes(stream.getnframes()),
                                                    dtype="<i2")


class ScenarioNode:
    def __init__(self, scenario, record_path, trajectory_period, command, robots=("",)):
        self.scenario, self.record_path = scenario, Path(record_path)
        self.trajectory_period = trajectory_period  # [s of simulated time]
        self.command = command
        self.lock = threading.Lock()
        self.robots = tuple(robots)        # namespaces ("" = the one robot's global topics)
        self.trajectories = {r: [] for r in self.robots}
        self.activities = {r: [] for r in self.robots}  # robot -> [[t, activity], ...]
        self.said, self.state, self.events = [], None, []
        self.poses = {}                    # robot -> (stamp, x, y, yaw) of its ground truth
        self.positions = {}                # person -> (x, y) of their ground truth
        self.truth, self.belief = {}, {}   # name -> [[t, place], ...] when the place changed
        self.doing = {}                    # name -> [[t, activity], ...]: the simulator's
        self.doing_now = {}                # name -> their activity now (the last of doing)
        self.activity_counts = {}          # true activity -> {activity read: frames}
        self.table = {}                    # human_db's table: name -> phone ip
        self.shirts = {}                   # human_db's table: name -> shirt (9 values) or None
        self.unmet = {}                    # resident to (re)meet -> the shirt human_db had then
        self.recalls = []                  # dict(time, person, place, dialogue_s, why)
        self.wearing = dict(scenario.shirts or {})   # person -> the shirt the world has on them
        self.where = {p: place for p, (place, _) in scenario.initial.items()}   # their place
        self.speaking = None               # who is answering the robot's questions now
        self.meeting = None                # the introduce instruction they answer (its id)
        self.ended = None                  # the introduce instruction whose dialogue ended last
        self.heard = 0                     # sentences of self.said the visitors have heard
        self.sent = {}                     # request index -> when it was sent [s]
        self.held = []                     # (index, request) of visitors not registered yet
        self.registrations = []            # dict(time, visitor, name, dialogue_s, answers)
        self.dialogues = {}                # visitor name -> dict(start, answers) while met
        self.own_waited = None             # finish_own: ids of the robot's own instructions
        #                                    open when the requests were first all served
        self.graph_spec = yaml.safe_load(Path(scenario.graph).read_text())
        self.inbox = []                    # (time, "truth" | "belief", message) to grade
        self.faults = set()                # reasons of the faults already recorded as events
        self.history = (None, None)        # (state message, get_buffer's instructions then)

    # ---- callbacks: cache only ----

    def _on_pose(self, robot, msg):
        with self.lock:
            q = msg.pose.pose.orientation
            self.poses[robot] = (msg.header.stamp.to_sec(), msg.pose.pose.position.x,
                                 msg.pose.pose.position.y,
                                 2.0 * math.atan2(q.z, q.w))   # the base turns about z only

    def _on_say(self, msg):
        with self.lock:
            self.said.append((rospy.get_time(), msg.data))

    def _on_activity(self, robot, msg):
        with self.lock:
            self.activities[robot].append([rospy.get_time(), msg.data])

    def _on_state(self, msg):
        with self.lock:
            self.state = msg

    def _on_markers(self, msg):
        with self.lock:
            self.inbox.append((rospy.get_time(), "truth", msg))

    def _on_known(self, msg):
        with self.lock:
            self.inbox.append((rospy.get_time(), "belief", msg))

    def _on_observed(self, msg):
        with self.lock:
            self.inbox.append((rospy.get_time(), "observed", msg))

    def _grade(self):
        """Ground truth of the people's places (sim2d's labels) next to what the robot believes
        (human_db's table), for grading only."""
        with self.lock:
            inbox, self.inbox = self.inbox, []
        for now, kind, msg in inbox:
            if kind == "observed":
                count_frame(self.activity_counts, self.doing_now,
                            [(h.name, h.activity) for h in msg.humans])
                continue
            if kind == "belief":
                with self.lock:
                    self.table = {human.name: human.ip for human in msg.humans}
                    self.shirts = {human.name: tuple(human.shirt_color) if human.shirt_known
                                   else None for human in msg.humans}
                for human in msg.humans:   # residents nobody has met answer when asked
                    if (not human.shirt_known and human.name in self.where
                            and human.name not in self.unmet
                            and human.name not in {v.name for v in self.scenario.visitors}):
                        self.unmet[human.name] = None
                for human in msg.humans:
                    _changed(self.belief.setdefault(human.name, []), now, human.location)
                continue
            for marker in msg.markers:
                if marker.ns == "people_labels":
                    place = place_of(self.graph_spec, marker.pose.position.x,
                                     marker.pose.position.y)
                    name, activity = parse_label(marker.text)
                    _changed(self.truth.setdefault(name, []), now, place)
                    _changed(self.doing.setdefault(name, []), now, activity)
                    self.doing_now[name] = activity
                    with self.lock:
                        self.positions[name] = (marker.pose.position.x, marker.pose.position.y)

    # ---- the run ----

    def setup(self, timeout, sup):
        """Subscribe under the node's Supervisor `sup`, synthesise the spoken requests and
        answers, and wait for the executor and human_db; False when human_db never lists the
        speakers."""
        self.sup = sup
        for robot in self.robots:
            prefix = f"/{robot}" if robot else ""
            sup.subscriber(f"{prefix}/base_pose_ground_truth", Odometry,
                           lambda msg, r=robot: self._on_pose(r, msg), queue_size=1)
            sup.subscriber(f"{prefix}/robot/say", String, self._on_say, queue_size=20)
            sup.subscriber(f"{prefix}/task_planner/activity", String,
                           lambda msg, r=robot: self._on_activity(r, msg), queue_size=20)
        if "" not in self.robots:   # the introduction node speaks for the fleet
            sup.subscriber("/robot/say", String, self._on_say, queue_size=20)
        sup.subscriber("/task_planner/state", TaskBufferState, self._on_state, queue_size=5)
        sup.subscriber("/sim2d/markers", MarkerArray, self._on_markers, queue_size=2)
        sup.subscriber("/humans/known", HumanArray, self._on_known, queue_size=5)
        sup.subscriber("/humans/observed", ObservedHumanArray, self._on_observed, queue_size=20)
        self.voice = rospy.Publisher("/voice_message", Utterance, queue_size=10)
        self.audio = rospy.Publisher("/audio_utterance", AudioUtterance, queue_size=2)
        rospy.wait_for_service("/task_planner/get_buffer", timeout)
        self.get_buffer = rospy.ServiceProxy("/task_planner/get_buffer", GetTaskBuffer)
        self._synthesise()
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline and not rospy.is_shutdown() and (
                self.voice.get_num_connections() == 0
                or (self.spoken and self.audio.get_num_connections() == 0)):
            time.sleep(0.1)
        # verbal perception identifies speakers from the latched table: wait until it is there
        table_deadline = time.monotonic() + timeout
        speakers = {r.person for r in self.scenario.requests if not r.visitor}
        while time.monotonic() < table_deadline:
            table = rospy.wait_for_message("/humans/known", HumanArray, timeout)
            if speakers <= {h.name for h in table.humans}:
                return True
            time.sleep(0.2)
        rospy.logerr("scenario: human_db never listed %s", ", ".join(sorted(speakers)))
        return False

    def _synthesise(self):
        """espeak-ng speech of the spoken requests, the visitors' answers and the residents'
        answers (their name, yes, no)."""
        self.spoken = {}
        self.answers = {}   # (person, answer text) -> (rate, samples)
        people = residents(self.scenario)
        if not (any(r.spoken for r in self.scenario.requests) or self.scenario.visitors
                or people):
            return
        from perception.speech_synthesis import synthesise
        workdir = Path(tempfile.mkdtemp(prefix="scenario_audio_"))
        for k, request in enumerate(self.scenario.requests):
            if request.spoken:
                self.spoken[k] = _wav_samples(synthesise(request.text, workdir / f"{k}.wav"))
        for visitor in self.scenario.visitors:
            for question, text in visitor.answers.items():
                self.answers[visitor.name, text] = _wav_samples(synthesise(
                    text, workdir / f"{visitor.name}_{question}.wav"))
            for name, kind in (("nobody", "no"), (visitor.name, "yes")):
                text = identity_answer(visitor.name, IDENTITY_QUESTION.format(name=name))
                self.answers[visitor.name, text] = _wav_samples(synthesise(
                    text, workdir / f"{visitor.name}_{kind}.wav"))
        for person in people:
            for said, kind in (("your name", "name"), (f"Did you say {person}?", "yes"),
                               ("Did you say nobody?", "no")):
                text = resident_answer(person, said)
                self.answers[person, text] = _wav_samples(synthesise(
                    text, workdir / f"{person}_{kind}.wav"))

    def _send(self, index, request):
        if request.visitor and self._registered(request.person) is None:
            self.held.append((index, request))   # sent once the robot has met them
            return
        stamp = rospy.Time.now()
        self.sent[index] = stamp.to_sec()
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

    def _visitor(self, name):
        return next(v for v in self.scenario.visitors if v.name == name)

    def _registered(self, person):
        """The name human_db lists the visitor under (their phone, else their name), or None."""
        visitor = self._visitor(person)
        with self.lock:
            table = dict(self.table)
        return next((n for n, ip in table.items() if ip == visitor.ip),
                    visitor.name if visitor.name in table else None)

    def _answer_questions(self):
        """The person the robot is asking, in a robot's place, answers: a visitor from their
        phone, a resident to (re)meet on the robot's microphone (ip "")."""
        with self.lock:
            said, poses, state = self.said[self.heard:], list(self.poses.values()), self.state
            first = self.heard
            self.heard = len(self.said)
        if not poses:
            return
        places = {place_of(self.graph_spec, pose[1], pose[2]) for pose in poses}
        registered = {r["visitor"] for r in self.registrations}
        visitors = {v.name: v for v in self.scenario.visitors if v.name not in registered}
        for k, (said_at, text) in enumerate(said):
            if self._answer_who(text, poses):
                continue
            if ends_dialogue(text):
                self.speaking, self.ended = None, self.meeting
                continue
            here = {name: self.wearing[name] for name in list(visitors) + list(self.unmet)
                    if self.where.get(name) in places}
            meeting, seen = self._seen_stranger(state)
            if meeting is not None and meeting == self.ended:
                meeting, seen = None, None   # the state still shows the meeting just ended
            if meeting is not None and meeting != self.meeting:
                self.speaking, self.meeting = None, meeting   # another stranger: whoever
                #                                               answered the last one is done
            if (self.speaking not in here and len(here) > 1 and seen is None
                    and rospy.get_time() - said_at < WHO_WAIT_S):
                with self.lock:   # who is asked shows once the state has the meeting ACTIVE
                    self.heard = first + k
                return
            person = self.speaking if self.speaking in here else who_answers(seen, here)
            if person is None:
                continue
            visitor = visitors.get(person)
            answer = visitor_answer(visitor, text) if visitor else resident_answer(person, text)
            if not answer:
                continue
            self.speaking = person
            dialogue = self.dialogues.setdefault(person, dict(start=rospy.get_time(),
                                                              answers=[]))
            dialogue["answers"].append([text, answer])
            rate, samples = self.answers[person, answer]
            ip = visitor.ip if visitor else ""
            msg = AudioUtterance(ip=ip, sample_rate=rate, samples=samples.tolist())
            msg.header.stamp = rospy.Time.now()
            self.audio.publish(msg)
            where = f"visitor, phone {ip}" if visitor else "on the robot's microphone"
            self._event(msg.header.stamp.to_sec(), f"{person} ({where}) answers \"{answer}\" to "
                        f"\"{text}\" (audio -> STT)")

    def _answer_who(self, text, poses):
        """"Are you NAME?": the person a robot faces in its place answers yes or no on the
        robot's microphone; "NAME, are you here?": NAME answers yes when in a robot's place.
        False when the sentence asks no such thing."""
        if not (CALLED.search(text.lower()) or ASKED_WHO.search(text.lower())):
            return False
        with self.lock:
            positions = dict(self.positions)
        person = person_asked(text, [pose[1:] for pose in poses], positions,
                              lambda x, y: place_of(self.graph_spec, x, y))
        if person is None:
            self._event(rospy.get_time(), f"nobody answers \"{text}\"")
            return True
        answer = identity_answer(person, text)
        if person in self.unmet and person.lower() in text.lower():   # asked their own name:
            # the yes may register the shirt of a resident to be (re)met
            self.dialogues.setdefault(person, dict(start=rospy.get_time(), answers=[]))[
                "answers"].append([text, answer])
        rate, samples = self.answers[person, answer]
        msg = AudioUtterance(ip="", sample_rate=rate, samples=samples.tolist())
        msg.header.stamp = rospy.Time.now()
        self.audio.publish(msg)
        self._event(msg.header.stamp.to_sec(), f"{person} (on the robot's microphone) answers "
                                               f"\"{answer}\" to \"{text}\" (audio -> STT)")
        return True

    @staticmethod
    def _seen_stranger(state):
        """(id, the shirt the robot saw on the stranger) of the introduce instruction it is
        serving, or (None, None)."""
        for record in state.instructions if state is not None else ():
            if record.state == ACTIVE and record.instruction.text.startswith(INTRODUCE_TEXT):
                return record.instruction.id, seen_shirt(record.instruction.text)
        return None, None

    def _notice_recalls(self):
        """Residents whose shirt human_db registered since they were to be (re)met: met."""
        with self.lock:
            shirts = dict(self.shirts)
        for person, before in list(self.unmet.items()):
            if shirts.get(person) in (None, before):
                continue
            now = rospy.get_time()
            start = self.dialogues.pop(person, dict(start=now))["start"]
            del self.unmet[person]
            if self.speaking == person:
                self.speaking = None
            why = "first meeting" if before is None else "new clothes"
            place = self.where[person]
            self.recalls.append(dict(time=now - self.t0, person=person, place=place,
                                     dialogue_s=now - start, why=why))
            self._event(now, f"the robot registered {person}'s shirt in the {place} ({why}) "
                             f"after a {now - start:.1f} s dialogue")

    def _meet_visitors(self):
        """Record registrations; send the requests held for visitors now registered."""
        for visitor in self.scenario.visitors:
            if visitor.name in {r["visitor"] for r in self.registrations}:
                continue
            name = self._registered(visitor.name)
            if name is None:
                continue
            if self.speaking == visitor.name:
                self.speaking = None
            now = rospy.get_time()
            dialogue = self.dialogues.get(visitor.name, dict(start=now, answers=[]))
            self.registrations.append(dict(
                time=now - self.t0, visitor=visitor.name, name=name,
                dialogue_s=now - dialogue["start"], answers=dialogue["answers"]))
            self._event(now, f"the robot registered {visitor.name} (visitor) as {name} after a "
                             f"{now - dialogue['start']:.1f} s dialogue "
                             f"({len(dialogue['answers'])} answers)")
        ready = [(k, r) for k, r in self.held if self._registered(r.person) is not None]
        self.held = [h for h in self.held if h not in ready]
        for index, request in ready:
            self._send(index, request)

    def _move(self, move):
        self.where[move.person] = move.place
        if move.clothes:
            self.wearing[move.person] = move.shirt
            with self.lock:
                before = self.shirts.get(move.person)
            if before is not None:          # not met yet: still to be met, in any clothes
                self.unmet[move.person] = before
        self._event(rospy.get_time(), f"{move.person} sets off to the {move.place} "
                                      f"({move.activity}"
                                      f"{', to change clothes' if move.clothes else ''}), "
                                      "unannounced")

    def _event(self, now, what):
        self.events.append(dict(time=now - self.t0, what=what))
        rospy.loginfo("scenario %.1f s: %s", now - self.t0, what)

    def _record_pose(self, last):
        """Every robot's pose once per trajectory_period (its time then); the latest time."""
        with self.lock:
            poses = dict(self.poses)
        stamp = max((pose[0] for pose in poses.values()), default=None)
        if stamp is None or (any(self.trajectories.values()) and
                             stamp - last < self.trajectory_period):
            return last
        for robot, pose in poses.items():
            self.trajectories[robot].append([pose[0] - self.t0, pose[1], pose[2]])
        return stamp

    def _finished(self):
        """Every request answered by an instruction from its person, every person's instruction
        closed and nothing active; with the scenario's `finish_own`, also the robot's own
        instructions open at the moment that first held closed (`_own_closed`); else the
        robot's own pending instructions do not hold the run."""
        if not self._requests_served():
            self.own_waited = None   # an instruction reopened (a search): the requests again
            return False
        return not self.scenario.finish_own or self._own_closed()

    def _own_closed(self):
        """Whether the robot's own instructions open when the requests were first all served
        are closed (those it gives itself later are not waited for)."""
        with self.lock:
            state = self.state
        records = self._every_instruction(state) if state is not None else None
        if records is None:
            return False
        if self.own_waited is None:
            self.own_waited = {r.instruction.id for r in records
                               if r.instruction.type != HUMAN and r.state in OPEN}
        return not any(r.instruction.id in self.own_waited and r.state in OPEN for r in records)

    def _requests_served(self):
        with self.lock:
            state = self.state
        if state is None or any(r.state == ACTIVE or (r.state in OPEN and
                                                      r.instruction.type == HUMAN)
                                for r in state.instructions):   # it carries every open one
            return False
        if len(self.sent) < len(self.scenario.requests):
            return False   # a visitor's request waits for their registration
        records = self._every_instruction(state)
        if records is None:
            return False
        unmatched = list(records)
        for index, request in enumerate(self.scenario.requests):
            source = self._registered(request.person) if request.visitor else request.person
            match = next((r for r in unmatched if r.instruction.source == source
                          and r.instruction.start_time >= self.sent[index] - 0.5), None)
            if match is None or match.state in OPEN:
                return False   # the buffer read may be newer than `state`: open there too
            unmatched.remove(match)
        return True

    def _every_instruction(self, state):
        """Every instruction of the task buffer as of `state` (asked once per state from
        /task_planner/get_buffer); None when the service did not answer."""
        if state.complete:
            return list(state.instructions)
        asked_for, instructions = self.history
        if asked_for is not state:
            try:
                instructions = list(self.get_buffer().state.instructions)
            except rospy.ServiceException as error:
                rospy.logwarn_throttle(10.0, "scenario: /task_planner/get_buffer failed: %s",
                                       error)
                return None
            self.history = (state, instructions)
        return instructions

    def run(self, start_place):
        while rospy.get_time() <= 0 and not rospy.is_shutdown():
            time.sleep(0.05)  # sim time has not started
        self.t0 = 0.0  # the world's schedules count from the simulator's start
        wall_start = time.monotonic()
        events = timeline(self.scenario)
        last_request = max(r.time_s for r in self.scenario.requests)
        rate = rospy.Rate(LOOP_HZ)
        self.sup.worker("run", 1.0 / LOOP_HZ)
        last_pose, finished, index = -1e9, False, {id(r): k for k, r in
                                                   enumerate(self.scenario.requests)}
        while not rospy.is_shutdown():
            now = rospy.get_time() - self.t0
            while events and events[0][0] <= now:
                _, kind, event = events.pop(0)
                what = (f"request {index[id(event)]} of {event.person}" if kind == "request"
                        else f"move of {event.person}")
                with self.sup.guard("run", what) as failure:
                    if kind == "request":
                        self._send(index[id(event)], event)
                    else:
                        self._move(event)
                if failure:
                    self._fault(f"{what} not {'sent' if kind == 'request' else 'noted'}: "
                                f"{fault_text(failure[0])}")
            with self.sup.guard("run", "grading") as failure:
                self._grade()
                if self.scenario.visitors or self.unmet:
                    self._answer_questions()
                    self._meet_visitors()
                    self._notice_recalls()
                last_pose = self._record_pose(last_pose)
                finished = now > last_request and self._finished()
            if failure:
                self._fault(f"scenario pass failed: {fault_text(failure[0])}")
            if finished:
                break
            if now > last_request + self.scenario.timeout_s:
                if self.own_waited is not None:   # served every request; own ones still open
                    rospy.logwarn("scenario: every request served; the robot's own "
                                  "instructions still open %.0f s after the last request",
                                  self.scenario.timeout_s)
                    finished = True
                else:
                    rospy.logerr("scenario: timed out %.0f s after the last request",
                                 self.scenario.timeout_s)
                break
            rate.sleep()
        self._write(start_place, finished, time.monotonic() - wall_start)
        return finished

    def _fault(self, what):
        """Record a fault as an event, once per reason (the supervisor counts the repeats)."""
        if what not in self.faults:
            self.faults.add(what)
            self._event(rospy.get_time(), what)

    def _write(self, start_place, finished, wall_s):
        record = dict(
            scenario=self.scenario.name, command=self.command,
            date=datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC"),
            speed=rospy.get_param("/sim2d/speed", 1.0),
            planner=rospy.get_param(
                (f"/{self.robots[0]}" if self.robots[0] else "") + "/task_planner/planner",
                "seed"),
            start_place=start_place, t0=self.t0, sim_s=rospy.get_time() - self.t0,
            wall_s=wall_s, finished=finished, events=self.events,
            trajectory=self.trajectories[self.robots[0]],
            requests=[dict(time=r.time_s, person=r.person, text=r.text, spoken=r.spoken,
                           visitor=r.visitor, sent=self.sent[k] - self.t0 if k in self.sent
                           else None)
                      for k, r in enumerate(self.scenario.requests)],
            registrations=self.registrations, recalls=self.recalls,
            said=[[t - self.t0, text] for t, text in self.said],
            truth={n: [[t - self.t0, p] for t, p in c] for n, c in self.truth.items()},
            activities={r: [[t - self.t0, a] for t, a in c] for r, c in self.activities.items()},
            belief={n: [[t - self.t0, p] for t, p in c] for n, c in self.belief.items()},
            doing={n: [[t - self.t0, a] for t, a in c] for n, c in self.doing.items()},
            activity_counts=self.activity_counts)
        if len(self.robots) > 1:
            record["trajectories"] = self.trajectories
        self.record_path.parent.mkdir(parents=True, exist_ok=True)
        # written whole, then renamed: whoever waits for the file never reads half of it
        partial = self.record_path.with_name(self.record_path.name + ".partial")
        partial.write_text(json.dumps(record, indent=1))
        os.replace(partial, self.record_path)
        rospy.loginfo("scenario: record written to %s", self.record_path)


def main():
    rospy.init_node("scenario")
    sup = Supervisor("tamp_bringup: scenario")
    params = config_from_params(ScenarioParams)
    scenario = load_scenario(params.scenario)
    if params.timeout > 0:
        scenario = dataclasses.replace(scenario, timeout_s=params.timeout)
    node = ScenarioNode(scenario, params.record, params.trajectory_period, params.command,
                        params.robots)
    if not node.setup(params.setup_timeout, sup):
        return 1
    finished = node.run(params.start_place)
    return 0 if finished else 1
