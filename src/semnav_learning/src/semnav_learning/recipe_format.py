"""What a training recipe's parts share (semnav_learning.recipe, recipe_units): the error a
recipe that cannot run raises, and the Trainer log lines that mark progress."""
import re

from supervision import config_file

# Trainer lines that end a part of a training unit -> what the parts are
PROGRESS_LINE = {"epochs": re.compile(r"^Epoch (\d+)/(\d+) - "),
                 "Z_w batches": re.compile(r"^Z_w: (\d+)/(\d+) batches")}
# The Trainer line of a resumed training: parts done in an earlier run
RESUME_LINE = re.compile(r"^resuming after epoch (\d+)/(\d+) ")


class RecipeError(config_file.ConfigError):
    """A recipe that cannot run: names the key (or unit) that is wrong."""
