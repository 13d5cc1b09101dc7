"""The executor's behaviour tree (py_trees): the one place that shows what the robot does at
each event and in which priority. The tree is ticked once per event (an arrival, an abort, new
instructions, a cancel, a periodic tick); the leaves' commands collect in Context.out.

    [o] executor                        (selector: the event's branch)
        [-] tick       tick? · fleet sync · fleet news · battery low: charge (spends it first)
                       · predecessors overdue · person seen elsewhere (decide again)
            [o] activity  (selector: the leaf of the robot's mode steps it; a step that
                           changes the mode hands on to the next leaves in the same tick)
                --> execute           (finish when its time is up)
                --> stand and look    (the person turns up, or search on)
                --> look around       (the person is seen, or turn on)
                --> drive             (after a wait, send the goal again)
                --> decide: serve, drive or patrol
        [-] arrived    arrived? · spend battery · fleet sync · arrive
        [-] aborted    aborted? · spend battery · fleet sync · recover: ask to pass, retry, fail
        [-] received   received? · spend battery · fleet sync · take in, give way, decide again
        [-] cancelled  cancelled? · spend battery · fleet sync · cancel

A fleet sync that stopped the robot (what it drove for is another robot's now) fails the
arrival or abort it came with.
"""
from typing import Any

import py_trees
from py_trees.common import Status
from py_trees.composites import Selector, Sequence

from task_planner.behaviours import deciding
from task_planner.behaviours.charging import check_battery, drain
from task_planner.behaviours.context import (ABORTED, ARRIVED, CANCELLED, RECEIVED, TICK, Action,
                                             Context, IsEvent)
from task_planner.behaviours.deciding import Deciding
from task_planner.behaviours.driving import Arriving, Driving
from task_planner.behaviours.dropping import Cancelling
from task_planner.behaviours.fleet_sync import FleetSync, fleet_news
from task_planner.behaviours.looking import LookingAround, StandingToLook
from task_planner.behaviours.receiving import TakingIn
from task_planner.behaviours.recovery import Recovering
from task_planner.behaviours.serving import Executing, give_up_waiting
from task_planner.executor_commands import Command


def build_tree(ctx: Context) -> Selector:
    """The executor's tree over `ctx` (whose decide/redecide hooks it sets)."""
    ctx.decide = lambda now: deciding.decide(ctx, now)
    ctx.redecide = lambda now: deciding.redecide(ctx, now)

    def spend_battery() -> Action:
        return Action("spend battery", ctx, lambda c: drain(c, c.now))

    def branch(event: str, *leaves: py_trees.behaviour.Behaviour) -> Sequence:
        return Sequence(event, memory=False, children=[IsEvent(ctx, event), *leaves])

    activity = Selector("activity", memory=False, children=[
        Executing(ctx), StandingToLook(ctx), LookingAround(ctx), Driving(ctx), Deciding(ctx)])
    # one branch per event (they exclude each other); the periodic tick, the most frequent, first
    return Selector("executor", memory=False, children=[
        branch(TICK, FleetSync(ctx),
               Action("fleet: news, closed, lease", ctx, lambda c: fleet_news(c, c.now)),
               Action("battery low: charge", ctx, lambda c: check_battery(c, c.now)),
               Action("predecessors overdue", ctx, lambda c: give_up_waiting(c, c.now)),
               Action("person seen elsewhere", ctx, lambda c: deciding.seen_elsewhere(c, c.now)),
               activity),
        branch(ARRIVED, spend_battery(), FleetSync(ctx), Arriving(ctx)),
        branch(ABORTED, spend_battery(), FleetSync(ctx), Recovering(ctx)),
        branch(RECEIVED, spend_battery(), FleetSync(ctx), TakingIn(ctx)),
        branch(CANCELLED, spend_battery(), FleetSync(ctx), Cancelling(ctx))])


def tick(root: Selector, ctx: Context, event: str, now: float, **details: Any) -> list[Command]:
    """Handle one event: set it and its details on the context (the others' reset), tick the
    tree once; returns the commands."""
    ctx.event, ctx.now, ctx.out, ctx.synced = event, now, [], []
    ctx.inbox, ctx.results, ctx.reason, ctx.cancelled = [], [], "", None
    for name, value in details.items():
        setattr(ctx, name, value)
    if ctx.event != TICK or root.children[0].status != Status.RUNNING:
        root.stop(Status.INVALID)   # the drawing shows this event's statuses only
    root.tick_once()
    return ctx.out


def drawing(root: Selector) -> str:
    """The tree as text with each node's status of the last tick (py_trees' unicode view)."""
    return py_trees.display.unicode_tree(root, show_status=True)
