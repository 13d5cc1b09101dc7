"""The speech-to-text worker, without ROS: one utterance of audio at a time is checked
(`stt.check_audio`), resampled, transcribed and handed to `publish`.

No utterance can stop the worker: audio outside the bounds is refused with its reason (counted,
logged, WARN), and each utterance runs under the node's guard (`supervision.health.Health.run`,
worker "utterance"), whose `on_error` fails that one utterance with a reason (counted, logged,
ERROR; the guard logs the traceback once per kind of fault and counts it in the node's
supervision status); the next utterance is handled as usual. Both states last until an utterance
is transcribed again (speech or silence).
"""
import logging
import threading
import traceback
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from perception.stt import AudioError, AudioLimits, Transcript, audio_from_pcm16

OK, WARN, ERROR = 0, 1, 2  # diagnostic_msgs/DiagnosticStatus levels
MAX_REASON_CHARS = 300     # a reason shown on /diagnostics is cut to this length
WORKER = "utterance"       # the guard's worker name for the handling of one utterance


@dataclass(frozen=True)
class AudioInput:
    samples: Sequence[int] | np.ndarray   # int16 PCM, mono; or float32 at 16 kHz
    sample_rate: float    # [Hz] as the sender declared it
    ip: str = ""          # the sender's phone IP; "" = the robot's microphone
    stamp: object = None  # when it was spoken (the caller's time type), handed back to publish
    origin: str = ""      # where it came from, for the logs


@dataclass(frozen=True)
class Outcome:
    kind: str         # "published", "silent", "refused" or "failed"
    text: str = ""    # the published sentence
    reason: str = ""  # why it was refused or failed


def error_reason(error: BaseException) -> str:
    """'TypeName: message (at file:line in function)' of an exception, on one line."""
    text = " ".join(str(error).split())
    reason = f"{type(error).__name__}: {text}" if text else type(error).__name__
    frames = traceback.extract_tb(error.__traceback__)
    if frames:
        last = frames[-1]
        reason += f" (at {last.filename.rsplit('/', 1)[-1]}:{last.lineno} in {last.name})"
    return reason


class SttHealth:
    """Counts and last reasons of the worker, thread-safe; `status()` is its diagnostics."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.counts = {"utterances": 0, "silent": 0, "refused": 0, "failed": 0}
        self.last_refusal = self.last_failure = ""
        self.last_latency_s = self.last_real_time_factor = 0.0
        self._level = OK

    def record(self, outcome: Outcome, transcript: Transcript | None = None) -> None:
        with self._lock:
            self.counts[{"published": "utterances"}.get(outcome.kind, outcome.kind)] += 1
            if transcript is not None:
                self.last_latency_s = transcript.latency_s
                self.last_real_time_factor = transcript.latency_s / max(transcript.audio_s, 1e-9)
            if outcome.kind == "refused":
                self.last_refusal = outcome.reason[:MAX_REASON_CHARS]
                self._level = max(self._level, WARN)
            elif outcome.kind == "failed":
                self.last_failure = outcome.reason[:MAX_REASON_CHARS]
                self._level = ERROR
            else:
                self._level = OK

    def status(self, **extra: object) -> tuple[int, str, dict[str, str]]:
        """(level, message, {key: text}) now; `extra` values are added (e.g. queued=2)."""
        with self._lock:
            if self._level == ERROR:
                message = (f"{self.counts['failed']} utterance(s) failed; last: "
                           f"{self.last_failure}")
            elif self._level == WARN:
                message = (f"{self.counts['refused']} audio message(s) refused; last: "
                           f"{self.last_refusal}")
            else:
                message = "ok"
            values = dict(self.counts, last_refusal=self.last_refusal,
                          last_failure=self.last_failure,
                          last_latency_s=f"{self.last_latency_s:.3f}",
                          last_real_time_factor=f"{self.last_real_time_factor:.3f}", **extra)
            return self._level, message, {key: str(value) for key, value in values.items()}


def _python_log(level: str, text: str) -> None:
    logging.getLogger("perception.stt").log(
        {"info": logging.INFO, "warn": logging.WARNING}.get(level, logging.ERROR), text)


class SttWorker:
    """transcribe: float32 mono 16 kHz -> stt.Transcript (SpeechToText.transcribe);
    publish(text, audio): sends the sentence on; log(level, text) with level "info", "warn" or
    "error"; guard(worker, context, fn, *args, on_error=...): the node's guard, with the signature
    of `supervision.health.Health.run` (`Supervisor.health.run` in the node)."""

    def __init__(self, transcribe: Callable[[ArrayLike], Transcript],
                 publish: Callable[[str, AudioInput], None], limits: AudioLimits = AudioLimits(),
                 log: Callable[[str, str], None] = _python_log, *,
                 guard: Callable[..., Outcome | None]) -> None:
        self.transcribe, self.publish, self.limits, self.log = transcribe, publish, limits, log
        self.guard = guard
        self.health = SttHealth()

    def handle(self, audio: AudioInput, decoded: bool = False) -> Outcome | None:
        """One utterance -> its Outcome; never raises. `decoded`: the samples are already float32
        mono at 16 kHz (a WAV file read by `stt.read_wav`)."""
        failed: list[Outcome] = []

        def fail(error: BaseException) -> None:
            """The guard's on_error: the utterance fails with the reason of `error`."""
            failed.append(Outcome("failed", reason=error_reason(error)))
            self.health.record(failed[0])
            self.log("error", f"stt: utterance from {audio.origin} failed: {failed[0].reason}; "
                              f"going on with the next one")

        outcome = self.guard(WORKER, f"utterance from {audio.origin}", self._handle, audio,
                             decoded, on_error=fail)
        return failed[0] if failed else outcome
    def _handle(self, audio: AudioInput, decoded: bool) -> Outcome:
        try:
            samples = audio.samples if decoded else audio_from_pcm16(
                audio.samples, audio.sample_rate, self.limits)
            transcript = self.transcribe(samples)
        except AudioError as error:
            outcome = Outcome("refused", reason=str(error))
            self.health.record(outcome)
            self.log("warn", f"stt: audio from {audio.origin} refused: {outcome.reason}")
            return outcome
        if not transcript.text:
            self.health.record(Outcome("silent"), transcript)
            self.log("warn", f"stt: no speech in {transcript.audio_s:.2f} s of audio from "
                             f"{audio.origin} ({transcript.latency_s:.3f} s); nothing published")
            return Outcome("silent")
        rtf = transcript.latency_s / max(transcript.audio_s, 1e-9)
        held = (f"; held to the vocabulary, freely {transcript.free_text!r}"
                if transcript.held else "")
        self.log("info", f"stt: {transcript.text!r} from {transcript.audio_s:.2f} s of audio "
                         f"({audio.origin}) in {transcript.latency_s:.3f} s (real-time factor "
                         f"{rtf:.2f}{held})")
        self.publish(transcript.text, audio)
        outcome = Outcome("published", text=transcript.text)
        self.health.record(outcome, transcript)
        return outcome
