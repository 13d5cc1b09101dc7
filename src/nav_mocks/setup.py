from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["nav_mocks", "nav_mocks.tools"],
                                 package_dir={"": "src"}))
