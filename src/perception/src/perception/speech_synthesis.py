"""Test speech: a sentence spoken by Debian's espeak-ng, converted by sox to 16 kHz mono 16-bit
WAV, the format the STT node expects."""
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path


class SynthesisUnavailable(RuntimeError):
    """espeak-ng or sox is missing; the message names scripts/setup."""


@dataclass(frozen=True)
class Voice:
    name: str = "en"          # espeak-ng voice (`espeak-ng --voices=en` lists them)
    words_per_min: int = 175  # [words/min] espeak-ng speed (its default)
    pitch: int = 50           # espeak-ng pitch, 0..99 (its default)


def voice_of(spec: str) -> Voice:
    """Voice of a `name[:words-per-minute]` spec; ValueError naming the spec when malformed."""
    name, _, wpm = spec.partition(":")
    if not name or (wpm and not wpm.isdigit()) or (wpm and int(wpm) <= 0):
        raise ValueError(f"voice {spec!r} is not NAME or NAME:WORDS_PER_MINUTE (e.g. en:175)")
    return Voice(name=name, words_per_min=int(wpm or Voice.words_per_min))


def _tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        raise SynthesisUnavailable(f"{name} is not installed: run scripts/setup (it installs the "
                                   f"Debian packages espeak-ng and sox)")
    return path


def synthesise(text: str, wav_path: str | Path, voice: Voice = Voice(),
               sample_rate: int = 16000) -> Path:
    """Speak `text` into `wav_path` as 16-bit mono PCM at `sample_rate` [Hz]."""
    espeak, sox = _tool("espeak-ng"), _tool("sox")
    with tempfile.TemporaryDirectory() as workdir:
        raw = Path(workdir) / "espeak.wav"
        subprocess.run([espeak, "-v", voice.name, "-s", str(voice.words_per_min),
                        "-p", str(voice.pitch), "-w", str(raw), "--", text],
                       check=True, capture_output=True)
        # -D: no dither, whose random noise would make the same sentence differ run to run.
        subprocess.run([sox, "-D", str(raw), "-r", str(sample_rate), "-c", "1", "-b", "16",
                        str(wav_path)], check=True, capture_output=True)
    return Path(wav_path)
