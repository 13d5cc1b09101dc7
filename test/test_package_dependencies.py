"""Guard: the packages depend on each other in one direction (docs/DESIGN.md, "Layers").

The runtime packages run on the robot; the simulator and the navigation mocks stand in for the
hardware and the navigation stack; bringup and learning put the system together and train it.
A runtime package never imports or declares the simulation, bringup or learning packages, every
import of a workspace package is declared in package.xml, the package graph has no cycle, and no
package finds its files by path arithmetic (`parents[`, `../../../`): it asks rospkg or
`$(find ...)`.
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


PATH_ARITHMETIC = re.compile(r"parents\[|\.\./\.\./\.\.|\"\.\.\", \"\.\.\", \"\.\.\"")


def test_no_package_finds_its_files_by_path_arithmetic():
    offenders = []
    for path in sorted(SRC.rglob("*")):
        if not path.is_file() or path.suffix not in {".py", ".launch", ".test", ".yaml", ""}:
            continue
        if "__pycache__" in path.parts or path.suffix == "" and b"\0" in path.read_bytes()[:512]:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if PATH_ARITHMETIC.search(line):
                offenders.append(f"{path.relative_to(SRC)}:{number}: {line.strip()}")
    assert not offenders, "\n".join(offenders)


def module_name(path):
    """The dotted module name of a library file src/<pkg>/src/<module path>.py."""
    package_root = path.parents[len(path.relative_to(SRC).parts) - 3]
    return ".".join(path.relative_to(package_root).with_suffix("").parts).removesuffix(
        ".__init__")


def module_imports(path, modules):
    """The workspace library modules a file imports (at any depth: lazy imports count)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found |= {node.module} | {f"{node.module}.{alias.name}" for alias in node.names}
    return found & modules


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


def test_import_cycles_are_found():
    graph = {"a.x": {"a.y"}, "a.y": {"a.z"}, "a.z": {"a.x"}, "a.w": {"a.x"}, "b.v": set()}
    assert import_cycles(graph) == [["a.x", "a.y", "a.z"]]
    assert import_cycles({"a.x": {"a.y"}, "a.y": set()}) == []


def test_no_two_library_modules_import_each_other():
    paths = {module_name(path): path for path in sorted(SRC.glob("*/src/*/**/*.py"))}
    modules = set(paths)
    graph = {name: module_imports(path, modules) - {name} for name, path in paths.items()}
    assert import_cycles(graph) == []
