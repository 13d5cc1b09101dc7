"""scripts/make_maps: render blueprints into map_server maps."""
import argparse
from collections.abc import Iterable, Sequence
from pathlib import Path

from tamp_resources import resource

from floorplan.blueprint import load_blueprint, render_blueprint
from floorplan.occupancy_map import save_map


def require_files(parser: argparse.ArgumentParser, paths: Iterable[Path], what: str) -> None:
    """Stop with the parser's one-line error when one of `paths` is no file."""
    missing = [str(p) for p in paths if not Path(p).is_file()]
    if missing:
        parser.error(f"no such {what}: {', '.join(missing)}")


def main(argv: Sequence[str] | None = None) -> int:
    """Render every maps/blueprints/*.yaml into maps/<name>.yaml + .pgm (map_server format)."""
    maps = resource("maps")
    parser = argparse.ArgumentParser(prog="make_maps", description=main.__doc__)
    parser.add_argument("blueprints", nargs="*", type=Path,
                        default=sorted((maps / "blueprints").glob("*.yaml")))
    parser.add_argument("--out-dir", type=Path, default=maps,
                        help="where the maps go (default: the workspace's maps/)")
    args = parser.parse_args(argv)
    require_files(parser, args.blueprints, "blueprint")
    args.out_dir.mkdir(parents=True, exist_ok=True)
    shown = "maps" if args.out_dir == maps else str(args.out_dir)
    for path in args.blueprints:
        blueprint = load_blueprint(path)
        grid = render_blueprint(blueprint)
        save_map(grid, args.out_dir / f"{blueprint['name']}.yaml")
        print(f"{path.name} -> {shown}/{blueprint['name']}.yaml "
              f"({grid.width}x{grid.height} cells)")
    return 0
