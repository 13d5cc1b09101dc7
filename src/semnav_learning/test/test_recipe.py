"""The training recipe (semnav_learning.recipe) on a tiny recipe of the L floor: its units run in
order through the library, a rerun skips the done ones, nothing is written outside the work
directory without --install and --install copies the models and writes their cards, progress lines
carry elapsed times and ETAs, and a malformed recipe is refused naming its key."""
import json
import re

import pytest
import yaml
from penguin_base.record_format import read_records

from semnav_learning.recipe import (RecipeError, RecipeRun, Schedule, Unit, UnitProgress,
                                    unit_inputs,
                                    load_recipe)
from semnav_learning.tools.train_recipe import main
from semnav_learning.recipe_format import RESUME_LINE
from semnav_l_floor import write_l_floor
from semnav_train_data import write_words
from tamp_resources import resource

ROOT = resource()
URG_WORLD = ROOT / "config" / "worlds" / "office_penguin_urg.yaml"
UNITS = ["l_records", "l_plan", "tiny_bc", "tiny_tuned", "tiny_dagger", "tiny_zw", "tiny_eval"]


def tiny_recipe(folder):
    """A recipe of seconds: L-floor records, a plan, two short trainings, a DAgger episode, Z_w
    retraining and one evaluated episode; every path inside `folder`."""
    maps = folder / "maps"
    maps.mkdir(parents=True, exist_ok=True)
    write_l_floor(maps)
    recipe = {
        "work_dir": str(folder / "work"), "world": str(URG_WORLD), "maps_dir": str(maps),
        "install_dir": str(folder / "installed"), "words": str(write_words(folder / "words.txt")),
        "threads": 1, "install": {"tiny": "tiny_zw"},
        "training": {"epochs": 2, "batch_size": 4, "hold_steps": 10, "class_batches": 1,
                     "class_batch_size": 16, "class_warmup_batches": 5,
                     "class_monitor_every": 2, "class_monitor_size": 30},
        "network": {"word_units": 4, "scan_units": 8, "fused_units": 8, "learning_rate": 0.01},
        "stages": [
            {"name": "datasets", "units": [
                {"name": "l_records", "minutes": 0.2,
                 "build": {"split": {"train": ["l_floor"], "validation": ["l_floor"]},
                           "classes": [4], "per_class": 1, "candidates": 12,  # turn around
                           "record_rate": 10, "workers": 1}},
                {"name": "l_plan", "minutes": 0.05,
                 "plan": {"floors": ["l_floor"], "per_class": 1, "classes": [1]}}]},
            {"name": "seed_faithful", "units": [
                {"name": "tiny_bc", "minutes": 0.2,
                 "train": {"dataset": ["l_records"], "laser": "urg04lx"}}]},
            {"name": "default", "units": [
                {"name": "tiny_tuned", "minutes": 0.2,
                 "train": {"dataset": ["l_records"], "laser": "urg04lx", "init": "tiny_bc",
                           "stop_head": True, "training": {"epochs": 1}}},
                {"name": "tiny_dagger", "minutes": 0.2,
                 "dagger": {"model": "tiny_tuned", "floors": ["l_floor"], "per_class": 1,
                            "classes": [4],           # turn around: at most 30 s
                            "follower_config": "config/semnav_follower_no_guard.yaml"}},
                {"name": "tiny_zw", "minutes": 0.05,
                 "classifier": {"init": "tiny_tuned", "batches": 2}}]},
            {"name": "evaluation", "units": [
                {"name": "tiny_eval", "minutes": 0.2,
                 "evaluate": {"model": "tiny_zw", "plan": "l_one", "floors": ["l_floor"],
                              "per_class": 1, "classes": [1], "laser": "urg04lx",
                              "workers": 1,
                              "follower_config": "config/semnav_follower_no_guard.yaml"}}]}]}
    path = folder / "recipe.yaml"
    path.write_text(yaml.safe_dump(recipe))
    return path


def files_under(folder):
    return {p: p.stat().st_mtime_ns for p in folder.rglob("*") if p.is_file()}


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("recipe")
    path = tiny_recipe(folder)
    before = files_under(folder)
    lines = []
    done = RecipeRun(load_recipe(path, ROOT), report=lines.append).run()
    return folder, path, before, lines, done


def test_the_units_run_in_order_and_write_their_outputs(first_run):
    folder, _, _, lines, done = first_run
    started = [m[1] for m in (re.match(r"\[\d+/7\] \w+/(\w+) \(\w+\): started", line)
                              for line in lines) if m]
    assert started == UNITS and list(done) == UNITS
    work = folder / "work"
    assert (work / "datasets" / "l_records" / "train" / "l_floor.records").stat().st_size > 0
    assert json.loads((work / "plans" / "l_plan.json").read_text())[0]["labels"] == [1]
    for model in ("tiny_bc", "tiny_tuned", "tiny_zw"):
        assert (work / "models" / f"{model}.keras").stat().st_size > 0, model
        assert (work / "models" / f"{model}.json").is_file(), model
    assert done["tiny_dagger"]["episodes"] == 1
    assert (work / "dagger" / "tiny_dagger.records").is_file()
    # each sequence's counting mode beside the records (class 4 counts nothing: corners)
    assert json.loads((work / "dagger" / "tiny_dagger.json").read_text()) == {
        "countings": ["corners"] * len(read_records(work / "dagger" / "tiny_dagger.records"))}
    assert done["tiny_eval"]["episodes"] == 1 and done["tiny_eval"]["successes"] in (0, 1)
    followed = json.loads((work / "eval" / "tiny_eval.json").read_text())["args"]
    assert followed["follower_config"] == str(ROOT / "config" / "semnav_follower_no_guard.yaml")
    assert (work / "eval" / "summary.md").read_text().splitlines()[2].startswith(
        f"| tiny_eval | tiny_zw | {done['tiny_eval']['successes']}/1 | ")
    # the fine-tune started from tiny_bc: its card names that init
    card = json.loads((work / "models" / "tiny_tuned.json").read_text())
    assert card["args"]["init"] == str(work / "models" / "tiny_bc.keras")
    assert card["args"]["stop_head"] and card["training"]["epochs"] == 1


def test_nothing_is_written_outside_the_work_dir_without_install(first_run):
    folder, _, before, _, _ = first_run
    work = folder / "work"
    after = {p: t for p, t in files_under(folder).items() if work not in p.parents}
    assert after == before
    assert not (folder / "installed").exists()


def test_progress_lines_carry_elapsed_time_and_etas(first_run):
    lines = first_run[3]
    assert lines[0].startswith("recipe recipe.yaml: 7 units, 0 done earlier; estimate 1 min 06 s")
    epochs = [line for line in lines if re.match(r"\[3/7\] seed_faithful/tiny_bc: \d/2 epochs, ",
                                                 line)]
    assert len(epochs) == 2 and all(", unit ETA " in line and ", recipe ETA " in line
                                    for line in epochs)
    assert any(re.match(r"\[1/7\] datasets/l_records: 2/2 floors, .* elapsed, unit ETA 0.0 s",
                        line) for line in lines)
    assert any(line.startswith("[5/7] default/tiny_dagger: 1/1 episodes") for line in lines)
    assert any(line.startswith("[6/7] default/tiny_zw: 2/2 Z_w batches, ") for line in lines)
    ends = [line for line in lines if re.match(r"\[\d/7\] \S+: done in .* \(estimate ", line)]
    assert len(ends) == 7 and ends[-1].endswith("ETA 0.0 s")


def test_a_rerun_skips_the_done_units(first_run):
    folder, path, _, _, done = first_run
    models = files_under(folder / "work" / "models")
    lines = []
    again = RecipeRun(load_recipe(path, ROOT), report=lines.append).run()
    assert lines[0].endswith("7 units, 7 done earlier; estimate 0.0 s; work directory "
                             f"{folder / 'work'}")
    assert sum(line.endswith("skipped") for line in lines) == 7 and len(lines) == 8
    assert again == done and files_under(folder / "work" / "models") == models


def test_only_runs_the_named_units_and_install_copies_with_cards(first_run, capsys):
    folder, path, _, _, _ = first_run
    (folder / "work" / "done" / "l_plan.json").unlink()      # as if never run
    assert main(argv=["--recipe", str(path), "--only", "l_plan", "--install"]) == 0
    printed = capsys.readouterr().out
    assert "[1/1] datasets/l_plan (plan): started" in printed
    installed = folder / "installed" / "tiny.keras"
    assert installed.read_bytes() == (folder / "work" / "models" / "tiny_zw.keras").read_bytes()
    record = json.loads(installed.with_suffix(".json").read_text())
    assert record["recipe"] == str(path) and record["recipe_unit"] == "tiny_zw"
    assert record["retrain_classifier"] == 2
    # the card: the recipe's command, the data of every unit the model depends on (tiny_zw <-
    # tiny_tuned <- l_records, tiny_bc; tiny_dagger is not among them), its evaluation
    card = installed.with_suffix(".md").read_text()
    assert card.startswith("# tiny.keras\n")
    assert f"- made by: `scripts/train_recipe --recipe {path} --install`, unit `tiny_zw`" in card
    assert re.search(r"^- date: \d{4}-\d\d-\d\d$", card, re.M)
    records = json.loads((folder / "work" / "done" / "l_records.json").read_text())["records"]
    assert (f"- `l_records`: dataset `{folder / 'work' / 'datasets' / 'l_records'}` "
            f"({records} records)") in card
    assert "tiny_dagger" not in card
    assert "- LSTM_w and Z_w: the phrase sets of `config/semnav_phrases.yaml`" in card
    successes = json.loads((folder / "work" / "done" / "tiny_eval.json").read_text())["successes"]
    assert (f"| tiny_eval | {successes}/1 ({100.0 * successes:.1f} %) | "
            f"`scripts/train_recipe --recipe {path} --only tiny_eval` |") in card


def test_install_copies_the_models_whose_units_ran_and_names_the_others(first_run, tmp_path):
    folder, path, _, _, _ = first_run
    recipe = yaml.safe_load(path.read_text())
    recipe["install"]["other"] = "tiny_tuned"
    recipe["install_dir"] = str(tmp_path / "installed")
    lines = []
    run = RecipeRun(load_recipe(write(folder, recipe), ROOT), report=lines.append)
    (folder / "work" / "done" / "tiny_tuned.json").rename(tmp_path / "tiny_tuned.json")
    try:
        assert run.install() == [tmp_path / "installed" / "tiny.keras"]
        assert "not installed: other (unit tiny_tuned has not run yet)" in lines
        recipe["install"] = {"other": "tiny_tuned"}
        with pytest.raises(RecipeError, match="none of the models' units \\(tiny_tuned\\)"):
            RecipeRun(load_recipe(write(folder, recipe), ROOT), report=print).install()
    finally:
        (tmp_path / "tiny_tuned.json").rename(folder / "work" / "done" / "tiny_tuned.json")


def test_only_refuses_a_unit_whose_inputs_have_not_run(tmp_path):
    path = tiny_recipe(tmp_path)
    with pytest.raises(RecipeError, match="unit tiny_bc needs l_records, which has not run"):
        RecipeRun(load_recipe(path, ROOT), report=lambda line: None).run(["seed_faithful"])
    assert not (tmp_path / "work" / "train").exists()
    with pytest.raises(RecipeError, match="--only nothing: no such stage or unit"):
        RecipeRun(load_recipe(path, ROOT), report=lambda line: None).run(["nothing"])


def test_the_schedule_scales_the_estimates_by_measured_time():
    now = [0.0]
    units = [Unit("s", name, "build", minutes, {}) for name, minutes in
             (("a", 1.0), ("b", 2.0), ("c", 3.0))]
    schedule = Schedule(units, done={}, clock=lambda: now[0])
    assert schedule.eta() == 360.0
    schedule.finished("a", 120.0)                          # twice the estimate
    assert schedule.ratio() == 2.0 and schedule.eta() == 600.0
    assert schedule.eta("b", 30.0) == 30.0 + 360.0


def test_a_resumed_unit_paces_its_eta_by_the_parts_of_this_run():
    now, lines = [100.0], []
    units = [Unit("s", "train", "train", 10.0, {})]
    progress = UnitProgress("[1/1] s/train", "train", Schedule(units, {}, lambda: now[0]),
                            lines.append)
    progress.resumed(10)                                   # 10 of 30 epochs done earlier
    now[0] += 60.0
    progress(11, 30, "epochs")                             # one epoch in 60 s: 19 left
    assert lines[-1] == ("[1/1] s/train: 11/30 epochs, 1 min 00 s elapsed, "
                         "unit ETA 19 min 00 s, recipe ETA 19 min 00 s")
    # the Trainer's line (test_trainer checks its wording) that calls resumed()
    assert RESUME_LINE.match("resuming after epoch 10/30 from work/checkpoint")[1] == "10"


def write(folder, recipe):
    path = folder / "bad.yaml"
    path.write_text(yaml.safe_dump(recipe))
    return path


@pytest.mark.parametrize("change, message", [
    (lambda r: r["stages"][1]["units"][0]["train"].update(epoch=3),
     r"stages\[1\]\.units\[0\]\.train\.epoch: unknown key 'epoch' \(did you mean 'epochs'\?\)"),
    (lambda r: r["stages"][0]["units"][0]["build"].update(per_klass=3),
     r"stages\[0\]\.units\[0\]\.build\.per_klass: unknown key"),
    (lambda r: r["stages"][1]["units"][0]["train"].update(dataset=["nowhere"]),
     r"stages\[1\]\.units\[0\]\.train\.dataset: 'nowhere' is not an earlier unit"),
    (lambda r: r["stages"][2]["units"][2]["classifier"].pop("batches"),
     r"stages\[2\]\.units\[2\]\.classifier\.batches: missing"),
    (lambda r: r["stages"][0]["units"][0].update(minutes="soon"),
     r"stages\[0\]\.units\[0\]\.minutes: expected a number"),
    (lambda r: r["network"].update(fused=3), r"\.network\.fused: unknown key"),
    (lambda r: r.update(install={"tiny": "l_plan"}), r"install\.tiny: 'l_plan' is no training"),
    (lambda r: r.pop("work_dir"), r"work_dir: missing"),
])
def test_a_malformed_recipe_is_refused_naming_the_key(tmp_path, change, message):
    recipe = yaml.safe_load(tiny_recipe(tmp_path).read_text())
    change(recipe)
    with pytest.raises(RecipeError, match=message):
        load_recipe(write(tmp_path, recipe), ROOT)


def test_the_command_line_exits_naming_the_key(tmp_path):
    recipe = yaml.safe_load(tiny_recipe(tmp_path).read_text())
    recipe["stages"][0]["units"][1]["plan"]["floor"] = ["x"]
    with pytest.raises(SystemExit, match=r"train_recipe: .*plan\.floor: unknown key"):
        main(argv=["--recipe", str(write(tmp_path, recipe))])


def test_the_workspace_recipe_loads():
    recipe = load_recipe(ROOT / "config" / "semnav_recipe.yaml", ROOT)
    assert recipe.stages() == ["datasets", "seed_faithful", "default", "learned_counting",
                               "evaluation"]
    assert recipe.install == {"bc": "bc", "default": "default_zw",
                              "counting": "counting_aggregate"}
    scratch = recipe.unit("default_scratch").args
    assert scratch["stop_head"] and scratch["decision_head"] and scratch["count_input"]
    assert scratch["door_width"] == 1.4 and scratch["mirror"] == 0.5 and "init" not in scratch
    assert recipe.unit("default_aggregate").args["init"] == "default_scratch"
    assert not any(u.kind in ("train", "dagger") and "office_ring" in str(u.args)
                   for u in recipe.units)
    learned = recipe.unit("counting_learned").args      # a committed model as its init
    assert learned["count_head"] and "count_input" not in learned
    assert learned["init"] == "models/semantic_nav/default.keras"
    # --only counting_learned needs its datasets and plans, not a unit named after the model
    needs = unit_inputs(recipe.unit("counting_learned"), recipe)
    assert "side_counts" in needs and "plan_long" in needs and not any(
        name.endswith(".keras") for name in needs)
    assert recipe.unit("side_counts").args["side_counting"] > 0
    # the DAgger round aimed at counting drives the network with no counter, half on one side,
    # on training floors only, and its states feed the installed fine-tune
    dagger = recipe.unit("counting_dagger").args
    assert dagger["side_share"] == 0.5 and dagger["classes"] == [5, 6, 7, 8]
    assert dagger["follower_config"] == "config/semnav_follower_no_count.yaml"
    assert all(f.split(":")[0] in recipe.unit("counting_learned").args["dataset"]
               for f in dagger["floors"])
    assert recipe.unit("counting_aggregate").args["dagger_records"] == ["counting_dagger"]


def test_sigterm_stops_the_run_but_only_ends_a_pool_worker():
    import multiprocessing
    import signal
    from semnav_learning.tools.train_recipe import _interrupt
    with pytest.raises(KeyboardInterrupt):
        _interrupt(signal.SIGTERM, None)
    worker = multiprocessing.get_context("fork").Process(target=_interrupt,
                                                          args=(signal.SIGTERM, None))
    worker.start()
    worker.join(10)
    assert worker.exitcode == 128 + signal.SIGTERM           # no traceback, no KeyboardInterrupt
