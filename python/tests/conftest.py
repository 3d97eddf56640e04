"""Fixtures of the medspheres Python tests: the CLI of the same build, the bundled meshes."""

import os
import pathlib
import re
import shlex
import subprocess

import numpy as np
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


def flagged(message):
    """The CLI's message with its flags spelled as Python keywords (--max-spheres: max_spheres)."""
    return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), message)


def without_clocks(value):
    """The value with every key that names a time ("seconds", "bake_seconds", ...) left out."""
    if isinstance(value, dict):
        return {k: without_clocks(v) for k, v in value.items() if "seconds" not in k}
    if isinstance(value, list):
        return [without_clocks(v) for v in value]
    return value


def assert_edges_match_samples(checker, q0, q1, resolution, verdicts):
    """Each edge's verdict is the worst of its samples' (t = k / n, n = ceil(|q1 - q0| /
    resolution)) checked one by one."""
    for a, b, v in zip(q0, q1, verdicts):
        n = max(1, int(np.ceil(np.linalg.norm(b - a) / resolution)))
        samples = a + (np.arange(n + 1) / n)[:, None] * (b - a)
        assert v == checker.check(samples).max()


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


ARM_URDF = """<?xml version="1.0"?>
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


def write_arm(root):
    """Writes the small robot into the folder root: a box primitive link, a box mesh link, a
    mesh + sphere link (the hand: a 0.03 x 0.03 x 0.05 box at its origin and a
    sphere of radius 0.01 at z = 0.04). Returns the URDF's path."""
    (root / "meshes").mkdir()
    box_obj((0.04, 0.05, 0.12), root / "meshes" / "upper.obj")
    box_obj((0.03, 0.03, 0.05), root / "meshes" / "hand.obj")
    urdf = root / "arm.urdf"
    urdf.write_text(ARM_URDF)
    return urdf


@pytest.fixture
def arm(tmp_path):
    """The small robot of write_arm, in tmp_path."""
    return write_arm(tmp_path)
