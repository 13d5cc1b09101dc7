"""Plots of the route oracle (the walked corridor, its openings and the goal of every class) and
of the whole-floor structure (skeleton, junctions, dead ends, corridor network, starts)."""
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from floorplan.plotting import draw_map  # noqa: E402

CLASS_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:gray", "tab:purple", "tab:olive",
                 "tab:brown", "tab:pink", "tab:orange", "tab:cyan")


def _arrow(ax, pose, colour, length=0.8, width=0.25):
    x, y, yaw = pose
    ax.arrow(x, y, length * math.cos(yaw), length * math.sin(yaw), head_width=width,
             length_includes_head=True, color=colour, lw=1.2, zorder=4)


def draw_walk(ax, walk):
    """Centre line walked, corridor branches (green) and doors / side openings (orange)."""
    end = walk.point(walk.front)
    ax.plot([walk.origin[0], end[0]], [walk.origin[1], end[1]], ":", color="k", lw=0.8)
    for opening in walk.openings:
        normal = walk.axis + (math.pi / 2 if opening.side == "left" else -math.pi / 2)
        offset = walk.half_width * 1.1
        a, b = walk.point(opening.start), walk.point(opening.end)
        dx, dy = offset * math.cos(normal), offset * math.sin(normal)
        ax.plot([a[0] + dx, b[0] + dx], [a[1] + dy, b[1] + dy], lw=3, alpha=0.7,
                color="tab:green" if opening.is_branch else "tab:orange")


def plot_oracle_goals(grid, start, walk, goals, title, out_path, names):
    """One floor, one start: the start arrow, each class goal (disc + heading), n/a listed."""
    width, height = grid.width * grid.resolution, grid.height * grid.resolution
    fig, ax = plt.subplots(figsize=(min(13.0, max(8.0, 2.5 + width / 2.6)),
                                    min(11.0, 1.5 + height / 2.6)))
    draw_map(ax, grid)
    draw_walk(ax, walk)
    _arrow(ax, start, "k", length=1.0, width=0.35)
    ax.annotate("start", start[:2], fontsize=8, xytext=(-10, -14), textcoords="offset points")
    absent, shared = [], {}
    for label, goal in goals.items():
        colour = CLASS_COLOURS[(label - 1) % len(CLASS_COLOURS)]
        if goal is None:
            absent.append(str(label))
            continue
        ax.add_patch(plt.Circle(goal.pose[:2], goal.radius, color=colour, alpha=0.12, zorder=3))
        _arrow(ax, goal.pose, colour)
        shared.setdefault(tuple(round(v, 1) for v in goal.pose), []).append(str(label))
        ax.plot([], [], color=colour, lw=3, label=f"{label}: {names[label]}")
    for (x, y, _), labels in shared.items():   # classes sharing a goal get one label "3, 6"
        ax.annotate(", ".join(labels), (x, y), fontsize=9, weight="bold", xytext=(5, 5),
                    textcoords="offset points", zorder=5)
    ax.plot([], [], color="tab:green", lw=3, alpha=0.7, label="corridor branch")
    ax.plot([], [], color="tab:orange", lw=3, alpha=0.7, label="door / side opening")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.set_title(f"{title}\nnot applicable here: {', '.join(absent) or 'none'}", fontsize=9)
    fig.tight_layout()
    fig.savefig(out_path, dpi=100)
    plt.close(fig)


def plot_floor_structure(grid, structure, starts, title, out_path):
    """Corridor network (tinted), skeleton, junctions, dead ends and sampled starts."""
    width, height = grid.width * grid.resolution, grid.height * grid.resolution
    fig, ax = plt.subplots(figsize=(min(13.0, max(8.0, 2.5 + width / 2.6)),
                                    min(11.0, 1.5 + height / 2.6)))
    draw_map(ax, grid)
    x0, y0 = grid.origin[0], grid.origin[1]
    extent = [x0, x0 + width, y0, y0 + height]
    tint = np.ma.masked_where(~structure.corridors, structure.corridors.astype(float))
    ax.imshow(tint, cmap="Greens", vmin=0, vmax=3, origin="lower", extent=extent, alpha=0.5)
    rows, cols = np.nonzero(structure.skeleton)
    ax.plot(*grid.cell_to_world(rows, cols), ",", color="tab:blue")
    for cells, marker, label in ((structure.junctions, "o", "junction cell"),
                                 (structure.dead_ends, "s", "dead-end cell")):
        if len(cells):
            ax.plot(*grid.cell_to_world(cells[:, 0], cells[:, 1]), marker, ms=4, mfc="none",
                    color="tab:red" if marker == "o" else "tab:purple", label=label)
    for start in starts:
        _arrow(ax, start, "k", length=0.6, width=0.2)
    ax.plot([], [], color="tab:blue", label="skeleton")
    ax.plot([], [], color="tab:green", lw=6, alpha=0.4, label="corridor network")
    ax.plot([], [], "k>", label="sampled start")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(out_path, dpi=100)
    plt.close(fig)
