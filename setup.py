"""pip install . : builds the medspheres Python module with this repository's CMake project.

The module is the C++ library bound with pybind11 (Debian: python3-pybind11, python3-numpy,
python3-dev); setuptools only drives CMake and copies the package it builds. There is no
pyproject.toml on purpose: pip then builds in the current environment (no isolated build
environment to download), so `pip install .` works without a network.
"""

import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def cmake_generated(build):
    """True when CMake finished generating a build system in `build`: the reply of the file API
    query that cmake_build places there exists. A configure that fails (three.js missing, say)
    leaves a CMakeCache.txt behind but no reply, and no Makefile to build with."""
    return any((build / ".cmake" / "api" / "v1" / "reply").glob("index-*.json"))


def cmake_build(build, configure, jobs):
    """Configures `build` when it has no CMake cache (with `configure`) or when its last
    configure did not finish (again, keeping the settings in its cache); then builds the
    medspheres_python target. A finished build folder keeps its settings."""
    query = build / ".cmake" / "api" / "v1" / "query" / "client-medspheres-setup" / "cache-v2"
    query.parent.mkdir(parents=True, exist_ok=True)
    query.touch()
    if not (build / "CMakeCache.txt").exists():
        subprocess.check_call(configure)
    elif not cmake_generated(build):
        subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build)])
    subprocess.check_call(["cmake", "--build", str(build), "-j", jobs,
                           "--target", "medspheres_python"])


class CMakeBuild(build_ext):
    """Configures (see cmake_build) and builds the medspheres_python target in build/pip, or in
    MEDSPHERES_PIP_BUILD_DIR (an existing build folder, for instance build); copies the package
    it makes."""

    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("MEDSPHERES_PIP_BUILD_DIR", ROOT / "build" / "pip"))
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DMEDSPHERES_BUILD_TESTS=OFF", "-DMEDSPHERES_BUILD_BENCH=OFF",
            "-DMEDSPHERES_BUILD_PYTHON=ON", f"-DMEDSPHERES_PYTHON_EXECUTABLE={sys.executable}",
            f"-DPython3_EXECUTABLE={sys.executable}",
        ]
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 1))
        cmake_build(build, configure, jobs)
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).parent
        target.mkdir(parents=True, exist_ok=True)
        for f in (build / "python" / "medspheres").iterdir():
            shutil.copy2(f, target / f.name)


def version():
    text = (ROOT / "CMakeLists.txt").read_text()
    return text.split("project(medspheres VERSION ", 1)[1].split()[0]


if __name__ == "__main__":  # pip runs this file as __main__; tests import it
    setup(
        name="medspheres",
        version=version(),
        description="Medial sphere sets of meshes and robots, their fit, and fast queries",
        license="GPL-3.0-or-later",
        packages=[],
        ext_modules=[Extension("medspheres._medspheres", sources=[])],
        cmdclass={"build_ext": CMakeBuild},
        install_requires=["numpy"],
        python_requires=">=3.9",
        zip_safe=False,
    )
