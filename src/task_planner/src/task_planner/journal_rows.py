"""What is wrong with one row of a task buffer journal or fleet pool, before it is loaded.

SQLite keeps any value in any column, so a row written by hand, by another program or by an
older version may hold NULL or text in a number column, a BLOB in a text column, or a state
this code does not know. `column_problem` names the first such column, so the task buffer
quarantines the row with the reason instead of raising at every start (a respawning executor
would crash-loop on it); `fields_problem` does the same for the JSON of a fleet pool row.
"""
INTEGER, NUMBER, TEXT = "an integer", "a number", "text"

# the journal's columns in table order (task_buffer._COLUMNS) and the kind of value each holds
COLUMNS = (("id", INTEGER), ("previous_id", INTEGER), ("gamma", NUMBER), ("beta", NUMBER),
           ("destination", INTEGER), ("type", INTEGER), ("start_time", NUMBER),
           ("duration", INTEGER), ("source", TEXT), ("target", TEXT), ("status", INTEGER),
           ("function", INTEGER), ("destination_name", TEXT), ("text", TEXT),
           ("state", INTEGER), ("received_time", NUMBER), ("started_time", NUMBER),
           ("completion_time", NUMBER), ("reward_earned", NUMBER), ("reason", TEXT),
           ("seq", INTEGER))


def column_problem(row: tuple, state_names: tuple) -> str:
    """"" when every column of `row` (journal column order) holds a value of its kind and the
    state is one of `state_names` (index = state); else the first problem, naming the column."""
    for (name, kind), value in zip(COLUMNS, row):
        problem = value_problem(value, kind)
        if problem:
            return f"column {name} {problem}"
    state = row[14]
    if not 0 <= state < len(state_names):
        known = ", ".join(f"{i} {name}" for i, name in enumerate(state_names))
        return f"column state holds {state}, not a state ({known})"
    return ""


def fields_problem(values: object) -> str:
    """"" when `values` maps Instruction field names to values of their kind (a fleet pool row's
    JSON); else the first problem, naming the field."""
    if not isinstance(values, dict):
        return f"holds {type(values).__name__} {values!r:.40}, not an instruction's fields"
    kinds = dict(COLUMNS[:14])
    unknown = sorted(set(values) - set(kinds))
    if unknown:
        return f"unknown field(s) {', '.join(map(str, unknown))}"
    missing = [name for name in ("id", "gamma", "beta", "destination") if name not in values]
    if missing:
        return f"no field(s) {', '.join(missing)}"
    for name, value in values.items():
        problem = value_problem(value, kinds[name])
        if problem:
            return f"field {name} {problem}"
    return ""


def value_problem(value: object, kind: str) -> str:
    """"" when `value` (as sqlite3 returns it) is of `kind`; else what it is instead."""
    if value is None:
        return f"is NULL, not {kind}"
    if isinstance(value, bytes):
        return f"holds a BLOB ({len(value)} bytes), not {kind}"
    if kind == TEXT:
        return "" if isinstance(value, str) else f"holds {value!r}, not text"
    if isinstance(value, str):
        shown = value if len(value) <= 20 else value[:20] + "..."
        return f"holds text {shown!r}, not {kind}"
    if kind == INTEGER and not isinstance(value, int):
        return f"holds {value!r}, not {kind}"
    return ""   # a number out of range: Instruction names the rule it breaks
