"""Activity recognition in the loop (ROS-free): what visual perception read each identified
person doing (/humans/observed, thesis 000 §3.2.4) against what the simulator had them do (the
world file's activities, sim2d's people labels; ground truth, for the report only).

The scenario node counts, for every identified person in every analysed frame, the pair (true
activity, activity read); a category's share is the frames read right over its frames.
"""
from collections.abc import Collection, Mapping


def parse_label(text):
    """sim2d's people label "Bob: sitting, watch TV" -> ("Bob", "watch TV"); activity "" when
    the label carries none."""
    name, _, rest = text.partition(":")
    _, _, activity = rest.partition(",")
    return name.strip(), activity.strip()


def count_frame(counts, doing, observed):
    """Add one analysed frame to `counts` ({true: {read: frames}}): `observed` is [(name,
    activity read)] of the people perception identified, `doing` {name: true activity}."""
    for name, read in observed:
        truth = doing.get(name)
        if name and truth:
            row = counts.setdefault(truth, {})
            row[read] = row.get(read, 0) + 1


def activity_rows(counts: Mapping[str, Mapping[str, int]]):
    """[(true activity, frames, share read right, [(misreading, frames)] most frequent first)],
    by frames, most first."""
    rows = []
    for truth, reads in counts.items():
        frames = sum(reads.values())
        wrong = sorted(((read, n) for read, n in reads.items() if read != truth),
                       key=lambda item: (-item[1], item[0]))
        rows.append((truth, frames, reads.get(truth, 0) / frames if frames else 0.0, wrong))
    return sorted(rows, key=lambda row: (-row[1], row[0]))


def weakest(counts, categories: Collection[str]):
    """(category, share) of the lowest share among the true activities that are `categories`
    (the affordance table's: the seed's categories), or None when none was seen."""
    rows = [(truth, share) for truth, _, share, _ in activity_rows(counts) if truth in categories]
    return min(rows, key=lambda row: (row[1], row[0])) if rows else None


def activity_markdown(counts, categories: Collection[str]):
    """The report's section on activity recognition in the loop."""
    lines = ["## Activity recognition in the loop", "",
             "For every person visual perception identified in an analysed frame "
             "(`/humans/observed`), the activity it read against the one the simulator had them "
             "do (the world file's; ground truth, for this report only). Frames per true "
             "activity; an activity outside the seed's categories (`config/affordances.yaml`) "
             "is marked *not a category* and left out of the goal.", ""]
    rows = activity_rows(counts)
    if not rows:
        return lines + ["No identified person in any analysed frame.", ""]
    lines += ["| true activity | frames | read right | read instead (frames) |",
              "|---|---|---|---|"]
    for truth, frames, share, wrong in rows:
        label = truth if truth in categories else f"{truth} (*not a category*)"
        instead = ", ".join(f"{read or 'nothing'} ({n})" for read, n in wrong[:3])
        lines.append(f"| {label} | {frames} | {share:.2f} | {instead} |")
    return lines + [""]
