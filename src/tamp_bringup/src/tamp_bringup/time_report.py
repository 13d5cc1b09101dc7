"""Where the robot's time went during a scenario run (ROS-free): the executor's activity changes
(`/task_planner/activity`, recorded by the scenario node) summed per activity, as a table and a
stacked bar per robot."""
from task_planner.behaviours.accounting import ACTIVITIES, time_shares


def robot_shares(record):
    """{robot: {activity: seconds}} over the run (0 to sim_s); a record without activities
    (made before they were recorded) gives {}."""
    end_s = float(record["sim_s"])
    return {robot: time_shares(changes, 0.0, end_s)
            for robot, changes in sorted(record.get("activities", {}).items())}


def time_markdown(shares, plot_file):
    """The report's section: a table of seconds and shares per activity (a column per robot)
    and the stacked bar plot; [] when nothing was recorded."""
    if not shares:
        return []
    robots = list(shares)
    names = [r or "robot" for r in robots]
    lines = ["## Where the time went", "",
             "What the executor was doing (`/task_planner/activity`): travel to an "
             "instruction's place, look around there for its person, searching (moving and "
             "looking after the first place missed the person), waiting (asked to pass after an "
             "abort, or a corridor), dialogue (meeting a stranger), the robot functions, "
             "charging, patrol, idle. Seconds of simulated time and share of the run.", "",
             "| activity | " + " | ".join(names) + " |",
             "|---|" + "---|" * len(robots)]
    for label in ACTIVITIES:
        if not any(shares[r].get(label) for r in robots):
            continue
        cells = []
        for robot in robots:
            total = sum(shares[robot].values()) or 1.0
            seconds = shares[robot].get(label, 0.0)
            cells.append(f"{seconds:.0f} s ({100.0 * seconds / total:.0f} %)")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return lines + ["", f"![time]({plot_file})", ""]


def plot_time(path, shares, title):
    """PNG: one stacked horizontal bar per robot, a segment per activity [s]."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    robots = list(shares)
    fig, ax = plt.subplots(figsize=(8.0, 1.8 + 0.5 * len(robots)))
    left = [0.0] * len(robots)
    colours = plt.get_cmap("tab10")
    for k, label in enumerate(ACTIVITIES):
        widths = [shares[r].get(label, 0.0) for r in robots]
        if not any(widths):
            continue
        ax.barh([r or "robot" for r in robots], widths, left=left, color=colours(k),
                label=label)
        left = [a + b for a, b in zip(left, widths)]
    ax.set_xlabel("simulated time [s]")
    ax.set_title(title)
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
