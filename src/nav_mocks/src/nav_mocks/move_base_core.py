"""move_base mock, ROS-free: goal checks, global planning, DWA control, recovery, outcomes.

One `step()` per control cycle. Goal states use actionlib_msgs/GoalStatus numbers. The recovery
sequence is move_base's conservative one: when the robot is blocked (no admissible trajectory for
controller_patience) or makes no progress (less than oscillation_distance in oscillation_timeout),
or the planner finds no path, it first clears the costmap's laser marks and replans, then rotates
in place once; if it is still stuck the goal is ABORTED with the reason. A robot wedged in a door
(no admissible trajectory, or none that makes progress) is first backed out: it translates
straight, slowly, in the direction that gains the most clearance without coming closer to any
obstacle it is already within the collision radius of, then replans from there.

A goal in an obstacle or closer than the robot radius to one (e.g. a person standing on a place's
pose) is moved to the nearest free pose reachable from the robot within goal_search_radius of it,
keeping the requested heading (`global_planner.nearest_free_cell`). The search runs when the goal
arrives and at every replan, always from the requested goal, so the goal returns there when the
obstacle leaves; a moved goal that is still free and reachable is kept, so a goal beside another
robot does not jump from side to side of it as its laser marks flicker. The move is reported in
`StepResult.goal_note`; when no free pose is found the goal is REJECTED (on arrival) or ABORTED
(later), the reason naming the goal and the radius.
"""
import math
from dataclasses import dataclass, field

import numpy as np

from nav_mocks.clearance import ContactClearance
from nav_mocks.costmap import LETHAL_OBSTACLE
from nav_mocks.dwa import DwaController
from nav_mocks.global_planner import (GlobalPlanner, NoPath, goal_cells, nearest_free_cell,
                                      reachable_cells)
from nav_mocks.param_checks import non_negative_number, positive_number
from nav_mocks.pose2d import distance, wrap_angle
from nav_mocks.scan_rays import beam_cells, hit_points

# actionlib_msgs/GoalStatus values
PENDING, ACTIVE, PREEMPTED, SUCCEEDED, ABORTED, REJECTED = 0, 1, 2, 3, 4, 5
ZERO = (0.0, 0.0, 0.0)
CLEAR, BACK_OUT, ROTATE = "clear_costmaps", "back_out", "rotate_recovery"
BACK_OUT_DIRECTIONS = 16   # [-] headings tried by the back-out recovery (base frame)
BACK_OUT_STEP = 0.025      # [m] spacing of the clearance checks along a back-out line


@dataclass
class MoveBaseConfig:
    planner_frequency: float = 1.0       # [Hz] replanning rate while a goal is active
    controller_patience: float = 3.0     # [s] blocked this long -> recovery
    oscillation_timeout: float = 10.0    # [s] no progress this long -> recovery
    oscillation_distance: float = 0.3    # [m] progress that resets the oscillation timer
    recovery_behaviors: tuple = (CLEAR, BACK_OUT, ROTATE)  # tried in order
    rotation_angle: float = 2.0 * math.pi  # [rad] turned by the rotate recovery
    back_out_distance: float = 0.3       # [m] driven by the back-out recovery
    back_out_speed: float = 0.1          # [m/s]
    goal_search_radius: float = 1.0      # [m] a blocked goal moves to the nearest free pose
                                         # within this distance; 0 = never moved

    def validate(self):
        positive_number("planner_frequency", self.planner_frequency, "Hz")
        positive_number("controller_patience", self.controller_patience, "s")
        non_negative_number("goal_search_radius", self.goal_search_radius, "m")
        unknown = set(self.recovery_behaviors) - {CLEAR, BACK_OUT, ROTATE}
        if unknown:
            raise ValueError(f"move_base: unknown recovery behaviour(s) {sorted(unknown)}")


@dataclass
class StepResult:
    cmd: tuple                      # (vx [m/s], vy [m/s], wz [rad/s]) in the base frame
    status: int                     # GoalStatus value of the current goal
    reason: str = ""                # why a goal ended ABORTED / REJECTED / PREEMPTED
    new_plan: object = None         # a Plan made in this step (for /plan), else None
    goal_note: str = ""             # how the goal was moved off an obstacle ("" = not moved)


@dataclass
class _GoalRun:
    goal: tuple                     # (x, y, yaw) map frame: the pose driven to
    requested: tuple = None         # (x, y, yaw) the goal as sent (goal differs when moved)
    goal_note: str = ""             # how goal was moved off an obstacle ("" = goal is requested)
    status: int = ACTIVE
    reason: str = ""
    plan: object = None
    last_plan_time: float = -math.inf
    blocked_since: object = None    # time the controller first found no trajectory
    progress_pose: object = None
    progress_time: float = 0.0
    recovery_index: int = 0
    rotating: bool = False
    backing: object = None          # back-out: (unit direction in the map frame, start pose)
    rotated: float = 0.0
    last_yaw: float = 0.0
    xy_reached: bool = False
    history: list = field(default_factory=list)  # recoveries run, for diagnostics


class MoveBaseCore:
    def __init__(self, costmap, config=None, dwa_config=None, planner_config=None):
        self.config = config or MoveBaseConfig()
        self.config.validate()
        self.costmap = costmap
        self.planner = GlobalPlanner(costmap, planner_config)
        self.controller = DwaController(dwa_config, costmap.config)
        self.run = None
        self.scan_points = np.zeros((0, 2))   # last laser hits, map frame [m]

    # goal life cycle ---------------------------------------------------------------------------
    def check_goal(self, goal):
        """Reason to REJECT a goal (outside the map, in an obstacle or unknown), else ''."""
        reason = self.check_goal_place(goal)
        if reason:
            return reason
        x, y, _ = goal
        row, col = self.costmap.grid.world_to_cell(x, y)
        if self.costmap.static_lethal[row, col] or self.costmap.costs()[row, col] == \
                LETHAL_OBSTACLE:
            return f"goal ({x:.2f}, {y:.2f}) lies in an obstacle"
        return ""

    def check_goal_place(self, goal):
        """Reason no goal can be made of `goal` (not finite, outside the map, in unknown space
        when unknown is lethal), else ''. Obstacles are left to free_goal."""
        x, y, yaw = goal
        if not all(math.isfinite(v) for v in (x, y, yaw)):
            return f"goal ({x}, {y}, {yaw}) is not finite"
        grid = self.costmap.grid
        row, col = grid.world_to_cell(x, y)
        if not grid.inside(row, col):
            return f"goal ({x:.2f}, {y:.2f}) lies outside the map"
        if grid.cells[row, col] < 0 and self.costmap.config.unknown_is_lethal:
            return f"goal ({x:.2f}, {y:.2f}) lies in unknown space"
        return ""

    def start_goal(self, goal, now, pose):
        """Accept (ACTIVE) or reject (REJECTED) a new goal; a running goal is preempted.

        Returns (status, text): the reason of a rejection, or for an accepted goal that was
        moved off an obstacle how it was moved ("" when it was not)."""
        reason = self.check_goal_place(goal)
        if reason:
            return REJECTED, reason
        requested = tuple(float(v) for v in goal)
        target, note = self.free_goal(requested, pose)
        if target is None:
            return REJECTED, note
        self.run = _GoalRun(goal=target, requested=requested, goal_note=note,
                            progress_pose=pose, progress_time=now)
        return ACTIVE, note

    def free_goal(self, requested, pose, kept=None):
        """(goal, note) for a robot at `pose`: the requested goal and "" when its cell is free;
        when it lies in an obstacle or closer than the robot radius to one, `kept` (goal, note)
        when its goal's cell is free and reachable (a goal moved before), else the nearest free
        cell reachable from the robot within goal_search_radius, with the requested heading,
        and a note saying so; (None, reason naming the goal and the radius) when there is none.
        """
        x, y, yaw = requested
        grid = self.costmap.grid
        row, col = grid.world_to_cell(x, y)
        blocked = self.planner.blocked_cells(pose[:2])
        if not blocked[row, col]:
            return requested, ""
        start = self.planner.cell_of(pose[0], pose[1], "robot")
        costs = self.costmap.costs()
        ends = goal_cells(costs)
        if kept is not None:
            cell = grid.world_to_cell(kept[0][0], kept[0][1])
            if ends[cell] and reachable_cells(blocked, start)[cell]:
                return kept   # still free and reachable
        lethal = costs[row, col] == LETHAL_OBSTACLE
        what = ("lies in an obstacle" if lethal
                else "is closer than the robot radius to an obstacle")
        radius = self.config.goal_search_radius
        found = (nearest_free_cell(grid, blocked, start, (x, y), radius, ends) if radius > 0
                 else None)
        if found is None:
            return None, (f"goal ({x:.2f}, {y:.2f}) {what} and no free pose reachable from the "
                          f"robot lies within {radius:.2f} m of it (goal_search_radius)")
        fx, fy = (float(v) for v in grid.cell_to_world(*found))
        moved = math.hypot(fx - x, fy - y)
        return (fx, fy, yaw), (f"goal ({x:.2f}, {y:.2f}) {what}: moved {moved:.2f} m to "
                               f"({fx:.2f}, {fy:.2f}), heading kept")

    def cancel(self, reason="cancelled"):
        if self.run is not None and self.run.status == ACTIVE:
            self.run.status, self.run.reason = PREEMPTED, reason

    @property
    def active(self):
        return self.run is not None and self.run.status == ACTIVE

    def make_plan(self, start, goal, tolerance=0.0):
        """make_plan service: a Plan between two map points, or NoPath (does not touch a run).

        tolerance [m]: nav_msgs/GetPlan's, see GlobalPlanner.plan."""
        return self.planner.plan(start[:2], goal[:2], tolerance)

    # control cycle -----------------------------------------------------------------------------
    def observe(self, scan, laser_pose):
        """Obstacle layer update from a scan taken at laser_pose (map frame); keeps its hits."""
        cfg = self.costmap.config
        free, hit = beam_cells(scan, laser_pose, self.costmap.grid, cfg.raytrace_range,
                               cfg.obstacle_range)
        self.costmap.update_from_scan(free, hit)
        # The controller keeps the hits of obstacles the map does not have (_unmapped_hits); the
        # map's walls it takes from the static contact region, with contact_margin for the
        # localisation error.
        self.scan_points = hit_points(scan, laser_pose, cfg.obstacle_range)

    def step(self, now, pose, velocity):
        """One control cycle: pose (x, y, yaw) map frame, velocity (vx, vy, wz) base frame.

        Uses the laser hits of the last observe() for the local costmap."""
        run = self.run
        if run is None or run.status != ACTIVE:
            return StepResult(ZERO, run.status if run else PENDING, run.reason if run else "",
                              goal_note=run.goal_note if run else "")
        new_plan = None
        due = now - run.last_plan_time >= 1.0 / self.config.planner_frequency
        if not run.rotating and run.backing is None and (run.plan is None or due):
            new_plan = self._replan(run, now, pose)
        if run.status != ACTIVE or (run.plan is None and not run.rotating
                                    and run.backing is None):
            return StepResult(ZERO, run.status, run.reason, new_plan, run.goal_note)
        cmd = self._control(run, now, pose, velocity)
        return StepResult(cmd, run.status, run.reason, new_plan, run.goal_note)

    def _replan(self, run, now, pose):
        """Replan. Without a path: abort at once if only the static map is in the way (nothing
        to recover), else run the next recovery behaviour (abort when none is left)."""
        run.last_plan_time = now
        try:
            moved = (run.goal, run.goal_note) if run.goal_note else None
            target, note = self.free_goal(run.requested or run.goal, pose, kept=moved)
            if target is None:
                raise NoPath(note)
            if target != run.goal:
                run.goal, run.xy_reached = target, False
            run.goal_note = note
            run.plan = self.planner.plan(pose[:2], run.goal[:2])
        except NoPath as error:
            run.plan = None
            if not self.costmap.marked.any() and run.recovery_index == 0:
                self._abort(run, str(error))
            else:
                self._recover(run, now, pose, str(error))
            return None
        self.controller.set_plan(run.plan.points)
        return run.plan

    def _abort(self, run, reason):
        run.status, run.reason = ABORTED, reason

    def _control(self, run, now, pose, velocity):
        if run.rotating:
            return self._rotate_recovery(run, pose, velocity)
        if run.backing is not None:
            return self._back_out(run, now, pose)
        if run.xy_reached or self.controller.at_goal_xy(pose, run.goal):
            run.xy_reached = True  # latch_xy_goal_tolerance: finish by turning in place
            cmd, done = self.controller.rotate_to(pose, run.goal, velocity)
            if done:
                run.status = SUCCEEDED
            return cmd
        self._track_progress(run, now, pose)
        local = self._local_clearance()
        cmd = self.controller.best_command(pose, velocity, local)
        if cmd is not None:
            run.blocked_since = None
            return cmd
        run.blocked_since = now if run.blocked_since is None else run.blocked_since
        if now - run.blocked_since >= self.config.controller_patience:
            self._recover(run, now, pose, "blocked: no collision-free trajectory")
        return ZERO

    def _track_progress(self, run, now, pose):
        if distance(pose, run.progress_pose) >= self.config.oscillation_distance:
            run.progress_pose, run.progress_time = pose, now
            run.recovery_index = 0
        elif now - run.progress_time >= self.config.oscillation_timeout:
            self._recover(run, now, pose, "no progress")

    def _recover(self, run, now, pose, why):
        """Run the next recovery behaviour, or abort when all have been tried."""
        behaviours = self.config.recovery_behaviors
        if run.recovery_index >= len(behaviours):
            self._abort(run, f"stuck ({why}) after recovery: {', '.join(behaviours)}")
            return
        behaviour = behaviours[run.recovery_index]
        run.recovery_index += 1
        run.history.append(behaviour)
        run.blocked_since = None
        run.progress_pose, run.progress_time = pose, now
        if behaviour == CLEAR:
            self.costmap.clear_obstacles()
            run.last_plan_time = -math.inf   # replan on the next cycle
        elif behaviour == BACK_OUT:
            direction = self._back_out_direction(pose)
            if direction is None:            # nowhere to go: try the next behaviour at once
                self._recover(run, now, pose, why)
                return
            run.backing = (direction, pose)
        else:
            run.rotating, run.rotated, run.last_yaw = True, 0.0, pose[2]

    def _rotate_recovery(self, run, pose, velocity):
        run.rotated += abs(wrap_angle(pose[2] - run.last_yaw))
        run.last_yaw = pose[2]
        if run.rotated >= self.config.rotation_angle:
            run.rotating = False
            run.last_plan_time = -math.inf
            return ZERO
        cfg = self.controller.config
        w = min(cfg.max_vel_theta, abs(velocity[2]) + cfg.acc_lim_theta * cfg.control_period)
        return (0.0, 0.0, float(np.copysign(w, 1.0)))

    def _local_clearance(self):
        """The controller's clearance model (clearance.ContactClearance): the static map's
        contact region and the last scan's hits of obstacles not on the map. `pose` is unused
        (the model covers the whole map); kept so that every caller names where it asks."""
        subdivision = self.controller.config.clearance_subdivision
        return ContactClearance(self.costmap.contact_depth(subdivision), subdivision,
                                self.costmap.grid, self.costmap.config.robot_radius,
                                self._unmapped_hits())

    def _unmapped_hits(self):
        """(M, 2) hits of the last scan that are not a wall of the static map (inside the grid
        and farther than static_match_distance from a map obstacle; off the grid: kept)."""
        points = self.scan_points
        if not len(points):
            return np.zeros((0, 2))
        grid = self.costmap.grid
        rows, cols = grid.world_to_cell(points[:, 0], points[:, 1])
        inside = grid.inside(rows, cols)
        keep = ~inside
        keep[inside] = self.costmap.new_obstacle(rows[inside], cols[inside])
        return points[keep]

    def _back_out_direction(self, pose):
        """Map-frame unit vector of the straight line of back_out_distance whose end has the most
        clearance, among lines that never come closer than the robot is now to an obstacle
        within the collision radius (nor below it elsewhere); None when there is no such line.
        A differential-drive base may only reverse."""
        local = self._local_clearance()
        limit = self.controller.collision_radius(local)
        here = float(local.clearance(np.array([pose[0]]), np.array([pose[1]]))[0])
        floor = min(here, limit)
        if self.controller.config.holonomic:
            angles = pose[2] + np.linspace(0.0, 2.0 * math.pi, BACK_OUT_DIRECTIONS, endpoint=False)
        else:
            angles = np.array([pose[2] + math.pi])
        steps = np.arange(1, int(math.ceil(self.config.back_out_distance / BACK_OUT_STEP)) + 1)
        along = steps[None, :] * BACK_OUT_STEP
        xs = pose[0] + np.cos(angles)[:, None] * along
        ys = pose[1] + np.sin(angles)[:, None] * along
        clearance = local.clearance(xs, ys)
        ok = (clearance >= floor).all(axis=1)
        if not ok.any():
            return None
        best = int(np.argmax(np.where(ok, clearance[:, -1], -np.inf)))
        return np.array([math.cos(angles[best]), math.sin(angles[best])])

    def _back_out(self, run, now, pose):
        """One cycle of the back-out recovery: translate along the chosen line until it is
        driven or the next step would come closer to an obstacle; then replan."""
        direction, start = run.backing
        cfg = self.config
        step = cfg.back_out_speed * self.controller.config.control_period
        ahead = np.array(pose[:2]) + direction * step
        local = self._local_clearance()
        here = float(local.clearance(np.array([pose[0]]), np.array([pose[1]]))[0])
        nxt = float(local.clearance(np.array([ahead[0]]), np.array([ahead[1]]))[0])
        floor = min(here, self.controller.collision_radius(local))
        if distance(pose, start) >= cfg.back_out_distance or nxt < floor:
            run.backing = None
            run.last_plan_time = -math.inf
            run.progress_pose, run.progress_time = pose, now   # backing out is not progress
            return ZERO
        c, s = math.cos(pose[2]), math.sin(pose[2])
        vx, vy = direction * cfg.back_out_speed
        return (float(c * vx + s * vy), float(-s * vx + c * vy), 0.0)
