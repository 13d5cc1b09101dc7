"""The one loader of the YAML files users write (scenarios, household, worlds, follower, planner,
recipe): read, parse and key checks whose errors name the file, the field and what was wrong.

    data = read_yaml(path)                                   # ConfigError on a missing or
                                                             # unparsable file, one line
    check_keys(data, ("world", "graph"), f"{path}: requests[2]")
    # ConfigError "scenarios/s.yaml: requests[2]: unknown key 'planer' (did you mean 'planner'?)"

Each loader's own error (WorldError, SettingsError, ...) subclasses ConfigError, so a command-line
tool answers every config mistake the same way (`supervision.cli`).
"""
import difflib
from pathlib import Path

import yaml


class ConfigError(ValueError):
    """A config file that cannot be used; the message names the file, the field and the fault."""


def unknown_key_message(key, allowed):
    """"unknown key 'raduis' (did you mean 'radius'?)": the nearest valid key, or the list."""
    allowed = [str(name) for name in allowed]
    near = difflib.get_close_matches(str(key), allowed, n=1)
    hint = f"did you mean {near[0]!r}?" if near else f"valid keys: {', '.join(allowed)}"
    return f"unknown key {key!r} ({hint})"


def check_keys(data, allowed, where, error=ConfigError):
    """Raise `error` "<where>: unknown key ..." for the first key of mapping `data` not in
    `allowed`, or "<where>: expected a mapping" when `data` is not one. `where` names the file
    and the field path (e.g. "worlds/w.yaml: people[2]")."""
    if not isinstance(data, dict):
        raise error(f"{where}: expected a mapping, got {data!r}")
    for key in data:
        if key not in allowed:
            raise error(f"{where}: {unknown_key_message(key, allowed)}")
    return data


def read_yaml(path, error=ConfigError, what="file"):
    """The parsed YAML document at `path`. A missing or unreadable file or broken YAML raises
    `error` in one line: "<path>: no such <what>" or "<path>: not valid YAML (line 3, column 7:
    could not find expected ':')"."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: no such {what}") from None
    except (OSError, UnicodeDecodeError) as problem:
        raise error(f"{path}: cannot read the {what}: {problem}") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as problem:
        raise error(f"{path}: not valid YAML ({yaml_problem(problem)})") from None


def yaml_problem(problem):
    """A YAML parser error in one line: where (1-based line and column) and what."""
    mark = getattr(problem, "problem_mark", None)
    what = getattr(problem, "problem", None) or str(problem).splitlines()[0]
    if mark is None:
        return what
    return f"line {mark.line + 1}, column {mark.column + 1}: {what}"


def find_file(name, near, *fallbacks):
    """The path a config file names: absolute as given; relative, the first of `near` (the
    folder of the file that names it) and `fallbacks` (e.g. the workspace's resources) that
    holds it. None when none does (the caller names what is missing and where it looked)."""
    name = Path(name)
    if name.is_absolute():
        return name if name.exists() else None
    for folder in (near, *fallbacks):
        candidate = Path(folder) / name
        if candidate.exists():
            return candidate.resolve()
    return None
