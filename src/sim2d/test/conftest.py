"""Shared fixtures: a synthetic room map written in map_server format."""
import pytest
from sim2d_fixtures import room_grid

from floorplan.occupancy_map import save_map


@pytest.fixture
def room_map(tmp_path):
    path = tmp_path / "room.yaml"
    save_map(room_grid(), path)
    return path
