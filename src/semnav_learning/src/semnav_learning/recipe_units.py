"""The units of a training recipe (semnav_learning.recipe), each through the library: a dataset
build (dataset_build.build_dataset), a closed-loop plan (evaluation_run.episode_specs), a
training or Z_w retraining (trainer.Trainer), a DAgger collection (dagger.collect_round) and an
evaluation (evaluation_run.evaluate_run). Outputs under the recipe's work directory:
datasets/<unit>/, plans/<unit>.json, train/<unit>/, models/<unit>.keras (+ .json),
dagger/<unit>.records, eval/<unit>.json and eval/docs/. Each run returns the unit's record for
done/<unit>.json."""
import dataclasses
import json

import numpy as np

from semnav_learning.recipe_format import PROGRESS_LINE, RESUME_LINE, RecipeError
from semnav_learning.trainer import Trainer, TrainerConfig, TrainingError
from semnav_learning.training import TrainingConfig
from tamp_resources import resource

TEST_FLOORS = ["office_ring", "office_comb"]      # the floors never trained on


def floor_paths(recipe, floors):
    """Recipe floors -> map YAML paths: "office_grid" (maps_dir), "unit:gen0_003" (a generated
    floor of a build unit), "unit:*" (all of them)."""
    paths = []
    for floor in map(str, floors):
        if ":" not in floor:
            paths.append(recipe.maps_dir / f"{floor}.yaml")
            continue
        dataset, _, name = floor.partition(":")
        folder = recipe.work_dir / "datasets" / dataset / "floors"
        found = sorted(folder.glob(f"{name}.yaml"))
        if not found:
            raise RecipeError(f"floor {floor}: no {name}.yaml in {folder}")
        paths += found
    return paths


class UnitRunner:
    """Runs one unit of a Recipe; `progress(done, total, what)` gets its parts."""

    def __init__(self, recipe, report):
        self.recipe, self.report = recipe, report
        self.work = recipe.work_dir

    def run(self, unit, progress):
        """-> the unit's record (its outputs; "model" for a training)."""
        return getattr(self, f"run_{unit.kind}")(unit, progress)

    def model_path(self, name):
        """A model: a training unit's (models/<unit>.keras) or a workspace path."""
        if any(u.name == name for u in self.recipe.units):
            return self.work / "models" / f"{name}.keras"
        return self.recipe.root / name

    def follower_config(self, args):
        """A unit's `follower_config` (a workspace path, e.g. config/semnav_follower_*.yaml) as
        a path, None when it names none (the follower's defaults)."""
        follower = args.get("follower_config")
        return self.recipe.root / follower if follower else None

    def run_build(self, unit, progress):
        from semnav_learning.dataset_build import DatasetConfig, build_dataset, summary_lines
        out = self.work / "datasets" / unit.name
        config = DatasetConfig(**unit.args, world=self.recipe.world,
                               maps_dir=self.recipe.maps_dir, out=out, resume=True)
        summary = build_dataset(config, progress=False, on_floor=progress)
        for line in summary_lines(summary, out):
            self.report(f"  {line}")
        records = sum(e["records"] for floors in summary["splits"].values()
                      for e in floors.values())
        return {"dataset": str(out), "records": records}

    def run_plan(self, unit, progress):
        from semnav_learning.evaluation_run import EvaluationRun, EvaluationRunError, episode_specs
        path = self.work / "plans" / f"{unit.name}.json"
        args = unit.args
        run = EvaluationRun(maps=floor_paths(self.recipe, args["floors"]),
                            episodes_per_class=args["per_class"], seed=args.get("seed", 0),
                            plan=path, classes=args.get("classes", EvaluationRun().classes))
        try:
            specs, _, _ = episode_specs(run)
        except EvaluationRunError as error:
            raise RecipeError(f"unit {unit.name}: {error}") from error
        progress(1, 1, "plans")
        return {"plan": str(path), "episodes": len(specs)}

    def trainer_config(self, unit, **fields):
        """TrainerConfig of a training unit: references resolved, the recipe's and the unit's
        TrainingConfig / NetworkConfig overrides applied."""
        from semantic_nav.network import NetworkConfig
        args = dict(unit.args)
        training = {**self.recipe.training, **args.pop("training", {})}
        network = {**self.recipe.network, **args.pop("network", {})}
        names = {"dataset": lambda n: self.work / "datasets" / n,
                 "closed_loop_plan": lambda n: self.work / "plans" / f"{n}.json",
                 "dagger_records": lambda n: self.work / "dagger" / f"{n}.records"}
        for key, path in names.items():
            if key in args:
                args[key] = [path(name) for name in args[key]]
        if "init" in args:
            args["init"] = self.model_path(args["init"])
        if "follower_config" in args:
            args["follower_config"] = self.follower_config(args)
        config = resource("config")
        return TrainerConfig(**{**args, **fields}, work_dir=self.work / "train" / unit.name,
                             out=self.work / "models" / f"{unit.name}.keras",
                             laser_config=config / "semnav_laser.yaml",
                             phrases=config / "semnav_phrases.yaml",
                             world_template=self.recipe.world, cache=self.work / "cache",
                             threads=self.recipe.threads, words=self.recipe.words,
                             command=f"{self.recipe.path} unit {unit.name}", resume=True,
                             training=TrainingConfig(**training),
                             network=NetworkConfig(**network) if network else None)

    def train(self, unit, config, progress):
        """Trainer.run with its lines passed on and progress per epoch / 200 Z_w batches."""
        def report(line):
            self.report(f"  {line}")
            for what, pattern in PROGRESS_LINE.items():
                match = pattern.match(line)
                if match:
                    progress(int(match[1]), int(match[2]), what)
            resume = RESUME_LINE.match(line)
            if resume:
                progress.resumed(int(resume[1]))

        try:
            summary = Trainer(config, report=report).run()
        except TrainingError as error:
            raise RecipeError(f"unit {unit.name}: {error}") from error
        if summary.get("interrupted"):
            raise KeyboardInterrupt
        return {"model": str(config.out), "work_dir": str(config.work_dir),
                "seconds_training": summary["seconds"]}

    def run_train(self, unit, progress):
        return self.train(unit, self.trainer_config(unit), progress)

    def run_classifier(self, unit, progress):
        args = dict(unit.args)
        batches = args.pop("batches")
        config = self.trainer_config(dataclasses.replace(unit, args=args),
                                     retrain_classifier=batches)
        return self.train(unit, config, progress)

    def run_dagger(self, unit, progress):
        import torch
        from semantic_nav.follower import DirectionFollower
        from semnav_learning.dagger import collect_round, write_round
        from semnav_learning.phrase_sets import load_phrase_sets
        from semantic_nav.instruction_classes import CLASS_IDS
        args = unit.args
        torch.set_num_threads(1)
        policy = DirectionFollower.from_files(str(self.model_path(args["model"])),
                                              word_vectors=self.recipe.words,
                                              config=self.follower_config(args))
        sets = load_phrase_sets(resource("config", "semnav_phrases.yaml"))
        classes = args.get("classes", list(CLASS_IDS))
        rng = np.random.default_rng(args.get("seed", 0) * 1000 + 1)  # seed * 1000 + round 1
        total, count = len(classes) * args.get("per_class", 4), [0]

        def episode_done(result):
            count[0] += 1
            if count[0] % 10 == 0 or count[0] == total:     # a line per 10 episodes
                progress(count[0], total, "episodes")

        sequences, results, countings = collect_round(
            floor_paths(self.recipe, args["floors"]), self.recipe.world, policy, sets,
            args.get("per_class", 4), rng, progress=episode_done, classes=classes,
            max_route_offset=args.get("max_route_offset"), side_share=args.get("side_share"))
        path = self.work / "dagger" / f"{unit.name}.records"
        path.parent.mkdir(parents=True, exist_ok=True)
        write_round(path, sequences, countings)
        figures = {"records": str(path), "episodes": len(results),
                   "successes": sum(r.success for r in results),
                   "states": sum(len(s.samples) for s in sequences)}
        self.report(f"  {unit.name}: {figures['successes']}/{figures['episodes']} episodes "
                    f"reached the goal; {figures['states']} states labelled")
        return figures

    def run_evaluate(self, unit, progress):
        from semnav_learning.evaluation_run import EvaluationRun, EvaluationRunError, evaluate_run
        args, eval_dir = unit.args, self.work / "eval"
        result = eval_dir / f"{unit.name}.json"
        run = EvaluationRun(
            model=str(self.model_path(args["model"])),
            plan=eval_dir / f"plan_{args['plan']}.json",
            maps=floor_paths(self.recipe, args.get("floors", TEST_FLOORS)),
            episodes_per_class=args.get("per_class", 100), seed=args.get("seed", 0),
            laser=args.get("laser", "utm30lx"), workers=args.get("workers", 2), name=unit.name,
            docs=eval_dir / "docs", json=result,
            classes=args.get("classes", EvaluationRun().classes),
            follower_config=self.follower_config(args))
        try:
            evaluate_run(run, f"{self.recipe.path} unit {unit.name}")
        except EvaluationRunError as error:
            raise RecipeError(f"unit {unit.name}: {error}") from error
        _, episodes, successes, rate = json.loads(result.read_text())["policy"]["total"]
        progress(1, 1, "evaluations")
        self.report(f"  {unit.name} ({args['model']}): {successes}/{episodes} goals "
                    f"({rate:.4f})")
        return {"json": str(result), "evaluated": args["model"], "episodes": episodes,
                "successes": successes, "rate": rate}
