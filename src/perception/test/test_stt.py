"""Offline speech to text: model lookup, audio reading, resampling, WER, and one real
transcription of synthesised speech (espeak-ng + sox) and of silence."""
import wave
import zlib
from types import SimpleNamespace

import numpy as np
import pytest
from supervision.health import Health

from perception.speech_metrics import (misheard_words, normalise_words, word_alignment,
                                       word_edit_distance, word_error_rate)
from perception.speech_synthesis import synthesise, voice_of
from perception.stt import (AudioError, ModelMissing, SpeechToText, SttConfig, load_stt_config,
                            pcm16_to_float, read_wav, resample, whisper_model_dir)
from perception.stt_vocabulary import VocabularyError, vocabulary_path
from perception.stt_worker import AudioInput, SttWorker


def write_wav(path, samples, rate, channels=1, width=2):
    with wave.open(str(path), "wb") as stream:
        stream.setnchannels(channels)
        stream.setsampwidth(width)
        stream.setframerate(rate)
        stream.writeframes(samples.tobytes())


def test_missing_model_names_setup(tmp_path, monkeypatch):
    monkeypatch.setenv("TAMP_MODEL_CACHE", str(tmp_path))
    with pytest.raises(ModelMissing, match=r"whisper_tiny_en.*scripts/setup"):
        whisper_model_dir()


def test_partial_model_lists_missing_files(tmp_path):
    (tmp_path / "config.json").write_text("{}")
    with pytest.raises(ModelMissing, match="missing model.bin, tokenizer.json, vocabulary.txt"):
        whisper_model_dir(str(tmp_path))


def sine(frequency, rate, seconds=1.0):
    t = np.arange(int(rate * seconds)) / rate
    return np.sin(2 * np.pi * frequency * t)


def test_stt_config_from_yaml_keeps_the_defaults_of_fields_left_out(tmp_path):
    path = tmp_path / "stt.yaml"
    path.write_text("beam_size: 5\nmax_compression_ratio: 3\n")
    assert load_stt_config(path) == SttConfig(beam_size=5, max_compression_ratio=3.0)
    path.write_text("")
    assert load_stt_config(path) == SttConfig()
    with pytest.raises(FileNotFoundError, match="nope.yaml not found"):
        load_stt_config(tmp_path / "nope.yaml")


@pytest.mark.parametrize("text, message", [
    ("beam: 5", "unknown STT setting 'beam'"),
    ("language: de", "unknown STT setting 'language'"),     # the node does not read it
    ("beam_size: [5", "not YAML"),
    ("beam_size: 0", "beam_size must be at least 1; got 0"),
    ("max_compression_ratio: 0", "max_compression_ratio must be > 0 and finite; got 0.0"),
    ("beam_size: five", "beam_size must be of type int; got 'five'"),
    ("vad_filter: 1", "vad_filter must be of type bool; got 1"),
    ("cpu_threads: true", "cpu_threads must be of type int; got True"),
    ("- beam_size", "expected a mapping")])
def test_stt_config_from_yaml_names_what_is_wrong(tmp_path, text, message):
    path = tmp_path / "stt.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"{path}.*{message}"):
        load_stt_config(path)


@pytest.mark.parametrize("config, message", [
    (SttConfig(temperatures=()), "temperatures must be numbers in \\[0, 1\\]"),
    (SttConfig(temperatures=("a",)), "temperatures"), (SttConfig(cpu_threads=0), "cpu_threads")])
def test_stt_config_check_names_a_setting_no_decoding_can_use(config, message):
    with pytest.raises(ValueError, match=message):
        config.check()
    SttConfig().check()


def test_a_decode_stuck_repeating_is_retried_greedily_and_else_gives_no_text():
    """Whisper's decoder can loop on a phrase (Whisper's test: the text compresses too well);
    beam search that loops is retried with beam 1, and a decode still looping is no text."""
    def segment(text):
        data = text.encode()
        return SimpleNamespace(text=text, compression_ratio=len(data) / len(zlib.compress(data)),
                               avg_logprob=-0.5, tokens=[0], seek=0)

    class Model:
        def __init__(self, greedy_loops):
            self.greedy_loops, self.beams = greedy_loops, []

        def transcribe(self, samples, beam_size, **options):
            self.beams.append(beam_size)
            if beam_size > 1 or self.greedy_loops:
                return iter([segment(" Walk to the"), segment(" end of the" * 30)]), None
            return iter([segment(" Walk to the"), segment(" end.")]), None

    stt = object.__new__(SpeechToText)          # the decoding without loading Whisper
    audio = np.zeros(1600, dtype=np.float32)
    stt._held_suppress = None
    stt.config, stt._model = SttConfig(beam_size=5), Model(greedy_loops=False)
    assert stt.transcribe(audio).text == "Walk to the end."
    assert stt._model.beams == [5, 1]
    stt._model = Model(greedy_loops=True)
    assert stt.transcribe(audio).text == ""
    stt.config, stt._model = SttConfig(beam_size=1), Model(greedy_loops=True)
    assert stt.transcribe(audio).text == "" and stt._model.beams == [1]
    stt.config = SttConfig(beam_size=1, max_compression_ratio=100.0)
    assert stt.transcribe(audio).text.startswith("Walk to the end of the end of")


class HeldModel:
    """Whisper stand-in: the free decoding and the held one (suppress_tokens other than the
    default) give these (text, log-probability of each of its tokens and its end)."""

    def __init__(self, free, held):
        self.readings, self.calls = {"free": free, "held": held}, []

    def transcribe(self, samples, suppress_tokens, **options):
        kind = "free" if suppress_tokens == [-1] else "held"
        self.calls.append((kind, suppress_tokens))
        text, per_token = self.readings[kind]
        segment = SimpleNamespace(text=" " + text, compression_ratio=1.0, tokens=[0, 0, 0],
                                  avg_logprob=per_token, seek=0)
        return iter([segment]), None


@pytest.mark.parametrize("free, held, text, is_held", [
    (("Take the dog left.", -0.6), ("Take the third left.", -0.3), "Take the third left.", True),
    # 4 tokens at -0.6 (free) against -0.9: 1.2 nats lower, within the 2.0 margin
    (("Take the dog left.", -0.6), ("Take the third left.", -0.9), "Take the third left.", True),
    # 4 at -1.2: 2.4 nats lower, speech the vocabulary does not hold
    (("What's for dinner?", -0.6), ("What's for the end?", -1.2), "What's for dinner?", False),
    (("Go on.", -0.2), ("", 0.0), "Go on.", False)])
def test_the_reading_held_to_the_vocabulary_is_taken_when_it_scores_close(free, held, text,
                                                                         is_held):
    stt = object.__new__(SpeechToText)
    stt.config, stt._held_suppress = SttConfig(beam_size=5, vocabulary="words.txt"), [7, 9]
    stt._model = HeldModel(free, held)
    transcript = stt.transcribe(np.zeros(1600, dtype=np.float32))
    assert (transcript.text, transcript.held, transcript.free_text) == (text, is_held, free[0])
    assert stt._model.calls == [("free", [-1]), ("held", [7, 9])]


def test_no_held_decoding_without_a_vocabulary_or_without_speech():
    stt = object.__new__(SpeechToText)
    stt.config, stt._held_suppress = SttConfig(), None
    stt._model = HeldModel(("Go on.", -0.2), ("Go.", 0.0))
    assert stt.transcribe(np.zeros(1600, dtype=np.float32)).text == "Go on."
    stt._held_suppress, stt._model = [7], HeldModel(("", 0.0), ("Go.", 0.0))
    assert stt.transcribe(np.zeros(1600, dtype=np.float32)).text == ""
    assert [kind for kind, _ in stt._model.calls] == ["free"]


def test_stt_config_names_a_vocabulary_it_cannot_read(tmp_path):
    path = tmp_path / "stt.yaml"
    path.write_text(f"vocabulary: {tmp_path / 'missing.txt'}\n")
    with pytest.raises(VocabularyError, match="missing.txt"):
        load_stt_config(path)
    (tmp_path / "words.txt").write_text("turn left, turn right\n")
    path.write_text(f"vocabulary: {tmp_path / 'words.txt'}\nvocabulary_margin: 3\n")
    assert load_stt_config(path) == SttConfig(vocabulary=str(tmp_path / "words.txt"),
                                              vocabulary_margin=3.0)
    path.write_text("vocabulary_margin: -1\n")
    with pytest.raises(ValueError, match="vocabulary_margin must be >= 0"):
        load_stt_config(path)


def test_resample_48k_sine_to_16k_matches_a_16k_sine():
    out = resample(sine(440.0, 48000), 48000, 16000)
    assert out.size == 16000
    assert np.max(np.abs(out - sine(440.0, 16000))) < 1e-4


def test_resample_8k_to_16k_doubles_length_and_keeps_tone():
    out = resample(sine(300.0, 8000), 8000, 16000)
    assert out.size == 16000
    assert np.max(np.abs(out - sine(300.0, 16000))) < 1e-4


def test_resample_refuses_zero_rate():
    with pytest.raises(AudioError, match="sample rate must be > 0"):
        resample(np.zeros(10), 0)


def test_pcm16_scale():
    assert pcm16_to_float([-32768, 0, 16384]).tolist() == [-1.0, 0.0, 0.5]


def test_read_stereo_8k_wav_gives_mono_16k(tmp_path):
    left = (sine(200.0, 8000) * 16000).astype("<i2")
    stereo = np.stack([left, left], axis=1).reshape(-1)
    write_wav(tmp_path / "s.wav", stereo, 8000, channels=2)
    samples = read_wav(tmp_path / "s.wav")
    assert samples.size == 16000
    assert np.max(np.abs(samples - sine(200.0, 16000) * 16000 / 32768)) < 1e-3


def test_read_wav_refuses_8_bit_and_non_wav(tmp_path):
    write_wav(tmp_path / "b.wav", np.zeros(100, dtype=np.uint8), 16000, width=1)
    with pytest.raises(AudioError, match=r"b.wav: sample_width 1 bytes \(8-bit samples\): "
                                         r"need 16-bit PCM"):
        read_wav(tmp_path / "b.wav")
    (tmp_path / "t.wav").write_text("not audio")
    with pytest.raises(AudioError, match="cannot read WAV file .*t.wav"):
        read_wav(tmp_path / "t.wav")


def test_word_alignment_lists_the_edits_by_hand():
    said, heard = "turn left at the second corner".split(), "turn lift at second corner".split()
    assert word_alignment(said, heard) == [
        ("turn", "turn"), ("left", "lift"), ("at", "at"), ("the", None), ("second", "second"),
        ("corner", "corner")]
    pairs = word_alignment("a b c".split(), "a x c d".split())
    assert sum(a != b for a, b in pairs) == word_edit_distance("a b c".split(),
                                                               "a x c d".split())
    assert misheard_words("Take the 2nd right.", "Take the second right, then.") == [
        ("2nd", "second"), (None, "then")]
    assert misheard_words("go on", "go on") == []


def test_word_error_rate_by_hand():
    assert normalise_words("Chat with me, I feel bad.") == ["chat", "with", "me", "i", "feel",
                                                             "bad"]
    assert word_edit_distance("a b c".split(), "a x c d".split()) == 2  # 1 sub + 1 ins
    # 1 substitution in 6 words + 1 deletion in 3 words = 2 edits / 9 words.
    wer = word_error_rate(["Chat with me, I feel bad.", "check Bob status"],
                          ["chat with me I fell bad", "check Bob"])
    assert wer == pytest.approx(2 / 9)
    with pytest.raises(ValueError, match="2 references but 1 hypotheses"):
        word_error_rate(["a", "b"], ["a"])


@pytest.fixture(scope="module")
def stt():
    return SpeechToText()


def test_synthesised_request_is_transcribed(stt, tmp_path):
    wav = synthesise("Chat with me, I feel bad.", tmp_path / "chat.wav")
    with wave.open(str(wav), "rb") as stream:
        assert (stream.getframerate(), stream.getnchannels(), stream.getsampwidth()) == \
            (16000, 1, 2)
    transcript = stt.transcribe(read_wav(wav))
    assert normalise_words(transcript.text) == ["chat", "with", "me", "i", "feel", "bad"]
    assert transcript.audio_s == pytest.approx(1.88, abs=0.3)


def test_speech_of_a_direction_is_read_in_the_vocabulary_and_other_speech_freely(tmp_path):
    """The semantic_nav setting: the phrase sets as the vocabulary. espeak-ng's Scottish voice
    saying "three intersections along" comes out of free decoding as "free into section along",
    held to the vocabulary as said; a household request keeps its free reading."""
    stt = SpeechToText(SttConfig(beam_size=5, vocabulary="semnav_phrases.yaml"))
    words = set(normalise_words(vocabulary_path("semnav_phrases.yaml").read_text()))
    direction = stt.transcribe(read_wav(synthesise(
        "i need you to three intersections along make the next right thanks", tmp_path / "d.wav",
        voice_of("en-gb-scotland:160"))))
    assert direction.held and set(normalise_words(direction.text)) <= words
    assert normalise_words(direction.text)[3:7] == ["to", "three", "intersections", "along"]
    request = stt.transcribe(read_wav(synthesise("Play some music for me.", tmp_path / "r.wav")))
    assert not request.held and normalise_words(request.text) == ["play", "some", "music",
                                                                   "for", "me"]


def test_silence_gives_no_text(stt):
    assert stt.transcribe(np.zeros(32000, dtype=np.float32)).text == ""


def test_empty_and_non_finite_audio_refused(stt):
    with pytest.raises(AudioError, match="non-empty mono"):
        stt.transcribe(np.zeros(0, dtype=np.float32))
    with pytest.raises(AudioError, match="NaN"):
        stt.transcribe(np.full(1600, np.nan, dtype=np.float32))


def test_worker_transcribes_speech_after_a_4e9_hz_message(stt, tmp_path):
    wav = synthesise("Chat with me, I feel bad.", tmp_path / "chat.wav")
    with wave.open(str(wav), "rb") as stream:
        pcm = np.frombuffer(stream.readframes(stream.getnframes()), dtype="<i2")
    published = []
    worker = SttWorker(stt.transcribe, lambda text, audio: published.append((text, audio.ip)),
                       guard=Health("perception: stt").run)
    bad = worker.handle(AudioInput(tuple(pcm.tolist()), 4000000000, "192.168.1.110"))
    assert (bad.kind, bad.reason) == \
        ("refused", "sample_rate 4000000000 Hz is outside [8000, 192000] Hz")
    good = worker.handle(AudioInput(tuple(pcm.tolist()), 16000, "192.168.1.110"))
    assert good.kind == "published"
    assert [(normalise_words(text), ip) for text, ip in published] == \
        [(["chat", "with", "me", "i", "feel", "bad"], "192.168.1.110")]
    assert worker.health.status()[2]["refused"] == "1"
