"""Command line of scripts/eval_semnav: plan (or reload) episodes, drive them in sim2d, print and
write the Table 4.2-1 layout, a JSON file of every episode and Fig. 4.2.3-style path pictures."""
import argparse
import json
import os
import sys
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np
from tqdm import tqdm

from floorplan.occupancy_map import load_map
from semantic_nav.instruction_classes import CLASS_IDS, COUNTING_IDS
from semnav_learning.episodes import chain_goals
from semnav_learning.eval_plot import plot_episodes
from semnav_learning.evaluation import (EvaluationConfig, PolicySpec, breakdown,
                                        counting_breakdown, evaluate, failure_places,
                                        format_table, load_plan, outcome_record,
                                        plan_chain_episodes, plan_episodes, success_table)
from semnav_learning.phrase_sets import PhraseSetError, load_phrase_sets
from semnav_learning.route_oracle import RouteOracle
from semnav_learning.spoken import DEFAULT_VOICES, speak_specs, spoken_report
from tamp_resources import resource, workspace

COMMAND = "scripts/eval_semnav"
TEST_FLOORS = ("office_ring", "office_comb")   # never used in training


def laser_templates():
    """{laser name: sim2d world template of the Penguin with that laser} of tamp_resources."""
    worlds = resource("config", "worlds")
    return {"utm30lx": worlds / "office_penguin.yaml",
            "urg04lx": worlds / "office_penguin_urg.yaml"}


def argument_parser(description=None):
    """The options of eval_semnav; floors, worlds and configs default to tamp_resources', the
    docs outputs to the workspace's docs/."""
    parser = argparse.ArgumentParser(description=description,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--map", nargs="+", type=Path,
                        default=[resource("maps", f"{floor}.yaml") for floor in TEST_FLOORS],
                        help="map_server YAML floor(s) (default: the test floors)")
    parser.add_argument("--laser", choices=sorted(laser_templates()), default="utm30lx")
    parser.add_argument("--episodes-per-class", type=int, default=100)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--candidates", type=int, default=EvaluationConfig().candidates,
                        help="corridor starts a new plan samples per floor at most (fewer: a "
                             "floor where some classes never apply is sampled sooner)")
    parser.add_argument("--json", type=Path, help="write every episode and the table here")
    parser.add_argument("--model", help="model file of the follower (default: its default)")
    parser.add_argument("--follower-config", type=Path,
                        help="follower YAML (config/semnav_follower.yaml keys), e.g. the guard off")
    parser.add_argument("--policy", choices=("model", "expert"), default="model")
    parser.add_argument("--expert-reference", action="store_true",
                        help="also run the expert on the same episodes (reference, plots)")
    parser.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1))
    parser.add_argument("--classes", type=int, nargs="+", choices=CLASS_IDS,
                        default=list(CLASS_IDS))
    parser.add_argument("--name", default=None, help="name of the docs outputs (table, plot)")
    parser.add_argument("--docs", type=Path, default=workspace() / "docs" / "semantic_nav" / "eval")
    parser.add_argument("--first", type=int, help="run only the first N episodes of each class "
                        "of the plan")
    parser.add_argument("--skip", type=int, default=0, metavar="K",
                        help="leave out the first K episodes of each class of the plan (before "
                             "--first): another subset of the same plan")
    parser.add_argument("--chain", type=int, nargs="+", metavar="CLASS",
                        help="instead of the per-class table: --episodes-per-class episodes of "
                             "one chained instruction of these classes, e.g. --chain 1 3 "
                             "--sentence \"go straight to the end, then turn left\"")
    parser.add_argument("--sentence", help="the sentence of --chain")
    parser.add_argument("--spoken", nargs="*", metavar="VOICE",
                        help="speak each sentence with espeak-ng (these voice:words-per-minute "
                             f"in turn; none given: {' '.join(DEFAULT_VOICES)}), transcribe it "
                             "with Whisper tiny.en and follow the transcript as the node "
                             "reads /voice_message; lists the misheard words")
    parser.add_argument("--stt-config", type=Path,
                        default=resource("config", "semnav_stt.yaml"),
                        help="Whisper's settings for --spoken (perception.stt.SttConfig as YAML; "
                             "default config/semnav_stt.yaml, as semantic_nav.launch starts the "
                             "STT node)")
    parser.add_argument("--plan", type=Path, help="episode plan (JSON, or an earlier --json "
                        "result): reused when it exists (same episodes for every model and "
                        "laser), else written")
    parser.add_argument("--phrases", type=Path,
                        default=resource("config", "semnav_phrases.yaml"),
                        help="phrase sets a new plan's sentences are drawn from (default: "
                             "config/semnav_phrases.yaml)")
    return parser


def run(specs, policy_spec, template, workers, label):
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
             "failure_places": failure_places(outcomes, oracles)}
    step = float(np.median([o.step_seconds for o in outcomes])) * 1e3
    print(table)
    print(f"by phrasing: {extra['by_phrasing']}; reasons: {extra['reasons']}")
    if extra["by_counting"]:
        print(f"classes {COUNTING_IDS[0]}-{COUNTING_IDS[-1]} by whether corners on the other "
              f"side count: {extra['by_counting']}")
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


def episode_specs(args, phrases):
    """The episodes to run: --plan's if the file exists, else drawn (phrase sets from the file
    `phrases`; written to --plan) -> (specs, floors, {floor: RouteOracle}). A bad plan or a
    --chain without --sentence exits with its message."""
    if args.plan and args.plan.is_file():
        try:
            specs = load_plan(args.plan)
        except ValueError as error:
            sys.exit(f"eval_semnav: --plan {error}")
        floors = sorted({s.floor for s in specs})
        return specs, floors, {f: RouteOracle(load_map(f)) for f in floors}
    rng = np.random.default_rng(args.seed)
    batch = min(EvaluationConfig().batch, args.candidates)      # starts sampled per round
    config = EvaluationConfig(candidates=args.candidates, batch=batch)
    floors = [str(p.resolve()) for p in args.map]
    oracles = {f: RouteOracle(load_map(f)) for f in floors}
    if args.chain:
        if not args.sentence:
            sys.exit("--chain needs --sentence (the chained instruction's words)")
        specs = plan_chain_episodes(oracles, args.chain, args.sentence, args.episodes_per_class,
                                    rng, config)
    else:
        try:
            sets = load_phrase_sets(phrases)
        except (OSError, PhraseSetError) as error:
            sys.exit(f"eval_semnav: --phrases {phrases}: {error}")
        specs = plan_episodes(oracles, args.episodes_per_class, sets, rng, config, args.classes)
    if args.plan:
        args.plan.parent.mkdir(parents=True, exist_ok=True)
        args.plan.write_text(json.dumps([asdict(s) for s in specs]))
    return specs, floors, oracles


def first_of_each_class(specs, count, skip=0):
    """The first `count` specs of each (last) class after its first `skip`, classes in ascending
    order."""
    return [s for label in sorted({s.labels[-1] for s in specs})
            for s in [s for s in specs if s.labels[-1] == label][skip:skip + count]]


def spoken_specs(specs, voices, stt_config):
    """speak_specs with a progress bar and Whisper as `stt_config` (a YAML file) sets it; a bad
    voice or STT config, missing espeak-ng / sox or Whisper model exits with its message."""
    from perception.speech_synthesis import SynthesisUnavailable, voice_of
    from perception.stt import ModelMissing, SpeechToText, load_stt_config
    try:
        for voice in voices:
            voice_of(voice)
        stt = SpeechToText(load_stt_config(stt_config))
        with tqdm(total=len(specs), unit="sentence", desc="speak + transcribe",
                  file=sys.stderr) as bar:
            return speak_specs(specs, voices, stt, progress=bar.update)
    except (OSError, ValueError, SynthesisUnavailable, ModelMissing) as error:
        sys.exit(f"eval_semnav: --spoken: {error}")


def follower_config(path):
    """The --follower-config file (None: the follower's defaults); a bad file exits."""
    if not path:
        return None
    from semantic_nav.follower import load_follower_config
    try:
        return load_follower_config(path)
    except (OSError, ValueError) as error:
        sys.exit(f"eval_semnav: {error}")


def write_outputs(args, name, title, result, outcomes, reference, oracles, argv):
    """Path pictures, the Markdown table and (--json) every episode."""
    args.docs.mkdir(parents=True, exist_ok=True)
    plot_episodes(path_panels(outcomes, reference, oracles), args.docs / f"{name}_paths.png",
                  title.replace("**", ""))
    failures = path_panels(outcomes, reference, oracles, success=False)
    if failures:     # what goes wrong, one failed episode per class
        plot_episodes(failures, args.docs / f"{name}_failures.png",
                      "failures: " + title.replace("**", ""))
    tables = result["policy"]["table"] + ("\n\n" + result["expert"]["table"]
                                          if reference else "")
    (args.docs / f"{name}.md").write_text(f"{tables}\n\n`{' '.join([COMMAND] + argv)}`\n")
    if args.json:
        result["episodes"] = [outcome_record(o) for o in outcomes]
        if reference:
            result["expert_episodes"] = [outcome_record(o) for o in reference]
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=1))


def main(description=None, argv=None):
    """Parse, evaluate, report on stdout and write the outputs -> exit status 0 (bad input
    exits with its message)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = argument_parser(description).parse_args(argv)
    config = follower_config(args.follower_config)   # a bad file fails before any floor loads
    specs, floors, oracles = episode_specs(args, args.phrases)
    if args.first or args.skip:
        specs = first_of_each_class(specs, args.first or len(specs), args.skip)
    heard = None
    if args.spoken is not None:
        specs, heard = spoken_specs(specs, args.spoken or list(DEFAULT_VOICES), args.stt_config)
    name = args.name or f"{args.policy}_{args.laser}"
    floor_names = ", ".join(Path(f).stem for f in floors)
    template = laser_templates()[args.laser]
    policy_spec = PolicySpec(kind=args.policy, model_path=args.model, config=config)
    outcomes, seconds = run(specs, policy_spec, template, args.workers, name)
    # the model's file as the follower finds it: --model, else $SEMNAV_MODEL, else the default
    model = args.model or os.environ.get("SEMNAV_MODEL") or "models/semantic_nav/default.keras"
    title = (f"**{name}** ({args.policy}{' ' + model if args.policy == 'model' else ''}, "
             f"{args.laser}, {floor_names}, seed {args.seed})")
    result = {"args": {k: str(v) for k, v in vars(args).items()},
              "policy": report(outcomes, seconds, title, oracles)}
    if heard is not None:
        lines = spoken_report(heard, outcomes)
        print("\n".join(lines))
        result["spoken"] = {"report": lines, "heard": [asdict(h) for h in heard]}
    reference = None
    if args.expert_reference and args.policy != "expert":
        reference, ref_seconds = run(specs, PolicySpec(kind="expert"), template, args.workers,
                                     "expert")
        title = f"**expert** on the same episodes ({args.laser}, {floor_names})"
        result["expert"] = report(reference, ref_seconds, title, oracles)
    write_outputs(args, name, title, result, outcomes, reference, oracles, argv)
    print(f"wrote {args.docs / (name + '.md')}, {args.docs / (name + '_paths.png')}"
          + (f", {args.json}" if args.json else ""))
    return 0
