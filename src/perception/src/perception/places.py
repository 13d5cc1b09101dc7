"""Place names of a semantic graph (maps/<map>.graph.yaml) and their node ids."""
from pathlib import Path

import yaml


class PlaceGraphError(ValueError):
    """The semantic graph file is missing or malformed; the message names the file."""


def place_ids_from_dict(data, where="graph"):
    """{place name: node id} from a parsed graph YAML mapping (its `nodes` list)."""
    try:
        ids = {str(node["name"]): int(node["id"]) for node in data["nodes"]}
    except (KeyError, TypeError, ValueError) as error:
        raise PlaceGraphError(f"{where}: every node needs a name and an integer id ({error})") \
            from error
    if len(set(ids.values())) != len(ids):
        raise PlaceGraphError(f"{where}: node ids must be unique; got {sorted(ids.values())}")
    return ids


def load_place_ids(path):
    """{place name: node id} of maps/<map>.graph.yaml."""
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text())
    except (OSError, yaml.YAMLError) as error:
        raise PlaceGraphError(f"cannot read semantic graph {path}: {error}") from error
    return place_ids_from_dict(data, str(path))
