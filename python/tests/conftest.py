"""Fixtures of the medspheres Python tests: the CLI of the same build, the bundled meshes."""

import os
import pathlib
import shlex
import subprocess

import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent


def _cli_path():
    path = os.environ.get("MEDSPHERES_CLI")
    if path:
        return path
    candidate = ROOT / "build" / "bin" / "medspheres"
    if candidate.exists():
        return str(candidate)
    pytest.skip("no medspheres CLI (set MEDSPHERES_CLI)")


@pytest.fixture(scope="session")
def cli():
    """Runs the medspheres CLI: cli("bake", ...) -> CompletedProcess (text)."""
    exe = _cli_path()

    def run(*args, check=True):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError(
                f"medspheres {shlex.join(map(str, args))} exited {r.returncode}: {r.stderr}"
            )
        return r

    return run


@pytest.fixture(scope="session")
def examples():
    return pathlib.Path(os.environ.get("MEDSPHERES_EXAMPLES", ROOT / "examples" / "data"))


@pytest.fixture(scope="session")
def eight(examples):
    """A closed genus-2 mesh of 634 triangles."""
    return examples / "eight.off"


def box_obj(size, path):
    """Writes a closed box (12 triangles, outward) centred at the origin as an OBJ file."""
    hx, hy, hz = (s / 2 for s in size)
    v = [(x, y, z) for x in (-hx, hx) for y in (-hy, hy) for z in (-hz, hz)]
    faces = [
        (1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2),
        (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4),
    ]
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in v]
    for a, b, c, d in faces:
        lines += [f"f {a} {b} {c}", f"f {a} {c} {d}"]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def arm(tmp_path):
    """A small robot: a box link with a cylinder, a box mesh link, a mesh + sphere link."""
    (tmp_path / "meshes").mkdir()
    box_obj((0.04, 0.05, 0.12), tmp_path / "meshes" / "upper.obj")
    box_obj((0.03, 0.03, 0.05), tmp_path / "meshes" / "hand.obj")
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(
        """<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <collision><geometry><box size="0.2 0.1 0.05"/></geometry></collision>
  </link>
  <link name="upper">
    <collision>
      <origin xyz="0 0 0.06" rpy="0.1 0 0.2"/>
      <geometry><mesh filename="meshes/upper.obj"/></geometry>
    </collision>
  </link>
  <link name="hand">
    <collision><geometry><mesh filename="meshes/hand.obj"/></geometry></collision>
    <collision><origin xyz="0 0 0.04"/><geometry><sphere radius="0.01"/></geometry></collision>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base"/><child link="upper"/><origin xyz="0 0 0.03"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/>
  </joint>
  <joint name="j2" type="fixed">
    <parent link="upper"/><child link="hand"/><origin xyz="0 0 0.12"/>
  </joint>
</robot>
"""
    )
    return urdf
