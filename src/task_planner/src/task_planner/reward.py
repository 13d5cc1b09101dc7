"""Decaying reward of thesis 000 (Eq. 4-2) and the priority table of Table 5-5."""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml
from numpy.typing import ArrayLike


class PriorityError(ValueError):
    """The priority file is missing, malformed, or breaks Eq. 4-2's constraints."""


def decayed_reward(gamma: ArrayLike, beta: ArrayLike, elapsed_s: ArrayLike) -> np.ndarray:
    """Eq. 4-2: r_i(t) = gamma_i * beta_i ** t_i, t_i = time from launch to completion [s].

    Works element-wise on numpy arrays.
    """
    return np.asarray(gamma, dtype=float) * np.power(beta, elapsed_s)


@dataclass(frozen=True)
class Priority:
    """One row of Table 5-5."""

    name: str
    gamma: float  # initial reward, > 0
    beta: float   # decay factor per second, in (0, 1)


def load_priorities(path: str | Path) -> dict[str, Priority]:
    """Read config/priorities.yaml into {name: Priority}, highest gamma first."""
    try:
        document = yaml.safe_load(Path(path).read_text())
    except (OSError, yaml.YAMLError) as error:
        raise PriorityError(f"{path}: cannot read priorities: {error}") from error
    table = (document or {}).get("priorities") if isinstance(document, dict) else None
    if not isinstance(table, dict) or not table:
        raise PriorityError(f"{path}: expected a non-empty mapping under 'priorities'")
    priorities = {}
    for name, row in table.items():
        try:
            gamma, beta = float(row["gamma"]), float(row["beta"])
        except (TypeError, KeyError, ValueError) as error:
            raise PriorityError(
                f"{path}: priority '{name}' needs numeric gamma and beta") from error
        if gamma <= 0 or not 0 < beta < 1:
            raise PriorityError(f"{path}: priority '{name}': need gamma > 0 and 0 < beta < 1, "
                                f"got gamma={gamma}, beta={beta}")
        priorities[name] = Priority(name, gamma, beta)
    return dict(sorted(priorities.items(), key=lambda item: -item[1].gamma))
