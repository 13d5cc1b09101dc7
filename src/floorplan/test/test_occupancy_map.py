import cv2
import numpy as np
import pytest
import yaml

from floorplan.blueprint import render_blueprint
from floorplan.occupancy_map import (FREE, OCCUPIED, UNKNOWN, MapError, OccupancyMap, load_map,
                                 save_map)


def write_map(tmp_path, pixels, **meta):
    cv2.imwrite(str(tmp_path / "m.pgm"), np.asarray(pixels, dtype=np.uint8))
    fields = dict(image="m.pgm", resolution=0.1, origin=[-1.0, 2.0, 0.0], negate=0,
                  occupied_thresh=0.65, free_thresh=0.196)
    fields.update(meta)
    (tmp_path / "m.yaml").write_text(yaml.safe_dump(fields))
    return tmp_path / "m.yaml"


def test_trinary_thresholds_and_row_order(tmp_path):
    # Top image row = highest y. Occupancy (255 - p) / 255: p=0 -> 1.0; p=254 -> 0.004;
    # p=205 -> 0.1961 (between the thresholds: unknown); p=50 -> 0.80.
    grid = load_map(write_map(tmp_path, [[0, 254], [205, 50]]))
    assert grid.cells.tolist() == [[UNKNOWN, OCCUPIED], [OCCUPIED, FREE]]
    assert (grid.resolution, grid.origin) == (0.1, (-1.0, 2.0, 0.0))


def test_negate_inverts_occupancy(tmp_path):
    grid = load_map(write_map(tmp_path, [[0, 255]], negate=1))
    assert grid.cells.tolist() == [[FREE, OCCUPIED]]


def test_scale_mode_interpolates_between_thresholds(tmp_path):
    # p=127 -> occ = 128/255 = 0.502 -> 99 * (0.502 - 0.196) / (0.65 - 0.196) = 66.7 -> 67
    grid = load_map(write_map(tmp_path, [[127]], mode="scale"))
    assert grid.cells.tolist() == [[67]]


def test_missing_image_names_the_file(tmp_path):
    path = write_map(tmp_path, [[0]])
    (tmp_path / "m.pgm").unlink()
    with pytest.raises(MapError, match="m.pgm: map image missing"):
        load_map(path)


def test_missing_key_names_the_key(tmp_path):
    (tmp_path / "bad.yaml").write_text("image: m.pgm\nresolution: 0.05\n")
    with pytest.raises(MapError, match="missing key.*origin"):
        load_map(tmp_path / "bad.yaml")


def test_save_then_load_round_trip(tmp_path):
    cells = np.array([[FREE, OCCUPIED, UNKNOWN]], dtype=np.int8)
    grid = OccupancyMap(cells=cells, resolution=0.05, origin=(1.0, 2.0, 0.0))
    save_map(grid, tmp_path / "r.yaml")
    again = load_map(tmp_path / "r.yaml")
    assert again.cells.tolist() == cells.tolist() and again.origin == (1.0, 2.0, 0.0)


def test_world_cell_conversion_is_consistent():
    grid = OccupancyMap(cells=np.zeros((10, 20), np.int8), resolution=0.5, origin=(-2.0, 1.0, 0.0))
    assert tuple(int(v) for v in grid.world_to_cell(0.3, 2.9)) == (3, 4)
    assert tuple(float(v) for v in grid.cell_to_world(3, 4)) == (0.25, 2.75)


def test_blueprint_draws_walls_doors_and_furniture():
    blueprint = dict(size=[2.0, 1.0], resolution=0.1, wall_thickness=0.2,
                     walls=[[1.0, 0.0, 1.0, 1.0]], doors=[[0.9, 0.4, 1.1, 0.6]],
                     furniture=[[0.3, 0.3, 0.5, 0.5]])
    cells = render_blueprint(blueprint).cells
    assert cells.shape == (10, 20)
    assert (cells[0, :] == OCCUPIED).all() and (cells[:, 0] == OCCUPIED).all()   # outline
    assert cells[2, 9] == OCCUPIED and cells[2, 10] == OCCUPIED                   # wall x=1.0
    assert cells[4, 9] == FREE and cells[5, 10] == FREE                           # door
    assert cells[3:5, 3:5].tolist() == [[OCCUPIED] * 2] * 2 and cells[5, 5] == FREE  # furniture
