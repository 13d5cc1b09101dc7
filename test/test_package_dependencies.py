"""Guard: the packages depend on each other in one direction (docs/DESIGN.md, "Layers").

The runtime packages run on the robot; the simulator and the navigation mocks stand in for the
hardware and the navigation stack; bringup and learning put the system together and train it.
A runtime package never imports or declares the simulation, bringup or learning packages, every
import of a workspace package is declared in package.xml, the package graph has no cycle, no
package finds its files by path arithmetic (`parents[`, `.parent.parent`, `../../../`): it asks
rospkg, tamp_resources.resource() or `$(find ...)`, and no library module builds a path from a
workspace root (outputs default under tamp_resources.workspace()).
"""
import ast
import functools
import re
from pathlib import Path

import pytest
from catkin_pkg.package import parse_package

SRC = Path(__file__).resolve().parent.parent / "src"
RUNTIME = {"perception", "human_db", "task_planner", "semantic_nav", "penguin_base"}
BASE = {"floorplan", "supervision", "tamp_msgs", "tamp_resources"}
SIMULATION = {"sim2d", "nav_mocks"}
SYSTEM = {"tamp_bringup", "semnav_learning"}
PACKAGES = {p.name: parse_package(p / "package.xml") for p in sorted(SRC.iterdir())
            if (p / "package.xml").is_file()}


def run_depends(package):
    """Workspace packages that `package` needs to build or run (tests excluded)."""
    declared = (package.build_depends + package.buildtool_depends + package.exec_depends
                + package.build_export_depends)
    return {d.name for d in declared} & PACKAGES.keys()


def declared_test_depends(package):
    return {d.name for d in package.test_depends} & PACKAGES.keys()


def python_files(package_dir, parts):
    """Python sources of a package under `parts` (src, nodes, test, scripts), scripts included."""
    for part in parts:
        root = package_dir / part
        if not root.is_dir():
            continue
        for path in sorted(root.rglob("*")):
            if not path.is_file() or "__pycache__" in path.parts:
                continue
            if path.suffix == ".py" or (path.suffix == "" and path.read_bytes()[:64].startswith(
                    b"#!") and b"python" in path.read_bytes()[:64]):
                yield path


@functools.cache   # two tests read the runtime packages' files
def imported_packages(path):
    """Top-level names of the workspace packages that a Python file imports."""
    tree = ast.parse(path.read_text(), str(path))
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names.add(node.module.split(".")[0])
    return names & PACKAGES.keys()


def test_the_layers_are_all_there():
    assert RUNTIME | BASE | SIMULATION | SYSTEM == PACKAGES.keys()


@pytest.mark.parametrize("name", sorted(RUNTIME | BASE))
def test_runtime_packages_declare_no_simulator_mock_bringup_or_learning(name):
    package = PACKAGES[name]
    forbidden = (SIMULATION | SYSTEM) & (run_depends(package) | declared_test_depends(package))
    assert not forbidden, f"{name}/package.xml depends on {sorted(forbidden)}"


@pytest.mark.parametrize("name", sorted(RUNTIME | BASE))
def test_runtime_packages_import_no_simulator_mock_bringup_or_learning(name):
    offenders = {str(path.relative_to(SRC)): sorted(imported_packages(path) & (SIMULATION | SYSTEM))
                 for path in python_files(SRC / name, ("src", "nodes", "test", "scripts"))}
    assert not {k: v for k, v in offenders.items() if v}


@pytest.mark.parametrize("name", sorted(PACKAGES))
def test_every_imported_package_is_declared(name):
    package, missing = PACKAGES[name], {}
    for parts, declared in ((("src", "nodes", "scripts"), run_depends(package)),
                            (("test",), run_depends(package) | declared_test_depends(package))):
        for path in python_files(SRC / name, parts):
            undeclared = imported_packages(path) - declared - {name}
            if undeclared:
                missing[str(path.relative_to(SRC))] = sorted(undeclared)
    assert not missing, f"imports not declared in {name}/package.xml: {missing}"


def test_the_package_graph_has_no_cycle():
    graph = {name: run_depends(p) | declared_test_depends(p) for name, p in PACKAGES.items()}
    done, on_path = set(), []

    def visit(name):
        if name in on_path:
            cycle = on_path[on_path.index(name):] + [name]
            raise AssertionError("package cycle: " + " -> ".join(cycle))
        if name in done:
            return
        on_path.append(name)
        for dependency in sorted(graph[name]):
            visit(dependency)
        on_path.pop()
        done.add(name)

    for name in sorted(graph):
        visit(name)


PATH_ARITHMETIC = re.compile(
    r"parents\[|\.parent\.parent|\.\./\.\./\.\.|\"\.\.\", \"\.\.\", \"\.\.\"")
# folders of the workspace (and of tamp_resources): a library reaches them only through
# tamp_resources.resource() (config, maps, models, urdf) or tamp_resources.workspace() (outputs)
WORKSPACE_FOLDERS = {"config", "maps", "models", "urdf", "build", "docs", "scripts", "src",
                     "launch", "devel"}
FOLDER_GIVERS = {"resource", "workspace"}
ROOT_NAME = re.compile(r"(^|_)(root|ws|workspace|repo)($|_)", re.IGNORECASE)
# modules whose subject is a workspace tree handed to them to inspect (not their own files)
INSPECT_A_WORKSPACE = {"tamp_bringup/src/tamp_bringup/doc_commands.py"}


def path_arithmetic(src):
    """Lines of the files under `src` that find files by path arithmetic -> ["file:line: text"]."""
    offenders = []
    for path in sorted(src.rglob("*")):
        if not path.is_file() or path.suffix not in {".py", ".launch", ".test", ".yaml", ""}:
            continue
        if "__pycache__" in path.parts or path.suffix == "" and b"\0" in path.read_bytes()[:512]:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if PATH_ARITHMETIC.search(line):
                offenders.append(f"{path.relative_to(src)}:{number}: {line.strip()}")
    return offenders


def _folder(node):
    """The workspace folder a string constant starts with ("build/x" -> "build"), else None."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        first = node.value.split("/")[0]
        return first if first in WORKSPACE_FOLDERS else None
    return None


def _root_named(node):
    """Whether `node` is a path named as a root (`root`, `self.root`, `Path(root)`, ...)."""
    while isinstance(node, ast.Call) and getattr(node.func, "id", None) in {"Path", "str"} \
            and node.args:
        node = node.args[0]
    name = node.attr if isinstance(node, ast.Attribute) else getattr(node, "id", "")
    return bool(ROOT_NAME.search(name))


def _gives_folders(node, givers):
    """Whether `node` is resource(...) / workspace() or a name bound to one at module level."""
    if isinstance(node, ast.Call):
        name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(
            node.func, "id", None)
        return name in FOLDER_GIVERS
    return isinstance(node, ast.Name) and node.id in givers


def _joins(node):
    """(base, first joined part) of `base / part`, `base.joinpath(part, ...)`,
    `Path(base, part, ...)` and `os.path.join(base, part, ...)`, else None."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Div):
        return node.left, node.right
    if isinstance(node, ast.Call) and node.args:
        name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(
            node.func, "id", None)
        if name == "joinpath" and isinstance(node.func, ast.Attribute):
            return node.func.value, node.args[0]
        if name in {"Path", "join"} and len(node.args) > 1:
            return node.args[0], node.args[1]
    return None


def roots_handed_down(src):
    """Lines of the library modules under `src` (<pkg>/src/) that join a workspace folder onto a
    root (a path named root, workspace, ws or repo) that is not resource() / workspace(): a
    workspace root handed down or worked out."""
    offenders = []
    for path in sorted(src.glob("*/src/**/*.py")):
        if str(path.relative_to(src)) in INSPECT_A_WORKSPACE:
            continue
        tree = ast.parse(path.read_text(), str(path))
        givers = {target.id for node in tree.body if isinstance(node, ast.Assign)
                  and _gives_folders(node.value, set()) for target in node.targets
                  if isinstance(target, ast.Name)}
        for node in ast.walk(tree):
            joined = _joins(node)
            if joined and _folder(joined[1]) and _root_named(joined[0]) \
                    and not _gives_folders(joined[0], givers):
                offenders.append(f"{path.relative_to(src)}:{node.lineno}: "
                                 f"{ast.unparse(node)}")
    return sorted(offenders)


def _mentions_file(node, rooted):
    return any(isinstance(n, ast.Name) and (n.id == "__file__" or n.id in rooted)
               for n in ast.walk(node))


def roots_passed_to_libraries(path, packages):
    """Calls in a script that hand a workspace package a path worked out from the script's own
    location (`Path(__file__)...`) -> ["file:line: call"]."""
    tree = ast.parse(path.read_text(), str(path))
    imported, rooted = set(), set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and \
                node.module.split(".")[0] in packages:
            imported |= {alias.asname or alias.name for alias in node.names}
        elif isinstance(node, ast.Import):
            imported |= {(alias.asname or alias.name).split(".")[0] for alias in node.names
                         if alias.name.split(".")[0] in packages}
        elif isinstance(node, ast.Assign) and _mentions_file(node.value, set()):
            rooted |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    offenders = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        callee = node.func
        while isinstance(callee, ast.Attribute):
            callee = callee.value
        arguments = [*node.args, *(k.value for k in node.keywords)]
        if isinstance(callee, ast.Name) and callee.id in imported and any(
                _mentions_file(a, rooted) for a in arguments):
            offenders.append(f"{path.name}:{node.lineno}: {ast.unparse(node)}")
    return offenders


def test_no_package_finds_its_files_by_path_arithmetic():
    assert not path_arithmetic(SRC), "\n".join(path_arithmetic(SRC))


def test_no_library_module_builds_a_path_from_a_workspace_root():
    offenders = roots_handed_down(SRC)
    scripts = [*python_files(SRC.parent, ("scripts",))] + [
        path for name in PACKAGES for path in python_files(SRC / name, ("scripts", "nodes"))]
    for path in scripts:
        offenders += roots_passed_to_libraries(path, PACKAGES.keys())
    assert not offenders, "\n".join(offenders)


def test_the_path_guards_catch_a_root_in_a_library_module(tmp_path):
    """The guards above report a `.parent.parent` chain, a root joined onto a workspace folder
    and a script that hands its own location to a library; resource() / workspace() pass."""
    library = tmp_path / "src" / "pkg" / "src" / "pkg"
    library.mkdir(parents=True)
    (library / "paths.py").write_text(
        "from pathlib import Path\n"
        "from tamp_resources import resource, workspace\n"
        "ROOT = resource()\n"
        "HERE = Path(__file__).resolve().parent.parent\n"
        "def main(root):\n"
        "    return root / 'config' / 'x.yaml', Path(root, 'build'), root.joinpath('docs/a')\n"
        "def fine():\n"
        "    return ROOT / 'maps', resource('config'), workspace() / 'build' / 'x'\n")
    script = tmp_path / "tool"
    script.write_text("#!/usr/bin/env python3\nfrom pathlib import Path\n"
                      "from pkg.paths import main\nmain(Path(__file__).resolve().parent)\n")
    assert path_arithmetic(tmp_path / "src") == [
        "pkg/src/pkg/paths.py:4: HERE = Path(__file__).resolve().parent.parent"]
    assert roots_handed_down(tmp_path / "src") == [
        f"pkg/src/pkg/paths.py:6: {call}" for call in (
            "Path(root, 'build')", "root / 'config'", "root.joinpath('docs/a')")]
    assert roots_passed_to_libraries(script, {"pkg"}) == [
        "tool:4: main(Path(__file__).resolve().parent)"]


def module_name(path, src=SRC):
    """The dotted module name of a library file src/<pkg>/src/<module path>.py; a node or script
    (src/<pkg>/nodes/<name>) is named by its path, as nothing imports it."""
    parts = path.relative_to(src).parts
    if parts[1] != "src":
        return "/".join(parts)
    return ".".join(Path(*parts[2:]).with_suffix("").parts).removesuffix(".__init__")


def module_imports(path, modules, name=None):
    """The workspace library modules a file imports (at any depth: lazy imports count; relative
    imports resolved against `name`, the importer's module)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level and name:
                package = name.split(".")[:-node.level + (path.name == "__init__.py") or None]
                module = ".".join([*package, *([module] if module else [])])
            if module:
                found |= {module} | {f"{module}.{alias.name}" for alias in node.names}
    return found & modules


def import_graph(src=SRC):
    """{module: the workspace modules it imports} over the library modules under
    src/<pkg>/src/ and the nodes under src/<pkg>/nodes/."""
    paths = {module_name(path, src): path for path in sorted(src.glob("*/src/*/**/*.py"))}
    paths |= {module_name(path, src): path for name in sorted(p.name for p in src.iterdir())
              for path in python_files(src / name, ("nodes",))}
    modules = set(paths)
    return {name: module_imports(path, modules, name) - {name} for name, path in paths.items()}


def import_cycles(graph):
    """The sets of modules that import each other, directly or round a loop (strongly connected
    components of more than one module), each sorted."""
    index, low, stack, on_stack, cycles = {}, {}, [], set(), []

    def visit(module):
        index[module] = low[module] = len(index)
        stack.append(module)
        on_stack.add(module)
        for other in sorted(graph[module]):
            if other not in index:
                visit(other)
                low[module] = min(low[module], low[other])
            elif other in on_stack:
                low[module] = min(low[module], index[other])
        if low[module] == index[module]:
            component = []
            while not component or component[-1] != module:
                component.append(stack.pop())
                on_stack.discard(component[-1])
            if len(component) > 1:
                cycles.append(sorted(component))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return cycles


def test_import_cycles_are_found(tmp_path):
    """A loop of three modules (one through a relative, lazy import) is reported; a module that
    only imports into the loop, and a node, are not part of it."""
    graph = {"a.x": {"a.y"}, "a.y": {"a.z"}, "a.z": {"a.x"}, "a.w": {"a.x"}, "b.v": set()}
    assert import_cycles(graph) == [["a.x", "a.y", "a.z"]]
    assert import_cycles({"a.x": {"a.y"}, "a.y": set()}) == []
    library = tmp_path / "pkg" / "src" / "pkg"
    (library / "tools").mkdir(parents=True)
    (tmp_path / "pkg" / "nodes").mkdir()
    for name, text in {"__init__.py": "", "tools/__init__.py": "",
                       "x.py": "from pkg import y\n",
                       "y.py": "import pkg.tools.z\n",
                       "tools/z.py": "def late():\n    from ..x import late\n",
                       "w.py": "from pkg.x import late\n"}.items():
        (library / name).write_text(text)
    (tmp_path / "pkg" / "nodes" / "run").write_text("#!/usr/bin/env python3\nimport pkg.w\n")
    graph = import_graph(tmp_path)
    assert graph["pkg/nodes/run"] == {"pkg.w"}
    assert import_cycles(graph) == [["pkg.tools.z", "pkg.x", "pkg.y"]]


def test_no_two_library_modules_import_each_other():
    cycles = import_cycles(import_graph())
    assert not cycles, "modules that import each other: " + "; ".join(
        " <-> ".join(cycle) for cycle in cycles)
