"""What would have to be true for the thesis's Tables 5-7 and 5-9: the static benchmark re-run
over the settings §5.3 leaves open.

§5.3.1 fixes the instruction sets (ten instructions, priorities and decay factors of Table 5-5)
and the similarity metric (Eq. 5-1) but not the graph, the robot's speed or the service
durations. Speed scales every travel time on a fixed graph, so a slower robot stands for a larger
home as well; another graph changes how many places there are and how they connect. `sweep` runs
the same seeded static sets on every graph under every (speed, duration range) of a grid and
scores each against the thesis's figures (`thesis_comparison`), for both readings of
Algorithm 4-2.
"""
import dataclasses
import time

from task_planner.tools import benchmark as bench
from task_planner.tools import thesis_comparison as thesis
from task_planner.planner_registry import label

SPEEDS_MPS = (0.5, 0.35, 0.25, 0.15, 0.1)
DURATIONS_S = ((0, 5), (1, 10), (5, 20))


@dataclasses.dataclass(frozen=True)
class SettingResult:
    graph: str              # the graph's name (its file's stem)
    speed_mps: float
    durations_s: tuple      # (min, max) of the uniform integer durations [s]
    shapes: dict            # reading label -> thesis-named shape (thesis_comparison)

    def gap(self, reading):
        return thesis.reward_gap(self.shapes[reading])

    def time_gap(self, reading):
        return thesis.time_gap(self.shapes[reading])

    def orders_hold(self, reading):
        """(Table 5-7's reward order holds, Table 5-9's similarity order holds)."""
        shape = self.shapes[reading]
        return thesis.reward_order_holds(shape), thesis.similarity_order_holds(shape)


def readings():
    """The two readings of Algorithm 4-2 the benchmark runs: per node and per step."""
    return (label("seed"), label("seed_step"))


def run_setting(name, graph, priorities, config, speed_mps, durations_s):
    """Static sets (`config.static_trials`, `config.seed`) on `graph` (called `name`) at one
    speed and duration range."""
    config = dataclasses.replace(config, speed_mps=speed_mps, duration_min_s=durations_s[0],
                                 duration_max_s=durations_s[1], opt_trials=0)
    _, rows = bench.run_static(graph, priorities, config)
    shape = thesis.static_shape(rows, label("exact_offline"))
    return SettingResult(name, speed_mps, tuple(durations_s),
                         {r: thesis.as_thesis_names(shape, r) for r in readings()})


def sweep(graphs, priorities, config, speeds=SPEEDS_MPS, durations=DURATIONS_S, report=print):
    """Every graph ({name: TopologicalGraph}) under every (speed, durations) of the grid; one
    progress line per setting with an ETA."""
    grid = [(g, s, d) for g in graphs for s in speeds for d in durations]
    results, started = [], time.perf_counter()
    for k, (name, speed, duration) in enumerate(grid, 1):
        results.append(run_setting(name, graphs[name], priorities, config, speed, duration))
        elapsed = time.perf_counter() - started
        report(f"[fit_planner_settings] {k}/{len(grid)}: {name}, {speed} m/s, durations "
               f"{duration[0]}-{duration[1]} s; {elapsed:.0f} s elapsed, ETA "
               f"{elapsed / k * (len(grid) - k):.0f} s")
    return results


def best(results, reading):
    """The setting whose reward ratios come closest to Table 5-7 for `reading`."""
    return min(results, key=lambda r: r.gap(reading))


def best_times(results, reading):
    """The setting whose completion times come closest to Table 5-7 for `reading`."""
    return min(results, key=lambda r: r.time_gap(reading))


def fit_rows(results, reading):
    """Markdown rows: setting, the five ratios, both orders, both gaps, for one reading."""
    rows = []
    for r in results:
        shape = r.shapes[reading]
        rows.append([r.graph, f"{r.speed_mps}", f"{r.durations_s[0]}-{r.durations_s[1]}"]
                    + [f"{shape[n]['ratio']:.3f}" for n in thesis.REWARD_ORDER]
                    + [f"{shape[n]['similarity']:.1f}" for n in thesis.SIMILARITY_ORDER]
                    + [f"{shape[n]['completion_s']:.0f}" for n in thesis.TIMED]
                    + ["yes" if thesis.reward_order_holds(shape) else "no",
                       "yes" if thesis.similarity_order_holds(shape) else "no",
                       f"{thesis.reward_gap(shape):.3f}", f"{thesis.similarity_gap(shape):.2f}",
                       f"{thesis.time_gap(shape):.2f}"])
    return rows


def fit_header():
    return (["graph", "speed [m/s]", "durations [s]"]
            + [f"{n} / opt" for n in thesis.REWARD_ORDER]
            + [f"{n} sim." for n in thesis.SIMILARITY_ORDER]
            + [f"{n} time [s]" for n in thesis.TIMED]
            + ["5-7 order", "5-9 order", "ratio gap", "sim. gap", "time gap"])


def thesis_row():
    """The thesis's own figures in the layout of fit_rows."""
    return (["thesis", "-", "-"] + [f"{thesis.thesis_ratio(n):.3f}" for n in thesis.REWARD_ORDER]
            + [f"{thesis.TABLE_5_9_SIMILARITY[n]:.1f}" for n in thesis.SIMILARITY_ORDER]
            + [f"{thesis.TABLE_5_7_TIME_S[n]:.0f}" for n in thesis.TIMED]
            + ["yes", "yes", "0", "0", "0"])


def summary_rows(results, reading):
    """Per graph: settings run, where each order holds, where both do, the closest setting."""
    rows = []
    for graph in dict.fromkeys(r.graph for r in results):
        mine = [r for r in results if r.graph == graph]
        holds = [r.orders_hold(reading) for r in mine]
        top = best(mine, reading)
        shape = top.shapes[reading]
        rows.append([graph, len(mine), sum(a for a, _ in holds), sum(b for _, b in holds),
                     sum(a and b for a, b in holds),
                     f"{top.speed_mps} m/s, {top.durations_s[0]}-{top.durations_s[1]} s",
                     f"{shape['Ours']['ratio']:.3f} / {shape['SF']['ratio']:.3f} / "
                     f"{shape['PF']['ratio']:.3f}",
                     f"{shape['Ours']['similarity']:.1f} / {shape['PF']['similarity']:.1f} / "
                     f"{shape['SF']['similarity']:.1f}", f"{top.gap(reading):.3f}"])
    return rows


def summary_header():
    return ["graph", "settings", "5-7 order holds", "5-9 order holds", "both hold",
            "closest to Table 5-7", "Ours / SF / PF to opt", "Ours / PF / SF sim.", "ratio gap"]


def plot(results, path):
    """Ours vs SF ratio to the optimum for every setting, per reading, with the thesis's point."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharex=True, sharey=True)
    graphs = list(dict.fromkeys(r.graph for r in results))
    for axis, reading in zip(axes, readings()):
        for k, graph in enumerate(graphs):
            mine = [r.shapes[reading] for r in results if r.graph == graph]
            axis.scatter([m["SF"]["ratio"] for m in mine], [m["Ours"]["ratio"] for m in mine],
                         s=18, color=f"C{k}", label=graph)
        axis.scatter([thesis.thesis_ratio("SF")], [thesis.thesis_ratio("Ours")], marker="*",
                     s=220, color="black", label="thesis (Table 5-7)")
        axis.plot([0.5, 1.0], [0.5, 1.0], color="grey", linewidth=0.8, linestyle=":")
        axis.set_title(f"Ours = {reading}")
        axis.set_xlabel("SF reward / optimum")
        axis.grid(alpha=0.3)
    axes[0].set_ylabel("Ours reward / optimum")
    axes[1].legend(fontsize=8, loc="lower right")
    fig.suptitle("Every graph, speed and duration range of the sweep against Table 5-7")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
