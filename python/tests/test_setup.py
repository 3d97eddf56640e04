"""setup.py (pip install .): when it configures CMake and when it only builds.

The build folders are real CMake folders of a tiny project (configured in a fraction of a
second); the calls setup.py would make on the medspheres project are recorded, not run."""

import importlib.util
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent.parent


@pytest.fixture()
def setup_py(monkeypatch):
    """setup.py as a module, its subprocess calls recorded in .calls instead of run."""
    spec = importlib.util.spec_from_file_location("medspheres_setup", ROOT / "setup.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.calls = []
    monkeypatch.setattr(module.subprocess, "check_call", lambda args: module.calls.append(args))
    return module


def tiny_project(tmp_path, fail):
    """A CMake project that configures in an instant, or stops with an error like a missing
    three.js does (message(FATAL_ERROR) during configure)."""
    src = tmp_path / "src"
    src.mkdir()
    (src / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.16)\nproject(tiny NONE)\n"
        + ('message(FATAL_ERROR "three.js is not installed")\n' if fail else "")
        + "add_custom_target(medspheres_python)\n"
    )
    return src


def configure_tiny(setup_py, tmp_path, fail):
    """Configures the tiny project into tmp_path/build the way setup.py's first run does (its
    file API query placed, then cmake run); returns the build folder."""
    src, build = tiny_project(tmp_path, fail), tmp_path / "build"
    setup_py.cmake_build(build, ["cmake", "-S", str(src), "-B", str(build)], "1")
    r = subprocess.run(setup_py.calls[0], capture_output=True, text=True)
    assert (r.returncode != 0) == fail, r.stderr
    assert (build / "CMakeCache.txt").exists()  # a failed configure leaves its cache behind
    setup_py.calls.clear()
    return build


def test_a_failed_configure_is_configured_again(setup_py, tmp_path):
    build = configure_tiny(setup_py, tmp_path, fail=True)
    assert not setup_py.cmake_generated(build)
    setup_py.cmake_build(build, ["cmake", "-S", "unused", "-B", str(build)], "1")
    assert [c[:2] for c in setup_py.calls] == [["cmake", "-S"], ["cmake", "--build"]]
    assert setup_py.calls[0] == ["cmake", "-S", str(ROOT), "-B", str(build)]  # keeps its cache


def test_a_finished_build_folder_is_only_built(setup_py, tmp_path):
    build = configure_tiny(setup_py, tmp_path, fail=False)
    assert setup_py.cmake_generated(build)
    setup_py.cmake_build(build, ["cmake", "-S", "unused", "-B", str(build)], "1")
    assert setup_py.calls == [["cmake", "--build", str(build), "-j", "1", "--target",
                               "medspheres_python"]]


def test_a_new_build_folder_is_configured_with_the_given_command(setup_py, tmp_path):
    build = tmp_path / "build"
    configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DMEDSPHERES_BUILD_PYTHON=ON"]
    setup_py.cmake_build(build, configure, "1")
    assert setup_py.calls[0] == configure
    assert setup_py.calls[1][:2] == ["cmake", "--build"]
