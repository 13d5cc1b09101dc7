"""The verbal perception node: /voice_message (tamp_msgs/Utterance) -> /task_planner/submit.

Thesis 000 §3.3 / Fig. 3-15: the speaker is found from the phone IP in the human database, the
sentence is read for sentiment, physical terms, the requested robot function and its target, and
the result becomes one instruction or a chain (§4.2.1) with Table 5-5 priorities. The chain is
submitted in order with id 0 (task_planner.submission.submit_chain): the task buffer allocates
each id, and a successor names the id allocated for its predecessor. A request not taken is said
on /robot/say with the reason and logged: one refused here (empty, too long, not English, no
robot function, an unknown name, a bad phone address) and one the task planner does not take
(refused, or the service not reachable). An unknown speaker's answer to the introduction
dialogue is no request and gets no reply here.

Every timer and subscriber runs under one supervision.ros_supervisor.Supervisor: a fault while
an utterance is handled fails that utterance (the robot says a refusal naming the reason on
/robot/say, counted as `failed` in the node's own diagnostics) and raises the node's
"perception: verbal: supervision" status to ERROR; the next utterance is handled as usual.
"""
import collections
import threading
from dataclasses import dataclass

import rospy
from floorplan.semantic_graph import load_graph
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from std_msgs.msg import Bool, String, Time
from supervision.health import fault_text
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor
from tamp_msgs.msg import Utterance
from task_planner.reward import load_priorities
from task_planner.ros_submit import SubmitClient
from task_planner.submission import submit_chain

from perception.conversions import utterance_time
from perception.requests import RejectedUtterance, keyword_config_from_dict
from perception.ros_people import HumanTableDirectory
from perception.sentiment import SentimentAnalyzer
from perception.verbal_instructions import (InstructionBuilder, VerbalPipeline, refusal_sentence,
                                            rejection_sentence)


@dataclass(frozen=True)
class VerbalParams:
    keywords: dict                        # ~keywords: config/keywords.yaml (rosparam load)
    priorities_file: str                  # ~priorities_file: config/priorities.yaml (Table 5-5)
    graph: str                            # ~graph: maps/<map>.graph.yaml
    submit_timeout: float = 5.0           # ~submit_timeout: wall-clock wait for
                                          # /task_planner/submit per instruction [s]
    humans_topic: str = "humans/known"    # ~humans_topic: human_db's latched table
    period: float = 0.05                  # ~period: work timer period [s]
    max_queue: int = 20                   # ~max_queue: utterances kept while busy
    diagnostics_period: float = 1.0       # ~diagnostics_period [s]
    dialogue_topic: str = "introduction/dialogue_open"  # ~dialogue_topic: true while the
                                          # introduction node takes unknown speakers' answers
    answers_until_topic: str = "introduction/answers_until"  # ~answers_until_topic: stamp of
                                          # a completed dialogue's last answer (0: no limit)


def read_params():
    """Node parameters; raises KeyError naming a missing required parameter."""
    return config_from_params(VerbalParams, hint=" (see src/perception/launch/verbal.launch)")


class VerbalNode:
    def __init__(self, params):
        self.params = params
        self._lock = threading.Lock()
        self._queue = collections.deque()
        self._counts = {"accepted": 0, "refused": 0, "instructions": 0, "dropped": 0,
                        "dialogue_answers": 0, "not_taken": 0, "failed": 0}
        self._dialogue_open = False
        self._dialogue_phones = set()  # phones that answered the open dialogue: still answers
        self._answers_until = 0.0      # utterances stamped later are no answers (0: no limit)
        #                                once the introduction registered them, until it closes
        self._last_not_taken = ""   # why the task planner last did not take a request
        self._last_failure = ""     # why the handling of an utterance last failed
        self._handling = None       # the utterance being handled by the work timer
        self.pipeline = self._submit = self._say = self._diagnostics = None
        self.directory = HumanTableDirectory(params.humans_topic)
        self._timers = []

    def setup(self, sup):
        """Build the pipeline from the parameters and start the ROS API under the node's
        Supervisor `sup`; raises ValueError on bad configuration (the message names the
        entry)."""
        keywords = keyword_config_from_dict(self.params.keywords)
        builder = InstructionBuilder(keywords, load_priorities(self.params.priorities_file),
                                     load_graph(self.params.graph).place_ids(), self.directory)
        self.pipeline = VerbalPipeline(keywords, SentimentAnalyzer(), builder, self.directory)
        self.directory.setup()
        self._submit = SubmitClient(self.params.submit_timeout)
        self._say = rospy.Publisher("robot/say", String, queue_size=10)
        self._diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)
        sup.subscriber("voice_message", Utterance, self._on_utterance, queue_size=10)
        sup.subscriber(self.params.dialogue_topic, Bool, self._on_dialogue, queue_size=1)
        sup.subscriber(self.params.answers_until_topic, Time, self._on_answers_until,
                       queue_size=1)
        self._timers = [
            sup.timer(self.params.period, self._on_work, worker="work",
                      on_error=self._fail_utterance),
            sup.timer(self.params.diagnostics_period, self._on_diagnostics,
                      worker="diagnostics")]

    def _on_utterance(self, msg):
        with self._lock:
            if len(self._queue) >= self.params.max_queue:
                self._queue.popleft()
                self._counts["dropped"] += 1
                rospy.logwarn_throttle(5.0, "verbal: more than %d voice messages waiting; "
                                       "dropping the oldest", self.params.max_queue)
            self._queue.append(msg)

    def _on_dialogue(self, msg):
        with self._lock:
            self._dialogue_open = msg.data
            if not msg.data:
                self._dialogue_phones.clear()

    def _on_answers_until(self, msg):
        with self._lock:
            self._answers_until = msg.data.to_sec()

    def _on_work(self, _event):
        while True:
            with self._lock:
                if not self._queue:
                    return
                msg = self._queue.popleft()
            self._handling = msg
            self.handle(msg)
            self._handling = None

    def _fail_utterance(self, error):
        """The work timer faulted while handling an utterance: that utterance fails, the robot
        says so with the reason; the next one is handled as usual."""
        msg, self._handling = self._handling, None
        if msg is None:
            return
        reason = fault_text(error)
        with self._lock:
            self._counts["failed"] += 1
            self._last_failure = f"{msg.text!r} from {msg.ip or 'an unknown phone'}: {reason}"
        rospy.logerr("verbal: voice message %r from %s failed: %s", msg.text,
                     msg.ip or "an unknown phone", reason)
        self._say.publish(String(f"Sorry, I cannot take your request: it failed ({reason})"))

    def handle(self, msg):
        """Turn one voice message into submitted instructions, or log (and say) why not."""
        sender = msg.ip or "an unknown phone"
        with self._lock:
            dialogue = self._dialogue_open
            answered_before = msg.ip in self._dialogue_phones
            if self._answers_until and utterance_time(msg) > self._answers_until:
                dialogue = False  # said after the completed dialogue's last answer: a request
        if dialogue and (answered_before or self.directory.lookup_by_ip(msg.ip) is None):
            with self._lock:   # an unknown speaker's answer to the introduction node's question
                self._counts["dialogue_answers"] += 1
                self._dialogue_phones.add(msg.ip)
            rospy.loginfo("verbal: %r from %s answers the introduction dialogue; not a request",
                          msg.text, sender)
            return
        if not self.directory.received():
            rospy.logwarn_throttle(10.0, "verbal: no human table on %s yet; speakers cannot be "
                                   "identified", self.directory.topic)
        try:
            meaning, result = self.pipeline.process(msg.text, msg.ip, utterance_time(msg))
        except RejectedUtterance as error:
            with self._lock:
                self._counts["refused"] += 1
            rospy.logwarn("verbal: voice message from %s refused: %s", sender, error)
            self._say.publish(String(rejection_sentence(error)))
            return
        for note in result.notes:
            rospy.logwarn("verbal: %s", note)
        submission = submit_chain(result.instructions, self._submit)
        with self._lock:
            self._counts["accepted"] += 1
            self._counts["instructions"] += len(submission.accepted)
            if submission.complete:
                self._last_not_taken = self._last_failure = ""
        rospy.loginfo("verbal: %r from %s: %s (keyword %r), %s (compound %.3f) -> %s",
                      msg.text, sender, meaning.function.name, meaning.keyword, meaning.level,
                      meaning.compound, ", ".join(f"#{i.id} at {i.destination_name}"
                                                  for i in submission.accepted) or "nothing")
        if not submission.complete:
            self._not_taken(msg, sender, submission)

    def _not_taken(self, msg, sender, submission):
        """The task planner did not take (all of) the request: tell the speaker why."""
        sentence = refusal_sentence(submission)
        with self._lock:
            self._counts["not_taken"] += 1
            self._last_not_taken = submission.refusal
        rospy.logwarn("verbal: %r from %s not taken by the task planner (%d of %d instruction(s) "
                      "not sent): %s", msg.text, sender, submission.not_sent,
                      submission.not_sent + len(submission.accepted), submission.refusal)
        self._say.publish(String(sentence))

    def _on_diagnostics(self, _event):
        with self._lock:
            counts = dict(self._counts, queued=len(self._queue))
            not_taken, failure = self._last_not_taken, self._last_failure
        table = self.directory.received()
        message = ("ok" if table else f"no human table on {self.directory.topic}") + (
            f"; the last request was not taken: {not_taken}" if not_taken else "") + (
            f"; the last failed request: {failure}" if failure else "")
        status = DiagnosticStatus(
            name="perception: verbal", hardware_id="voice_message",
            level=(DiagnosticStatus.OK if table and not not_taken and not failure
                   else DiagnosticStatus.WARN),
            message=message,
            values=[KeyValue(k, str(v)) for k, v in sorted(counts.items())]
            + [KeyValue("people_table_stamp", f"{self.directory.stamp() or 0.0:.6f}")])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self._diagnostics.publish(array)


def main():
    rospy.init_node("verbal")
    sup = Supervisor("perception: verbal", hardware_id="voice_message")
    try:
        node = VerbalNode(read_params())
        node.setup(sup)
    except (KeyError, ValueError) as error:
        rospy.logfatal("verbal: cannot start: %s", error)
        return 1
    rospy.loginfo("verbal: listening on /voice_message")
    rospy.spin()
    return 0
