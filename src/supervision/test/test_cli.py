"""Command-line tools answer a user mistake in one line with exit status 2; bugs keep their
traceback; --debug shows it for a mistake too."""
import sys

import pytest

from supervision import cli
from supervision.config_file import ConfigError


def mistaken(argv):
    raise ConfigError("s.yaml: unknown key 'planer' (did you mean 'planner'?)")


def test_a_user_mistake_is_one_line_and_status_2(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["tools/run_scenario", "s.yaml"])
    assert cli.run(mistaken) == 2
    captured = capsys.readouterr()
    assert captured.err == ("run_scenario: error: s.yaml: unknown key 'planer' (did you mean "
                            "'planner'?)\n")
    assert captured.out == ""


def test_a_missing_input_and_a_usage_error_are_mistakes_too(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["tool"])

    def missing(argv):
        open("/nonexistent/record.json")

    def refused(argv):
        raise cli.UsageError("--run-dir /tmp holds files no run writes")

    assert cli.run(missing) == 2
    assert capsys.readouterr().err == ("tool: error: /nonexistent/record.json: no such file or "
                                       "directory\n")
    assert cli.run(refused) == 2
    assert capsys.readouterr().err == "tool: error: --run-dir /tmp holds files no run writes\n"


def test_debug_shows_the_traceback_and_is_not_passed_on(monkeypatch):
    monkeypatch.setattr(sys, "argv", ["tool", "--debug", "x"])
    seen = []
    with pytest.raises(ConfigError):
        cli.run(lambda argv: seen.append((argv, sys.argv[1:])) or mistaken(argv))
    assert seen == [(["x"], ["x"])]


def test_a_bug_keeps_its_traceback_and_the_status_passes_through(monkeypatch):
    monkeypatch.setattr(sys, "argv", ["tool"])
    with pytest.raises(ZeroDivisionError):
        cli.run(lambda argv: 1 / 0)
    assert cli.run(lambda argv: 3) == 3
