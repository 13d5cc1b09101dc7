"""Errors of the human database; each names what was wrong so a caller can say it to a person."""


class HumanDbError(Exception):
    """Base of every error the human database raises on purpose."""


class InvalidHuman(HumanDbError, ValueError):
    """A record, colour, schedule or household file from outside breaks a rule of the database."""


class InvalidColour(InvalidHuman):
    """A shirt colour is not 3 joints x RGB integers in 0-255."""


class UnknownHuman(HumanDbError, LookupError):
    """No household member has the requested name or phone IP."""

    def __str__(self) -> str:  # LookupError would quote the message like a dict key
        return str(self.args[0]) if self.args else ""


class DuplicateHuman(HumanDbError):
    """A registration repeats an existing name or phone IP."""


class DatabaseUnusable(HumanDbError):
    """The database file is corrupted, foreign or newer than this code: it is left untouched."""


class StoreBusy(HumanDbError):
    """SQLite stayed locked past the retry budget (another process holds a long write)."""
