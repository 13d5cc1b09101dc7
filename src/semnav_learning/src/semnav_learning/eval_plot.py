"""Fig. 4.2.3-style pictures of evaluation episodes: the learned policy's path (red) and the
expert's path (green) from the same start; circles mark starts, triangles stops; for class 4
("turn around") arrows show the start (red) and final (green) headings."""
import math
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from floorplan.plotting import draw_map  # noqa: E402

MARGIN = 3.0     # [m] shown round the paths and the goal


def _heading_arrow(ax, pose, colour):
    x, y, yaw = pose
    ax.arrow(x, y, 0.8 * math.cos(yaw), 0.8 * math.sin(yaw), head_width=0.3,
             length_includes_head=True, color=colour, lw=1.5, zorder=5)


def draw_episode(ax, grid, model_path, expert_path, goal, title):
    """One panel: map crop, goal disc, model path (red), expert path (green)."""
    draw_map(ax, grid)
    ax.add_patch(plt.Circle(goal.pose[:2], goal.radius, color="tab:blue", alpha=0.15, zorder=2))
    points = [np.asarray(goal.pose[:2])[None, :]]
    for path, colour in ((expert_path, "tab:green"), (model_path, "tab:red")):
        if path is None or not len(path):
            continue
        path = np.asarray(path)
        points.append(path[:, :2])
        ax.plot(path[:, 0], path[:, 1], color=colour, lw=1.6, zorder=4)
        ax.plot(*path[0, :2], "o", color=colour, mfc="none", ms=8, zorder=5)
        ax.plot(*path[-1, :2], "^", color=colour, ms=8, zorder=5)
    if model_path is not None and len(model_path):
        _heading_arrow(ax, model_path[0], "tab:red")
        _heading_arrow(ax, model_path[-1], "darkred")
    allxy = np.vstack(points)
    lo, hi = allxy.min(axis=0) - MARGIN, allxy.max(axis=0) + MARGIN
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_title("\n".join(textwrap.wrap(title, 48)), fontsize=7)
    ax.tick_params(labelsize=6)


def plot_episodes(panels, out_path, suptitle=""):
    """panels: [(grid, model_path, expert_path, goal, title)] -> one PNG, 5 panels per row."""
    cols = min(5, len(panels))
    rows = int(math.ceil(len(panels) / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(3.4 * cols, 3.4 * rows), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, panel in zip(axes.flat, panels):
        draw_episode(ax, *panel)
    axes.flat[0].plot([], [], color="tab:red", label="learned policy")
    axes.flat[0].plot([], [], color="tab:green", label="expert")
    axes.flat[0].legend(fontsize=6, loc="lower left")
    if suptitle:
        fig.suptitle(suptitle, fontsize=10)
    fig.tight_layout()
    fig.savefig(out_path, dpi=90)
    plt.close(fig)
