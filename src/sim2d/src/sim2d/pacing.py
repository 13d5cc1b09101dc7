"""Pacing of the simulation loop: sim time = `speed` x wall time, as Stage and Gazebo keep it.

After a stall (another process holding the CPU, a loaded machine) the loop does not race to
make the lost time up, which would hand the nodes a burst of sim time faster than `speed`: once
it is more than `slip` wall seconds behind, it carries on from where it is and counts a slip.
A speed the loop cannot hold is told apart from a stall by the speed achieved over the last
`window` wall seconds: below `min_ratio` x `speed` it is a shortfall.
"""
from dataclasses import dataclass


@dataclass
class PacerConfig:
    speed: float                 # [-] sim seconds per wall second; <= 0: as fast as possible
    slip: float = 0.5            # [s] wall time behind schedule that counts as a slip
    window: float = 10.0         # [s] wall time over which the achieved speed is judged
    min_ratio: float = 0.9       # [-] achieved / requested below this over a window: shortfall


class Pacer:
    """`delay(sim, wall)` -> wall seconds to sleep before the next step; `slips` and
    `seconds_lost` count the stalls; `shortfall(sim, wall)` -> the speed achieved over the last
    full window when it fell short of the requested one, else None."""

    def __init__(self, config: PacerConfig, sim: float, wall: float) -> None:
        self.config = config
        self.base_sim, self.base_wall = sim, wall
        self.slips, self.seconds_lost = 0, 0.0
        self.window_sim, self.window_wall = sim, wall

    def delay(self, sim: float, wall: float) -> float:
        speed = self.config.speed
        if speed <= 0:
            return 0.0
        ahead = self.base_wall + (sim - self.base_sim) / speed - wall
        if ahead < -self.config.slip:
            self.slips += 1
            self.seconds_lost += -ahead
            self.base_sim, self.base_wall = sim, wall
            return 0.0
        return max(ahead, 0.0)

    def shortfall(self, sim: float, wall: float) -> float | None:
        """The achieved speed of the window just completed if below min_ratio x speed."""
        elapsed = wall - self.window_wall
        if self.config.speed <= 0 or elapsed < self.config.window:
            return None
        achieved = (sim - self.window_sim) / elapsed
        self.window_sim, self.window_wall = sim, wall
        return achieved if achieved < self.config.min_ratio * self.config.speed else None
