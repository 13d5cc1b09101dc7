"""The command lines that read a model (classify_instruction, semnav_fit_report,
mix_semnav_models) with a tiny network and synthetic words and records: what they print and
write, and their errors for bad input."""
import json
import subprocess
import sys

import numpy as np
import pytest

from semnav_learning.tools import classify_instruction, semnav_fit_report, mix_semnav_models
from semnav_train_data import write_dataset, write_words
from tamp_resources import resource

ROOT = resource()


def tiny_model(path, seed):
    """A freshly built network of a few hundred weights, saved to `path`."""
    import keras

    from semantic_nav.network import NetworkConfig, build_network
    keras.utils.set_random_seed(seed)
    build_network(NetworkConfig(word_units=4, scan_units=8, fused_units=8)).save(path)
    return path


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    folder = tmp_path_factory.mktemp("model_tools")
    return {"model": tiny_model(folder / "a.keras", 0), "other": tiny_model(folder / "b.keras", 1),
            "words": write_words(folder / "words.txt"), "data": write_dataset(folder / "data"),
            "folder": folder}


class AlwaysOne:
    """A follower whose Z_w says class 1 to every sentence with known words."""

    def start(self, text):
        from semantic_nav.follower import UnknownInstructionError
        if "gromit" in text:
            raise UnknownInstructionError("'gromit' is not a known word")
        return [1]


def test_classify_prints_classes_per_line_and_fails_on_unknown_words(capsys):
    assert classify_instruction.classify_lines(AlwaysOne(), ["go on\n", "  \n", "turn left\n"]) == 0
    assert classify_instruction.classify_lines(AlwaysOne(), ["go\n", "wallace and gromit\n"]) == 1
    assert capsys.readouterr().out.splitlines() == [
        "1", "1", "1", "unknown: 'gromit' is not a known word"]


def test_held_out_accuracy_counts_per_class(capsys):
    sets = classify_instruction.read_phrase_sets(ROOT / "config" / "semnav_phrases.yaml")
    accuracy = classify_instruction.phrasing_accuracy(AlwaysOne(), sets, "held_out", 20, 0)
    printed = capsys.readouterr().out.splitlines()
    assert accuracy == pytest.approx(0.1)     # classes in turn: class 1 is 2 of 20
    assert printed[0] == "held_out phrasings: 2/20 = 10.00% classified correctly"
    assert printed[1].startswith("per class: 1: 2/2, 2: 0/2, 3: 0/2")


def test_classify_main_on_lines_and_its_errors(tiny, tmp_path, capsys):
    argv = ["--model", str(tiny["model"]), "--words", str(tiny["words"])]
    status = classify_instruction.main(argv=argv, lines=["turn left\n", "zzyzx\n"])
    printed = capsys.readouterr().out.splitlines()
    assert status == 1 and printed[1].startswith("unknown: ")
    assert all(int(c.split(":")[0]) in range(1, 11) for c in printed[0].split())
    (tmp_path / "bad.yaml").write_text("[unclosed")
    with pytest.raises(SystemExit, match="classify_instruction: --phrases .*bad.yaml"):
        classify_instruction.main(argv=[*argv, "--held-out", "5", "--phrases",
                                      str(tmp_path / "bad.yaml")])
    with pytest.raises(SystemExit, match="make train"):
        classify_instruction.main(argv=["--model", str(tmp_path / "none.keras")], lines=[])


def test_blind_set_through_main_prints_the_score_and_names_a_bad_file(tiny, tmp_path, capsys):
    argv = ["--model", str(tiny["model"]), "--words", str(tiny["words"])]
    blind = tmp_path / "blind.yaml"
    blind.write_text("entries: [{text: turn left, classes: [3]}, {text: zzyzx, classes: [1]}]")
    assert classify_instruction.main(argv=[*argv, "--blind", str(blind)]) == 0
    printed = capsys.readouterr().out.splitlines()
    assert printed[0].startswith("blind set: ") and "/2 = " in printed[0]
    assert any("'zzyzx': meant 1, read refused" in line for line in printed)
    blind.write_text("entries: [{text: go}]")
    with pytest.raises(SystemExit, match="--blind: .*blind.yaml: entries.0..classes"):
        classify_instruction.main(argv=[*argv, "--blind", str(blind)])


def test_a_reader_that_stops_early_ends_the_run_quietly(tiny, tmp_path):
    """`classify_instruction --blind FILE | head -1`: the score line, no traceback, status 0."""
    blind = tmp_path / "blind.yaml"
    blind.write_text("entries: [" + ", ".join(f"{{text: turn left {k}, classes: [1]}}"
                                              for k in range(400)) + "]")
    script = tmp_path / "classify_instruction"
    script.write_text("import sys\nfrom semnav_learning.tools.classify_instruction import main\n"
                      "sys.exit(main(argv=sys.argv[1:]))\n")
    command = (f"set -o pipefail; {sys.executable} {script} --model {tiny['model']} --words "
               f"{tiny['words']} --blind {blind} | head -1")
    done = subprocess.run(["bash", "-c", command], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("blind set: ") and len(done.stdout.splitlines()) == 1
    assert "Traceback" not in done.stderr and "BrokenPipe" not in done.stderr


def test_fit_report_has_a_row_per_turning_class(tiny, capsys):
    assert semnav_fit_report.main(argv=[
        "--model", str(tiny["model"]), "--dataset", str(tiny["data"]), "--words",
        str(tiny["words"]), "--cache", str(tiny["folder"] / "cache"), "--classes", "1", "2",
        "--threshold", "0.3"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith(f"model {tiny['model']}; train records of {tiny['data']}")
    assert lines[1] == ("| class | records with a turn | turning-step MSE(ω) | on time | early | "
                        "late | never |")
    # class 1 never turns (left out), class 3 not asked for; class 2's 3 records all turn
    rows = [line.split(" | ") for line in lines[3:]]
    assert [row[0] for row in rows] == ["| 2"] and rows[0][1] == "3"
    shares = [int(cell.strip(" |%")) for cell in rows[0][3:]]
    assert sum(shares) in (99, 100, 101)


def test_fit_report_without_records_names_the_split(tiny):
    with pytest.raises(SystemExit, match="no records in the 'test' split of .*data: run "
                                         "scripts/build_semnav_dataset"):
        semnav_fit_report.main(argv=["--model", str(tiny["model"]), "--dataset",
                                        str(tiny["data"]), "--split", "test"])


def test_mix_interpolates_every_layer_and_writes_a_card(tiny, tmp_path, capsys):
    from semantic_nav.network import load_network
    out = tmp_path / "mixed" / "m.keras"
    assert mix_semnav_models.main(["--base", str(tiny["model"]), "--tuned", str(tiny["other"]),
                                   "--alpha", "0.25", "--out", str(out)]) == 0
    base, tuned, mixed = (load_network(p) for p in (tiny["model"], tiny["other"], out))
    for layer in mixed.layers:
        for m, a, b in zip(layer.get_weights(), base.get_layer(layer.name).get_weights(),
                           tuned.get_layer(layer.name).get_weights()):
            np.testing.assert_allclose(m, 0.75 * a + 0.25 * b, rtol=1e-5, atol=1e-6)
    card = json.loads(out.with_suffix(".json").read_text())
    assert card["alpha"] == 0.25 and card["base"]["path"] == str(tiny["model"])
    assert card["tuned"]["sha256"] == mix_semnav_models.sha256_of(tiny["other"])
    assert card["command"].startswith("mix_semnav_models --base ")
    assert capsys.readouterr().out.strip() == (
        f"mix_semnav_models: {out} = 0.75 x {tiny['model']} + 0.25 x {tiny['other']}")


def test_mix_refuses_missing_files_other_shapes_and_a_bad_alpha(tiny, tmp_path):
    out = str(tmp_path / "m.keras")
    with pytest.raises(SystemExit, match="no model file .*none.keras"):
        mix_semnav_models.main(["--base", str(tmp_path / "none.keras"), "--tuned",
                                str(tiny["model"]), "--out", out])
    with pytest.raises(SystemExit, match="alpha must lie in"):
        mix_semnav_models.main(["--base", str(tiny["model"]), "--tuned", str(tiny["other"]),
                                "--alpha", "1.5", "--out", out])
    wide = tmp_path / "wide.keras"
    import keras

    from semantic_nav.network import NetworkConfig, build_network
    keras.utils.set_random_seed(2)
    build_network(NetworkConfig(word_units=4, scan_units=16, fused_units=8)).save(wide)
    with pytest.raises(SystemExit, match=r"a.keras and .*wide.keras: layer '\w+': weight shapes"):
        mix_semnav_models.main(["--base", str(tiny["model"]), "--tuned", str(wide), "--out", out])
    assert not (tmp_path / "m.keras").exists()


class CountingFive(AlwaysOne):
    """Reads every sentence as "go straight" then class 5, counting one side when it says so."""

    def start(self, text):
        self.countings = ["corners", "side" if "second right" in text else "corners"]
        return [1, 5]


def test_classify_prints_how_a_counted_class_counts(capsys):
    lines = ["go on then take the second right\n", "go on then right at corner two\n"]
    assert classify_instruction.classify_lines(CountingFive(), lines) == 0
    assert capsys.readouterr().out.splitlines() == ["1 5:side", "1 5:corners"]
