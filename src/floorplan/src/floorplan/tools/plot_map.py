"""scripts/plot_map: a map and its semantic graph -> PNG."""
import argparse
from collections.abc import Sequence
from pathlib import Path

from floorplan.occupancy_map import load_map
from floorplan.plotting import plot_map
from floorplan.semantic_graph import load_graph
from floorplan.tools.make_maps import require_files


def main(argv: Sequence[str] | None = None) -> int:
    """Render a map_server map with its semantic graph (<map>.graph.yaml, when present) to PNG."""
    parser = argparse.ArgumentParser(prog="plot_map", description=main.__doc__)
    parser.add_argument("maps", nargs="+", type=Path, help="map YAML files (maps/<name>.yaml)")
    parser.add_argument("--out-dir", type=Path, default=None,
                        help="where the PNGs go (default: beside each map)")
    args = parser.parse_args(argv)
    require_files(parser, args.maps, "map")
    for map_path in args.maps:
        if map_path.name.endswith(".graph.yaml"):
            continue                     # a graph file: it is drawn with its map
        graph_path = map_path.with_name(map_path.stem + ".graph.yaml")
        graph = load_graph(graph_path) if graph_path.is_file() else None
        out_dir = args.out_dir or map_path.parent
        out_dir.mkdir(parents=True, exist_ok=True)
        out = out_dir / f"{map_path.stem}.png"
        plot_map(load_map(map_path), graph, title=map_path.stem, out_path=out)
        print(f"{map_path} -> {out}" + ("" if graph else " (no graph)"))
    return 0
