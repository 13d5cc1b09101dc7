"""The introduction node: meeting a new person (thesis 000 §3.2.3, Initialization phase).

Unidentified people on /humans/observed -> an `introduce` instruction submitted on
/task_planner/submit with id 0, under the id the task buffer allocates
(perception.introduction.NewcomerWatch); while the executor serves it
(ACTIVE in /task_planner/state, having said the function's greeting, which asks the name; in a
fleet ACTIVE in any robot's state of ~state_topics, since the robot that received the instruction
need not be the one that serves it) the
node asks the gender and the age on /robot/say, reads the answers from /voice_message, registers
the person with /human_db/register and says "Nice to meet you, NAME.". A name human_db already
lists is a resident whose clothes changed: the node updates their shirt colours (and place) with
/human_db/update, source "recall" (human_db keeps the old shirt), and says so.

Which utterances are answers: while a dialogue is open, every utterance whose phone is not a
registered person's (a stranger's phone, or the robot's own microphone, ip "") is an answer. The
node says so on the latched ~dialogue_open (std_msgs/Bool), and verbal perception skips exactly
those utterances then, so an answer never also becomes a refused request. When the last answer
completes the dialogue, the latched ~answers_until (std_msgs/Time) gets that answer's stamp before
the person is registered: whatever the new person says after it is a request, even while
~dialogue_open still lingers (Time 0: no such limit, the open dialogue waits for answers).

Asking who someone is (perception.identity_question): an executor that faced a person it cannot
tell asks on its ~ask_who (tamp_msgs/AskWho, beside each of ~state_topics) whether they are the
person it looks for (with `call`: calls them, "NAME, are you here?", when the camera saw no sign
of them where they are expected). When no dialogue is open, the node says the question, reads a
yes or a no from the robot's microphone (ip "") and, on a yes, puts NAME at the place with
/human_db/update (location only, source "asked"; when the camera saw exactly one stranger there in
the last ~recall_window seconds, also that stranger's shirt, source "recall": NAME changed
clothes, identity_question.RecentStrangers, and the meeting asked for that stranger is
cancelled with each executor's ~cancel); the executor's belief follows from human_db's table.
The answer ("yes", "no", "unanswered") goes out on ~asked (a no ends the executor's wait); an
ask the node cannot put (another dialogue is open) is "unanswered" at once. The
question holds ~dialogue_open like a dialogue. The speech-to-text node says on ~heard_topic
(tamp_msgs/Utterance with its stamp and ip, no text) when it queues an utterance: one from the
robot's microphone spoken within ~ask_timeout whose transcript has not come yet holds the
question for up to ~transcript_wait seconds of the wall clock after it was queued, so a busy
speech-to-text node does not turn a yes into "unanswered" (at 20x real time a transcript
takes tens of simulated seconds).

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor: a fault in the
work timer while a dialogue is open ends that dialogue as not met, with the reason (the robot
says it gives up; the stranger is left alone for `retry_after`), and raises
"perception: introduction: supervision" to ERROR.
"""
import collections
import threading
import time
from dataclasses import dataclass

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from human_db.conversions import colours_from_msg, human_to_msg
from human_db.errors import HumanDbError
from floorplan.semantic_graph import load_graph
from std_msgs.msg import Bool, String, Time, UInt32
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor
from tamp_msgs.msg import AskWho, HumanArray, InstructionState, ObservedHumanArray, TaskBufferState
from tamp_msgs.msg import Utterance
from tamp_msgs.srv import CancelInstruction, RegisterHuman, UpdateHuman
from task_planner.reward import load_priorities
from task_planner.robot_functions import load_robot_functions
from task_planner.ros_submit import SubmitClient

from perception.conversions import utterance_time
from perception.identity_question import (UNANSWERED, YES, IdentityQuestion,
                                          PendingTranscripts, QuestionConfig, RecentStrangers)
from perception.introduction import (COMPLETE, FAILED, IntroductionConfig, IntroductionDialogue,
                                     NewcomerWatch, answered_by_the_stranger, seen_shirt,
                                     shirts_known, walked_off)

ENDED = (InstructionState.DONE, InstructionState.FAILED, InstructionState.CANCELLED)


def greeted_at(states, record, now: float) -> float:
    """When the executor greeted the stranger of `record` (an active instruction): the stamp
    of the state that reports it, said as the function starts, so an answer may come before
    that state reaches this node; `now` [s] when the state carries no stamp."""
    stamp = next(state.header.stamp.to_sec() for state in states
                 if any(r is record for r in state.instructions))
    return min(now, stamp) if stamp > 0 else now


@dataclass(frozen=True)
class IntroductionParams:
    graph: str                            # ~graph: maps/<map>.graph.yaml
    priorities_file: str                  # ~priorities_file: config/priorities.yaml
    robot_functions: str                  # ~robot_functions: config/robot_functions.yaml
    function: str = "introduce"           # ~function: the robot function that meets people
    priority: str = "self_generated"      # ~priority: Table 5-5 level of the introduce
                                          # instruction (config/priorities.yaml)
    humans_topic: str = "humans/known"    # ~humans_topic: human_db's latched table
    period: float = 0.1                   # ~period: work timer period [s]
    close_linger: float = 3.0             # ~close_linger [s]: ~dialogue_open stays true this
                                          # long after a dialogue ends (a late last answer)
    register_timeout: float = 5.0         # ~register_timeout [s] for /human_db/register and
                                          # /task_planner/submit
    state_topics: tuple = ("task_planner/state",)  # ~state_topics: the executors' states (one
                                          # per robot of a fleet)
    question: QuestionConfig = QuestionConfig()  # ~ask_timeout: [s] an "are you NAME?"
                                          # waits for a yes or a no; ~transcript_wait [s]
                                          # more for the transcript of one spoken in time
    heard_topic: str = "stt/heard"        # ~heard_topic: the STT node's "utterance queued"
                                          # (tamp_msgs/Utterance, no text): answers on the way
    recall_window: float = 10.0           # ~recall_window [s]: a yes takes the shirt of the
                                          # one stranger seen at the place this recently
    config: IntroductionConfig = IntroductionConfig()  # ~threshold, ~ambiguity_margin,
                                          # ~min_sightings,
                                          # ~max_retries, ~answer_timeout,
                                          # ~transcript_wait, ~retry_after,
                                          # ~seen_within, ~gone_after,
                                          # ~pass_through, ~settle_after


def beside_state(state_topic, name):
    """The executor's topic `name` beside its state topic ("robot1/task_planner/state",
    "function_over" -> "robot1/task_planner/function_over")."""
    return state_topic.rsplit("/", 1)[0] + "/" + name


def read_params():
    """Node parameters; KeyError names a missing required one."""
    config = config_from_params(IntroductionConfig, only=(
        "threshold", "ambiguity_margin", "min_sightings", "max_retries", "answer_timeout",
        "transcript_wait", "retry_after", "seen_within", "gone_after", "pass_through",
        "settle_after"))
    question = config_from_params(QuestionConfig, only=("ask_timeout", "transcript_wait"))
    return config_from_params(IntroductionParams, only=(
        "graph", "priorities_file", "robot_functions", "function", "priority", "humans_topic",
        "period", "close_linger", "register_timeout", "state_topics", "heard_topic"),
        hint=" (see tamp_bringup's social_household.launch)", config=config, question=question)


class IntroductionNode:
    def __init__(self, params):
        self.params = params
        self._lock = threading.Lock()
        self._frames = collections.deque(maxlen=50)
        self._utterances = collections.deque(maxlen=20)
        self._transcribing = PendingTranscripts(   # on the wall clock: transcribing is
            max(params.question.transcript_wait,   # computation, not simulated time
                params.config.transcript_wait))
        self._asks = collections.deque(maxlen=5)
        self.question = None      # the IdentityQuestion being asked, if any
        self._states = {}         # state topic -> latest TaskBufferState
        self._known = None        # {name: (shirt (r, g, b) x 3, None = not met; ip)}; None
                                  # until the first table
        self.watch = self.dialogue = self.stranger = None
        self._met_id = 0          # id of the introduce instruction the last dialogue was for
        self._open_until = None   # ~dialogue_open is true until this time [s]; None = closed
        self._free_since = 0.0    # [s] when the last dialogue or question ended: a greeting
                                  # said before then was answered into that one
        self._published_open = None
        self._counts = {"instructions": 0, "not_submitted": 0, "dialogues": 0, "registered": 0,
                        "recalled": 0, "not_met": 0, "asked": 0, "asked_yes": 0,
                        "asked_no": 0, "asked_unanswered": 0, "asks_not_taken": 0,
                        "answers": 0, "refused_answers": 0, "bad_observations": 0}
        self._last = ""           # last registration or failure, for diagnostics
        self._timers = []

    def setup(self, sup):
        """Load the configuration (ValueError names a bad entry) and start the ROS API under the
        node's Supervisor `sup`."""
        p = self.params
        functions = {f.name: f for f in load_robot_functions(p.robot_functions).values()}
        if p.function not in functions:
            raise ValueError(f"{p.robot_functions}: no robot function '{p.function}' "
                             f"(known: {', '.join(sorted(functions))})")
        function = functions[p.function]
        self.watch = NewcomerWatch(
            p.config, (function.code, function.duration_s),
            self._priority(p), load_graph(p.graph).place_ids())
        self.recent = RecentStrangers(float(p.recall_window), p.config.threshold)
        self.register = rospy.ServiceProxy("human_db/register", RegisterHuman)
        self.update = rospy.ServiceProxy("human_db/update", UpdateHuman)
        # acknowledged: a lost or refused introduce instruction must not block later meetings
        self.submit = SubmitClient(p.register_timeout)
        self.say = rospy.Publisher("robot/say", String, queue_size=5)
        # a dialogue that is over ends the introduce function at once, on every robot's executor
        self.function_over = [rospy.Publisher(beside_state(topic, "function_over"), UInt32,
                                              queue_size=5) for topic in p.state_topics]
        self.dialogue_open = rospy.Publisher("~dialogue_open", Bool, queue_size=1, latch=True)
        self.asked = rospy.Publisher("~asked", AskWho, queue_size=5)
        self.answers_until = rospy.Publisher("~answers_until", Time, queue_size=1, latch=True)
        self.diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        sup.subscriber("humans/observed", ObservedHumanArray, self._on_observed, queue_size=10)
        sup.subscriber(p.humans_topic, HumanArray, self._on_known, queue_size=1)
        for topic in p.state_topics:
            sup.subscriber(topic, TaskBufferState, lambda msg, t=topic: self._on_state(t, msg),
                           queue_size=1)
        for topic in p.state_topics:
            sup.subscriber(beside_state(topic, "ask_who"), AskWho, self._on_ask, queue_size=5)
        sup.subscriber("voice_message", Utterance, self._on_utterance, queue_size=10)
        sup.subscriber(p.heard_topic, Utterance, self._on_heard, queue_size=10)
        self._publish_open(False)
        self.answers_until.publish(Time(rospy.Time(0)))
        self._timers = [sup.timer(p.period, self._on_work, worker="work",
                                  on_error=self._fail_dialogue),
                        sup.timer(1.0, self._on_diagnostics, worker="diagnostics")]

    @staticmethod
    def _priority(params):
        """The Table 5-5 priority of the introduce instructions; ValueError names a bad level."""
        levels = load_priorities(params.priorities_file)
        if params.priority not in levels:
            raise ValueError(f"~priority {params.priority!r} is not a level of "
                             f"{params.priorities_file} ({', '.join(levels)})")
        return levels[params.priority]

    # ---- callbacks: cache only ----

    def _on_observed(self, msg):
        with self._lock:
            self._frames.append(msg)

    def _on_known(self, msg):
        table = {h.name: (colours_from_msg(h.shirt_color) if h.shirt_known else None, h.ip)
                 for h in msg.humans}
        with self._lock:
            self._known = table

    def _on_state(self, topic, msg):
        with self._lock:
            self._states[topic] = msg

    def _on_utterance(self, msg):
        with self._lock:
            self._utterances.append(msg)
            self._transcribing.transcribed(utterance_time(msg))

    def _on_heard(self, msg):
        """The STT node queued an utterance of the robot's microphone: its transcript is on the
        way, with the same stamp."""
        if msg.ip:
            return
        with self._lock:
            self._transcribing.heard(utterance_time(msg), time.monotonic())

    def _on_ask(self, msg):
        with self._lock:
            self._asks.append(msg)

    # ---- work ----

    def _on_work(self, _event):
        with self._lock:
            frames, self._frames = list(self._frames), collections.deque(maxlen=50)
            utterances, self._utterances = list(self._utterances), collections.deque(maxlen=20)
            asks, self._asks = list(self._asks), collections.deque(maxlen=5)
            states, known = list(self._states.values()), self._known
        now = rospy.get_time()
        if known is None:
            rospy.logwarn_throttle(10.0, "introduction: no human table on %s yet; nobody is met",
                                   self.params.humans_topic)
            return
        for frame in frames:
            self._look(frame, known)
        if states:
            self._follow(states, now)
        for msg in asks:
            self._ask(msg, now)
        ips = {ip for _, ip in known.values() if ip}
        for msg in utterances:
            if self.dialogue is not None and self.dialogue.open and msg.ip not in ips:
                self._answer(msg, now)
            elif self.question is not None and self.question.open and not msg.ip:
                self._answer_question(self.question.hear(msg.text, now), msg)
        with self._lock:
            transcribing = self._transcribing.spoken(time.monotonic())
        if self.dialogue is not None and self.dialogue.open:
            if walked_off(self.stranger, self.dialogue, now, transcribing):
                self._gone(now)
            else:
                self._turn(self.dialogue.tick(now, transcribing), now)
        if self.question is not None and self.question.open:
            self._answer_question(self.question.tick(now, transcribing), None)
        talking = any(d is not None and d.open for d in (self.dialogue, self.question))
        self._publish_open(self._open_until is not None and (talking or now < self._open_until))

    def _ask(self, msg, now):
        """An executor asks whether the person it faces is msg.name: say the question, unless
        a dialogue or another question is open (the robot talks with one person at a time)."""
        if any(d is not None and d.open for d in (self.dialogue, self.question)):
            self._count("asks_not_taken")
            rospy.logwarn("introduction: not asking whether the person at %s is %s: another "
                          "dialogue is open", msg.place, msg.name)
            self._not_asked(msg)
            return
        try:
            self.question = IdentityQuestion(self.params.question, msg.name, msg.place, now,
                                             call=msg.call)
        except ValueError as error:
            self._count("asks_not_taken")
            self._last = f"ask_who refused: {error}"
            rospy.logwarn("introduction: %s", self._last)
            self._not_asked(msg)
            return
        self._count("asked")
        self._open_until = now
        self.answers_until.publish(Time(rospy.Time(0)))  # answers until the question ends
        self.say.publish(String(self.question.question()))
        rospy.loginfo("introduction: %s", f"calling {msg.name} at {msg.place}" if msg.call else
                      f"asking whether the person at {msg.place} is {msg.name}")

    def _not_asked(self, msg):
        """An ask not put: "unanswered" on ~asked at once, so the executor turns on instead of
        waiting its ~ask_wait for an answer that cannot come."""
        answered = AskWho(name=msg.name, place=msg.place, call=msg.call, answer=UNANSWERED)
        answered.header.stamp = rospy.Time.now()
        self.asked.publish(answered)

    def _answer_question(self, reply, msg):
        """The question's reply to an answer (msg) or a tick (msg None): say it; on a yes put
        the person at the place in human_db."""
        question = self.question
        if msg is not None:
            self._count("answers")
            rospy.loginfo("introduction: heard %r from the microphone -> %s", msg.text,
                          reply.state)
        if reply.say:
            self.say.publish(String(reply.say))
        if question.open:
            return
        if msg is not None:
            self.answers_until.publish(Time(rospy.Time.from_sec(utterance_time(msg))))
        self._count(f"asked_{reply.state}")
        self._free_since = rospy.get_time()
        self._open_until = self._free_since + self.params.close_linger
        answered = AskWho(name=question.name, place=question.place, answer=reply.state)
        answered.header.stamp = rospy.Time.now()
        self.asked.publish(answered)
        if reply.state != YES:
            rospy.loginfo("introduction: the person at %s is not %s (%s)", question.place,
                          question.name, reply.state)
            return
        shirt = self.recent.one_at(question.place, rospy.get_time())
        fields = ({} if shirt is None else
                  {"set_shirt_color": True, "shirt_color": [int(c) for c in shirt.reshape(-1)]})
        try:
            rospy.wait_for_service("human_db/update", self.params.register_timeout)
            result = self.update(name=question.name, location=question.place,
                                 source="asked" if shirt is None else "recall", **fields)
            problem = "" if result.success else result.message
        except (rospy.ServiceException, rospy.ROSException) as error:
            problem = str(error)
        if not problem and shirt is not None:
            self._count("recalled")
            self._known_now(shirt, question.name)
        self._last = (f"asked: {question.name} is at {question.place}"
                      + ("" if shirt is None else ", in new clothes (shirt registered)")
                      if not problem else
                      f"ask: {question.name} said yes at {question.place}, but human_db "
                      f"refused the update: {problem}")
        (rospy.logwarn if problem else rospy.loginfo)("introduction: %s", self._last)

    def _known_now(self, shirt, name):
        """The stranger in `shirt` is `name` (NewcomerWatch.known_as): the meeting asked for
        them is cancelled on every executor (one that does not hold it refuses)."""
        meeting = self.watch.known_as(shirt, name)
        if not meeting:
            return
        for topic in self.params.state_topics:
            try:
                rospy.ServiceProxy(beside_state(topic, "cancel"), CancelInstruction)(id=meeting)
            except (rospy.ServiceException, rospy.ROSException) as error:
                rospy.logwarn("introduction: meeting #%d not cancelled on %s: %s", meeting,
                              topic, error)
        rospy.loginfo("introduction: #%d needs no meeting: the stranger is %s", meeting, name)

    def _look(self, frame, known):
        stamp = frame.header.stamp.to_sec() if not frame.header.stamp.is_zero() \
            else rospy.get_time()
        for person in frame.humans:
            if person.name:
                continue
            shirts = shirts_known(known, person.doubted_as)
            try:
                colours = seen_shirt(person.shirt_color)
            except HumanDbError as error:
                self._count("bad_observations")
                rospy.logwarn_throttle(10.0, "introduction: observation refused: %s", error)
                continue
            if colours is not None and person.location:
                self.recent.add(stamp, person.location, colours)
            instruction = self.watch.observe(colours, person.location, stamp, shirts)
            if instruction is not None:
                self._submit(instruction, stamp)

    def _submit(self, instruction, now):
        """Hand the introduce instruction to the executor (id 0: the task buffer allocates it);
        leave the stranger for later if the executor does not take it."""
        accepted, instruction_id, problem = self.submit(instruction, previous_id=0)
        if not accepted:
            self.watch.not_taken(now)
            self._count("not_submitted")
            self._last = f"introduce instruction not taken by the executor: {problem}"
            rospy.logwarn("introduction: %s", self._last)
            return
        self.watch.taken(instruction_id)
        self._count("instructions")
        rospy.loginfo("introduction: #%d: %s", instruction_id, instruction.text)

    def _follow(self, states, now):
        """Start a dialogue when a stranger's introduce instruction becomes ACTIVE (in any
        robot's state; one dialogue at a time); give a stranger whose instruction ended without
        one a rest. An open dialogue whose instruction ended (the robot moved on) ends too: its
        answers could only come from someone else."""
        if self.dialogue is not None and self.dialogue.open:
            records = [r for state in states for r in state.instructions
                       if r.instruction.id == self._met_id]
            if records and all(r.state in ENDED for r in records):
                self.dialogue.abort()
                self._end(now, f"#{self._met_id} ended before the stranger answered", met=False)
        for stranger in self.watch.open_strangers():
            records = [r for state in states for r in state.instructions
                       if r.instruction.id == stranger.instruction_id]
            if not records or self._met_id == stranger.instruction_id:
                continue
            record = next((r for r in records if r.state == InstructionState.ACTIVE),
                          next((r for r in records if r.state in ENDED), records[0]))
            if record.state == InstructionState.ACTIVE and not (
                    self.dialogue is not None and self.dialogue.open):
                self._meet(stranger, max(greeted_at(states, record, now), self._free_since))
            elif record.state in ENDED:
                self._last = (f"#{stranger.instruction_id} ended unmet: "
                              f"{record.reason or 'no reason'}")
                self.watch.not_met(stranger, now)
                self._count("not_met")
                rospy.logwarn("introduction: %s", self._last)

    def _meet(self, stranger, now):
        """Open the dialogue with `stranger`, greeted at `now` [s]."""
        self.stranger, self._met_id = stranger, stranger.instruction_id
        with self._lock:
            residents = tuple(self._known or ())
        place = stranger.asked_in or stranger.place   # where the robot serves the meeting
        self.dialogue = IntroductionDialogue(self.params.config, stranger.colours, now, place,
                                             residents)
        self._open_until = now
        self.answers_until.publish(Time(rospy.Time(0)))  # answers until the dialogue ends
        self._count("dialogues")
        rospy.loginfo("introduction: meeting the stranger of #%d in %s; waiting for a name",
                      stranger.instruction_id, place)

    def _answer(self, msg, now):
        self._count("answers")
        turn = self.dialogue.hear(msg.text, msg.ip, now)
        if turn.state == self.dialogue.state and turn.say.startswith("Sorry"):
            self._count("refused_answers")
        rospy.loginfo("introduction: heard %r from %s -> %s", msg.text, msg.ip or "microphone",
                      turn.state)
        if turn.state == COMPLETE:  # before registering: a request may follow at once
            self.answers_until.publish(Time(rospy.Time.from_sec(utterance_time(msg))))
        self._turn(turn, now)

    def _turn(self, turn, now):
        if turn.say:
            self.say.publish(String(turn.say))
        if turn.state == COMPLETE:
            self._register(now)
        elif turn.state == FAILED:
            self._end(now, f"no answers understood from the stranger of "
                           f"#{self.stranger.instruction_id}", met=False)

    def _register(self, now):
        if not answered_by_the_stranger(self.stranger, self.dialogue.place,
                                        self.dialogue.started, self.params.config):
            self.say.publish(String(self.params.config.not_seen))
            self._end(now, f"the stranger of #{self.stranger.instruction_id} was last seen in "
                           f"{self.stranger.place} at {self.stranger.last_seen:.1f} s, not with "
                           f"the robot in {self.dialogue.place}: the answers are not theirs",
                      met=False)
            return
        if self.dialogue.recalled:
            self._recall(now)
            return
        try:
            human = self.dialogue.human()
            reply = self._call_register(human)
        except (HumanDbError, rospy.ServiceException, rospy.ROSException) as error:
            reply, human = None, None
            problem = str(error)
        if reply is not None and reply.success:
            self.say.publish(String(self.dialogue.welcome()))
            self.watch.registered(self.stranger, human.name)
            self._count("registered")
            self._end(now, f"registered {human.name} ({human.gender}, {human.age}, phone "
                           f"{human.ip or 'none'}) after {now - self.dialogue.started:.1f} s",
                      met=True)
            return
        problem = reply.message if reply is not None else problem
        self.say.publish(String(f"I am sorry, I could not remember you: {problem}"))
        self._end(now, f"registration refused: {problem}", met=False)

    def _recall(self, now):
        """A resident in new clothes: their shirt becomes the one seen now (human_db keeps the
        old one in its shirt history), in the place the robot met them."""
        name = self.dialogue.recalled
        try:
            rospy.wait_for_service("human_db/update", self.params.register_timeout)
            reply = self.update(name=name, location=self.dialogue.place, source="recall",
                                set_shirt_color=True,
                                shirt_color=[c for joint in self.dialogue.shirt() for c in joint])
            problem = reply.message
        except (rospy.ServiceException, rospy.ROSException) as error:
            reply, problem = None, str(error)
        if reply is not None and reply.success:
            self.say.publish(String(self.dialogue.welcome()))
            self.watch.registered(self.stranger, name)
            self._count("recalled")
            self._end(now, f"recalled {name} by name, shirt registered after "
                           f"{now - self.dialogue.started:.1f} s", met=True)
            return
        self.say.publish(String(f"I am sorry, I could not remember your clothes: {problem}"))
        self._end(now, f"recall of {name} refused: {problem}", met=False)

    def _call_register(self, human):
        rospy.wait_for_service("human_db/register", self.params.register_timeout)
        return self.register(human=human_to_msg(human), replace=False)

    def _gone(self, now):
        """The stranger walked off before answering (walked_off): end the meeting."""
        self.dialogue.abort()
        self.say.publish(String(self.params.config.not_seen))
        self._end(now, f"nothing heard from the stranger of #{self.stranger.instruction_id} "
                       f"{now - self.dialogue.started:.0f} s after the greeting and not seen in "
                       f"{self.dialogue.place} since: they walked off", met=False)

    def _end(self, now, what, met):
        for publisher in self.function_over:
            publisher.publish(UInt32(self._met_id))
        if not met:
            self.watch.not_met(self.stranger, now)
            self._count("not_met")
        self._last = what
        self._free_since = now
        self._open_until = now + self.params.close_linger
        (rospy.loginfo if met else rospy.logwarn)("introduction: %s", what)

    def _fail_dialogue(self, error):
        """The work timer faulted: an open dialogue ends as not met, with the reason."""
        if self.dialogue is None or not self.dialogue.open or self.stranger is None:
            self._last = f"work failed: {fault_text(error)}"
            return
        turn = self.dialogue.abort()
        self.say.publish(String(turn.say))
        self._end(rospy.get_time(), f"dialogue with the stranger of "
                                    f"#{self.stranger.instruction_id} failed: {fault_text(error)}",
                  met=False)

    def _publish_open(self, value):
        if value != self._published_open:
            self.dialogue_open.publish(Bool(value))
            self._published_open = value

    def _count(self, key):
        with self._lock:
            self._counts[key] += 1

    def _on_diagnostics(self, _event):
        with self._lock:
            counts, table = dict(self._counts), self._known is not None
        state = self.dialogue.state if self.dialogue is not None and self.dialogue.open \
            else f"asking {self.question.name}" if self.question is not None \
            and self.question.open else "idle"
        failed = self._last and not self._last.startswith(("registered", "recalled", "asked:"))
        level = DiagnosticStatus.OK if table and not failed else DiagnosticStatus.WARN
        message = (f"no human table on {self.params.humans_topic}" if not table else
                   self._last if failed else "ok")
        status = DiagnosticStatus(
            name="perception: introduction", hardware_id="introduction", level=level,
            message=message,
            values=[KeyValue(k, str(v)) for k, v in sorted(counts.items())]
            + [KeyValue("dialogue", state), KeyValue("last", self._last),
               KeyValue("strangers", str(len(self.watch.strangers)))])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self.diagnostics.publish(array)


def main():
    rospy.init_node("introduction")
    sup = Supervisor("perception: introduction", hardware_id="introduction")
    try:
        node = IntroductionNode(read_params())
        node.setup(sup)
    except (KeyError, ValueError, OSError) as error:
        rospy.logfatal("introduction: cannot start: %s", error)
        return 1
    rospy.loginfo("introduction: watching /humans/observed for people nobody has met")
    rospy.spin()
    return 0
