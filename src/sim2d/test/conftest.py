"""Shared fixtures: a synthetic room map written in map_server format; worlds whose range tables
fill lazily and are shared."""
import hashlib

import pytest
from sim2d_fixtures import room_grid

from floorplan.occupancy_map import save_map
from sim2d.world import World

_TABLES = {}    # map digest -> a World's _tables (range tables by (max_range, min_clearance))


@pytest.fixture
def room_map(tmp_path):
    path = tmp_path / "room.yaml"
    save_map(room_grid(), path)
    return path


@pytest.fixture
def lazy_tables(monkeypatch):
    """Worlds keep no range-table cache and the worlds of one map share their range tables, so
    a table fills only the rows some laser cast from, once (the entries a full build gives:
    test_lazy_range_table): a test on a whole floor neither tabulates it on a fresh machine (a
    minute and more) nor depends on ~/.cache/sim2d. For World(...) pass cache_dir=None."""
    load, table = World.from_file.__func__, World._table

    def from_file(cls, path, laser_dir=None, cache_dir=None, raycast=None, lazy_tables=True):
        return load(cls, path, laser_dir, None, raycast, True)

    def shared_table(self, laser_mount, robot_config):
        assert self.lazy_tables, "a World built with a cache_dir tabulates its whole map"
        g = self.geometry
        digest = hashlib.sha256(g.occupied.tobytes())
        digest.update(repr((g.occupied.shape, g.resolution, g.origin_x, g.origin_y)).encode())
        self._tables = _TABLES.setdefault(digest.hexdigest(), {})
        return table(self, laser_mount, robot_config)

    monkeypatch.setattr(World, "from_file", classmethod(from_file))
    monkeypatch.setattr(World, "_table", shared_table)
