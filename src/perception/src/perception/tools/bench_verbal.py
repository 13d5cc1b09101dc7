"""Benchmark of verbal perception (issue 8): the labelled corpus read as text and as speech.

Text: accuracy of function, priority level, target and chain on src/perception/data/
verbal_corpus.yaml, with our pipeline and with the seed's plain method (VADER on the whole
sentence, physical terms by plain dictionary look-up). Speech: every accepted corpus sentence is
spoken by espeak-ng (16 kHz mono via sox), transcribed by faster-whisper with Whisper tiny.en (the
SpeechToText core of the STT node), and read again: word error rate, function-extraction accuracy,
full accuracy, latency (p50, p99). Writes docs/perception/verbal.md and prints the same figures.

Run: source scripts/env.sh && scripts/bench_verbal [--voices en:175 en-us:150] [--limit N]
"""
import argparse
import dataclasses
import hashlib
import os
import platform
import re
import statistics
import tempfile
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
import rospkg
from floorplan.semantic_graph import load_graph
from supervision.latency import summarise
from tamp_resources import resource, workspace

from perception.request_corpus import case_passes, function_matches, load_corpus, outcome_of
from perception.requests import load_keyword_config
from perception.sentiment import SentimentAnalyzer
from perception.speech_metrics import normalise_words, word_error_rate
from perception.speech_synthesis import synthesise, voice_of
from perception.stt import SpeechToText, SttConfig, read_wav
from perception.verbal_instructions import DictPeopleDirectory, InstructionBuilder, VerbalPipeline
from task_planner.reward import load_priorities

PRIORITIES = ("config", "priorities.yaml")
# SHA-256 of lowercase slurs that Whisper has produced from espeak speech here; masked in the
# report (stored as hashes so the words themselves are not in the source).
MASKED_WORDS = {"08a841e996781e9e77d30a4e4420a8f501a280b00624e6d1224bf54aaff73eba"}


def _voice_argument(spec):
    try:
        voice_of(spec)
    except ValueError as error:
        raise argparse.ArgumentTypeError(str(error)) from error
    return spec


def parse_args(argv=None):
    parser = argparse.ArgumentParser(prog="bench_verbal", description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--voices", nargs="+", default=["en:175", "en-us:150"],
                        type=_voice_argument,
                        help="espeak-ng voice:words-per-minute pairs to speak the corpus with")
    parser.add_argument("--limit", type=int, default=0, help="speak only the first N sentences")
    parser.add_argument("--beam-size", type=int, default=SttConfig.beam_size)
    parser.add_argument("--doc", type=Path, default=workspace() / "docs/perception/verbal.md",
                        help="Markdown report to write")
    args = parser.parse_args(argv)
    if args.limit < 0:
        parser.error(f"--limit must be 0 (all) or a positive count; got {args.limit}")
    if args.beam_size < 1:
        parser.error(f"--beam-size must be at least 1; got {args.beam_size}")
    return args


def corpus_path():
    return Path(rospkg.RosPack().get_path("perception")) / "data" / "verbal_corpus.yaml"


def make_pipeline(keywords, people, table, place_ids):
    directory = DictPeopleDirectory(people)
    builder = InstructionBuilder(keywords, table, place_ids, directory)
    return VerbalPipeline(keywords, SentimentAnalyzer(), builder, directory)


def seed_method(keywords):
    """The seed's §3.3 as written: VADER on the whole sentence, plain physical-term look-up."""
    return dataclasses.replace(keywords, sentiment_neutral_words=frozenset(),
                               physical_exceptions=(), negations=())


def score_text(pipeline, cases):
    """Passing counts (all, unambiguous, function) and the time per sentence [ms]."""
    passed, unambiguous, function_ok, ms = [], [], [], []
    for case in cases:
        start = time.perf_counter()
        outcome = outcome_of(pipeline, case.text, case.ip)
        ms.append(1000 * (time.perf_counter() - start))
        passed.append(case_passes(case, outcome))
        if not case.ambiguous:
            unambiguous.append(passed[-1])
        function_ok.append(function_matches(case, outcome))
    return {"all": (sum(passed), len(passed)),
            "unambiguous": (sum(unambiguous), len(unambiguous)),
            "function": (sum(function_ok), len(function_ok)), "ms": statistics.mean(ms),
            "latency_ms": summarise(ms)}


def _reading(item):
    text = item.rejected or f"{item.function}/{item.level}/{item.target}"
    return text if item.rejected or not item.chain else text + "+" + "+".join(item.chain)


def failures(pipeline, cases):
    """(sentence, expected, got, ambiguous) of every case the pipeline reads wrongly."""
    out = []
    for case in cases:
        outcome = outcome_of(pipeline, case.text, case.ip)
        if not case_passes(case, outcome):
            out.append((case.text, _reading(case), _reading(outcome), case.ambiguous))
    return out


def spoken_listener(stt, voice, workdir):
    """listen(index, text) -> Transcript: espeak-ng speaks the text, the STT core reads it."""
    def listen(index, text):
        wav = synthesise(text, Path(workdir) / f"{voice.name}_{index}.wav", voice)
        return stt.transcribe(read_wav(wav))
    return listen


def score_speech(listen, pipeline, cases):
    """WER, function and full accuracy, latencies [s] and misheard examples of spoken cases."""
    refs, hyps, latencies, audio, function_ok, full_ok, examples = [], [], [], [], [], [], []
    for i, case in enumerate(cases):
        transcript = listen(i, case.text)
        refs.append(case.text)
        hyps.append(transcript.text)
        latencies.append(transcript.latency_s)
        audio.append(transcript.audio_s)
        outcome = outcome_of(pipeline, transcript.text, case.ip)
        function_ok.append(function_matches(case, outcome))
        full_ok.append(case_passes(case, outcome))
        if normalise_words(transcript.text) != normalise_words(case.text):
            examples.append((case.text, masked(transcript.text), function_ok[-1]))
    return {"wer": word_error_rate(refs, hyps), "function": (sum(function_ok), len(cases)),
            "full": (sum(full_ok), len(cases)), "latency": latencies, "audio": audio,
            "examples": examples}


def masked(text):
    """The text with masked words replaced by asterisks (the WER still counts them)."""
    def mask(match):
        word = match.group(0)
        digest = hashlib.sha256(word.lower().encode()).hexdigest()
        return "*" * len(word) if digest in MASKED_WORDS else word
    return re.sub(r"[A-Za-z]+", mask, text)


def pct(pair):
    return f"{pair[0]}/{pair[1]} ({100.0 * pair[0] / pair[1]:.1f}%)"


def speech_line(spec, result):
    """The progress line of one voice."""
    latency = summarise(result["latency"])
    return (f"[bench_verbal] speech {spec}: WER {result['wer']:.3f}, function "
            f"{pct(result['function'])}, full {pct(result['full'])}, latency "
            f"{latency.mean:.2f} s mean, {latency.describe('s')}")


def text_lines(text, seed):
    """The summary lines of the text path (ours and the seed's method)."""
    return [f"[bench_verbal] text, ours: all {pct(text['all'])}, unambiguous "
            f"{pct(text['unambiguous'])}, function {pct(text['function'])}, "
            f"{text['ms']:.2f} ms/sentence ({text['latency_ms'].describe()})",
            f"[bench_verbal] text, seed method: all {pct(seed['all'])}, unambiguous "
            f"{pct(seed['unambiguous'])}, function {pct(seed['function'])}"]


def main(argv=None):
    args = parse_args(argv)
    keywords = load_keyword_config(resource("config", "keywords.yaml"))
    people, cases = load_corpus(corpus_path())
    table = load_priorities(resource(*PRIORITIES))
    place_ids = load_graph(resource("maps", "household.graph.yaml")).place_ids()
    ours = make_pipeline(keywords, people, table, place_ids)
    text = score_text(ours, cases)
    seed = score_text(make_pipeline(seed_method(keywords), people, table, place_ids), cases)
    misread = failures(ours, cases)

    spoken = [c for c in cases if not c.rejected][: args.limit or None]
    config = SttConfig(beam_size=args.beam_size)
    start = time.perf_counter()
    stt = SpeechToText(config)
    load_s = time.perf_counter() - start
    silence = stt.transcribe(np.zeros(32000, dtype=np.float32))
    speech = {}
    with tempfile.TemporaryDirectory() as workdir:
        for spec in args.voices:
            listen = spoken_listener(stt, voice_of(spec), workdir)
            speech[spec] = score_speech(listen, make_pipeline(keywords, people, table, place_ids),
                                        spoken)
            print(speech_line(spec, speech[spec]), flush=True)

    for line in text_lines(text, seed):
        print(line)
    print(f"[bench_verbal] model load {load_s:.2f} s; 2 s of silence -> {silence.text!r} in "
          f"{silence.latency_s:.3f} s")
    run = {"command": " ".join(["scripts/bench_verbal", *(argv or [])]), "load_s": load_s,
           "silence": silence, "config": config, "table_source": "/".join(PRIORITIES)}
    args.doc.parent.mkdir(parents=True, exist_ok=True)
    args.doc.write_text(report_markdown(run, cases, spoken, text, seed, misread, speech))
    print(f"[bench_verbal] wrote {args.doc}")
    return 0


def report_markdown(run, cases, spoken, text, seed, misread, speech):
    """docs/perception/verbal.md of one run."""
    lines = [
        "# Verbal perception: measured results", "",
        "Written by `scripts/bench_verbal` (do not edit by hand). Command:", "",
        "```bash", "source scripts/env.sh && " + run["command"], "```", "",
        f"Run {datetime.now(UTC):%Y-%m-%d %H:%M} UTC on {platform.machine()}, "
        f"Python {platform.python_version()}, {os.cpu_count()} cores shared with other jobs "
        f"(load average {os.getloadavg()[0]:.1f} at the end: latencies vary with load); "
        f"priorities from {run['table_source']}; corpus "
        f"`src/perception/data/verbal_corpus.yaml` ({len(cases)} "
        f"sentences, {sum(c.ambiguous for c in cases)} marked ambiguous, "
        f"{sum(bool(c.rejected) for c in cases)} to be refused).", "",
        "## Text (the phone app's path)", "",
        "A case passes when function, priority level, target and chain (or the refusal) all "
        "match; *function* counts the requested function (or the refusal) alone.", "",
        "| method | all cases | unambiguous cases | function | time per sentence (mean, p50, "
        "p99) |",
        "|---|---|---|---|---|",
        f"| ours (request words kept out of VADER, negated/idiomatic physical terms dropped) | "
        f"{pct(text['all'])} | {pct(text['unambiguous'])} | {pct(text['function'])} | "
        f"{_text_times(text)} |",
        f"| seed §3.3 as written (VADER on the whole sentence, plain term look-up) | "
        f"{pct(seed['all'])} | {pct(seed['unambiguous'])} | {pct(seed['function'])} | "
        f"{_text_times(seed)} |", "",
        "Cases our pipeline reads differently from the corpus:", "",
        "| sentence | expected | got | ambiguous |", "|---|---|---|---|"]
    lines += [f"| {t} | {w} | {g} | {'yes' if a else 'no'} |" for t, w, g, a in misread]
    lines += speech_markdown(run, spoken, speech)
    return "\n".join(lines) + "\n"


def _text_times(result):
    latency = result["latency_ms"]
    return f"{result['ms']:.2f} / {latency.p50:.2f} / {latency.p99:.2f} ms"


def speech_markdown(run, spoken, speech):
    """The speech section of the report: one row per voice, then each voice's misheard lines."""
    config, silence = run["config"], run["silence"]
    lines = [
        "", "## Speech (espeak-ng → sox 16 kHz mono → faster-whisper tiny.en → the same pipeline)",
        "",
        f"{len(spoken)} accepted corpus sentences spoken per voice. STT: Whisper tiny.en "
        f"(CTranslate2, {config.compute_type}), beam {config.beam_size}, "
        f"{config.cpu_threads} CPU thread, Silero VAD {'on' if config.vad_filter else 'off'}; "
        f"model load {run['load_s']:.2f} s. Two seconds of silence gave {silence.text!r} "
        f"(no utterance) in {silence.latency_s:.3f} s.", "",
        "| voice:wpm | WER | function extracted | full case | latency mean / p50 / p99 / max | "
        "real-time factor |",
        "|---|---|---|---|---|---|"]
    for spec, r in speech.items():
        rtf = sum(r["latency"]) / sum(r["audio"])
        latency = summarise(r["latency"])
        lines.append(f"| {spec} | {r['wer']:.3f} | {pct(r['function'])} | {pct(r['full'])} | "
                     f"{latency.mean:.2f} s / {latency.p50:.2f} s / {latency.p99:.2f} s / "
                     f"{latency.max:.2f} s | {rtf:.2f} |")
    for spec, r in speech.items():
        lines += ["", f"Transcripts whose words differ from the sentence ({spec}):", "",
                  "| spoken | recognised | function right |", "|---|---|---|"]
        lines += [f"| {s} | {h} | {'yes' if ok else 'no'} |" for s, h, ok in r["examples"]]
    return lines
