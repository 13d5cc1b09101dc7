"""Command lines of scripts/make_maps (blueprints -> map_server maps) and scripts/plot_map
(a map and its semantic graph -> PNG)."""
import argparse
from collections.abc import Iterable, Sequence
from pathlib import Path

from tamp_resources import resource

from floorplan.blueprint import load_blueprint, render_blueprint
from floorplan.occupancy_map import load_map, save_map
from floorplan.plotting import plot_map
from floorplan.semantic_graph import load_graph


def _existing_files(parser: argparse.ArgumentParser, paths: Iterable[Path], what: str) -> None:
    missing = [str(p) for p in paths if not Path(p).is_file()]
    if missing:
        parser.error(f"no such {what}: {', '.join(missing)}")


def make_maps_main(argv: Sequence[str] | None = None) -> int:
    """Render every maps/blueprints/*.yaml into maps/<name>.yaml + .pgm (map_server format)."""
    maps = resource("maps")
    parser = argparse.ArgumentParser(prog="make_maps", description=make_maps_main.__doc__)
    parser.add_argument("blueprints", nargs="*", type=Path,
                        default=sorted((maps / "blueprints").glob("*.yaml")))
    parser.add_argument("--out-dir", type=Path, default=maps,
                        help="where the maps go (default: the workspace's maps/)")
    args = parser.parse_args(argv)
    _existing_files(parser, args.blueprints, "blueprint")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    shown = "maps" if args.out_dir == maps else str(args.out_dir)
    for path in args.blueprints:
        blueprint = load_blueprint(path)
        grid = render_blueprint(blueprint)
        save_map(grid, args.out_dir / f"{blueprint['name']}.yaml")
        print(f"{path.name} -> {shown}/{blueprint['name']}.yaml "
              f"({grid.width}x{grid.height} cells)")
    return 0


def plot_map_main(argv: Sequence[str] | None = None) -> int:
    """Render a map_server map with its semantic graph (<map>.graph.yaml, when present) to PNG."""
    parser = argparse.ArgumentParser(prog="plot_map", description=plot_map_main.__doc__)
    parser.add_argument("maps", nargs="+", type=Path, help="map YAML files (maps/<name>.yaml)")
    parser.add_argument("--out-dir", type=Path, default=None,
                        help="where the PNGs go (default: beside each map)")
    args = parser.parse_args(argv)
    _existing_files(parser, args.maps, "map")
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
