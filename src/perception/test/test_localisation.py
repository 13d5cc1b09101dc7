"""Localisation (thesis 000 Sec. 3.2.2): pinhole Eqs. 3-3..3-5, adaptive depth window, transform."""
import math
import os

import numpy as np
import pytest
from floorplan.semantic_graph import load_graph

from perception.localisation import (
    DepthWindowConfig, Intrinsics, box_depth, depth_window, localise_box,
    optical_to_map_transform, pixel_to_camera, semantic_place, stitched_pixel)
from tamp_resources import resource

GRAPH = os.path.join(resource("maps"), "household.graph.yaml")
PEPPER = Intrinsics(fx=583.9, fy=588.5, cx=320.0, cy=240.0, width=640, height=480)


def test_pinhole_eqs_3_3_to_3_5():
    """(px - cx) / fx * d: pixel (903.9, 828.5) at 2 m -> (2, 2, 2) m; the centre -> (0, 0, d)."""
    assert pixel_to_camera(320.0 + 583.9, 240.0 + 588.5, 2.0, PEPPER) == pytest.approx([2, 2, 2])
    assert pixel_to_camera(320.0, 240.0, 3.5, PEPPER) == pytest.approx([0.0, 0.0, 3.5])
    assert pixel_to_camera(20.0, 240.0, 1.0, PEPPER)[0] == pytest.approx(-300.0 / 583.9)


def test_depth_window_adapts_to_box():
    cfg = DepthWindowConfig(fraction=0.2, min_side=3)
    assert depth_window((100, 100, 100, 200), cfg, (480, 640)) == (140, 180, 160, 220)
    # a tiny box still gets the minimum 3 px side
    assert depth_window((10, 10, 4, 4), cfg, (480, 640)) == (10, 10, 14, 14)
    # clipped at the image border
    assert depth_window((630, 470, 40, 40), cfg, (480, 640))[2:] == (640, 480)


def test_box_depth_ignores_nan_zero_and_out_of_range():
    depth = np.full((100, 100), 2.0)
    depth[45:55, 45:50] = np.nan
    depth[45:55, 50:52] = 0.0
    depth[45:47, 52:55] = 20.0
    depth[47:55, 52:55] = 3.0
    cfg = DepthWindowConfig(fraction=0.1, min_side=1)
    window = depth_window((0, 0, 100, 100), cfg, depth.shape)
    assert window == (45, 45, 55, 55)
    # valid pixels in the window: rows 47..54 x cols 52..54, all 3.0 m
    assert box_depth(depth, (0, 0, 100, 100), cfg) == pytest.approx(3.0)
    depth[45:55, 45:55] = np.nan
    assert box_depth(depth, (0, 0, 100, 100), cfg) is None
    with pytest.raises(ValueError, match="depth image"):
        box_depth(np.zeros((0, 0)), (0, 0, 1, 1), cfg)


def test_localise_box_in_front_of_robot():
    """Robot at the origin facing +x, level camera at 1.15 m, centred box at 2 m -> (2.09, 0)."""
    depth = np.full((480, 640), 2.0)
    T = optical_to_map_transform((0.0, 0.0, 0.0), 0.09, 1.15, 0.0)
    p = localise_box(depth, (270, 190, 100, 100), PEPPER, T, DepthWindowConfig())
    assert p == pytest.approx([2.09, 0.0, 1.15])
    T90 = optical_to_map_transform((1.0, 1.0, math.pi / 2), 0.0, 1.0, 0.0)
    assert localise_box(depth, (270, 190, 100, 100), PEPPER, T90,
                        DepthWindowConfig())[:2] == pytest.approx([1.0, 3.0])


def test_semantic_place_from_graph_regions():
    graph = load_graph(GRAPH)
    place = graph.places[0]
    xs, ys = zip(*place.region)
    inside = semantic_place(graph, sum(xs) / len(xs), sum(ys) / len(ys))
    assert inside == place.name
    assert semantic_place(graph, -100.0, -100.0) == ""


def test_stitched_pixel_split():
    assert stitched_pixel(10, 100, 480) == ("top", 10, 100)
    assert stitched_pixel(10, 500, 480) == ("bottom", 10, 20)
