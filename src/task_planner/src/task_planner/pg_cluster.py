"""A throw-away PostgreSQL 15 cluster in a temporary folder, on 127.0.0.1 only (ROS-free).

For tests of the fleet pool's PostgreSQL backend: `initdb` makes the cluster (one superuser
`fleet`, trust authentication: it listens on 127.0.0.1 and on a socket in its own folder only),
`pg_ctl` starts and stops it on a free port, `create_database` gives a fresh database's URL.
Durability is traded for speed (fsync off): the cluster is thrown away. Run as root (initdb
refuses root), the cluster's programs run as `nobody` and its folder belongs to that user.
Every step is bounded in time; a failure raises PgClusterError with the program's output.
"""
import os
import pwd
import shutil
import socket
import subprocess
import tempfile
from typing import Any

PG_BIN = "/usr/lib/postgresql/15/bin"
SUPERUSER = "fleet"
STEP_TIMEOUT_S = 60.0   # initdb, a start or a stop takes this long at most


class PgClusterError(RuntimeError):
    """The cluster could not be made, started or stopped; the message says why."""


class PgCluster:
    """start() it (or use it as a context), then `create_database`; `remove` stops it and
    deletes its folder. `stop` / `start` again keep its data and port (a server restart)."""

    def __init__(self, bin_dir: str = PG_BIN) -> None:
        missing = [name for name in ("initdb", "pg_ctl", "postgres")
                   if not os.access(os.path.join(bin_dir, name), os.X_OK)]
        if missing:
            raise PgClusterError(f"PostgreSQL server programs {missing} not found in {bin_dir}: "
                                 "install Debian's postgresql (scripts/setup does)")
        self.bin_dir, self.port = bin_dir, 0
        self.folder: str | None = None
        self._user = "nobody" if os.geteuid() == 0 else None
        self._databases = 0

    def __enter__(self) -> "PgCluster":
        return self.start()

    def __exit__(self, *_: Any) -> None:
        self.remove()

    def start(self) -> "PgCluster":
        """Make the cluster (the first time) and start its server; returns self."""
        if self.folder is None:
            self.folder = tempfile.mkdtemp(prefix="pg_cluster_")
            if self._user:
                entry = pwd.getpwnam(self._user)
                os.chown(self.folder, entry.pw_uid, entry.pw_gid)
            self._run("initdb", "-D", self._data(), "-U", SUPERUSER, "--auth=trust", "-N",
                      "-E", "UTF8", "--locale=C.UTF-8")
            self.port = _free_port()
        self._run("pg_ctl", "-D", self._data(), "-l", os.path.join(self._made(), "server.log"),
                  "-w", "-t", str(int(STEP_TIMEOUT_S)), "-o",
                  f"-c listen_addresses=127.0.0.1 -p {self.port} -c unix_socket_directories="
                  f"{self.folder} -c fsync=off -c full_page_writes=off", "start")
        return self

    def stop(self) -> None:
        """Stop the server (fast: open sessions are ended), keeping the cluster."""
        self._run("pg_ctl", "-D", self._data(), "-m", "fast", "-w", "-t",
                  str(int(STEP_TIMEOUT_S)), "stop")

    def running(self) -> bool:
        return self.folder is not None and os.path.exists(os.path.join(self._data(),
                                                                       "postmaster.pid"))

    def remove(self) -> None:
        """Stop the server if it runs and delete the cluster's folder."""
        if self.folder is None:
            return
        try:
            if self.running():
                self.stop()
        finally:
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None

    def url(self, database: str = "postgres") -> str:
        return f"postgresql://{SUPERUSER}@127.0.0.1:{self.port}/{database}"

    def create_database(self, name: str | None = None) -> str:
        """A new empty database (`name`, else the next `db<n>`); returns its URL."""
        import psycopg2   # only where PostgreSQL is used
        self._databases += 1
        name = name or f"db{self._databases}"
        db = psycopg2.connect(self.url(), connect_timeout=10)
        try:
            db.autocommit = True
            db.cursor().execute(f'CREATE DATABASE "{name}" STRATEGY FILE_COPY')
        finally:
            db.close()
        return self.url(name)

    def _data(self) -> str:
        return os.path.join(self._made(), "data")

    def _made(self) -> str:
        """The cluster's folder; PgClusterError before `start` made it (or after `remove`)."""
        if self.folder is None:
            raise PgClusterError("the PostgreSQL cluster is not made: start it first")
        return self.folder

    def _run(self, program: str, *args: str) -> None:
        command = [os.path.join(self.bin_dir, program), *args]
        if self._user:
            command = ["runuser", "-u", self._user, "--", *command]
        try:
            done = subprocess.run(command, capture_output=True, text=True, timeout=STEP_TIMEOUT_S,
                                  cwd=self.folder, check=False)
        except subprocess.TimeoutExpired:
            raise PgClusterError(f"{program} took more than {STEP_TIMEOUT_S:.0f} s") from None
        if done.returncode != 0:
            log = os.path.join(self._made(), "server.log")
            tail = open(log).read()[-800:] if os.path.exists(log) else ""
            raise PgClusterError(f"{' '.join(command)} failed ({done.returncode}): "
                                 f"{done.stderr.strip()[-800:]}\n{tail}")


def _free_port() -> int:
    """A TCP port on 127.0.0.1 nobody listens on now."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port: int = probe.getsockname()[1]
        return port

