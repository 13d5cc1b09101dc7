"""The speech-to-text node: a WAV file (~wav) or tamp_msgs/AudioUtterance messages on
/audio_utterance -> tamp_msgs/Utterance on /voice_message, with the latency of each utterance
logged and on /diagnostics. The work is `perception.stt_worker.SttWorker`: audio outside the
bounds (~min_sample_rate, ~max_sample_rate, ~max_audio_s) is refused (WARN), an utterance whose
handling raises fails alone (ERROR), and the worker goes on with the next one.

Every timer, the subscriber and each utterance run under one supervision.ros_supervisor.Supervisor
("perception: stt: supervision" on /diagnostics): a fault while an utterance is handled fails
that utterance with the reason and raises the supervision status to ERROR."""
import collections
import threading
from dataclasses import dataclass

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from supervision.ros_params import config_from_params
from supervision.ros_supervisor import Supervisor
from tamp_msgs.msg import AudioUtterance, Utterance

from perception.conversions import audio_input_from_msg, utterance_to_msg
from perception.stt import (NODE_FIELDS, WHISPER_RATE, AudioError, AudioLimits, ModelMissing,
                            SpeechToText, SttConfig, read_wav)
from perception.stt_vocabulary import VocabularyError
from perception.stt_worker import WORKER, AudioInput, SttWorker


@dataclass(frozen=True)
class SttParams:
    wav: str = ""                          # ~wav: transcribe this file once and exit
    ip: str = ""                           # ~ip: phone IP attached to the file's utterance
    wait: float = 10.0                     # ~wait: [s] for a /voice_message subscriber (file)
    audio_topic: str = "audio_utterance"  # ~audio_topic
    period: float = 0.1                    # ~period: work timer period [s]
    max_queue: int = 5                     # ~max_queue: utterances kept while busy
    stt: SttConfig = SttConfig()           # ~<field> for each field of stt.NODE_FIELDS
    limits: AudioLimits = AudioLimits()    # ~min_sample_rate, ~max_sample_rate, ~max_audio_s,
    #                                        ~max_channels


def read_params():
    """~params; raises ValueError naming a bound that is not a positive finite number."""
    stt = config_from_params(SttConfig, only=NODE_FIELDS)
    return config_from_params(SttParams, only=("wav", "ip", "wait", "audio_topic", "period",
                                               "max_queue"),
                              stt=stt, limits=config_from_params(AudioLimits))


_LOGGERS = {"info": rospy.loginfo, "warn": rospy.logwarn, "error": rospy.logerr}


def _log(level, text):
    _LOGGERS[level](text)


class SttNode:
    """The node's ROS API around SttWorker; `sup` is its Supervisor."""

    def __init__(self, params, sup):
        self.params, self.sup = params, sup
        self._lock = threading.Lock()
        self._queue = collections.deque()
        self.stt = self.worker = self._publisher = self._diagnostics = None
        self._timers = []

    def setup(self):
        """Load the model (raises ModelMissing naming scripts/setup, VocabularyError naming an
        unreadable ~vocabulary) and create the publishers."""
        self.stt = SpeechToText(self.params.stt)
        rospy.loginfo("stt: Whisper tiny.en loaded from %s", self.stt.model_dir)
        self.worker = SttWorker(self.stt.transcribe, self._publish, self.params.limits, _log,
                                guard=self.sup.health.run)
        self.sup.worker(WORKER)
        self._publisher = rospy.Publisher("voice_message", Utterance, queue_size=10)
        # an utterance queued for transcription: its stamp and ip, text "" (listeners such as
        # the introduction node wait for the transcript of an answer spoken in time)
        self._heard = rospy.Publisher("stt/heard", Utterance, queue_size=10)
        self._diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)

    def start_listening(self):
        p = self.params
        self.sup.subscriber(p.audio_topic, AudioUtterance, self._on_audio, worker="audio",
                            queue_size=5)
        self._timers = [self.sup.timer(p.period, self._on_work, worker="work"),
                        self.sup.timer(1.0, self._on_diagnostics, worker="diagnostics")]
        # One transcription keeps the work timer busy: it is silent only once an utterance has
        # taken longer than the longest audio lasts (~max_audio_s, a real-time factor above 1).
        self.sup.worker("work", max(p.period,
                                    p.limits.max_audio_s / self.sup.health.config.stale_periods))
        rospy.loginfo("stt: listening on %s", self.params.audio_topic)

    def transcribe_file(self):
        """Transcribe ~wav, publish the utterance; returns a process exit code."""
        try:
            samples = read_wav(self.params.wav, self.params.limits)
        except AudioError as error:
            rospy.logerr("stt: %s", error)
            return 2
        deadline = rospy.get_time() + self.params.wait
        while self._publisher.get_num_connections() == 0 and rospy.get_time() < deadline:
            rospy.sleep(0.05)
        audio = AudioInput(samples, WHISPER_RATE, self.params.ip, rospy.Time.now(), self.params.wav)
        if self.worker.handle(audio, decoded=True).kind != "published":
            return 1
        rospy.sleep(0.5)  # let the message leave before the node exits
        return 0

    def _on_audio(self, msg):
        with self._lock:
            if len(self._queue) >= self.params.max_queue:
                self._queue.popleft()
                rospy.logwarn_throttle(5.0, "stt: more than %d utterances waiting; dropping the "
                                       "oldest", self.params.max_queue)
            self._queue.append(msg)
        self._heard.publish(Utterance(header=msg.header, text="", ip=msg.ip))

    def _on_work(self, _event):
        while True:
            with self._lock:
                if not self._queue:
                    return
                msg = self._queue.popleft()
            self.sup.beat("work")
            self.worker.handle(audio_input_from_msg(msg, self.params.audio_topic))

    def _publish(self, text, audio):
        self._publisher.publish(utterance_to_msg(text, audio.ip, audio.stamp))

    def _on_diagnostics(self, _event):
        with self._lock:
            queued = len(self._queue)
        level, message, values = self.worker.health.status(queued=queued)
        status = DiagnosticStatus(name="perception: stt", hardware_id=self.params.audio_topic,
                                  level=level, message=message,
                                  values=[KeyValue(k, v) for k, v in sorted(values.items())])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self._diagnostics.publish(array)


def main():
    rospy.init_node("stt")
    try:
        params = read_params()
        sup = Supervisor("perception: stt", hardware_id=params.audio_topic)
    except ValueError as error:
        rospy.logfatal("stt: %s", error)
        return 1
    node = SttNode(params, sup)
    try:
        node.setup()
    except (ModelMissing, VocabularyError) as error:
        rospy.logfatal("stt: %s", error)
        return 1
    if node.params.wav:
        return node.transcribe_file()
    node.start_listening()
    rospy.spin()
    return 0
