"""Where the workspace's shared data lives: `resource("config", "task_planner.yaml")` is that file
of the tamp_resources package, found through rospkg as `$(find tamp_resources)` is in a launch file,
so a package finds it in a source, devel or install space alike. `workspace()` is the workspace a
command runs in (where its outputs go by default: build/, docs/), named by scripts/env.sh."""
import functools
import os
from pathlib import Path

import rospkg

PACKAGE = "tamp_resources"


@functools.lru_cache(maxsize=1)
def root():
    """The tamp_resources package directory (it holds config/, maps/ and models/)."""
    try:
        return Path(rospkg.RosPack().get_path(PACKAGE))
    except rospkg.ResourceNotFound as error:
        raise RuntimeError(f"ROS package {PACKAGE} not found on ROS_PACKAGE_PATH; source "
                           "scripts/env.sh (or the workspace's devel/setup.bash) first") from error


def resource(*parts):
    """Path of a file or folder of the tamp_resources package, e.g. ("maps", "household.yaml")."""
    return root().joinpath(*parts)


def workspace():
    """The workspace a command runs in ($TAMP_WS, exported by scripts/env.sh): the one place a
    tool's default outputs (build/..., docs/...) and workspace-relative paths are taken from."""
    named = os.environ.get("TAMP_WS")
    if not named:
        raise RuntimeError("TAMP_WS is not set, so the workspace for outputs is unknown; source "
                           "scripts/env.sh first")
    return Path(named)
