from pathlib import Path

import numpy as np

from floorplan.occupancy_map import FREE, OCCUPIED, OccupancyMap
from floorplan.plotting import plot_map
from floorplan.semantic_graph import Place, SemanticGraph


def test_plot_map_writes_a_png_with_graph_paths_and_points(tmp_path):
    cells = np.full((20, 30), FREE, np.int8)
    cells[0, :] = OCCUPIED
    grid = OccupancyMap(cells=cells, resolution=0.1, origin=(0.0, 0.0, 0.0))
    region = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    graph = SemanticGraph("m.yaml", [Place(0, "a", (0.5, 0.5, 0.0), region),
                                     Place(1, "b", (2.5, 1.5, 1.57), region)], [("a", "b")])
    out = tmp_path / "map.png"
    plot_map(grid, graph, paths=[("robot", [[0.5, 0.5], [2.5, 1.5]])],
             points=[("scan", [[1.0, 1.0]])], title="t", out_path=out)
    assert Path(out).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
