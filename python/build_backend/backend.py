"""setuptools' build backend, plus CMake from PyPI when the machine has no cmake.

setup.py builds the Fortran library with CMake; a machine with Debian's cmake
(or any on the PATH) uses it, one without gets the `cmake` wheel in pip's
isolated build environment.
"""
import shutil

from setuptools import build_meta as _setuptools
from setuptools.build_meta import *  # noqa: F401,F403  (the backend's other hooks, unchanged)


def _cmake():
    return [] if shutil.which("cmake") else ["cmake>=3.18"]


def get_requires_for_build_wheel(config_settings=None):
    return _setuptools.get_requires_for_build_wheel(config_settings) + _cmake()


def get_requires_for_build_editable(config_settings=None):
    return _setuptools.get_requires_for_build_editable(config_settings) + _cmake()
