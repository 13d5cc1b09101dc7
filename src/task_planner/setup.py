from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["task_planner", "task_planner.behaviours",
                                           "task_planner.tools"],
                                 package_dir={"": "src"}))
