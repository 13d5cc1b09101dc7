"""tamp_resources: its files through rospkg, and the workspace of a command from $TAMP_WS."""
import pytest

from tamp_resources import resource, workspace


def test_resource_names_a_file_of_the_package():
    assert resource("config", "task_planner.yaml").is_file()
    assert resource("maps").is_dir() and resource().name == "tamp_resources"


def test_the_workspace_is_tamp_ws(monkeypatch, tmp_path):
    monkeypatch.setenv("TAMP_WS", str(tmp_path))
    assert workspace() == tmp_path


def test_without_tamp_ws_the_workspace_is_an_error_naming_it(monkeypatch):
    monkeypatch.delenv("TAMP_WS", raising=False)
    with pytest.raises(RuntimeError, match="TAMP_WS is not set.*scripts/env.sh"):
        workspace()
