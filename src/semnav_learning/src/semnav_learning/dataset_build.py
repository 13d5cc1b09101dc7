"""The semantic_nav demonstration dataset (thesis 002 §3.3, §3.4): floors x instruction classes x
start poses -> expert demonstrations driven in sim2d, one record file per floor.

`build_dataset(DatasetConfig(...))` does what scripts/build_semnav_dataset does. Per floor,
candidate starts are sampled on the corridor skeleton and, for each class, up to `per_class` of
the starts from which that class applies are driven; `after_end` and `counting` add the turns at
a corridor's end and the corner counts where the other side's corners matter. Generated floors
(floor_generator) join the training split. Layout of `out`:
<split>/<floor>.records (penguin_base record format), <split>/<floor>.json (the floor's summary
entry and failures, what `resume` keeps), floors/<generated>.yaml/.pgm, summary.yaml.
Random numbers: each floor has its own generator seeded [seed, index] (named floors, in split
order) or [seed, 2000 + i] (generated floor i, drawn from [seed, 1000 + i]), so a floor's records
do not depend on the order the workers finish in.
"""
import functools
import json
import multiprocessing
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml
from tqdm import tqdm

from floorplan.occupancy_map import save_map
from penguin_base.record_format import write_records
from semantic_nav.instruction_classes import CLASS_IDS, COUNT_CORNERS, COUNT_SIDE
from semnav_learning.demonstrations import (demonstrate, plan_counting_demonstrations,
                                            plan_demonstrations, plan_side_demonstrations,
                                            world_for_floor)
from semnav_learning.episodes import STRAIGHT_TO_END, TURN_AT_END, chain_applies
from semnav_learning.floor_generator import FloorGeneratorConfig, random_floor
from semnav_learning.floor_structure import floor_structure, sample_corridor_starts
from semnav_learning.route_oracle import OracleError, RouteOracle
from sim2d.world_config import WorldError

# office_grid gives the training split its third corners (classes 7 and 8); the test floors
# office_ring and office_comb are never used in training (scripts/eval_semnav's default floors)
DEFAULT_SPLIT = {"train": ["office_crossroads", "office_loop", "office_grid"],
                 "validation": ["office_longhall"], "test": ["office_ring", "office_comb"]}
DEFAULT_RECORD_RATE = 40.0   # [Hz] every scan of the UTM-30LX: what `record_rate` None records


@dataclass
class DatasetConfig:
    """One dataset build (the command line of scripts/build_semnav_dataset as data)."""

    world: Path = None            # robot and laser template (sim2d world YAML)
    maps_dir: Path = None         # the named floors are <maps_dir>/<floor>.yaml
    out: Path = Path("build/semnav_dataset")
    split: dict = field(default_factory=lambda: {k: list(v) for k, v in DEFAULT_SPLIT.items()})
    per_class: int = 4            # demonstrations per class and floor (fewer where rare)
    classes: list = field(default_factory=lambda: list(CLASS_IDS))
    after_end: int = 0            # per floor, classes 2/3 standing at a corridor's end
    counting: int = 0             # per floor, each of classes 5-8 where counting matters
    side_counting: int = 0        # per floor, each of classes 5-8 counted on its side only
    candidates: int = 80          # candidate start poses sampled per floor
    generated: int = 0            # random office floors added to the training split
    corridors: tuple = FloorGeneratorConfig.corridors    # generated floors: per direction
    width: tuple = FloorGeneratorConfig.width            # [m] along x
    depth: tuple = FloorGeneratorConfig.depth            # [m] along y
    spacing: float = FloorGeneratorConfig.spacing        # [m] parallel corridors
    side_branches: float = 0.0    # one-sided branches per metre of corridor [1/m]
    side_branch_length: tuple = FloorGeneratorConfig.side_branch_length  # [m]
    end_doors: float = 0.0        # probability of a door at a corridor end [0, 1]
    record_rate: float = None     # [Hz] one scan per 1/rate s (None: every laser scan)
    workers: int = 2              # floors built in parallel
    resume: bool = False          # keep the floors an earlier build of `out` finished
    seed: int = 0

    def generator_config(self):
        """The FloorGeneratorConfig of the generated floors."""
        return FloorGeneratorConfig(corridors=tuple(self.corridors), width=tuple(self.width),
                                    depth=tuple(self.depth), spacing=self.spacing,
                                    side_branch_rate=self.side_branches,
                                    side_branch_length=tuple(self.side_branch_length),
                                    end_door_probability=self.end_doors)


def parse_split(text):
    """"train=a,b validation=c test=d" -> {split: [floor, ...]}; ValueError on a bad part."""
    split = {}
    for part in text.split():
        name, _, floors = part.partition("=")
        if not floors:
            raise ValueError(f"expected name=floor[,floor], got {part!r}")
        split[name] = floors.split(",")
    return split


@dataclass
class FloorJob:
    """One floor to build."""

    split: str
    floor: str
    map_path: Path
    seed: list            # of the floor's random generator
    cache_tables: bool    # cache the laser's range table (not for one-off generated floors)


def read_floor_entry(entry_path):
    """<split>/<floor>.json of a finished floor -> (summary entry, failures)."""
    saved = json.loads(entry_path.read_text())
    per_class = {int(label): count for label, count in saved["entry"]["per_class"].items()}
    return {**saved["entry"], "per_class": per_class}, saved["failures"]


def plan_after_end(oracle, starts, per_class, rng):
    """Beyond the seed: "turn right / left" (classes 2, 3) standing at the end of a corridor, as
    the second part of "go straight to the end, then turn ..." -> [(start, class, (1,))]; up to
    `per_class` of the starts from which class 1 and then the turn are applicable."""
    plan, first = [], STRAIGHT_TO_END
    for label in TURN_AT_END:
        candidates = [start for start in starts if chain_applies(oracle, start, (first, label))]
        chosen = rng.permutation(len(candidates))[:per_class]
        plan.extend((candidates[i], label, (first,)) for i in sorted(chosen))
    return plan


def floor_plan(oracle, starts, config, rng):
    """Demonstrations of one floor -> [(start, class, classes driven before it, counting)]."""
    plan = [(start, label, ()) for start, label in
            plan_demonstrations(oracle, starts, config.per_class, rng) if label in config.classes]
    plan += plan_after_end(oracle, starts, config.after_end, rng)
    plan += [(start, label, ()) for start, label in
             plan_counting_demonstrations(oracle, starts, config.counting, rng)]
    plan = [(*item, COUNT_CORNERS) for item in plan]
    return plan + [(start, label, (), COUNT_SIDE) for start, label in
                   plan_side_demonstrations(oracle, starts, config.side_counting, rng)]


def build_floor(job, config):
    """All demonstrations of one floor -> (split, floor, summary entry, failures); the records
    go to <out>/<split>/<floor>.records, the entry to <floor>.json beside them."""
    split, floor = job.split, job.floor
    path = Path(config.out) / split / f"{floor}.records"
    entry_path = path.with_suffix(".json")
    if config.resume and entry_path.is_file():
        return (split, floor, *read_floor_entry(entry_path))
    rng = np.random.default_rng(job.seed)
    try:
        world = world_for_floor(config.world, job.map_path,
                                **({} if job.cache_tables else {"cache_dir": None}))
        oracle = RouteOracle(world.grid)
        starts = sample_corridor_starts(oracle, floor_structure(oracle.field, 0.3),
                                        config.candidates, rng)
    except (WorldError, OracleError) as error:     # a floor without usable corridors
        return split, floor, {"records": 0, "samples": 0, "per_class": {}, "bytes": 0,
                              "error": str(error)}, []
    sequences, countings, counts, failures = [], [], Counter(), []
    for start, label, after, counting in floor_plan(oracle, starts, config, rng):
        offset = (rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.14, 0.14))
        demo = demonstrate(world, "penguin", oracle, start, label, rng=rng, start_offset=offset,
                           record_rate=config.record_rate, after=after, counting=counting)
        if demo.ok:              # planned from starts where the class applies: never None
            sequences.append(demo.sequence)
            countings.append(counting)
            counts[label] += 1
        else:
            failures.append({"start": [round(float(v), 2) for v in start], "class": label,
                             "after": list(after), "counting": counting,
                             "reached": demo.reached, "bumps": demo.bumps})
    path.parent.mkdir(parents=True, exist_ok=True)
    write_records(path, sequences)
    entry = {"records": len(sequences), "samples": sum(len(s.samples) for s in sequences),
             "per_class": dict(sorted(counts.items())), "bytes": path.stat().st_size}
    # each record's counting mode (training.record_countings): the record format has no field
    entry_path.write_text(json.dumps({"entry": entry, "failures": failures,
                                      "countings": countings}))
    return split, floor, entry, failures


def floor_jobs(config):
    """FloorJobs of the named floors and of the generated ones (their maps written first)."""
    named = [(split, floor) for split, floors in config.split.items() for floor in floors]
    jobs = [FloorJob(split, floor, Path(config.maps_dir) / f"{floor}.yaml", [config.seed, index],
                     True) for index, (split, floor) in enumerate(named)]
    generator = config.generator_config()
    for index in range(config.generated):
        name = f"gen{config.seed}_{index:03d}"
        path = Path(config.out) / "floors" / f"{name}.yaml"
        path.parent.mkdir(parents=True, exist_ok=True)
        if not (config.resume and path.is_file()):    # the floor its records were driven on
            save_map(random_floor([config.seed, 1000 + index], generator)[0], path)
        jobs.append(FloorJob("train", name, path, [config.seed, 2000 + index], False))
    return jobs


def build_dataset(config, progress=True, on_floor=None):
    """Build every floor in `config.workers` processes (a progress bar on stderr unless
    `progress` is False; `on_floor(floors done, floors, "floors")` after each floor), add the
    floors of earlier runs of `out` and write <out>/summary.yaml -> the summary
    ({record_rate, splits, failures, seconds})."""
    began = time.perf_counter()
    # record_rate: what scripts/train_semnav reads (None: every scan of the 40 Hz laser)
    summary = {"record_rate": config.record_rate or DEFAULT_RECORD_RATE, "splits": {},
               "failures": {}}
    jobs = floor_jobs(config)
    with multiprocessing.get_context("fork").Pool(config.workers) as pool, \
            tqdm(total=len(jobs), unit="floor", disable=not progress) as bar:
        for done, (split, floor, entry, failures) in enumerate(pool.imap_unordered(
                functools.partial(build_floor, config=config), jobs), 1):
            summary["splits"].setdefault(split, {})[floor] = entry
            summary["failures"][floor] = failures
            bar.set_postfix_str(f"{floor}: {entry['records']} records")
            bar.update(1)
            if on_floor:
                on_floor(done, len(jobs), "floors")
    for entry_path in sorted(Path(config.out).glob("*/*.json")):  # floors of earlier runs
        split, floor = entry_path.parent.name, entry_path.stem
        if floor not in summary["splits"].get(split, {}):
            entry, summary["failures"][floor] = read_floor_entry(entry_path)
            summary["splits"].setdefault(split, {})[floor] = entry
    summary["seconds"] = round(time.perf_counter() - began, 1)
    Path(config.out).mkdir(parents=True, exist_ok=True)   # also when no floor had corridors
    (Path(config.out) / "summary.yaml").write_text(yaml.safe_dump(summary, sort_keys=False))
    return summary


def summary_lines(summary, out):
    """The closing report: per split its records, samples, size and classes; the failures."""
    lines = []
    for split, floors in summary["splits"].items():
        per_class = Counter()
        for entry in floors.values():
            per_class.update(entry["per_class"])
        records = sum(e["records"] for e in floors.values())
        samples = sum(e["samples"] for e in floors.values())
        size = sum(e["bytes"] for e in floors.values()) / 1e6
        lines.append(f"{split} ({', '.join(floors)}): {records} records, {samples} samples, "
                     f"{size:.0f} MB; per class {dict(sorted(per_class.items()))}")
    failed = sum(len(f) for f in summary["failures"].values())
    lines.append(f"failed demonstrations (not recorded): {failed}; {summary['seconds']} s; "
                 f"written to {out}")
    return lines
