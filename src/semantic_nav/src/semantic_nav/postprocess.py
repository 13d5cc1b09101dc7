"""Post-processing layer (thesis 002 §2.2.5): speed adjusting (Eq. 2.2-12) and the halting
counter (§2.2.5.2)."""
import math
from dataclasses import dataclass


@dataclass
class PostprocessConfig:
    """§2.2.5 values."""

    v_min: float = 1e-3     # |output| at or below this means "stop" [m/s] or [rad/s]
    v_move: float = 2e-2    # slowest speed the robot can really move with [m/s] or [rad/s]
    halt_steps: int = 50    # zero outputs in a row that end a simple instruction (≈ 5 s)
    stop_threshold: float = 0.5   # beyond the seed: stop-head output above this -> (0, 0) [1]


def apply_stop(v: float, w: float, stop_probability: float | None,
               config: PostprocessConfig | None = None) -> tuple[float, float]:
    """Beyond the seed: a network with a stop head (network.NetworkConfig.stop_head) that says
    "standing at the goal" (probability > stop_threshold) outputs (0, 0), which the halting
    counter then counts; without a stop head (None) the raw output passes unchanged."""
    config = config or PostprocessConfig()
    if stop_probability is not None and stop_probability > config.stop_threshold:
        return 0.0, 0.0
    return v, w


def adjust_speed(v: float, config: PostprocessConfig | None = None) -> float:
    """Eq. 2.2-12: f(v) = 0 if |v| <= v_min; sgn(v) * v_move if v_min < |v| <= v_move; else v.

    Applied to the moving and to the rotating velocity alike (§2.2.5.1)."""
    config = config or PostprocessConfig()
    magnitude = abs(v)
    if magnitude <= config.v_min:
        return 0.0
    if magnitude <= config.v_move:
        return math.copysign(config.v_move, v)
    return float(v)


class HaltingCounter:
    """§2.2.5.2: counts consecutive (0, 0) outputs; `update` returns True on the step the count
    reaches `halt_steps` (the stopping signal), and the count starts again from zero."""

    def __init__(self, config: PostprocessConfig | None = None) -> None:
        self.config = config or PostprocessConfig()
        self.count = 0

    def reset(self) -> None:
        self.count = 0

    def update(self, v: float, w: float) -> bool:
        """Feed one post-processed command; True when the simple instruction is finished."""
        self.count = self.count + 1 if v == 0.0 and w == 0.0 else 0
        if self.count >= self.config.halt_steps:
            self.count = 0
            return True
        return False
