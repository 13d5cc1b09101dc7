"""AMCL mock: a pose estimate from the simulator's ground truth plus a noise and covariance model.

ROS-free. The estimate is truth + e(t) + o(t):
  * e(t) is first-order Gauss-Markov noise per axis (std sigma, correlation time tau): a particle
    filter's estimate wanders smoothly around the truth rather than jumping at every update;
  * o(t) is the error of the last initial pose (/initialpose), decaying as exp(-t / T_conv) when
    the initial pose lies within the convergence radius of the truth (the particle cloud then
    covers the true pose); farther off, AMCL would lock onto the wrong place, and so does the mock.
The reported covariance is sigma^2 plus the square of the remaining initial-pose error.
"""
import math
from dataclasses import dataclass

import numpy as np

from nav_mocks.pose2d import compose, inverse, wrap_angle


@dataclass
class AmclConfig:
    noise_xy_std: float = 0.02             # [m] std of the position error
    noise_yaw_std: float = 0.02            # [rad] std of the heading error
    noise_correlation_time: float = 2.0    # [s] Gauss-Markov time constant of the error
    convergence_time: float = 1.5          # [s] time constant of an initial-pose error's decay
    convergence_radius: float = 1.0        # [m] farther initial poses do not converge
    require_initial_pose: bool = False     # [-] "not localised" until an /initialpose arrives

    def validate(self):
        for name in ("noise_xy_std", "noise_yaw_std"):
            if getattr(self, name) < 0:
                raise ValueError(f"amcl: {name} must be >= 0, got {getattr(self, name)}")
        for name in ("noise_correlation_time", "convergence_time", "convergence_radius"):
            if getattr(self, name) <= 0:
                raise ValueError(f"amcl: {name} must be > 0, got {getattr(self, name)}")


def gauss_markov_step(error, dt, tau, sigma, rng):
    """Exact discretisation of dx = -x/tau dt + noise, stationary std sigma."""
    decay = math.exp(-max(dt, 0.0) / tau)
    return decay * error + math.sqrt(1.0 - decay * decay) * sigma * rng.standard_normal(error.shape)


def map_to_odom(map_pose, odom_pose):
    """tf map -> odom such that map->odom ⊕ odom->base_link equals the map-frame estimate."""
    return compose(map_pose, inverse(odom_pose))


def latest_pair(truths, odoms, max_gap):
    """The newest odometry sample with a ground-truth sample at (nearly) the same time.

    map -> odom = truth ⊕ odom⁻¹ holds only for poses of one instant: pairing the latest of each
    stream, which arrive through separate callbacks, turns the correction by however far the
    robot turned between them, and every scan placed through it is laid down turned.
    Args: truths, odoms: sequences of (stamp [s], pose), oldest first; max_gap [s].
    Returns: (truth_pose, odom_pose), or None when no odometry sample has a truth within
    max_gap.
    """
    if not truths:
        return None
    truth_stamps = np.array([stamp for stamp, _ in truths])
    for stamp, odom_pose in reversed(odoms):
        nearest = int(np.argmin(np.abs(truth_stamps - stamp)))
        if abs(truth_stamps[nearest] - stamp) <= max_gap:
            return truths[nearest][1], odom_pose
    return None


class AmclModel:
    """Pose estimates over time; call estimate() with increasing times."""

    def __init__(self, config=None, seed=0):
        self.config = config or AmclConfig()
        self.config.validate()
        self.rng = np.random.default_rng(seed)
        self.noise = np.zeros(3)             # e(t): x [m], y [m], yaw [rad]
        self.offset = np.zeros(3)            # o at the time of the initial pose
        self.offset_time = 0.0               # [s]
        self.converging = True
        self.localised = not self.config.require_initial_pose
        self.last_time = None

    def set_initial_pose(self, time, initial_pose, true_pose):
        """An /initialpose at `time`: the estimate starts there and converges when close enough."""
        dx, dy = initial_pose[0] - true_pose[0], initial_pose[1] - true_pose[1]
        self.offset = np.array([dx, dy, wrap_angle(initial_pose[2] - true_pose[2])])
        self.offset_time = time
        self.converging = math.hypot(dx, dy) <= self.config.convergence_radius
        self.localised = True

    def _remaining_offset(self, time):
        if not self.converging:
            return self.offset
        return self.offset * math.exp(-max(time - self.offset_time, 0.0)
                                      / self.config.convergence_time)

    def estimate(self, time, true_pose):
        """(pose (x, y, yaw), 6x6 row-major covariance list) at `time`, or None if not localised."""
        if not self.localised:
            return None
        cfg = self.config
        dt = 0.0 if self.last_time is None else time - self.last_time
        self.last_time = time
        sigma = np.array([cfg.noise_xy_std, cfg.noise_xy_std, cfg.noise_yaw_std])
        self.noise = gauss_markov_step(self.noise, dt, cfg.noise_correlation_time, sigma, self.rng)
        offset = self._remaining_offset(time)
        error = self.noise + offset
        pose = (true_pose[0] + error[0], true_pose[1] + error[1],
                wrap_angle(true_pose[2] + error[2]))
        return pose, self.covariance(offset)

    def covariance(self, offset):
        """PoseWithCovariance layout (x, y, z, roll, pitch, yaw), row-major, 36 floats."""
        cfg = self.config
        cov = np.zeros((6, 6))
        cov[0, 0] = cfg.noise_xy_std ** 2 + offset[0] ** 2
        cov[1, 1] = cfg.noise_xy_std ** 2 + offset[1] ** 2
        cov[5, 5] = cfg.noise_yaw_std ** 2 + offset[2] ** 2
        return cov.ravel().tolist()
