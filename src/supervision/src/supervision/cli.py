"""How every command-line tool of the workspace answers a user mistake: in one line.

    sys.exit(cli.run(main))        # scripts/<tool>: main(argv) -> exit status

A config file that cannot be used (`config_file.ConfigError` and the loaders' subclasses), an
input file that does not exist, or a `UsageError` the tool raises prints
"<tool>: error: <what was wrong>" on stderr and exits with status 2, as argparse does for a bad
option. Anything else is a bug and keeps its traceback. `--debug` anywhere on the command line
shows the traceback of a user mistake too.
"""
import sys
from pathlib import Path

from supervision.config_file import ConfigError

DEBUG_FLAG = "--debug"
USER_MISTAKE = 2     # exit status, as argparse's for a bad option


class UsageError(ValueError):
    """A tool was asked for something it cannot do; the message says what and why."""


def run(main, argv=None):
    """main(argv) with `--debug` taken out of argv (and sys.argv, for tools that read it);
    returns main's exit status, or 2 after one line on stderr for a user mistake."""
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = DEBUG_FLAG in argv
    argv = [arg for arg in argv if arg != DEBUG_FLAG]
    sys.argv[1:] = argv
    try:
        return main(argv)
    except (ConfigError, UsageError, FileNotFoundError) as error:
        if debug:
            raise
        print(f"{Path(sys.argv[0]).name}: error: {describe(error)}", file=sys.stderr)
        return USER_MISTAKE


def describe(error):
    """One line for a user mistake: a missing file named as such, else the error's message."""
    if isinstance(error, FileNotFoundError) and error.filename:
        return f"{error.filename}: no such file or directory"
    return str(error).splitlines()[0] if str(error) else type(error).__name__
