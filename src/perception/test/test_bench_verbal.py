"""scripts/bench_verbal's library: arguments, text and speech scoring on tiny inputs, the report."""
import hashlib

import pytest

from perception.tools import bench_verbal as bench
from perception.request_corpus import CorpusCase
from perception.speech_synthesis import Voice, voice_of
from perception.stt import Transcript

ALEX = "192.168.1.110"
RIGHT = CorpusCase("Chat with me, I feel bad.", ALEX, "chat", "negative", "Alex")
# the same sentence with a wrong expectation: the pipeline reads chat/negative/Alex
WRONG = CorpusCase("Chat with me, I feel bad.", ALEX, "encourage", "negative", "Alex",
                   ambiguous=True)


def test_voice_specs_and_their_errors():
    assert voice_of("en-us:150").name == "en-us"
    assert voice_of("en-us:150").words_per_min == 150
    assert voice_of("en").words_per_min == Voice.words_per_min
    for bad in ("en:fast", ":150", "en:0"):
        with pytest.raises(ValueError, match=f"voice '{bad}'"):
            voice_of(bad)


@pytest.mark.parametrize("argv, message", [
    (["--voices", "en:fast"], "voice 'en:fast'"),
    (["--limit", "-1"], "--limit must be 0"),
    (["--beam-size", "0"], "--beam-size must be at least 1"),
])
def test_bad_arguments_are_named(argv, message, capsys):
    with pytest.raises(SystemExit) as stop:
        bench.parse_args(argv)
    assert stop.value.code == 2
    assert message in capsys.readouterr().err


def test_defaults(tmp_path, monkeypatch):
    monkeypatch.setenv("TAMP_WS", str(tmp_path))
    args = bench.parse_args([])
    assert args.voices == ["en:175", "en-us:150"] and args.limit == 0
    assert args.doc == tmp_path / "docs" / "perception" / "verbal.md"


def test_score_text_counts_passes_and_times_each_sentence(pipeline):
    text = bench.score_text(pipeline, [RIGHT, WRONG])
    assert text["all"] == (1, 2)
    assert text["unambiguous"] == (1, 1)
    assert text["function"] == (1, 2)
    assert text["latency_ms"].count == 2 and text["ms"] > 0.0


def test_failures_name_expected_and_got(pipeline):
    assert bench.failures(pipeline, [RIGHT, WRONG]) == [
        (WRONG.text, "encourage/negative/Alex", "chat/negative/Alex", True)]


def test_score_speech_with_a_listener_that_mishears_one_sentence(pipeline):
    heard = {0: RIGHT.text, 1: "Chat with me I feel bat"}

    def listen(index, text):
        return Transcript(heard[index], audio_s=2.0, latency_s=0.5 + index)

    result = bench.score_speech(listen, pipeline, [RIGHT, RIGHT])
    # 6 words per sentence, one substituted in the second: WER 1/12
    assert result["wer"] == pytest.approx(1 / 12)
    assert result["latency"] == [0.5, 1.5] and result["audio"] == [2.0, 2.0]
    assert result["function"] == (2, 2)
    assert [example[1] for example in result["examples"]] == [heard[1]]
    line = bench.speech_line("en:175", result)
    assert "latency 1.00 s mean, p50 1.00 s, p95 1.45 s, p99 1.49 s, max 1.50 s" in line


def test_masked_words_become_asterisks(monkeypatch):
    monkeypatch.setattr(bench, "MASKED_WORDS", {hashlib.sha256(b"banana").hexdigest()})
    assert bench.masked("A Banana, please") == "A ******, please"


def test_report_has_the_tables_with_percentiles(pipeline):
    text = bench.score_text(pipeline, [RIGHT, WRONG])
    speech = {"en:175": {"wer": 0.25, "function": (1, 2), "full": (1, 2), "latency": [0.2, 0.4],
                         "audio": [1.0, 1.0], "examples": [("a b", "a c", True)]}}
    run = {"command": "scripts/bench_verbal --limit 2", "load_s": 0.5,
           "silence": Transcript("", 2.0, 0.1), "config": bench.SttConfig(),
           "table_source": "config/priorities.yaml"}
    doc = bench.report_markdown(run, [RIGHT, WRONG], [RIGHT], text, text,
                                bench.failures(pipeline, [RIGHT, WRONG]), speech)
    assert "source scripts/env.sh && scripts/bench_verbal --limit 2\n" in doc
    assert "| 1/2 (50.0%) | 1/1 (100.0%) | 1/2 (50.0%) |" in doc
    assert "| en:175 | 0.250 | 1/2 (50.0%) | 1/2 (50.0%) | 0.30 s / 0.30 s / 0.40 s / 0.40 s | " \
           "0.30 |" in doc
    assert "| a b | a c | yes |" in doc
    assert "| Chat with me, I feel bad. | encourage/negative/Alex | chat/negative/Alex | yes |" \
        in doc
