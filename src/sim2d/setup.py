from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["sim2d", "sim2d.tools"],
                                 package_dir={"": "src"}))
