from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["semnav_learning", "semnav_learning.tools"],
                                 package_dir={"": "src"}))
