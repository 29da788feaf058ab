# The Python package occlusion_env (python/occlusion_env), installed by catkin: catkin_make makes
# it importable from the devel space, catkin_make install copies it to the install space. The
# compiled modules (_core, _agents) are built by CMakeLists.txt next to it. Not run by hand.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["occlusion_env"], package_dir={"": "python"}))
