"""A behaviours' Context on a small graph, for the tests of task_planner.behaviours."""
from task_planner.baselines import FirstComeFirstServe
from task_planner.behaviours.context import Context, ExecutorConfig
from task_planner.behaviours.fleet_sync import fleet_sync
from task_planner.behaviours.tree import build_tree
from task_planner.fleet_link import FleetLink
from task_planner.fleet_pool import FleetPool
from task_planner.people_belief import PeopleAtPlaces
from task_planner.planner_api import NODE, kind_of
from task_planner.robot_functions import load_robot_functions
from task_planner.task_buffer import BufferConfig, TaskBuffer
from tamp_resources import resource

FUNCTIONS = load_robot_functions(resource("config") / "robot_functions.yaml")
A, B, C, D = range(4)  # line_graph: A -1- B -2- C -3- D (metres), 0.5 m/s


def make_context(graph, tmp_path, node=A, people=None, planner=None, **config):
    """A Context whose decide hooks are wired (build_tree), with FCFS unless told."""
    planner = planner or FirstComeFirstServe()
    ctx = Context(TaskBuffer(tmp_path / "buffer.sqlite", BufferConfig(node_count=graph.size)),
                  graph, planner, people or PeopleAtPlaces(), FUNCTIONS,
                  ExecutorConfig(speed_mps=0.5, **config), node=node,
                  node_planner=kind_of(planner) == NODE)
    build_tree(ctx)
    return ctx


def journal(ctx, *instructions, now=0.0):
    """Journal `instructions` (no reaction); their records."""
    return [record for record, _ in ctx.buffer.submit_many(list(instructions), now)]


def robots(graph, tmp_path, **config):
    """Robots a (at A) and b (at D), each with its journal, on one pool; both rejoined."""
    made = []
    for name, node in (("a", A), ("b", D)):
        (tmp_path / name).mkdir()
        ctx = make_context(graph, tmp_path / name, node=node, **config)
        ctx.fleet = FleetLink(FleetPool(tmp_path / "pool.sqlite"), name)
        assert fleet_sync(ctx, 0.0) == [] and ctx.in_fleet
        made.append(ctx)
    return made
