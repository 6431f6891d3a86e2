"""Build the demstep library with the repository's CMake project and bundle it.

`pip install ./python` (from the repository root) runs build_py below: CMake
configures the repository one directory up, builds the shared library and the
app, and the package gets demstep/_lib/libdemstep.so.0, the app `demstep` and
the header demstep.h (the package reads its enum values from it). The version
is fpm.toml's. The wheel is platform-specific (it holds a compiled library).
"""
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def version():
    text = (ROOT / "fpm.toml").read_text()
    return re.search(r'^version = "([0-9.]+)"', text, re.M).group(1)


def need(tool, packages):
    if shutil.which(tool) is None:
        raise SystemExit(f"demstep: building the library needs {tool}: on Debian, "
                         f"apt-get install -y {packages}")


class BuildLibrary(build_py):
    """build_py, then the Fortran library built by CMake into the package's _lib/."""

    def run(self):
        super().run()
        need("gfortran", "gfortran liblapack-dev libarpack2-dev")
        need("cmake", "cmake")
        target = Path(self.build_lib) / "demstep" / "_lib"
        target.mkdir(parents=True, exist_ok=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        with tempfile.TemporaryDirectory(prefix="demstep-build-") as build:
            log = Path(build) / "cmake.log"
            for command in (["cmake", "-S", str(ROOT), "-B", build, "-DCMAKE_BUILD_TYPE=Release",
                             "-DBUILD_SHARED_LIBS=ON"],
                            ["cmake", "--build", build, "-j", jobs, "--target", "demstep", "demstep-app"]):
                with open(log, "a") as out:
                    done = subprocess.run(command, stdout=out, stderr=subprocess.STDOUT)
                if done.returncode != 0:
                    print(log.read_text())
                    raise SystemExit(f"demstep: {' '.join(command)} failed (its output is above)")
            shutil.copy2(Path(build) / "libdemstep.so.0", target / "libdemstep.so.0", follow_symlinks=True)
            shutil.copy2(Path(build) / "demstep", target / "demstep")
        shutil.copy2(ROOT / "include" / "demstep.h", target / "demstep.h")


class BinaryDistribution(Distribution):
    """A wheel tagged for this platform: it carries a shared library."""

    def has_ext_modules(self):
        return True


setup(version=version(), cmdclass={"build_py": BuildLibrary}, distclass=BinaryDistribution)
