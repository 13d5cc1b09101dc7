"""One evaluation of a direction-following policy per instruction class (thesis 002 §4.2.1) as a
library call: plan (or reload) the episodes, drive them in sim2d, print the Table 4.2-1 layout and
write it with a JSON file of every episode and Fig. 4.2.3-style path pictures. scripts/eval_semnav
(tools.eval_semnav) and the training recipe's plan and evaluate units call it."""
import json
import os
import sys
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
from tqdm import tqdm

from floorplan.occupancy_map import load_map
from semantic_nav.instruction_classes import CLASS_IDS, COUNTING_IDS
from semnav_learning.episodes import EpisodeError, chain_goals
from semnav_learning.eval_plot import plot_episodes
from semnav_learning.evaluation import (EpisodeOutcome, EvaluationConfig, PolicySpec, breakdown,
                                        counting_breakdown, evaluate, failure_places,
                                        format_table, load_plan, mode_breakdown, outcome_record,
                                        plan_chain_episodes, plan_episodes, success_table)
from semnav_learning.phrase_sets import PhraseSetError, load_phrase_sets
from semnav_learning.route_oracle import RouteOracle
from semnav_learning.spoken import DEFAULT_VOICES, STAYED, speak_specs, spoken_report
from tamp_resources import resource, workspace

TEST_FLOORS = ("office_ring", "office_comb")   # never used in training


class EvaluationRunError(ValueError):
    """A run that cannot start: a bad plan, phrase, follower or STT file, or a chain without its
    sentence; the message names what was wrong."""


def laser_templates():
    """{laser name: sim2d world template of the Penguin with that laser} of tamp_resources."""
    worlds = resource("config", "worlds")
    return {"utm30lx": worlds / "office_penguin.yaml",
            "urg04lx": worlds / "office_penguin_urg.yaml"}


@dataclass
class EvaluationRun:
    """What to evaluate and where the outputs go (the options of scripts/eval_semnav); floors,
    worlds and configs default to tamp_resources', the docs outputs to the workspace's docs/."""
    maps: list = field(default_factory=lambda: [resource("maps", f"{floor}.yaml")
                                                for floor in TEST_FLOORS])
    laser: str = "utm30lx"            # a key of laser_templates()
    episodes_per_class: int = 100
    seed: int = 0
    candidates: int = EvaluationConfig().candidates  # corridor starts a new plan samples a floor
    json: Path | None = None          # every episode and the table, when given
    model: str | None = None          # the follower's model file (None: its default)
    follower_config: Path | None = None  # follower YAML (None: the follower's defaults)
    policy: str = "model"             # "model" or "expert"
    expert_reference: bool = False    # also run the expert on the same episodes
    workers: int = min(2, os.cpu_count() or 1)
    classes: list = field(default_factory=lambda: list(CLASS_IDS))
    name: str | None = None           # of the docs outputs (None: <policy>_<laser>)
    docs: Path = field(default_factory=lambda: workspace() / "docs" / "semantic_nav" / "eval")
    first: int | None = None          # only the first N episodes of each class of the plan
    skip: int = 0                     # ... after leaving out its first K
    chain: list | None = None         # classes of one chained instruction instead
    sentence: str | None = None       # the words of `chain`
    spoken: list | None = None        # voices to speak and transcribe each sentence with
    stt_config: Path = field(default_factory=lambda: resource("config", "semnav_stt.yaml"))
    plan: Path | None = None          # reused when the file exists, else written
    phrases: Path = field(default_factory=lambda: resource("config", "semnav_phrases.yaml"))
    side_share: float | None = None   # a new plan's classes 5-8 counted on one side (None: as
    #                                   the sentences fall; EvaluationConfig.side_share)


def drive(specs, policy_spec, template, workers, label):
    """Drive every episode with a progress bar on stderr -> (outcomes, seconds)."""
    with tqdm(total=len(specs), unit="episode", desc=label, file=sys.stderr) as bar:
        began = time.perf_counter()
        outcomes = evaluate(specs, template, policy_spec, workers, progress=bar.update)
    return outcomes, time.perf_counter() - began


def report(outcomes, seconds, title, oracles):
    """Print the table and its breakdowns -> the result entry of the JSON file."""
    rows, total = success_table(outcomes)
    table = format_table(rows, total, title)
    extra = {**breakdown(outcomes), "by_counting": counting_breakdown(outcomes, oracles),
             "by_mode": mode_breakdown(outcomes),
             "failure_places": failure_places(outcomes, oracles)}
    step = float(np.median([o.step_seconds for o in outcomes if o.steps] or [0.0])) * 1e3
    print(table)
    print(f"by phrasing: {extra['by_phrasing']}; reasons: {extra['reasons']}")
    if extra["by_counting"]:
        print(f"classes {COUNTING_IDS[0]}-{COUNTING_IDS[-1]} by whether corners on the other "
              f"side count: {extra['by_counting']}")
    if extra["by_mode"]:
        print(f"classes {COUNTING_IDS[0]}-{COUNTING_IDS[-1]} by counting mode: " + "; ".join(
            f"{label} " + ", ".join(f"{mode} {c['successes']}/{c['tests']}"
                                    for mode, c in modes.items())
            for label, modes in extra["by_mode"].items()))
    for label, places in extra["failure_places"].items():
        print(f"class {label} failures ended: "
              + "; ".join(f"{n} {place}" for place, n in sorted(places.items(),
                                                                key=lambda kv: -kv[1])))
    if any(o.predicted for o in outcomes):
        print(f"Z_w class prediction: {extra['class_prediction_accuracy']:.4f} "
              f"(held-out phrasings {extra['held_out_class_prediction_accuracy']:.4f})")
    print(f"{len(outcomes)} episodes in {seconds:.0f} s; median {step:.2f} ms per control step "
          f"(episode, in-process)")
    return {"rows": [list(r) for r in rows], "total": list(total), "table": table,
            "seconds": round(seconds, 1), "median_step_ms": round(step, 3), **extra}


def path_panels(outcomes, reference, oracles, success=True):
    """One panel per class: prefer an episode the policy got right (success=False: one it got
    wrong; classes without one are left out), else the first."""
    panels, by_key = [], {id(o.spec): r for o, r in zip(outcomes, reference or [])}
    for label in sorted({o.spec.labels[-1] for o in outcomes}):
        chosen = [o for o in outcomes if o.spec.labels[-1] == label]
        outcome = next((o for o in chosen if o.success == success),
                       chosen[0] if success else None)
        if outcome is None:
            continue
        oracle = oracles[outcome.spec.floor]
        goal = chain_goals(oracle, outcome.spec.start, outcome.spec.labels,
                           outcome.spec.countings)[-1].goal
        expert = by_key.get(id(outcome.spec))
        title = (f"class {label}: {'success' if outcome.success else outcome.reason}: "
                 f"\"{outcome.spec.sentence}\"")
        panels.append((oracle.field.grid, np.array(outcome.path),
                       np.array(expert.path) if expert else None, goal, title))
    return panels


def episode_specs(run):
    """The episodes to run: run.plan's if the file exists, else drawn (sentences from
    run.phrases; written to run.plan) -> (specs, floors, {floor: RouteOracle}). A bad plan or
    phrase file, or a chain without its sentence, raises EvaluationRunError."""
    if run.plan and Path(run.plan).is_file():
        try:
            specs = load_plan(run.plan)
        except ValueError as error:
            raise EvaluationRunError(f"plan {error}") from error
        floors = sorted({s.floor for s in specs})
        return specs, floors, {f: RouteOracle(load_map(f)) for f in floors}
    rng = np.random.default_rng(run.seed)
    batch = min(EvaluationConfig().batch, run.candidates)      # starts sampled per round
    config = EvaluationConfig(candidates=run.candidates, batch=batch, side_share=run.side_share)
    floors = [str(Path(p).resolve()) for p in run.maps]
    oracles = {f: RouteOracle(load_map(f)) for f in floors}
    if run.chain:
        if not run.sentence:
            raise EvaluationRunError("a chain needs its sentence (the chained instruction's "
                                     "words)")
        specs = plan_chain_episodes(oracles, run.chain, run.sentence, run.episodes_per_class,
                                    rng, config)
    else:
        try:
            sets = load_phrase_sets(run.phrases)
        except (OSError, PhraseSetError) as error:
            raise EvaluationRunError(f"phrases {run.phrases}: {error}") from error
        try:
            specs = plan_episodes(oracles, run.episodes_per_class, sets, rng, config,
                                  run.classes)
        except (EpisodeError, ValueError) as error:
            raise EvaluationRunError(f"plan: {error}") from error
    if run.plan:
        Path(run.plan).parent.mkdir(parents=True, exist_ok=True)
        Path(run.plan).write_text(json.dumps([asdict(s) for s in specs]))
    return specs, floors, oracles


def first_of_each_class(specs, count, skip=0):
    """The first `count` specs of each (last) class after its first `skip`, classes in ascending
    order."""
    return [s for label in sorted({s.labels[-1] for s in specs})
            for s in [s for s in specs if s.labels[-1] == label][skip:skip + count]]


def spoken_specs(specs, voices, stt_config, follower=None):
    """speak_specs with a progress bar and Whisper as `stt_config` (a YAML file) sets it, the
    robot asking back with `follower` (None: it drives every transcript); a bad voice or STT
    config, missing espeak-ng / sox or Whisper model raises EvaluationRunError."""
    from perception.speech_synthesis import SynthesisUnavailable, voice_of
    from perception.stt import ModelMissing, SpeechToText, load_stt_config
    try:
        for voice in voices:
            voice_of(voice)
        stt = SpeechToText(load_stt_config(stt_config))
        with tqdm(total=len(specs), unit="sentence", desc="speak + transcribe",
                  file=sys.stderr) as bar:
            return speak_specs(specs, voices, stt, progress=bar.update, follower=follower)
    except (OSError, ValueError, SynthesisUnavailable, ModelMissing) as error:
        raise EvaluationRunError(f"spoken: {error}") from error


def asking_follower(run, config):
    """The follower that takes spoken directions as the node does, asking back when unsure
    (config's `ask`), or None: the model's follower with asking back off, or the expert."""
    from semantic_nav.follower import DirectionFollower, FollowerConfig
    if run.policy != "model" or not (config or FollowerConfig()).ask.enabled:
        return None
    return DirectionFollower.from_files(run.model, None, config)


def with_stayed(specs, heard, driven):
    """Outcomes of every spec: those driven (`driven`, in order) and, where the robot did not
    drive (Heard.drives false), an episode not reached, the robot at its start."""
    driven = iter(driven)
    outcomes = []
    for spec, said in zip(specs, heard):
        if said.drives:
            outcomes.append(next(driven))
            continue
        last = said.again or said
        why = last.reading.refused or f"answered {last.reading.answer} to {last.reading.question!r}"
        outcomes.append(EpisodeOutcome(spec, False, f"{STAYED}: {why}", 0.0, 0, [],
                                       [list(spec.start)]))
    return outcomes


def follower_config(path):
    """The follower config file (None: the follower's defaults); a bad file raises
    EvaluationRunError."""
    if not path:
        return None
    from semantic_nav.follower import load_follower_config
    try:
        return load_follower_config(path)
    except (OSError, ValueError) as error:
        raise EvaluationRunError(str(error)) from error


def write_outputs(run, name, title, result, outcomes, reference, oracles, command):
    """Path pictures, the Markdown table (ending with `command`, the line that made it) and
    (run.json) every episode."""
    docs = Path(run.docs)
    docs.mkdir(parents=True, exist_ok=True)
    plot_episodes(path_panels(outcomes, reference, oracles), docs / f"{name}_paths.png",
                  title.replace("**", ""))
    failures = path_panels(outcomes, reference, oracles, success=False)
    if failures:     # what goes wrong, one failed episode per class
        plot_episodes(failures, docs / f"{name}_failures.png",
                      "failures: " + title.replace("**", ""))
    tables = result["policy"]["table"] + ("\n\n" + result["expert"]["table"]
                                          if reference else "")
    (docs / f"{name}.md").write_text(f"{tables}\n\n`{command}`\n")
    if run.json:
        result["episodes"] = [outcome_record(o) for o in outcomes]
        if reference:
            result["expert_episodes"] = [outcome_record(o) for o in reference]
        Path(run.json).parent.mkdir(parents=True, exist_ok=True)
        Path(run.json).write_text(json.dumps(result, indent=1))


def evaluate_run(run, command):
    """Plan, evaluate, report on stdout and write the outputs (the Markdown table ends with
    `command`) -> the result written to run.json. A run that cannot start raises
    EvaluationRunError before anything is driven or written."""
    config = follower_config(run.follower_config)   # a bad file fails before any floor loads
    specs, floors, oracles = episode_specs(run)
    if run.first or run.skip:
        specs = first_of_each_class(specs, run.first or len(specs), run.skip)
    heard = None
    if run.spoken is not None:
        specs, heard = spoken_specs(specs, run.spoken or list(DEFAULT_VOICES), run.stt_config,
                                    asking_follower(run, config))
    name = run.name or f"{run.policy}_{run.laser}"
    floor_names = ", ".join(Path(f).stem for f in floors)
    template = laser_templates()[run.laser]
    policy_spec = PolicySpec(kind=run.policy, model_path=run.model, config=config)
    driven = [spec for k, spec in enumerate(specs) if heard is None or heard[k].drives]
    outcomes, seconds = drive(driven, policy_spec, template, run.workers, name)
    if heard is not None:      # the robot stayed where asking back ended without a yes
        outcomes = with_stayed(specs, heard, outcomes)
    # the model's file as the follower finds it: run.model, else $SEMNAV_MODEL, else the default
    model = run.model or os.environ.get("SEMNAV_MODEL") or "models/semantic_nav/default.keras"
    title = (f"**{name}** ({run.policy}{' ' + model if run.policy == 'model' else ''}, "
             f"{run.laser}, {floor_names}, seed {run.seed})")
    result = {"args": {k: str(v) for k, v in asdict(run).items()},
              "policy": report(outcomes, seconds, title, oracles)}
    if heard is not None:
        lines = spoken_report(heard, outcomes)
        print("\n".join(lines))
        result["spoken"] = {"report": lines, "heard": [asdict(h) for h in heard]}
    reference = None
    if run.expert_reference and run.policy != "expert":
        reference, ref_seconds = drive(specs, PolicySpec(kind="expert"), template, run.workers,
                                       "expert")
        title = f"**expert** on the same episodes ({run.laser}, {floor_names})"
        result["expert"] = report(reference, ref_seconds, title, oracles)
    write_outputs(run, name, title, result, outcomes, reference, oracles, command)
    docs = Path(run.docs)
    print(f"wrote {docs / (name + '.md')}, {docs / (name + '_paths.png')}"
          + (f", {run.json}" if run.json else ""))
    return result
