"""Model cards (semnav_learning.model_card): the page renders its facts, and every committed model
has exactly one card, in the format the recipe writes, that says where it comes from."""
import json
import re
import subprocess

from semnav_learning.model_card import SECTIONS, model_card, source_commit
from tamp_resources import resource

MODELS = resource("models", "semantic_nav")


def test_the_card_renders_command_commit_date_data_and_evaluations():
    card = model_card("default.keras", "`scripts/train_recipe --install`, unit `default_zw`",
                      "abc1234", "2026-11-29", ["`handmade10`: dataset d (7 records)"],
                      [{"name": "eval_recipe", "episodes": 1000, "successes": 987,
                        "command": "scripts/train_recipe --only eval_recipe"}])
    assert card.splitlines()[:6] == [
        "# default.keras", "",
        "- made by: `scripts/train_recipe --install`, unit `default_zw`",
        "- commit: abc1234", "- date: 2026-11-29",
        "- training record: `default.json` (settings, monitors, chosen epoch)"]
    assert "## Data\n\n- `handmade10`: dataset d (7 records)\n" in card
    assert ("| eval_recipe | 987/1000 (98.7 %) | `scripts/train_recipe --only eval_recipe` |"
            in card)
    assert "make train` differs" not in card


def test_a_card_without_evaluations_or_data_says_so_and_names_differences():
    card = model_card("bc.keras", "c", "x", "d", [], [], differences="Trained on 3 floors.")
    assert "- (none recorded)" in card
    assert "No evaluation of the recipe evaluates this model." in card
    assert card.endswith("## How `make train` differs\n\nTrained on 3 floors.\n")


def test_source_commit_names_the_commit_or_says_it_is_unknown(tmp_path):
    assert source_commit(tmp_path) == "unknown (not a git checkout)"
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    (tmp_path / "f").write_text("1")
    git = ["git", "-C", str(tmp_path), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "add", "f"], check=True)
    subprocess.run([*git, "commit", "-qm", "f"], check=True)
    head = subprocess.run([*git, "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True, check=True).stdout.strip()
    assert source_commit(tmp_path) == head
    (tmp_path / "f").write_text("2")
    assert source_commit(tmp_path) == f"{head} + local changes"


def test_every_committed_model_has_one_card_in_the_recipe_format():
    models = sorted(p.stem for p in MODELS.glob("*.keras"))
    assert models == ["bc", "counting", "default"]
    for name in models:
        card = (MODELS / f"{name}.md").read_text()
        assert card.startswith(f"# {name}.keras\n"), name
        for field in ("made by: `scripts/", "commit: ", "date: ",
                      f"training record: `{name}.json`"):
            assert re.search(rf"^- {re.escape(field)}", card, re.M), (name, field)
        assert all(f"\n{section}\n" in card for section in SECTIONS), name
        # bc and default do not come from the recipe as it stands: their cards say what make
        # train does instead; counting.keras is the recipe's counting_aggregate
        assert ("\n## How `make train` differs\n" in card) == (name != "counting"), name
    # the training record holds settings and monitors, not the model's story
    for name in models:
        assert "note" not in json.loads((MODELS / f"{name}.json").read_text()), name
