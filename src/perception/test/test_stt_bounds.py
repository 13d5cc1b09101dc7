"""Bounds on audio from outside (declared rate, channels, sample format, duration), the bounded
resampler, and the STT worker going on after refused and failing utterances under the
supervision guard (no ROS, no model)."""
import math
import re
import wave

import numpy as np
import pytest
from supervision.health import Health, HealthConfig

import perception.stt as stt
from perception.stt import (AudioError, AudioLimits, Transcript, audio_from_pcm16, check_audio,
                            read_wav, resample)
from perception.stt_worker import ERROR, OK, WARN, WORKER, AudioInput, SttWorker

RANGE = "is outside [8000, 192000] Hz"


@pytest.mark.parametrize("rate, samples, reason", [
    (4e9, 16000, f"sample_rate 4000000000 Hz {RANGE}"),
    (4000000000, 100, f"sample_rate 4000000000 Hz {RANGE}"),
    (1, 100, f"sample_rate 1 Hz {RANGE}; "
             "duration 100.0 s (100 samples at 1 Hz) is longer than 30 s"),
    (0, 100, f"sample_rate 0 Hz {RANGE}"),
    (-16000, 100, f"sample_rate -16000 Hz {RANGE}"),
    (7999, 8000, f"sample_rate 7999 Hz {RANGE}"),
    (192001, 8000, f"sample_rate 192001 Hz {RANGE}"),
    (math.nan, 100, "sample_rate nan Hz is not finite"),
    (math.inf, 100, "sample_rate inf Hz is not finite"),
    ("16000", 100, "sample_rate '16000' is not a number"),
    (16000, 31 * 16000, "duration 31.0 s (496000 samples at 16000 Hz) is longer than 30 s"),
    (8000, 30 * 8000 + 1, "duration 30.0 s (240001 samples at 8000 Hz) is longer than 30 s"),
    (16000, 0, "samples 0: the audio is empty (duration 0 s)"),
])
def test_check_refuses_with_field_and_value(rate, samples, reason):
    assert check_audio(rate, samples) == reason


@pytest.mark.parametrize("rate, samples", [
    (8000, 1), (16000, 16000), (22050, 22050), (44100, 44100), (48000, 30 * 48000),
    (192000, 192000), (16000.0, 30 * 16000),
])
def test_check_accepts_speech_rates_up_to_30_s(rate, samples):
    assert check_audio(rate, samples) is None


def test_check_channels_and_sample_format():
    assert check_audio(16000, 100, channels=2) is None
    assert check_audio(16000, 100, channels=0) == "channels 0 is outside [1, 8]"
    assert check_audio(16000, 100, channels=9) == "channels 9 is outside [1, 8]"
    assert check_audio(16000, 100, sample_width=1) == \
        "sample_width 1 bytes (8-bit samples): need 16-bit PCM"
    assert check_audio(16000, 100, sample_width=4) == \
        "sample_width 4 bytes (32-bit samples): need 16-bit PCM"


def test_check_uses_the_given_limits():
    limits = AudioLimits(min_sample_rate=16000, max_sample_rate=16000, max_audio_s=2.0,
                         max_channels=1)
    assert check_audio(16000, 32000, limits=limits) is None
    assert check_audio(8000, 100, limits=limits) == \
        "sample_rate 8000 Hz is outside [16000, 16000] Hz"
    assert check_audio(16000, 32001, limits=limits) == \
        "duration 2.0 s (32001 samples at 16000 Hz) is longer than 2 s"
    assert check_audio(16000, 10, channels=2, limits=limits) == "channels 2 is outside [1, 1]"


@pytest.mark.parametrize("fields, message", [
    ({"min_sample_rate": math.nan}, "AudioLimits.min_sample_rate must be a positive finite"),
    ({"max_audio_s": 0}, "AudioLimits.max_audio_s must be a positive finite"),
    ({"max_sample_rate": math.inf}, "AudioLimits.max_sample_rate must be a positive finite"),
    ({"min_sample_rate": 48000, "max_sample_rate": 16000},
     "AudioLimits.min_sample_rate 48000 is above max_sample_rate 16000"),
])
def test_limits_refuse_bad_bounds(fields, message):
    with pytest.raises(ValueError, match=message):
        AudioLimits(**fields)


def test_resampled_length_is_bounded():
    # 100 samples declared at 1 Hz would become 1.6 M samples (100 s) at 16 kHz.
    with pytest.raises(AudioError, match=r"resampled length 1600000 samples \(100.0 s at 16000 "
                                         r"Hz\) is longer than 30 s"):
        resample(np.zeros(100), 1)
    with pytest.raises(AudioError, match="longer than 30 s"):
        resample(np.zeros(30 * 16000 + 1), 16000)
    assert resample(np.zeros(30 * 16000), 16000).size == 30 * 16000
    assert resample(np.zeros(100), 1, max_s=200.0).size == 1600000


def test_resample_refuses_non_finite_rate_and_empty_output():
    for rate in (math.nan, math.inf, -1.0):
        with pytest.raises(AudioError, match="sample rate must be > 0 Hz and finite"):
            resample(np.zeros(10), rate)
    with pytest.raises(AudioError, match="resampling 10 samples from 4000000000 Hz to 16000 Hz "
                                         "leaves no sample"):
        resample(np.zeros(10), 4e9)


def test_message_audio_is_checked_before_resampling(monkeypatch):
    def no_resampling(*_args, **_kwargs):
        raise AssertionError("resampled before the check")

    monkeypatch.setattr(stt, "resample", no_resampling)
    with pytest.raises(AudioError, match=re.escape(f"sample_rate 4000000000 Hz {RANGE}") + "$"):
        audio_from_pcm16(np.zeros(16000, dtype=np.int16), 4000000000)
    with pytest.raises(AudioError, match=re.escape(f"sample_rate 1 Hz {RANGE}; duration 100.0 s")):
        audio_from_pcm16([0] * 100, 1)


def test_message_audio_at_48k_becomes_16k():
    samples = (np.sin(2 * np.pi * 440 * np.arange(48000) / 48000) * 8000).astype(np.int16)
    assert audio_from_pcm16(tuple(samples.tolist()), 48000).size == 16000


def write_wav(path, samples, rate):
    with wave.open(str(path), "wb") as stream:
        stream.setnchannels(1)
        stream.setsampwidth(2)
        stream.setframerate(rate)
        stream.writeframes(np.asarray(samples, dtype="<i2").tobytes())


def test_wav_header_is_checked(tmp_path):
    write_wav(tmp_path / "fast.wav", np.zeros(100), 1000000000)  # a WAV header holds < 2.1 GHz
    with pytest.raises(AudioError, match=re.escape(f"fast.wav: sample_rate 1000000000 Hz {RANGE}")):
        read_wav(tmp_path / "fast.wav")
    write_wav(tmp_path / "long.wav", np.zeros(31 * 8000), 8000)
    with pytest.raises(AudioError, match=r"long.wav: duration 31.0 s \(248000 samples at 8000 "
                                         r"Hz\) is longer than 30 s"):
        read_wav(tmp_path / "long.wav")
    assert read_wav(tmp_path / "long.wav", AudioLimits(max_audio_s=40.0)).size == 31 * 16000


class FakeStt:
    """Speech where the signal is loud, silence elsewhere; optionally raises on chosen calls."""

    def __init__(self, fail_on=()):
        self.calls = 0
        self.fail_on = set(fail_on)

    def transcribe(self, samples):
        self.calls += 1
        if self.calls in self.fail_on:
            raise RuntimeError("decoder crashed")
        text = "chat with me" if np.max(np.abs(samples), initial=0.0) > 0.01 else ""
        return Transcript(text=text, audio_s=samples.size / 16000, latency_s=0.01)


def speech(rate=16000, seconds=1.0, ip="192.168.1.110"):
    samples = (np.sin(2 * np.pi * 300 * np.arange(int(rate * seconds)) / rate) * 8000)
    return AudioInput(tuple(samples.astype(np.int16).tolist()), rate, ip, stamp=7,
                      origin=f"{ip} on /audio_utterance")


class FakeClock:
    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def make_worker(fake, fail_publish=(), clock=None):
    """An SttWorker under a real supervision guard; logs gets (level, text) of the worker and
    ("guard", text) of the guard. Returns (worker, published, logs, health)."""
    published, logs, calls = [], [], []

    def publish(text, audio):
        calls.append(text)
        if len(calls) in fail_publish:
            raise OSError("publisher closed")
        published.append((text, audio.ip, audio.stamp))

    health = Health("perception: stt", HealthConfig(fault_hold_s=10.0),
                    clock=clock or FakeClock(), log=lambda text: logs.append(("guard", text)))
    worker = SttWorker(fake.transcribe, publish, guard=health.run,
                       log=lambda level, text: logs.append((level, text)))
    return worker, published, logs, health


BAD = [
    (AudioInput((0,) * 16000, 4000000000, "10.0.0.1"), f"sample_rate 4000000000 Hz {RANGE}"),
    (AudioInput((0,) * 100, 1, "10.0.0.1"), f"sample_rate 1 Hz {RANGE}; duration 100.0 s"),
    (AudioInput((0,) * 100, 0, "10.0.0.1"), f"sample_rate 0 Hz {RANGE}"),
    (AudioInput((0,) * 100, math.nan, "10.0.0.1"), "sample_rate nan Hz is not finite"),
    (AudioInput((0,) * (31 * 8000), 8000, "10.0.0.1"), "duration 31.0 s"),
    (AudioInput((), 16000, "10.0.0.1"), "samples 0: the audio is empty"),
]


def test_worker_transcribes_good_audio_after_each_bad_message():
    fake = FakeStt()
    worker, published, logs, health = make_worker(fake)
    for count, (bad, reason) in enumerate(BAD, start=1):
        outcome = worker.handle(bad)
        assert (outcome.kind, outcome.reason[:len(reason)]) == ("refused", reason)
        level, message, values = worker.health.status(queued=0)
        assert level == WARN
        assert message.startswith(f"{count} audio message(s) refused; last: {reason}")
        assert values["refused"] == str(count)
        assert values["last_refusal"].startswith(reason)
        assert logs[-1][0] == "warn" and reason in logs[-1][1]
    assert fake.calls == 0 and published == []
    assert len(logs) == len(BAD)  # each refusal logged once

    outcome = worker.handle(speech(48000))
    assert (outcome.kind, outcome.text) == ("published", "chat with me")
    assert published == [("chat with me", "192.168.1.110", 7)]
    level, message, values = worker.health.status(queued=0)
    assert (level, message) == (OK, "ok")
    assert (values["utterances"], values["refused"], values["failed"]) == ("1", "6", "0")
    assert values["last_refusal"].startswith("samples 0")
    assert health.report()[:2] == (OK, "all workers alive")  # a refusal is no fault
    assert dict(health.report()[2])[f"{WORKER} runs/faults"] == "7/0"


def test_an_utterance_that_raises_fails_alone_and_error_lasts_until_a_transcription():
    fake = FakeStt(fail_on={1})
    worker, published, logs, _ = make_worker(fake)
    outcome = worker.handle(speech())
    assert outcome.kind == "failed"
    assert outcome.reason.startswith("RuntimeError: decoder crashed (at test_stt_bounds.py:")
    assert outcome.reason.endswith("in transcribe)")
    level, message, values = worker.health.status()
    assert level == ERROR
    assert message == f"1 utterance(s) failed; last: {outcome.reason}"
    assert values["failed"] == "1" and values["last_failure"] == outcome.reason
    assert [level for level, _ in logs] == ["guard", "error"]
    assert "utterance from 192.168.1.110 on /audio_utterance" in logs[0][1]
    assert "Traceback" in logs[0][1]  # the guard logs the traceback once per kind of fault
    assert logs[1][1] == (f"stt: utterance from 192.168.1.110 on /audio_utterance failed: "
                          f"{outcome.reason}; going on with the next one")

    assert worker.handle(BAD[0][0]).kind == "refused"
    assert worker.health.status()[0] == ERROR  # a refusal does not hide the failure

    assert worker.handle(speech()).kind == "published"
    assert published == [("chat with me", "192.168.1.110", 7)]
    level, message, values = worker.health.status()
    assert (level, message, values["failed"], values["utterances"]) == (OK, "ok", "1", "1")


def test_silence_clears_the_warning_and_a_failing_publish_fails_that_utterance():
    fake = FakeStt()
    worker, published, logs, _ = make_worker(fake, fail_publish={1})
    assert worker.handle(BAD[0][0]).kind == "refused"
    silence = AudioInput((0,) * 16000, 16000, "", origin="the microphone")
    assert worker.handle(silence).kind == "silent"
    assert worker.health.status()[0] == OK
    outcome = worker.handle(speech())
    assert outcome.kind == "failed" and outcome.reason.startswith("OSError: publisher closed")
    assert worker.health.status()[0] == ERROR
    assert worker.handle(speech()).kind == "published"
    assert len(published) == 1


def test_decoded_samples_skip_the_message_check():
    fake = FakeStt()
    worker, published, _, _ = make_worker(fake)
    samples = np.full(16000, 0.5, dtype=np.float32)
    audio = AudioInput(samples, 16000, "192.168.1.102", stamp=3, origin="ill.wav")
    assert worker.handle(audio, decoded=True).kind == "published"
    assert published == [("chat with me", "192.168.1.102", 3)]


def test_a_failing_utterance_shows_error_on_the_supervision_status():
    clock = FakeClock()
    fake = FakeStt(fail_on={1, 2})
    worker, published, logs, health = make_worker(fake, clock=clock)
    assert worker.handle(speech()).kind == "failed"
    assert worker.handle(speech()).kind == "failed"
    level, message, values = health.report()
    assert level == ERROR
    assert message.startswith("degraded: failing: utterance: utterance from 192.168.1.110 on "
                              "/audio_utterance: RuntimeError: decoder crashed")
    assert dict(values)["faults"] == "2"
    assert dict(values)[f"{WORKER} runs/faults"] == "2/2"
    assert [level for level, _ in logs] == ["guard", "error", "error"]  # traceback logged once
    assert worker.health.status()[2]["failed"] == "2"

    assert worker.handle(speech()).kind == "published"
    level, message, _ = health.report()
    assert level == ERROR and message.startswith("degraded: fault 0.0 s ago: utterance:")
    clock.now += 10.5  # ~supervision/fault_hold_s later
    assert health.report()[:2] == (OK, "all workers alive")
    assert worker.health.status()[0] == OK
    assert published == [("chat with me", "192.168.1.110", 7)]
