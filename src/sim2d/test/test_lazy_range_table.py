"""A lazy range table fills only the rows that casts need, with the entries a full build gives."""
import numpy as np
import pytest
from sim2d_fixtures import room_grid

from sim2d.raycast import GridGeometry, RangeTable, RangeTableConfig

CONFIG = RangeTableConfig(cell_size=0.1, angle_bins=72, max_range=10.0)


@pytest.fixture(scope="module")
def geometry():
    return GridGeometry.from_map(room_grid())


@pytest.fixture(scope="module")
def full(geometry):
    return RangeTable.build(geometry, CONFIG)


def test_a_lazy_table_casts_what_the_full_table_casts_and_fills_only_those_rows(geometry, full):
    lazy = RangeTable.build(geometry, CONFIG, lazy=True)
    assert lazy.filled_rows == 0 and full.filled_rows == len(full.table) > 100
    angles = np.linspace(-np.pi, np.pi, 181)
    points = [(1.0, 1.0), (2.03, 1.47), (1.02, 1.04)]     # the last shares the first's row
    for x, y in points:
        np.testing.assert_array_equal(lazy.cast(x, y, angles), full.cast(x, y, angles))
    assert lazy.filled_rows == 2
    rows = lazy.cast_rows([3.0, 1.5], [2.0, 2.5], [0.3, -1.0], angles[:20])
    np.testing.assert_array_equal(rows, full.cast_rows([3.0, 1.5], [2.0, 2.5], [0.3, -1.0],
                                                       angles[:20]))
    assert lazy.filled_rows == 4
    filled = lazy._filled.nonzero()[0]
    np.testing.assert_array_equal(lazy.table[filled], full.table[filled])


def test_a_lazy_table_is_not_cached_and_a_cached_one_is_loaded_whole(geometry, full, tmp_path):
    RangeTable.build(geometry, CONFIG, cache_dir=tmp_path, lazy=True).cast(1.0, 1.0, [0.0])
    assert not list(tmp_path.iterdir())
    np.save(RangeTable._cache_path(geometry, CONFIG, tmp_path), full.table)
    loaded = RangeTable.build(geometry, CONFIG, cache_dir=tmp_path, lazy=True)
    assert loaded.filled_rows == len(loaded.table)
    np.testing.assert_array_equal(loaded.table, full.table)
