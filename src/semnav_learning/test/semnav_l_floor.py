"""Test helper: a 1.8 m corridor running east 10 m into an L corner that turns north for 6 m,
written as a map_server map plus a sim2d world file with the Penguin (URG-04LX, exact casting)."""

from semnav_learning.demonstrations import world_for_floor
from semnav_learning.route_oracle import RouteOracle
from floorplan.blueprint import render_blueprint
from floorplan.occupancy_map import save_map
from tamp_resources import resource

ROOT = resource()
LASER_DIR = ROOT / "config" / "lasers"
WORLD = """map: {map}
robots:
  - name: penguin
    drive: differential
    radius: 0.3
    pose: [1.0, 1.0, 0.0]
    limits: {{max_linear: 0.4, max_angular: 1.0, max_linear_accel: 0.8, max_angular_accel: 2.0}}
    wheels: {{radius: 0.075, separation: 0.45, encoder_ticks_per_rev: 4096}}
    lasers:
      - {{model: urg_04lx, mount: [0.0, 0.0, 0.0], mount_height: 0.45, raycast: march}}
"""


def write_l_floor(folder):
    """Writes l_floor.yaml/.pgm and world.yaml into `folder`; returns the occupancy grid."""
    grid = render_blueprint({"size": [10.0, 8.0], "resolution": 0.05, "wall_thickness": 0.2,
                             "walls": [[0, 2, 8, 2], [8, 2, 8, 8]]})
    save_map(grid, folder / "l_floor.yaml")
    (folder / "world.yaml").write_text(WORLD.format(map=folder / "l_floor.yaml"))
    return grid


def l_floor_world(folder):
    """The L floor written into `folder` -> (sim2d World with the Penguin, RouteOracle)."""
    grid = write_l_floor(folder)
    return world_for_floor(folder / "world.yaml", folder / "l_floor.yaml", LASER_DIR), \
        RouteOracle(grid)
