"""Instruction ids that a perception node never hands out twice, across restarts too.

The task buffer refuses an id it already journalled with other content, so a node that restarted
its counter at `first_id` would have its new instructions refused. The counter keeps the last id
it handed out in a small file, written (and synced) before the id is returned, so the instruction
carrying it is only published once the id is on disk: a restart continues after it.
"""
import os
from pathlib import Path


class IdCounter:
    """Consecutive ids from `first_id`, continuing after the last one recorded in `path`."""

    def __init__(self, first_id=1, path=None):
        if first_id < 1:
            raise ValueError(f"first_id must be >= 1, got {first_id}")
        self.path = Path(path) if path else None   # None: in memory only (tests, tools)
        last = self._read_last() if self.path and self.path.exists() else 0
        self._next = max(int(first_id), last + 1)

    def _read_last(self):
        text = self.path.read_text().strip()
        try:
            return int(text)
        except ValueError:
            raise ValueError(f"{self.path}: expected the last instruction id (an integer), "
                             f"got {text[:40]!r}") from None

    @property
    def next_id(self):
        """The id `take` returns next."""
        return self._next

    def take(self):
        """The next id, recorded durably before it is returned."""
        instruction_id = self._next
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            temporary = self.path.with_name(self.path.name + ".tmp")
            with open(temporary, "w") as stream:
                stream.write(f"{instruction_id}\n")
                stream.flush()
                os.fsync(stream.fileno())
            os.replace(temporary, self.path)
        self._next += 1
        return instruction_id
