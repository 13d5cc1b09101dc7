"""Guard: every package's core modules import without rospy (docs/DESIGN.md, "ROS-free cores,
thin nodes").

ROS-layer modules are named `ros_*.py` or `conversions.py`; everything else under
src/<pkg>/src/<pkg>/ is core and must not pull rospy in, directly or through another module.

One interpreter imports the modules one after another and says after each whether rospy is loaded;
after a module that loaded rospy or failed, a fresh interpreter goes on with the rest. So each
verdict is the one a fresh interpreter importing that module alone would give, at the cost of a few
interpreter starts instead of one per module.
"""
import functools
import json
import subprocess
import sys
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / "src"


def core_modules():
    for path in sorted(SRC.glob("*/src/*/**/*.py")):
        if path.name.startswith("ros_") or path.name == "conversions.py":
            continue
        package_root = path.parents[len(path.relative_to(SRC).parts) - 3]
        module = ".".join(path.relative_to(package_root).with_suffix("").parts)
        yield module.removesuffix(".__init__")


MODULES = list(core_modules())

MARK = "probe-verdict\t"
PROBE = f"""
import importlib, json, sys, traceback
for module in sys.argv[1:]:
    try:
        importlib.import_module(module)
    except BaseException:
        print({MARK!r} + json.dumps([module, "error", traceback.format_exc()]), flush=True)
        sys.exit(0)
    loaded = "rospy" in sys.modules
    print({MARK!r} + json.dumps([module, "rospy" if loaded else "ok", ""]), flush=True)
    if loaded:
        sys.exit(0)
"""


@functools.cache
def verdicts():
    """{module: (verdict, detail)}: "ok", "rospy" (importing it loaded rospy) or "error"."""
    found = {}
    while len(found) < len(MODULES):
        rest = [module for module in MODULES if module not in found]
        run = subprocess.run([sys.executable, "-c", PROBE, *rest], capture_output=True, text=True)
        lines = [line[len(MARK):] for line in run.stdout.splitlines() if line.startswith(MARK)]
        if not lines:  # the interpreter died importing the first module
            found[rest[0]] = ("error", run.stderr)
        for module, verdict, detail in map(json.loads, lines):
            found[module] = (verdict, detail)
        if lines and run.returncode != 0:   # it failed after the last verdict (at exit)
            module = json.loads(lines[-1])[0]
            found[module] = ("error", f"the interpreter exited with {run.returncode} after "
                                      f"importing it: {run.stderr}")
    return found


def test_every_package_has_core_modules():
    packages = {module.split(".")[0] for module in MODULES}
    expected = {p.name for p in SRC.iterdir() if (p / "setup.py").is_file()}
    assert packages == expected


@pytest.mark.parametrize("module", MODULES)
def test_core_module_does_not_import_rospy(module):
    verdict, detail = verdicts()[module]
    assert verdict != "error", detail
    assert verdict == "ok", f"{module} imports rospy"
