"""CertifiedChecker: verdicts against a brute force written with numpy (the separating axis
test of boxes, a ball against a box), edges against their samples, threads, bad input."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import medspheres
from conftest import assert_edges_match_samples

# A two-joint arm of URDF boxes: link2 hangs low enough to strike the base when folded back.
URDF = """<?xml version="1.0"?>
<robot name="folder">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="link1"><collision><origin xyz="0.15 0 0.04"/>
    <geometry><box size="0.3 0.06 0.06"/></geometry></collision></link>
  <link name="link2"><collision><origin xyz="0.125 0 -0.05"/>
    <geometry><box size="0.25 0.05 0.05"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-3.1" upper="3.1" velocity="1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3.1" upper="3.1" velocity="1" effort="1"/></joint>
</robot>
"""

# Boxes as (centre, rotation, half sides), in the link frames.
PARTS = {
    "base": (np.zeros(3), np.eye(3), np.array([0.1, 0.1, 0.05])),
    "link1": (np.array([0.15, 0, 0.04]), np.eye(3), np.array([0.15, 0.03, 0.03])),
    "link2": (np.array([0.125, 0, -0.05]), np.eye(3), np.array([0.125, 0.025, 0.025])),
}
CRATE = (np.array([0.35, 0.3, 0.1]), None, np.array([0.08, 0.05, 0.2]))
BALL = (np.array([-0.3, 0.25, 0.12]), 0.07)
CELLS = [np.array([-0.3, -0.3, 0.1]) + np.array([i, j, 0]) * 0.04 for i in range(3)
         for j in range(2)]


def rot(axis, a):
    c, s = np.cos(a), np.sin(a)
    i, j = [k for k in range(3) if k != axis]
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


CRATE = (CRATE[0], rot(2, 0.6) @ rot(0, 0.3), CRATE[2])


def placed(q):
    """The links' boxes in the world frame: the arm's forward kinematics, written out."""
    r1, p1 = rot(2, q[0]), np.array([0, 0, 0.1])
    r2, p2 = r1 @ rot(2, q[1]), p1 + r1 @ np.array([0.3, 0, 0])
    frames = {"base": (np.eye(3), np.zeros(3)), "link1": (r1, p1), "link2": (r2, p2)}
    return {k: (frames[k][1] + frames[k][0] @ c, frames[k][0] @ r, h)
            for k, (c, r, h) in PARTS.items()}


def boxes_meet(a, b):
    """The separating axis test of two boxes (centre, rotation, half sides): closed sets."""
    (ca, ra, ha), (cb, rb, hb) = a, b
    axes = [ra[:, i] for i in range(3)] + [rb[:, i] for i in range(3)]
    axes += [np.cross(ra[:, i], rb[:, j]) for i in range(3) for j in range(3)]
    for axis in axes:
        if np.linalg.norm(axis) < 1e-9:
            continue
        reach = np.abs(axis @ ra) @ ha + np.abs(axis @ rb) @ hb
        if abs(axis @ (cb - ca)) > reach:
            return False
    return True


def ball_meets(box, centre, radius):
    c, r, h = box
    d = r.T @ (centre - c)
    return np.linalg.norm(d - np.clip(d, -h, h)) <= radius


def brute_force(q):
    links = placed(q)
    cells = [(c, np.eye(3), np.full(3, 0.02)) for c in CELLS]
    for box in links.values():
        if boxes_meet(box, CRATE) or ball_meets(box, *BALL):
            return 1
        if any(boxes_meet(box, cell) for cell in cells):
            return 1
    return int(boxes_meet(links["base"], links["link2"]))  # the one pair not joined


def scene():
    s = medspheres.CheckScene()
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = CRATE[1], CRATE[0]
    s.add_box(2 * CRATE[2], pose, name="crate")
    s.add_sphere(BALL[0], BALL[1], name="ball")
    s.add_cells(np.array(CELLS), 0.04, name="octomap")
    return s


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    root = tmp_path_factory.mktemp("folder")
    urdf = root / "folder.urdf"
    urdf.write_text(URDF)
    medspheres.bake_robot(urdf, root / "out", spheres_per_link=4, formats=["robot"])
    return urdf, root / "out" / "folder.robot.json"


@pytest.fixture(scope="module")
def finer(folder, tmp_path_factory):
    """The same robot at 12 spheres a link: the fine level and the fallback's trees."""
    out = tmp_path_factory.mktemp("finer")
    medspheres.bake_robot(folder[0], out, spheres_per_link=12, formats=["robot"])
    return out / "folder.robot.json"


def configurations(n, seed):
    return np.random.default_rng(seed).uniform(-3.1, 3.1, (n, 2))


def test_verdicts_match_brute_force(folder):
    urdf, robot = folder
    checker = medspheres.CertifiedChecker(urdf, robot, scene())
    assert checker.joint_names == ["j1", "j2"]
    q = configurations(600, 1)
    verdicts, stats = checker.check(q, stats=True)
    assert verdicts.dtype == np.uint8 and verdicts.shape == (600,)
    expected = np.array([brute_force(x) for x in q])
    assert np.array_equal(verdicts, expected)
    assert 60 < expected.sum() < 540
    # The spheres leave some configurations to the meshes, which settle them.
    assert stats["configurations"] > 0 and stats["meshes"] > 0
    # Where the spheres' bounds decide, they say what the meshes say.
    bounds = medspheres.RobotChecker(robot, scene()).check(q, mode="bounds")
    decided = bounds != 2
    assert np.array_equal(bounds[decided], expected[decided])
    assert not decided.all()


def test_levels_change_no_verdict(folder, finer):
    urdf, robot = folder
    q = configurations(400, 5)
    plain = medspheres.CertifiedChecker(urdf, robot, scene()).check(q)
    levels = medspheres.CertifiedChecker(urdf, robot, scene(), fine=finer, trees=finer,
                                         table_cells=4096)
    verdicts, stats = levels.check(q, stats=True)
    assert np.array_equal(verdicts, plain)
    assert np.array_equal(verdicts, [brute_force(x) for x in q])
    assert stats["configurations"] < len(q)


def test_with_scene(folder, finer):
    urdf, robot = folder
    q = configurations(400, 7)
    alone = medspheres.CertifiedChecker(urdf, robot, medspheres.CheckScene(), fine=finer,
                                        order_samples=200, table_cells=4096)
    moved = alone.with_scene(scene())
    assert moved.joint_names == alone.joint_names
    verdicts, stats = moved.check(q, stats=True)
    assert np.array_equal(verdicts, [brute_force(x) for x in q])
    assert stats["meshes"] > 0
    anew = medspheres.CertifiedChecker(urdf, robot, scene(), fine=finer, order_samples=200,
                                       table_cells=4096)
    assert np.array_equal(verdicts, anew.check(q))
    self_only = [int(boxes_meet(placed(x)["base"], placed(x)["link2"])) for x in q]
    assert np.array_equal(moved.with_scene(medspheres.CheckScene()).check(q), self_only)
    assert np.array_equal(alone.check(q), self_only)
    assert not np.array_equal(verdicts, self_only)


def test_threads_and_edges(folder):
    urdf, robot = folder
    checker = medspheres.CertifiedChecker(urdf, robot, scene(), order_samples=200)
    q = configurations(401, 2)
    one = checker.check(q)
    assert np.array_equal(checker.check(q, threads=2), one)
    with ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda _: checker.check(q), range(4)))
    assert all(np.array_equal(r, one) for r in results)
    q0, q1 = q[:40], q[1:41]
    verdicts, checked = checker.check_edges(q0, q1, 0.05, threads=2)
    assert checked >= len(q0)
    assert_edges_match_samples(checker, q0, q1, 0.05, verdicts)
    assert 0 < verdicts.sum() < len(verdicts)


def test_bad_input(folder, tmp_path):
    urdf, robot = folder
    cloud = scene()
    cloud.add_points(np.zeros((2, 3)) + 1.0, name="lidar")
    with pytest.raises(ValueError, match='"lidar".*point cloud'):
        medspheres.CertifiedChecker(urdf, robot, cloud)
    other = tmp_path / "other.urdf"
    other.write_text(URDF.replace('"link2"', '"forearm"'))
    with pytest.raises(medspheres.InputError, match="forearm.*missing") as error:
        medspheres.CertifiedChecker(other, robot)
    assert error.value.file == str(robot)
    checker = medspheres.CertifiedChecker(urdf, robot)
    with pytest.raises(ValueError, match="q"):
        checker.check(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="margin"):
        medspheres.CertifiedChecker(urdf, robot, margin=-1.0)
    with pytest.raises(ValueError, match="simd"):
        medspheres.CertifiedChecker(urdf, robot, simd="neon")
