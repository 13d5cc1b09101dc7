"""build_semnav_dataset as a library (dataset_build, tools.build_semnav_dataset): a tiny build of
the L floor with the URG-04LX Penguin writes records, entries and summary that agree; --resume
keeps finished floors; a floor without corridors is an error entry, not a crash; bad --split
values exit."""
import json

import numpy as np
import pytest
import yaml

from floorplan.occupancy_map import OccupancyMap, save_map
from penguin_base.record_format import read_records
from semnav_learning.dataset_build import (DatasetConfig, build_dataset, floor_jobs,
                                           parse_split, summary_lines)
from semnav_learning.tools.build_semnav_dataset import argument_parser, main
from semnav_l_floor import write_l_floor
from tamp_resources import resource

URG_WORLD = resource("config", "worlds", "office_penguin_urg.yaml")   # march: no table cached


def tiny_config(folder, **fields):
    """The L floor alone in the training split, classes 1 (straight) and 4 (turn around)."""
    return DatasetConfig(**{"world": URG_WORLD, "maps_dir": folder, "out": folder / "ds",
                            "split": {"train": ["l_floor"]}, "classes": [1, 4], "per_class": 1,
                            "candidates": 12, "record_rate": 10.0, "workers": 1, **fields})


@pytest.fixture(scope="module")
def tiny_build(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dataset")
    write_l_floor(folder)
    return folder, build_dataset(tiny_config(folder), progress=False)


def test_a_tiny_build_writes_records_entry_and_summary_that_agree(tiny_build):
    folder, summary = tiny_build
    entry = summary["splits"]["train"]["l_floor"]
    records = read_records(folder / "ds" / "train" / "l_floor.records")
    assert entry["per_class"] == {1: 1, 4: 1} and summary["failures"]["l_floor"] == []
    assert sorted(r.instruction_class for r in records) == [1, 4]
    assert entry["records"] == 2 and entry["samples"] == sum(len(r.samples) for r in records)
    # 10 Hz records: a few metres at <= 0.4 m/s is tens of scans, not the laser's every scan
    assert all(10 <= len(r.samples) <= 400 for r in records)
    assert entry["bytes"] == (folder / "ds" / "train" / "l_floor.records").stat().st_size
    saved = yaml.safe_load((folder / "ds" / "summary.yaml").read_text())
    assert saved["record_rate"] == 10.0 and saved["splits"] == summary["splits"]
    lines = summary_lines(summary, folder / "ds")
    assert lines[0].startswith(f"train (l_floor): 2 records, {entry['samples']} samples, ")
    assert lines[0].endswith("per class {1: 1, 4: 1}")
    assert lines[1].startswith("failed demonstrations (not recorded): 0; ")


def test_resume_keeps_a_finished_floor_and_adds_earlier_floors(tiny_build):
    folder, summary = tiny_build
    records = folder / "ds" / "train" / "l_floor.records"
    written = records.stat().st_mtime_ns
    # another split this time (turning around: a short drive): the finished l_floor is read
    # back from its entry, not rebuilt
    again = build_dataset(tiny_config(folder, split={"validation": ["l_floor"]}, resume=True,
                                      classes=[4]), progress=False)
    assert again["splits"]["validation"]["l_floor"]["per_class"] == {4: 1}
    assert again["splits"]["train"]["l_floor"] == summary["splits"]["train"]["l_floor"]
    assert records.stat().st_mtime_ns == written


def test_a_floor_without_corridors_is_an_error_entry(tmp_path):
    save_map(OccupancyMap(np.full((40, 40), 100, np.int8), 0.05, (0.0, 0.0, 0.0)),
             tmp_path / "solid.yaml")
    summary = build_dataset(tiny_config(tmp_path, split={"train": ["solid"]}), progress=False)
    entry = summary["splits"]["train"]["solid"]
    assert entry["records"] == 0 and entry["error"]


def test_floor_jobs_seed_each_floor_and_write_generated_maps_once(tmp_path):
    config = tiny_config(tmp_path, split={"train": ["a", "b"], "test": ["c"]}, generated=2,
                         seed=7, width=(14.0, 16.0), depth=(12.0, 14.0), corridors=(1, 2))
    jobs = floor_jobs(config)
    assert [(j.split, j.floor, j.seed, j.cache_tables) for j in jobs] == [
        ("train", "a", [7, 0], True), ("train", "b", [7, 1], True), ("test", "c", [7, 2], True),
        ("train", "gen7_000", [7, 2000], False), ("train", "gen7_001", [7, 2001], False)]
    generated = tmp_path / "ds" / "floors" / "gen7_001.yaml"
    assert jobs[4].map_path == generated and jobs[0].map_path == tmp_path / "a.yaml"
    first = generated.stat().st_mtime_ns
    floor_jobs(DatasetConfig(**{**vars(config), "resume": True}))
    assert generated.stat().st_mtime_ns == first


def test_split_values():
    assert parse_split("train=a,b test=c") == {"train": ["a", "b"], "test": ["c"]}
    with pytest.raises(ValueError, match="expected name=floor"):
        parse_split("train=a validation")
    with pytest.raises(SystemExit, match="--split: expected name=floor.*'test'"):
        argument_parser(resource()).parse_args(["--split", "test"])


def test_main_prints_the_summary(tiny_build, tmp_path, capsys):
    folder, _ = tiny_build
    out = tmp_path / "copy"
    (out / "train").mkdir(parents=True)
    entry = folder / "ds" / "train" / "l_floor.json"
    (out / "train" / "l_floor.json").write_text(entry.read_text())
    # every floor of the split already finished: --resume only reads entries back
    assert main(argv=["--world", str(URG_WORLD), "--split", "train=l_floor", "--resume",
                      "--workers", "1", "--out", str(out)], progress=False) == 0
    printed = capsys.readouterr().out.splitlines()
    samples = json.loads(entry.read_text())["entry"]["samples"]
    assert printed[0].startswith(f"train (l_floor): 2 records, {samples} samples")
    assert printed[1].endswith(f"written to {out}")
