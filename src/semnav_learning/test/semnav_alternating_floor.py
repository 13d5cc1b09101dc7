"""Test helper: a corridor 2 m wide running east 30 m, its branches alternating left (north) and
right (south): left at x 5-7 m, right at 11-13 m, left at 17-19 m, right at 23-25 m, each 5 m
deep. Over both sides the second right branch is the fourth corner."""

from floorplan.blueprint import render_blueprint
from floorplan.occupancy_map import save_map
from semnav_l_floor import WORLD, LASER_DIR

from semnav_learning.demonstrations import world_for_floor
from semnav_learning.route_oracle import RouteOracle

START = (1.0, 6.0, 0.0)
LEFT_BRANCHES = ((5.0, 7.0), (17.0, 19.0))
RIGHT_BRANCHES = ((11.0, 13.0), (23.0, 25.0))


def alternating_walls():
    """Wall segments [x0, y0, x1, y1] of the floor (the blueprint adds the outer walls)."""
    walls = []
    for branches, y_wall, y_far in ((LEFT_BRANCHES, 7.0, 12.0), (RIGHT_BRANCHES, 5.0, 0.0)):
        x = 0.0
        for a, b in branches:
            walls += [[x, y_wall, a, y_wall], [a, y_wall, a, y_far], [b, y_wall, b, y_far]]
            x = b
        walls.append([x, y_wall, 30.0, y_wall])
    return walls


def alternating_floor_world(folder):
    """The floor written into `folder` -> (sim2d World with the Penguin, RouteOracle)."""
    grid = render_blueprint({"size": [30.0, 12.0], "resolution": 0.05, "wall_thickness": 0.2,
                             "walls": alternating_walls()})
    save_map(grid, folder / "alternating.yaml")
    (folder / "world.yaml").write_text(WORLD.format(map=folder / "alternating.yaml"))
    return world_for_floor(folder / "world.yaml", folder / "alternating.yaml", LASER_DIR), \
        RouteOracle(grid)
