"""The commands the READMEs and docs pages show, checked against the workspace so each runs as
written: `rostest PKG FILE`, `roslaunch PKG FILE` and `rosrun PKG EXE` name a package that exists
and a file it holds, and `scripts/<x>` is a script of the workspace.

Only code is read (fenced blocks and inline code spans), never prose. A package is found among
the workspace's `package.xml` files, else through rospkg (ROS_PACKAGE_PATH). Files are found as
the ROS tools find them: roslaunch and rostest take a file of that name anywhere under the
package (roslib's find_resource); rosrun takes an executable file of that name anywhere under the
package or in the devel space's `lib/<pkg>/` (catkin_find's share and libexec folders).
"""
import dataclasses
import os
import re
from pathlib import Path

SKIPPED_DIRS = {"build", "devel", "node_modules", "__pycache__"}
COMMAND = re.compile(r"\b(rostest|roslaunch|rosrun)((?:\s+--?[\w-]+)*)\s+(?!-)([^\s`'\"|;&)]+)"
                     r"(?:\s+([^\s`'\"|;&)]+))?")
SCRIPT = re.compile(r"(?<![\w/.$:-])scripts/([\w.-]+)")   # not a/scripts/, rev:scripts/
PLACEHOLDER = re.compile(r"[<>${}*]|\.\.\.")
INLINE_CODE = re.compile(r"`([^`]+)`")


@dataclasses.dataclass(frozen=True)
class Command:
    """One command a doc shows: `tool` is rostest, roslaunch, rosrun or scripts."""

    doc: Path
    line: int
    tool: str
    package: str
    target: str

    def __str__(self):
        shown = f"scripts/{self.target}" if self.tool == "scripts" else \
            f"{self.tool} {self.package} {self.target}".rstrip()
        return f"{self.doc}:{self.line}: {shown}"


def doc_files(root):
    """Every README.md and every .md under docs/ of the workspace `root` (sorted, relative)."""
    root = Path(root)
    found = []
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if not d.startswith(".") and d not in SKIPPED_DIRS)
        here = Path(folder).relative_to(root)
        for name in sorted(files):
            in_docs = here.parts[:1] == ("docs",) and name.endswith(".md")
            if name == "README.md" or in_docs:
                found.append(here / name)
    return found


def code_lines(text):
    """(line number, code) for every line of a fenced block and every inline code span (one
    that a paragraph wraps over two lines is one code, at the line where it starts), in order."""
    fenced, prose, codes = False, [], []
    for number, line in enumerate(text.splitlines(), start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
            prose.append("")
        elif fenced:
            prose.append("")
            codes.append((number, re.sub(r"(^|\s)#.*", "", line)))   # a shell comment is prose
        else:
            prose.append(line)
    prose = "\n".join(prose)
    for match in INLINE_CODE.finditer(prose):
        if "\n\n" not in match.group(1):   # a stray backtick does not join paragraphs
            codes.append((prose.count("\n", 0, match.start()) + 1,
                          match.group(1).replace("\n", " ")))
    return sorted(codes)


def extract(doc, text):
    """The commands of one doc's `text`; `doc` (its path) is kept for the messages."""
    commands = []
    for number, code in code_lines(text):
        for match in COMMAND.finditer(code):
            tool, _, package, target = match.groups()
            if ":=" in package or package.endswith((".launch", ".test")):
                continue   # roslaunch of a path, or arguments: no package named
            target = "" if target is None or ":=" in target else target
            commands.append(Command(doc, number, tool, package, target))
        for match in SCRIPT.finditer(code):
            commands.append(Command(doc, number, "scripts", "", match.group(1)))
    return commands


class Workspace:
    """Finds packages and their files as the ROS tools do, for the workspace at `root`."""

    def __init__(self, root, fallback=None):
        self.root = Path(root)
        self.packages = {}
        for folder, dirs, files in os.walk(self.root):
            dirs[:] = [d for d in dirs if not d.startswith(".") and d not in SKIPPED_DIRS]
            if "package.xml" in files:
                name = re.search(r"<name>\s*([^<\s]+)\s*</name>",
                                 (Path(folder) / "package.xml").read_text())
                if name:
                    self.packages[name.group(1)] = Path(folder)
        self.fallback = _rospack_path if fallback is None else fallback

    def package_dir(self, name):
        if name in self.packages:
            return self.packages[name]
        return self.fallback(name)

    def holders(self, filename, executable=False):
        """The workspace packages that hold `filename` (for a hint)."""
        return sorted(name for name, folder in self.packages.items()
                      if _find(folder, filename, executable))

    def has_executable(self, package, folder, filename):
        libexec = self.root / "devel" / "lib" / package
        return _find(folder, filename, True) or _find(libexec, filename, True)


def _rospack_path(name):
    try:
        import rospkg
        return Path(rospkg.RosPack().get_path(name))
    except Exception:   # noqa: BLE001 - rospkg missing or the package unknown: not found
        return None


def _find(folder, filename, executable):
    if folder is None or not Path(folder).is_dir():
        return False
    for here, _, files in os.walk(folder, followlinks=True):
        if filename in files:
            path = Path(here) / filename
            if path.is_file() and (not executable or os.access(path, os.X_OK)):
                return True
    return False


def problem(command, workspace):
    """Why `command` would not run as written, or None when it would."""
    if command.tool == "scripts":
        if PLACEHOLDER.search(command.target) or (workspace.root / "scripts" /
                                                  command.target).is_file():
            return None
        return f"{command}: no file scripts/{command.target} in the workspace"
    if PLACEHOLDER.search(command.package):
        return None
    folder = workspace.package_dir(command.package)
    if folder is None:
        return f"{command}: no package {command.package}"
    if not command.target or PLACEHOLDER.search(command.target):
        return None
    if command.tool == "rosrun":
        if workspace.has_executable(command.package, folder, command.target):
            return None
        holders = workspace.holders(command.target, executable=True)
        what = "no executable"
    else:
        if _find(folder, command.target, False):
            return None
        holders = workspace.holders(command.target)
        what = "no file"
    hint = f" (it is in {', '.join(holders)})" if holders else ""
    return f"{command}: package {command.package} has {what} {command.target}{hint}"


def check(root, fallback=None):
    """Every problem of every doc command of the workspace `root`, one line each."""
    workspace = Workspace(root, fallback)
    problems = []
    for doc in doc_files(root):
        for command in extract(doc, (Path(root) / doc).read_text()):
            found = problem(command, workspace)
            if found:
                problems.append(found)
    return problems
