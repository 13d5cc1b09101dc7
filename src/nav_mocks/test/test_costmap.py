import math

import numpy as np
import pytest
from helpers import grid_from_rows

from nav_mocks.costmap import (INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION,
                               Costmap, CostmapConfig, cost_penalty, inflate, inflation_cost)

CFG = CostmapConfig(robot_radius=0.25, footprint_padding=0.05, inflation_radius=0.55,
                    cost_scaling_factor=10.0)


def test_inflation_cost_values_follow_costmap_2d():
    assert inflation_cost(0.0, CFG) == LETHAL_OBSTACLE
    assert inflation_cost(0.2, CFG) == INSCRIBED_INFLATED_OBSTACLE
    assert inflation_cost(0.3, CFG) == INSCRIBED_INFLATED_OBSTACLE   # exactly inscribed
    # 252 * exp(-10 * (0.4 - 0.3)) = 92.70 -> 92 (costmap_2d truncates to unsigned char)
    assert inflation_cost(0.4, CFG) == 92
    assert inflation_cost(0.5, CFG) == 34                           # 252 e^-2 = 34.10
    assert inflation_cost(0.56, CFG) == 0                           # beyond the inflation radius


def test_inflation_marks_exactly_the_expected_cells():
    cfg = CostmapConfig(robot_radius=0.27, footprint_padding=0.05, inflation_radius=0.55,
                        cost_scaling_factor=10.0)   # inscribed 0.32 m: no cell on the boundary
    lethal = np.zeros((21, 21), dtype=bool)
    lethal[10, 10] = True
    costs = inflate(lethal, 0.1, cfg)
    assert costs[10, 10] == LETHAL_OBSTACLE and (costs == LETHAL_OBSTACLE).sum() == 1
    # inscribed: centres within 3.2 cells: 36 lattice points with 0 < i^2+j^2 <= 10
    # (4 at distance 1, 4 at sqrt2, 4 at 2, 8 at sqrt5, 4 at sqrt8, 4 at 3, 8 at sqrt10)
    inscribed = np.argwhere(costs == INSCRIBED_INFLATED_OBSTACLE) - 10
    assert len(inscribed) == 36
    assert set(map(tuple, inscribed)) == {(i, j) for i in range(-4, 5) for j in range(-4, 5)
                                          if 0 < i * i + j * j <= 10}
    # decaying ring up to 5.5 cells: 252 exp(-10 (d - 0.32)) truncated, 0 beyond
    ring = 0
    for (i, j), cost in np.ndenumerate(costs):
        d = 0.1 * math.hypot(i - 10, j - 10)
        if 0.32 < d <= 0.55:
            ring += 1
            assert cost == int(252 * math.exp(-10 * (d - 0.32))), (i, j)
        elif d > 0.55:
            assert cost == 0, (i, j)
    assert ring == 60   # lattice points with 10 < i^2+j^2 <= 30: 96 within sqrt30, minus 36


def test_laser_marks_and_clearing():
    grid = grid_from_rows(["....."] * 5)
    costmap = Costmap(grid, CFG)
    assert costmap.costs().max() == 0
    costmap.update_from_scan((np.array([], int), np.array([], int)), (np.array([2]), np.array([3])))
    assert costmap.costs()[2, 3] == LETHAL_OBSTACLE
    costmap.update_from_scan((np.array([2]), np.array([3])), (np.array([], int), np.array([], int)))
    assert costmap.costs()[2, 3] == 0
    costmap.update_from_scan((np.array([], int), np.array([], int)), (np.array([1]), np.array([1])))
    costmap.clear_obstacles()
    assert costmap.costs().max() == 0


def test_unknown_space_lethal_or_no_information():
    grid = grid_from_rows(["..?..", "....."])
    assert Costmap(grid, CFG).costs()[0, 2] == LETHAL_OBSTACLE
    cfg = CostmapConfig(unknown_is_lethal=False)
    assert Costmap(grid, cfg).costs()[0, 2] == NO_INFORMATION


def test_penalty_and_config_errors():
    costs = np.array([[0, 126, 252, 253, 254]], dtype=np.uint8)
    assert cost_penalty(costs, 3.0).tolist() == [[0.0, 1.5, 3.0, 0.0, 0.0]]
    with pytest.raises(ValueError, match="inflation_radius"):
        CostmapConfig(robot_radius=0.5, inflation_radius=0.4).validate()
