"""Plots: an occupancy map with its semantic graph, optionally with robot paths and scan
returns (matplotlib)."""
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from numpy.typing import ArrayLike  # noqa: E402

from floorplan.occupancy_map import FREE, UNKNOWN, OccupancyMap  # noqa: E402
from floorplan.semantic_graph import SemanticGraph  # noqa: E402

GRAPH_COLOUR = "tab:blue"
PATH_COLOURS = ("tab:red", "tab:green", "tab:orange", "tab:purple")


def draw_map(ax: Axes, grid: OccupancyMap) -> None:
    """Occupied black, free white, unknown grey, in map-frame metres."""
    shade = np.full(grid.cells.shape, 0.0)
    shade[grid.cells == FREE] = 1.0
    shade[grid.cells == UNKNOWN] = 0.8
    x0, y0 = grid.origin[0], grid.origin[1]
    extent = (x0, x0 + grid.width * grid.resolution, y0, y0 + grid.height * grid.resolution)
    ax.imshow(shade, cmap="gray", vmin=0, vmax=1, origin="lower", extent=extent)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal")


def draw_graph(ax: Axes, graph: SemanticGraph) -> None:
    """Regions as outlines, places as arrows with names, edges as lines."""
    for place in graph.places:
        region = np.array(place.region + place.region[:1])
        ax.plot(region[:, 0], region[:, 1], color=GRAPH_COLOUR, lw=0.6, alpha=0.5)
        x, y, yaw = place.pose
        ax.plot(x, y, "o", color=GRAPH_COLOUR, ms=4)
        ax.arrow(x, y, 0.5 * np.cos(yaw), 0.5 * np.sin(yaw), head_width=0.15,
                 color=GRAPH_COLOUR, lw=0.8)
        ax.annotate(place.name, (x, y), fontsize=6, xytext=(3, 3), textcoords="offset points")
    for a, b in graph.edges:
        pa, pb = graph.place(a).pose, graph.place(b).pose
        ax.plot([pa[0], pb[0]], [pa[1], pb[1]], "--", color=GRAPH_COLOUR, lw=0.8)


def plot_map(grid: OccupancyMap, graph: SemanticGraph | None = None,
             paths: Sequence[tuple[str, ArrayLike]] = (), title: str = "",
             out_path: str | Path | None = None,
             points: Sequence[tuple[str, ArrayLike]] = ()) -> Figure:
    """Render a map (and graph, [(label, xy array)] paths and [(label, xy array)] point sets,
    e.g. laser returns) to out_path as PNG."""
    width = grid.width * grid.resolution
    height = grid.height * grid.resolution
    fig, ax = plt.subplots(figsize=(min(12.0, 2.0 + width / 3.0), min(12.0, 1.5 + height / 3.0)))
    draw_map(ax, grid)
    if graph is not None:
        draw_graph(ax, graph)
    for (label, xy), colour in zip(paths, PATH_COLOURS * (1 + len(paths))):
        xy = np.asarray(xy)
        ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=1.2, label=label)
    for label, xy in points:
        xy = np.asarray(xy)
        ax.plot(xy[:, 0], xy[:, 1], ".", color="tab:red", ms=1.5, label=label)
    if paths or points:
        ax.legend(fontsize=7)
    ax.set_title(title)
    fig.tight_layout()
    if out_path is not None:
        fig.savefig(out_path, dpi=110)
    plt.close(fig)
    return fig
