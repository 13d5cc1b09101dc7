"""task_planner.behaviours.tree: the executor's tree, its priorities and its drawing."""
from pathlib import Path

import rospkg

from behaviour_factories import B, C, make_context
from planner_factories import make_instruction

from task_planner.behaviours.context import ARRIVED, RECEIVED, TICK
from task_planner.behaviours.tree import build_tree, drawing, tick
from task_planner.executor_commands import Navigate


def test_the_drawing_shows_every_behaviour_in_priority_order(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    text = drawing(build_tree(ctx))
    names = ["fleet: news, closed, lease", "battery low: charge", "predecessors overdue",
             "person seen elsewhere", "execute", "stand and look", "look around", "drive",
             "decide: serve, drive or patrol", "arrive", "recover: ask to pass, retry, fail",
             "take in, give way, decide again", "cancel"]
    positions = [text.index(name) for name in names]
    assert positions == sorted(positions)
    # every event spends the battery and syncs with the fleet first (a tick: in its news)
    assert text.count("spend battery") == 4 and text.count("fleet: owed commands, rejoin") == 5


def test_one_event_runs_one_branch_and_shows_it(line_graph, tmp_path):
    ctx = make_context(line_graph, tmp_path)
    root = build_tree(ctx)
    commands = tick(root, ctx, RECEIVED, 0.0, inbox=[make_instruction(1, C, function=1)])
    assert commands == [Navigate(B, 1)]
    assert "take in, give way, decide again [✓]" in drawing(root)
    assert tick(root, ctx, TICK, 0.5) == []                 # driving: nothing new
    assert "drive [*]" in drawing(root)                     # running
    assert tick(root, ctx, ARRIVED, 2.0) == [Navigate(C, 1)]
    assert (ctx.node, ctx.goal) == (B, C) and ctx.buffer.get(1).is_open


def test_the_readme_draws_the_tree_as_it_is(line_graph, tmp_path):
    """The drawing in the package README is the tree of a robot driving to serve."""
    ctx = make_context(line_graph, tmp_path)
    root = build_tree(ctx)
    tick(root, ctx, RECEIVED, 0.0, inbox=[make_instruction(1, C, function=1)])
    tick(root, ctx, TICK, 0.5)
    readme = (Path(rospkg.RosPack().get_path("task_planner")) / "README.md").read_text()
    assert "```\n" + drawing(root).rstrip("\n") + "\n```" in readme
