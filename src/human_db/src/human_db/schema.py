"""The SQLite schema of the human database and its migrations.

`PRAGMA user_version` holds the schema version; migration i (1-based) takes a database from
version i-1 to version i inside one transaction, so a crash mid-migration leaves the old version.
"""
COLOUR_COLUMNS = tuple(f"{c}{j}" for j in (1, 2, 5) for c in "rgb")  # r1 g1 b1 r2 ... b5

_COLOUR_DEFS = ", ".join(f"{c} INTEGER NOT NULL CHECK ({c} BETWEEN 0 AND 255)"
                         for c in COLOUR_COLUMNS)

MIGRATIONS = (
    # v1: thesis 000 Table 3-1 as the seed describes it (one record per person, schedules).
    (
        f"""CREATE TABLE humans (
            id INTEGER PRIMARY KEY,
            name TEXT NOT NULL UNIQUE COLLATE NOCASE,
            ip TEXT NOT NULL DEFAULT '',
            gender TEXT NOT NULL CHECK (gender IN ('female', 'male')),
            age INTEGER NOT NULL CHECK (age BETWEEN 0 AND 255),
            {_COLOUR_DEFS},
            location TEXT NOT NULL DEFAULT '',
            activity TEXT NOT NULL DEFAULT '')""",
        """CREATE TABLE schedules (
            human_id INTEGER NOT NULL REFERENCES humans (id) ON DELETE CASCADE,
            start_s REAL NOT NULL,
            end_s REAL NOT NULL,
            place TEXT NOT NULL DEFAULT '',
            activity TEXT NOT NULL DEFAULT '')""",
        "CREATE INDEX schedules_by_human ON schedules (human_id)",
    ),
    # v2: when each person was last seen, the history of observations, one person per phone IP.
    (
        "ALTER TABLE humans ADD COLUMN last_seen REAL",
        """CREATE TABLE history (
            id INTEGER PRIMARY KEY,
            human_id INTEGER NOT NULL REFERENCES humans (id) ON DELETE CASCADE,
            time REAL NOT NULL,
            location TEXT NOT NULL,
            activity TEXT NOT NULL,
            source TEXT NOT NULL)""",
        "CREATE INDEX history_by_human_time ON history (human_id, time)",
        "CREATE UNIQUE INDEX humans_by_ip ON humans (ip) WHERE ip != ''",
    ),
    # v3: every shirt a person has been registered in (§3.2.3: "needs to update once the human
    # changes his/her clothes"); a clothes change keeps the old shirt here.
    (
        f"""CREATE TABLE shirts (
            id INTEGER PRIMARY KEY,
            human_id INTEGER NOT NULL REFERENCES humans (id) ON DELETE CASCADE,
            time REAL NOT NULL,
            {_COLOUR_DEFS},
            source TEXT NOT NULL)""",
        "CREATE INDEX shirts_by_human_time ON shirts (human_id, time)",
        f"""INSERT INTO shirts (human_id, time, {', '.join(COLOUR_COLUMNS)}, source)
            SELECT id, COALESCE(last_seen, 0), {', '.join(COLOUR_COLUMNS)}, 'migrated'
            FROM humans""",
    ),
    # v4: a person the robot has not met yet has no shirt (§3.2.3 Initialization phase: the
    # colours are stored when the robot meets them); their colour columns hold 0.
    (
        "ALTER TABLE humans ADD COLUMN shirt_known INTEGER NOT NULL DEFAULT 1 "
        "CHECK (shirt_known IN (0, 1))",
    ),
)

SCHEMA_VERSION = len(MIGRATIONS)
