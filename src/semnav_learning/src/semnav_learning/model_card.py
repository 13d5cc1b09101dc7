"""A trained model's card: one Markdown page next to `<model>.keras` that tells where the model
comes from (the command, the commit and the date it was made, the data it was trained on) and
how it does (its evaluations, each with the command that reproduces it). The trainer's run record
(`<model>.json`: settings, monitors, chosen epoch) stays beside it; the card is the model's story.

`model_card(...)` renders the page; `recipe_card(...)` gathers the facts of a recipe unit from the
recipe's done records (`RecipeRun.install` writes it when it installs a model)."""
import os
import subprocess

SECTIONS = ("## Data", "## Evaluation")


def model_card(model, made_by, commit, date, data, evaluations, differences=""):
    """The card of `model` (file name, e.g. "default.keras") as Markdown.

    made_by: the command that made it (Markdown); data: [str] what it was trained on, one line
    each (Markdown); evaluations: [dict] with `name`,
    `episodes`, `successes` and `command`; differences: what differs from what `make train`
    makes (empty for a model the recipe installed)."""
    lines = [f"# {model}", "",
             f"- made by: {made_by}",
             f"- commit: {commit}",
             f"- date: {date}",
             f"- training record: `{model.rsplit('.', 1)[0]}.json` (settings, monitors, chosen "
             "epoch)", "", SECTIONS[0], ""]
    lines += [f"- {item}" for item in data] or ["- (none recorded)"]
    lines += ["", SECTIONS[1], ""]
    if evaluations:
        lines += ["| evaluation | goals reached | command |", "|---|---:|---|"]
        lines += [f"| {e['name']} | {e['successes']}/{e['episodes']} "
                  f"({100 * e['successes'] / e['episodes']:.1f} %) | `{e['command']}` |"
                  for e in evaluations]
    else:
        lines.append("No evaluation of the recipe evaluates this model.")
    if differences:
        lines += ["", "## How `make train` differs", "", differences.strip()]
    return "\n".join(lines) + "\n"


def source_commit(root):
    """The workspace's commit (with "+ local changes" when the tree differs from it), or
    "unknown" outside a git checkout."""
    def git(*args):
        return subprocess.run(["git", "-C", str(root), *args], capture_output=True, text=True,
                              check=True).stdout.strip()
    try:
        commit = git("rev-parse", "--short", "HEAD")
        return commit + (" + local changes" if git("status", "--porcelain", "--untracked-files=no")
                         else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


def recipe_card(recipe, unit, done, model, commit, date, inputs):
    """The card of recipe unit `unit` installed as `model`. done: {unit name: done record};
    inputs(unit) -> the names of the units it reads (recipe.unit_inputs)."""
    def shown(path):                               # workspace paths relative to it
        path = os.path.relpath(path, recipe.root)
        return path if not path.startswith("..") else os.path.abspath(recipe.root / path)

    upstream, todo = [], [unit]
    while todo:                                    # every unit the model depends on
        name = todo.pop()
        for needed in inputs(recipe.unit(name)):
            if needed not in upstream:
                upstream.append(needed)
                todo.append(needed)
    data = []
    for name in (u.name for u in recipe.units if u.name in upstream):
        kind, record = recipe.unit(name).kind, done.get(name, {})
        if kind == "build":
            data.append(f"`{name}`: dataset `{shown(record.get('dataset'))}` "
                        f"({record.get('records')} records)")
        elif kind == "dagger":
            data.append(f"`{name}`: DAgger round `{shown(record.get('records'))}` "
                        f"({record.get('states')} states of {record.get('episodes')} episodes)")
    if any(recipe.unit(name).kind == "classifier" for name in [unit, *upstream]):
        data.append("LSTM_w and Z_w: the phrase sets of `config/semnav_phrases.yaml`")
    evaluations = [{"name": u.name, "episodes": done[u.name]["episodes"],
                    "successes": done[u.name]["successes"],
                    "command": f"scripts/train_recipe --recipe {shown(recipe.path)} "
                               f"--only {u.name}"}
                   for u in recipe.units
                   if u.kind == "evaluate" and u.args["model"] == unit and u.name in done]
    return model_card(model, f"`scripts/train_recipe --recipe {shown(recipe.path)} --install`, "
                             f"unit `{unit}`", commit, date, data, evaluations)
