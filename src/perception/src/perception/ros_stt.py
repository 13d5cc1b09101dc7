"""The speech-to-text node: a WAV file (~wav) or tamp_msgs/AudioUtterance messages on
/audio_utterance -> tamp_msgs/Utterance on /voice_message, with the latency of each utterance
logged and on /diagnostics."""
import collections
import threading
from dataclasses import dataclass

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from tamp_msgs.msg import AudioUtterance, Utterance

from perception.conversions import audio_from_msg, utterance_to_msg
from perception.stt import AudioError, ModelMissing, SpeechToText, SttConfig, read_wav


@dataclass(frozen=True)
class SttParams:
    wav: str = ""                          # ~wav: transcribe this file once and exit
    ip: str = ""                           # ~ip: phone IP attached to the file's utterance
    wait: float = 10.0                     # ~wait: [s] for a /voice_message subscriber (file)
    audio_topic: str = "/audio_utterance"  # ~audio_topic
    period: float = 0.1                    # ~period: work timer period [s]
    max_queue: int = 5                     # ~max_queue: utterances kept while busy
    stt: SttConfig = SttConfig()           # ~model_dir, ~compute_type, ~cpu_threads, ~beam_size


def read_params():
    default = SttConfig()
    stt = SttConfig(model_dir=rospy.get_param("~model_dir", default.model_dir),
                    compute_type=rospy.get_param("~compute_type", default.compute_type),
                    cpu_threads=int(rospy.get_param("~cpu_threads", default.cpu_threads)),
                    beam_size=int(rospy.get_param("~beam_size", default.beam_size)),
                    vad_filter=bool(rospy.get_param("~vad_filter", default.vad_filter)))
    return SttParams(wav=rospy.get_param("~wav", ""), ip=rospy.get_param("~ip", ""),
                     wait=float(rospy.get_param("~wait", SttParams.wait)),
                     audio_topic=rospy.get_param("~audio_topic", SttParams.audio_topic),
                     period=float(rospy.get_param("~period", SttParams.period)),
                     max_queue=int(rospy.get_param("~max_queue", SttParams.max_queue)), stt=stt)


class SttNode:
    def __init__(self, params):
        self.params = params
        self._lock = threading.Lock()
        self._queue = collections.deque()
        self._stats = {"utterances": 0, "silent": 0, "refused": 0, "last_latency_s": 0.0,
                       "last_real_time_factor": 0.0}
        self.stt = self._publisher = self._diagnostics = None
        self._timers = []

    def setup(self):
        """Load the model (raises ModelMissing naming scripts/setup) and create the publishers."""
        self.stt = SpeechToText(self.params.stt)
        rospy.loginfo("stt: Whisper tiny.en loaded from %s", self.stt.model_dir)
        self._publisher = rospy.Publisher("/voice_message", Utterance, queue_size=10)
        self._diagnostics = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=1)

    def start_listening(self):
        rospy.Subscriber(self.params.audio_topic, AudioUtterance, self._on_audio, queue_size=5)
        self._timers = [rospy.Timer(rospy.Duration(self.params.period), self._on_work),
                        rospy.Timer(rospy.Duration(1.0), self._on_diagnostics)]
        rospy.loginfo("stt: listening on %s", self.params.audio_topic)

    def transcribe_file(self):
        """Transcribe ~wav, publish the utterance; returns a process exit code."""
        try:
            samples = read_wav(self.params.wav)
        except AudioError as error:
            rospy.logerr("stt: %s", error)
            return 2
        if not self._transcribe_and_publish(samples, self.params.ip, rospy.Time.now(),
                                            self.params.wav, wait=self.params.wait):
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

    def _on_work(self, _event):
        while True:
            with self._lock:
                if not self._queue:
                    return
                msg = self._queue.popleft()
            try:
                samples = audio_from_msg(msg)
            except AudioError as error:
                self._count("refused")
                rospy.logwarn("stt: audio from %s refused: %s", msg.ip or "the microphone", error)
                continue
            stamp = msg.header.stamp if not msg.header.stamp.is_zero() else rospy.Time.now()
            self._transcribe_and_publish(samples, msg.ip, stamp, self.params.audio_topic)

    def _transcribe_and_publish(self, samples, ip, stamp, origin, wait=0.0):
        """True when an utterance was published."""
        try:
            transcript = self.stt.transcribe(samples)
        except AudioError as error:
            self._count("refused")
            rospy.logwarn("stt: audio from %s refused: %s", origin, error)
            return False
        rtf = transcript.latency_s / max(transcript.audio_s, 1e-9)
        with self._lock:
            self._stats.update(last_latency_s=transcript.latency_s, last_real_time_factor=rtf)
        if not transcript.text:
            self._count("silent")
            rospy.logwarn("stt: no speech in %.2f s of audio from %s (%.3f s); nothing published",
                          transcript.audio_s, origin, transcript.latency_s)
            return False
        rospy.loginfo("stt: %r from %.2f s of audio (%s) in %.3f s (real-time factor %.2f)",
                      transcript.text, transcript.audio_s, origin, transcript.latency_s, rtf)
        deadline = rospy.get_time() + wait
        while self._publisher.get_num_connections() == 0 and rospy.get_time() < deadline:
            rospy.sleep(0.05)
        self._publisher.publish(utterance_to_msg(transcript.text, ip, stamp))
        self._count("utterances")
        return True

    def _count(self, key):
        with self._lock:
            self._stats[key] += 1

    def _on_diagnostics(self, _event):
        with self._lock:
            stats = dict(self._stats, queued=len(self._queue))
        status = DiagnosticStatus(name="perception: stt", hardware_id=self.params.audio_topic,
                                  level=DiagnosticStatus.OK, message="ok",
                                  values=[KeyValue(k, f"{v:.3f}" if isinstance(v, float) else
                                                   str(v)) for k, v in sorted(stats.items())])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self._diagnostics.publish(array)


def main():
    rospy.init_node("stt")
    node = SttNode(read_params())
    try:
        node.setup()
    except ModelMissing as error:
        rospy.logfatal("stt: %s", error)
        return 1
    if node.params.wav:
        return node.transcribe_file()
    node.start_listening()
    rospy.spin()
    return 0
