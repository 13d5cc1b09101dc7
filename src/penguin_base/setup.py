from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["penguin_base", "penguin_base.tools"],
                                 package_dir={"": "src"}))
