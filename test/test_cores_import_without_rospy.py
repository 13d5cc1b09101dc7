"""Guard: every package's core modules import without rospy (the one rule of DESIGN.md).

ROS-layer modules are named `ros_*.py` or `conversions.py`; everything else under
src/<pkg>/src/<pkg>/ is core and must not pull rospy in, directly or through another module.
"""
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


def test_every_package_has_core_modules():
    packages = {module.split(".")[0] for module in MODULES}
    expected = {p.name for p in SRC.iterdir() if (p / "setup.py").is_file()}
    assert packages == expected


@pytest.mark.parametrize("module", MODULES)
def test_core_module_does_not_import_rospy(module):
    probe = f"import sys, {module}; print('rospy' in sys.modules)"
    result = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "False", f"{module} imports rospy"
