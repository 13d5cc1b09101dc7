"""Tables (Markdown) and figures (PNG) of the planner benchmark, from its result dicts."""
import numpy as np

from task_planner.metrics import reward_curve, similarity_cost
from task_planner.planner_api import NODE, STEP
from task_planner.planner_registry import (BENCH_DYNAMIC, BENCH_SCALING, BENCH_STATIC,
                                           BENCH_STATIC_FEW, display_order, entries, label)

ORDER = display_order()  # rows, columns and curves in this order
OPT, EXACT = label("opt"), label("exact_offline")
# the per-node online planners, whose decision latency is tabled and plotted
LATENCY_NAMES = tuple(e.label for e in entries(BENCH_SCALING) if e.kind in (NODE, STEP))


def planner_legend():
    """One sentence per benchmarked planner: display name, role and description."""
    bench = {e.label: e for e in entries(BENCH_STATIC, BENCH_STATIC_FEW, BENCH_SCALING,
                                         BENCH_DYNAMIC)}
    return "; ".join(f"{name} ({bench[name].role}) = {bench[name].description}"
                     for name in ORDER if name in bench)


def _names(present):
    return [n for n in ORDER if n in present] + sorted(set(present) - set(ORDER))


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def static_table(rows):
    """Table 5-7 + 5-9 shape: means over trials (Opt only over the trials it ran on)."""
    out = []
    for name in _names({n for row in rows for n in row}):
        entries = [row[name] for row in rows if name in row]
        mean = lambda key: float(np.mean([e[key] for e in entries]))  # noqa: E731
        out.append([name, len(entries), f"{mean('reward'):.3f}",
                    f"{mean('reward_with_decision'):.3f}",
                    f"{mean('completion_s'):.1f}", f"{mean('completion_with_decision_s'):.1f}",
                    f"{1e3 * mean('decision_s'):.2f}", f"{mean('similarity'):.2f}",
                    f"{100 * mean('ratio_to_exact'):.1f}",
                    f"{100 * min(e['ratio_to_exact'] for e in entries):.1f}"])
    header = ["planner", "trials", "reward", "reward w/ decision", "completion [s]",
              "completion w/ decision [s]", "decision [ms]", "similarity cost to optimum",
              "% of exact (mean)", "% of exact (worst)"]
    return _table(header, out)


def thesis_table(rows):
    """`thesis_comparison.comparison_rows` as Markdown."""
    return _table(["thesis", "planner", "Table 5-7 reward / Opt", "reward / optimum",
                   "Table 5-9 similarity cost", "similarity cost"], rows)


def opt_check(rows):
    """One sentence comparing exhaustive Opt with Exact on the trials Opt ran on."""
    pairs = [(row[OPT]["reward"], row[EXACT]["reward"]) for row in rows if OPT in row]
    if not pairs:
        return f"{OPT} was not run."
    gap = max(abs(a - b) for a, b in pairs)
    return (f"On the {len(pairs)} trials Opt ran on, Opt and Exact rewards average "
            f"{np.mean([a for a, _ in pairs]):.3f} and {np.mean([b for _, b in pairs]):.3f}; the "
            f"largest difference is {gap:.2e}.")


def named_case_table(problem, record, schedules):
    """Table 5-8 shape: each planner's service order and its Eq. 5-1 cost to Opt."""
    orders = {name: [int(problem.ids[i]) for i, _ in s.served] for name, s in schedules.items()}
    rows = []
    for name in _names(orders):
        entry = record["planners"][name]
        rows.append([name, " ".join(map(str, orders[name])),
                     "-" if name == OPT else similarity_cost(orders[name], orders[OPT]),
                     f"{entry['reward']:.3f}", f"{entry['reward_with_decision']:.3f}",
                     f"{entry['completion_s']:.1f}", f"{1e3 * entry['decision_s']:.1f}"])
    return _table(["planner", "instruction id sequence", "cost (Eq. 5-1)", "reward",
                   "reward w/ decision", "completion [s]", "decision [ms]"], rows)


def instructions_table(problem):
    rows = [[i.id, i.gamma, i.beta, problem.graph.names[i.destination], i.duration]
            for i in problem.instructions]
    return _table(["id", "gamma", "beta", "node", "duration [s]"], rows)


def scaling_table(results, key, fmt):
    names = _names(results)
    counts = sorted({c for r in results.values() for c in r})
    rows = [[count] + [fmt.format(np.mean([e[key] for e in results[n][count]])) for n in names]
            for count in counts]
    return _table(["instructions"] + names, rows)


def latency_table(results, names=LATENCY_NAMES):
    counts = sorted({c for r in results.values() for c in r})
    rows = []
    for count in counts:
        row = [count]
        for name in names:
            entries = results[name][count]
            row += [f"{np.mean([e['latency_mean_ms'] for e in entries]):.3f}",
                    f"{np.median([e['latency_median_ms'] for e in entries]):.3f}",
                    f"{max(e['latency_p99_ms'] for e in entries):.3f}",
                    f"{max(e['latency_max_ms'] for e in entries):.3f}",
                    f"{max(e['cpu_p99_ms'] for e in entries):.3f}"]
        rows.append(row)
    header = ["instructions"] + [f"{n} {k}" for n in names for k in (
        "mean [ms]", "median [ms]", "p99 [ms]", "max [ms]", "CPU p99 [ms]")]
    return _table(header, rows)


def exact_table(results):
    rows = [[r["count"], f"{r['solved']}/{r['trials']}", f"{r['mean_s']:.3f}", f"{r['max_s']:.3f}"]
            for r in results]
    return _table(["instructions", "solved within limit", "mean [s]", "max [s]"], rows)


def dynamic_table(rows):
    out = []
    for name in _names(rows[0]):
        entries = [row[name] for row in rows]
        out.append([name, f"{np.mean([e['reward'] for e in entries]):.3f}",
                    f"{np.mean([e['reward_with_decision'] for e in entries]):.3f}",
                    f"{np.mean([e['completion_s'] for e in entries]):.1f}",
                    f"{1e3 * np.mean([e['decision_s'] for e in entries]):.2f}"])
    return _table(["planner", "reward", "reward w/ decision", "completion [s]", "decision [ms]"],
                  out)


def plot_named_case(problem, schedules, path):
    """Fig. 5-6: accumulated reward over time per planner, Opt also with its decision time."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    for name in _names(schedules):
        times, accumulated = reward_curve(problem, schedules[name])
        wide = {OPT: 5, EXACT: 3}.get(name, 1.5)  # Opt and Exact coincide with other curves
        axes.step(np.r_[0, times], np.r_[0, accumulated], where="post", label=name, lw=wide,
                  alpha=0.6 if name in (OPT, EXACT) else 1.0)
    times, accumulated = reward_curve(problem, schedules[OPT], with_decision=True)
    axes.step(np.r_[0, times], np.r_[0, accumulated], where="post", label=f"{OPT} w/m", ls="--")
    axes.set(xlabel="time [s]", ylabel="accumulated reward", title="Table 5-6 set (cf. Fig. 5-6)")
    axes.legend()
    figure.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(figure)


def plot_scaling(results, key, ylabel, title, path, names=None):
    """Fig. 5-8 / 5-9 / latency: mean of `key` vs instruction count per planner."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    for name in names or _names(results):
        counts = sorted(results[name])
        axes.plot(counts, [np.mean([e[key] for e in results[name][c]]) for c in counts],
                  marker="o", label=name)
    axes.set(xlabel="number of instructions", ylabel=ylabel, title=title)
    axes.legend()
    figure.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(figure)


def plot_exact(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    axes.semilogy([r["count"] for r in results], [r["mean_s"] for r in results], marker="o",
                  label="mean")
    axes.semilogy([r["count"] for r in results], [r["max_s"] for r in results], marker="x",
                  label="max")
    axes.set(xlabel="number of instructions", ylabel="runtime [s]",
             title="Exact optimiser runtime")
    axes.legend()
    figure.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(figure)
