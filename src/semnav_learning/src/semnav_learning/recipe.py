"""`make train`: the training recipe of the semantic_nav models (config/semnav_recipe.yaml).

`load_recipe(path, root)` reads and checks a recipe: named stages, each a list of units (one
dataset build, closed-loop plan, training, DAgger collection, Z_w retraining or evaluation) with
an estimated duration. `RecipeRun(recipe, report=print).run()` runs the units in order in this
process through the library (dataset_build, evaluation_run, trainer, dagger), everything under the
recipe's work directory; a unit whose done/<unit>.json exists is skipped (resume). Progress goes
to `report` as lines: one per unit and per floor, epoch or episode block, each with the elapsed
time, the unit's ETA and the recipe's ETA (the estimates of the units still to run, scaled by
the measured/estimated ratio of the units run so far). `install()` copies the models named by
the recipe's `install` to the install directory with their training records and writes their
cards (model_card.py); nothing else is written outside the work directory.
"""
import dataclasses
import datetime
import json
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path


from semnav_learning.dataset_build import DatasetConfig
from semnav_learning.model_card import recipe_card, source_commit
from semnav_learning.recipe_format import RecipeError
from semnav_learning.recipe_units import UnitRunner
from semnav_learning.trainer import TrainerConfig, format_duration
from semnav_learning.training import TrainingConfig
from supervision import config_file

KINDS = ("build", "plan", "train", "dagger", "classifier", "evaluate")
MODEL_KINDS = ("train", "classifier")
TOP_KEYS = {"work_dir", "stages", "world", "threads", "install", "install_dir", "maps_dir",
            "words", "training", "network"}
# keys the runner sets itself, not the recipe
MANAGED = {"work_dir", "out", "command", "laser_config", "phrases", "world_template", "cache",
           "threads", "retrain_classifier", "words"}
KIND_KEYS = {
    "build": {f.name for f in dataclasses.fields(DatasetConfig)}
    - {"world", "maps_dir", "out", "resume"},
    "plan": {"floors", "per_class", "seed", "classes"},
    "train": {f.name for f in dataclasses.fields(TrainerConfig)} - MANAGED,
    "dagger": {"model", "floors", "per_class", "seed", "classes", "max_route_offset",
               "side_share", "follower_config"},
    "classifier": {"init", "batches", "word_noise", "seed", "training", "network"},
    "evaluate": {"model", "plan", "per_class", "seed", "floors", "classes", "laser", "workers",
                 "follower_config"},
}
REQUIRED = {"plan": ("floors", "per_class"), "dagger": ("model", "floors"),
            "classifier": ("init", "batches"), "evaluate": ("model", "plan"), "train": ("dataset",)}
# references to earlier units: key -> the kinds it may name
REFERENCES = {("train", "dataset"): ("build",), ("train", "closed_loop_plan"): ("plan",),
              ("train", "init"): MODEL_KINDS, ("train", "dagger_records"): ("dagger",),
              ("dagger", "model"): MODEL_KINDS, ("classifier", "init"): MODEL_KINDS}
@dataclass
class Unit:
    """One unit of work of a stage."""

    stage: str
    name: str
    kind: str          # one of KINDS
    minutes: float     # estimated duration on 2 cores
    args: dict


@dataclass
class Recipe:
    """A checked recipe; paths are absolute (relative ones are under the workspace root)."""

    path: Path
    root: Path
    work_dir: Path
    world: Path
    maps_dir: Path
    install_dir: Path
    threads: int = 2
    words: str = None
    install: dict = field(default_factory=dict)     # model name -> unit name
    training: dict = field(default_factory=dict)    # TrainingConfig overrides of every training
    network: dict = field(default_factory=dict)     # NetworkConfig overrides of every training
    units: list = field(default_factory=list)       # [Unit] in order

    def unit(self, name):
        return next(u for u in self.units if u.name == name)

    def stages(self):
        """Stage names in order."""
        return list(dict.fromkeys(u.stage for u in self.units))


def _mapping(value, where):
    if not isinstance(value, dict):
        raise RecipeError(f"{where}: expected a mapping, got {type(value).__name__}")
    return value


def _check_keys(mapping, allowed, where):
    for key in mapping:
        if key not in allowed:
            raise RecipeError(f"{where}.{key}: "
                              f"{config_file.unknown_key_message(key, sorted(allowed))}")


def _check_overrides(overrides, where):
    """`training` / `network` mappings: fields of TrainingConfig / NetworkConfig."""
    from semantic_nav.network import NetworkConfig
    for key, config in (("training", TrainingConfig), ("network", NetworkConfig)):
        if key in overrides:
            _check_keys(_mapping(overrides[key], f"{where}.{key}"),
                        {f.name for f in dataclasses.fields(config)}, f"{where}.{key}")


def committed_model(kinds, name):
    """A model reference that names a workspace file (models/semantic_nav/*.keras, read by
    RecipeUnits.model_path), not an earlier unit."""
    return kinds == MODEL_KINDS and str(name).endswith(".keras")


def _check_references(unit, done, where):
    """Names of earlier units in `unit`'s arguments (a model may also be a workspace path
    ending in .keras), and dataset floors ("unit:floor")."""
    for (kind, key), kinds in REFERENCES.items():
        if unit.kind != kind or key not in unit.args:
            continue
        names = unit.args[key]
        for name in names if isinstance(names, list) else [names]:
            if committed_model(kinds, name):
                continue
            if done.get(name) not in kinds:
                raise RecipeError(f"{where}.{kind}.{key}: {name!r} is not an earlier unit of kind "
                                  f"{' / '.join(kinds)}")
    for floor in unit.args.get("floors", []):
        dataset = str(floor).partition(":")[0] if ":" in str(floor) else None
        if dataset is not None and done.get(dataset) != "build":
            raise RecipeError(f"{where}.{unit.kind}.floors: {floor!r} names no earlier build unit")


def _unit(entry, stage, where):
    """One unit entry -> Unit (keys checked)."""
    entry = _mapping(entry, where)
    kinds = [k for k in KINDS if k in entry]
    if "name" not in entry or len(kinds) != 1:
        raise RecipeError(f"{where}: a unit needs a name and exactly one of {', '.join(KINDS)}")
    kind = kinds[0]
    _check_keys(entry, {"name", "minutes", kind}, where)
    minutes = entry.get("minutes", 0)
    if not isinstance(minutes, (int, float)) or minutes < 0:
        raise RecipeError(f"{where}.minutes: expected a number of minutes >= 0, got {minutes!r}")
    args = _mapping(entry[kind], f"{where}.{kind}")
    _check_keys(args, KIND_KEYS[kind], f"{where}.{kind}")
    missing = [key for key in REQUIRED.get(kind, ()) if key not in args]
    if missing:
        raise RecipeError(f"{where}.{kind}.{missing[0]}: missing")
    _check_overrides(args, f"{where}.{kind}")
    return Unit(stage, str(entry["name"]), kind, float(minutes), dict(args))


def _stage_units(stages, where="stages"):
    """The `stages` list -> [Unit], every name unique and every reference to an earlier unit."""
    if not isinstance(stages, list) or not stages:
        raise RecipeError(f"{where}: expected a list of stages")
    units, done = [], {}
    for s, stage in enumerate(stages):
        at = f"{where}[{s}]"
        stage = _mapping(stage, at)
        _check_keys(stage, {"name", "units"}, at)
        if "name" not in stage or not isinstance(stage.get("units"), list):
            raise RecipeError(f"{at}: a stage needs a name and a list of units")
        for u, entry in enumerate(stage["units"]):
            unit = _unit(entry, str(stage["name"]), f"{at}.units[{u}]")
            if unit.name in done:
                raise RecipeError(f"{at}.units[{u}].name: {unit.name!r} is used twice")
            _check_references(unit, done, f"{at}.units[{u}]")
            units.append(unit)
            done[unit.name] = unit.kind
    return units


def load_recipe(path, root):
    """Read and check a recipe YAML -> Recipe; RecipeError naming the key that is wrong."""
    path, root = Path(path), Path(root)
    data = _mapping(config_file.read_yaml(path, RecipeError, "recipe"), str(path))
    _check_keys(data, TOP_KEYS, str(path))
    if "work_dir" not in data:
        raise RecipeError(f"{path}.work_dir: missing")
    _check_overrides(data, str(path))
    try:
        units = _stage_units(data.get("stages"))
    except RecipeError as error:
        raise RecipeError(f"{path}: {error}") from None
    kinds = {u.name: u.kind for u in units}
    install = _mapping(data.get("install") or {}, f"{path}.install")
    for model, unit in install.items():
        if kinds.get(unit) not in MODEL_KINDS:
            raise RecipeError(f"{path}: install.{model}: {unit!r} is no training unit")
    def here(value, default):
        return root / (value if value is not None else default)

    return Recipe(path=path, root=root, work_dir=here(data["work_dir"], ""),
                  world=here(data.get("world"), "config/worlds/office_penguin.yaml"),
                  maps_dir=here(data.get("maps_dir"), "maps"),
                  install_dir=here(data.get("install_dir"), "models/semantic_nav"),
                  threads=int(data.get("threads", 2)), words=data.get("words"),
                  install=dict(install), training=dict(data.get("training") or {}),
                  network=dict(data.get("network") or {}), units=units)


def unit_inputs(unit, recipe):
    """Names of the earlier units `unit` reads (references, dataset floors, a unit's model; a
    committed model, a path ending in .keras, is none)."""
    names = []
    for (kind, key), kinds in REFERENCES.items():
        if unit.kind == kind and key in unit.args:
            value = unit.args[key]
            names += [name for name in (value if isinstance(value, list) else [value])
                      if not committed_model(kinds, name)]
    names += [str(f).partition(":")[0] for f in unit.args.get("floors", []) if ":" in str(f)]
    if unit.kind == "evaluate" and unit.args["model"] in {u.name for u in recipe.units}:
        names.append(unit.args["model"])
    return list(dict.fromkeys(names))


class Schedule:
    """Estimated and measured durations -> the recipe's ETA."""

    def __init__(self, units, done, clock=time.perf_counter):
        self.estimates = {u.name: 60.0 * u.minutes for u in units}
        self.order = [u.name for u in units]
        self.pending = [u.name for u in units if u.name not in done]
        self.measured, self.clock, self.began = {}, clock, clock()

    def ratio(self):
        """Measured / estimated duration of the units run so far (1 before any)."""
        estimated = sum(self.estimates[name] for name in self.measured)
        if not self.measured or estimated <= 0:
            return 1.0
        return sum(self.measured.values()) / estimated

    def eta(self, current=None, current_remaining=None):
        """Seconds left: the current unit's remaining time (measured; None: its scaled
        estimate) plus the scaled estimates of the units after it."""
        later = [n for n in self.pending if n != current]
        left = self.ratio() * sum(self.estimates[n] for n in later)
        if current is not None:
            left += (current_remaining if current_remaining is not None
                     else self.ratio() * self.estimates[current])
        return left

    def finished(self, name, seconds):
        self.measured[name] = seconds
        self.pending.remove(name)

    def elapsed(self):
        return self.clock() - self.began


class UnitProgress:
    """Progress lines of one unit: k/N parts done, elapsed, the unit's ETA and the recipe's."""

    def __init__(self, label, name, schedule, report, every=1):
        self.label, self.name, self.schedule, self.report = label, name, schedule, report
        self.began, self.every = schedule.clock(), max(1, every)
        self.done_before = 0

    def resumed(self, done):
        """`done` parts were finished by an earlier run: the unit's ETA is the pace of the
        parts done in this run."""
        self.done_before = done
        self.began = self.schedule.clock()

    def __call__(self, done, total, unit):
        if done % self.every and done != total:
            return
        elapsed = self.schedule.clock() - self.began
        remaining = elapsed / max(done - self.done_before, 1) * (total - done)
        recipe = self.schedule.eta(self.name, remaining)
        self.report(f"{self.label}: {done}/{total} {unit}, {format_duration(elapsed)} elapsed, "
                    f"unit ETA {format_duration(remaining)}, recipe ETA "
                    f"{format_duration(recipe)}")


class RecipeRun:
    """Runs a Recipe's units in order (resume: units with done/<unit>.json are skipped)."""

    def __init__(self, recipe, report=print, clock=time.perf_counter):
        self.recipe, self.report, self.clock = recipe, report, clock
        self.done_dir = recipe.work_dir / "done"

    def done(self):
        """{unit name: its done record} of the units finished in earlier runs."""
        return {u.name: json.loads((self.done_dir / f"{u.name}.json").read_text())
                for u in self.recipe.units if (self.done_dir / f"{u.name}.json").is_file()}

    def selected(self, only):
        """The units of `only` (stage or unit names; None: all) -> [Unit]; RecipeError if a
        name is neither."""
        if not only:
            return list(self.recipe.units)
        names = {u.name for u in self.recipe.units} | set(self.recipe.stages())
        unknown = [name for name in only if name not in names]
        if unknown:
            raise RecipeError(f"--only {unknown[0]}: no such stage or unit")
        return [u for u in self.recipe.units if u.name in only or u.stage in only]

    def check_inputs(self, units, done):
        """Every unit to run names only units done earlier or run before it here; RecipeError
        naming the first that is neither (e.g. --only a training whose dataset is not built)."""
        ready = set(done)
        for unit in units:
            if unit.name in done:
                continue
            missing = [name for name in unit_inputs(unit, self.recipe) if name not in ready]
            if missing:
                raise RecipeError(f"unit {unit.name} needs {missing[0]}, which has not run "
                                  f"(add it to --only or run the recipe without --only)")
            ready.add(unit.name)

    def run(self, only=None):
        """Run the (selected) units not done yet -> {unit name: done record}."""
        units, done = self.selected(only), self.done()
        self.check_inputs(units, done)
        schedule = Schedule(units, done, self.clock)
        self.report(f"recipe {self.recipe.path.name}: {len(units)} units, "
                    f"{sum(u.name in done for u in units)} done earlier; estimate "
                    f"{format_duration(schedule.eta())}; work directory {self.recipe.work_dir}")
        runner = UnitRunner(self.recipe, self.report)
        for index, unit in enumerate(units, 1):
            label = f"[{index}/{len(units)}] {unit.stage}/{unit.name}"
            if unit.name in done:
                self.report(f"{label}: done earlier ({format_duration(done[unit.name]['seconds'])}"
                            "), skipped")
                continue
            self.report(f"{label} ({unit.kind}): started; recipe "
                        f"{format_duration(schedule.elapsed())} elapsed, ETA "
                        f"{format_duration(schedule.eta(unit.name))}")
            began = self.clock()
            result = runner.run(unit, UnitProgress(label, unit.name, schedule, self.report))
            seconds = self.clock() - began
            schedule.finished(unit.name, seconds)
            done[unit.name] = {"unit": unit.name, "kind": unit.kind, "seconds": round(seconds, 1),
                               "estimate_minutes": unit.minutes, **result}
            self.done_dir.mkdir(parents=True, exist_ok=True)
            (self.done_dir / f"{unit.name}.json").write_text(json.dumps(done[unit.name],
                                                                        indent=1))
            if unit.kind == "evaluate":
                self.write_evaluations(done)
            self.report(f"{label}: done in {format_duration(seconds)} (estimate "
                        f"{format_duration(60 * unit.minutes)}); recipe "
                        f"{format_duration(schedule.elapsed())} elapsed, ETA "
                        f"{format_duration(schedule.eta())}")
        return done

    def write_evaluations(self, done):
        """eval/summary.md: every evaluation done so far, its model and goals reached (the
        same plan's episodes for every model of the recipe's `evaluate` units)."""
        lines = ["| unit | model | goals | success rate |", "|---|---|---:|---:|"]
        lines += [f"| {name} | {d['evaluated']} | {d['successes']}/{d['episodes']} | "
                  f"{d['rate']:.4f} |" for name, d in done.items() if d["kind"] == "evaluate"]
        path = self.recipe.work_dir / "eval" / "summary.md"
        path.write_text("\n".join(lines) + "\n")
        self.report(f"evaluations so far -> {path}")

    def install(self, date=None):
        """Copy the `install` models whose units are done (+ their training records, with the
        recipe and unit named) to the install directory and write each one's card
        (`<model>.md`, model_card.py: data, command, commit, `date` (default today),
        evaluations) -> [installed paths]; a model whose unit has not run is left as it is
        (said so); RecipeError if none has been trained."""
        done, installed = self.done(), []
        date = date or datetime.date.today().isoformat()
        commit = source_commit(self.recipe.root)
        ready = {model: unit for model, unit in self.recipe.install.items() if unit in done}
        for model, unit in self.recipe.install.items():
            if model not in ready:
                self.report(f"not installed: {model} (unit {unit} has not run yet)")
        if not ready:
            raise RecipeError("--install: none of the models' units "
                              f"({', '.join(self.recipe.install.values())}) has run yet")
        self.recipe.install_dir.mkdir(parents=True, exist_ok=True)
        for model, unit in ready.items():
            source = Path(done[unit]["model"])
            target = self.recipe.install_dir / f"{model}.keras"
            shutil.copyfile(source, target)
            record = json.loads(source.with_suffix(".json").read_text())
            record = {"recipe": str(self.recipe.path), "recipe_unit": unit, **record}
            target.with_suffix(".json").write_text(json.dumps(record, indent=1, default=str))
            target.with_suffix(".md").write_text(recipe_card(
                self.recipe, unit, done, target.name, commit, date,
                lambda u: unit_inputs(u, self.recipe)))
            self.report(f"installed {unit} -> {target}")
            installed.append(target)
        return installed
