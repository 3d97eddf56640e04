"""RobotChecker: verdicts against a brute force written with numpy, thread counts, edges
against their samples, and bad input."""

import json
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import medspheres
from conftest import assert_edges_match_samples

# A planar two-joint arm: base (one ball), link1 and link2 along x, both joints about z.
LINK1 = np.array([[0.1, 0, 0, 0.05], [0.2, 0, 0, 0.05]])
LINK2 = np.array([[0.1, 0, 0, 0.04], [0.15, 0, 0.05, 0.03]])
BASE = np.array([[0, 0, 0, 0.1]])


def link(name, balls):
    return {"name": name, "inner": balls.tolist(), "outer": balls.tolist()}


def joint(name, parent, child, xyz):
    return {
        "name": name,
        "type": "revolute",
        "parent": parent,
        "child": child,
        "origin": {"xyz": xyz, "quaternion_xyzw": [0, 0, 0, 1]},
        "axis": [0, 0, 1],
        "limits": {"lower": -3.2, "upper": 3.2, "velocity": 1, "effort": 1},
    }


@pytest.fixture
def robot_file(tmp_path):
    robot = {
        "format": "medspheres.robot",
        "version": 1,
        "name": "planar",
        "root_link": "base",
        "links": [link("base", BASE), link("link1", LINK1), link("link2", LINK2)],
        "joints": [
            joint("j1", "base", "link1", [0, 0, 0.2]),
            joint("j2", "link1", "link2", [0.3, 0, 0]),
        ],
    }
    path = tmp_path / "planar.robot.json"
    path.write_text(json.dumps(robot))
    return path


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


BOX_CENTRE, BOX_HALF = np.array([0.35, 0.2, 0.2]), np.array([0.1, 0.1, 0.3])
CLOUD = np.random.default_rng(3).uniform([-0.5, -0.5, 0.15], [-0.3, -0.2, 0.3], (40, 3))


def brute_force(q, margin):
    r1 = rz(q[0])
    p1 = np.array([0, 0, 0.2])
    r2 = r1 @ rz(q[1])
    p2 = p1 + r1 @ np.array([0.3, 0, 0])
    balls = [(p1 + r1 @ b[:3], b[3]) for b in LINK1] + [(p2 + r2 @ b[:3], b[3]) for b in LINK2]
    for c, r in balls:
        d = c - BOX_CENTRE
        if np.linalg.norm(d - np.clip(d, -BOX_HALF, BOX_HALF)) - r <= margin:
            return 1
        if np.min(np.linalg.norm(CLOUD - c, axis=1)) - r <= margin:
            return 1
    for c, r in balls[2:]:  # link2 against the base (link1 is adjacent to both)
        if np.linalg.norm(c - BASE[0, :3]) - r - BASE[0, 3] <= margin:
            return 1
    return 0


def scene():
    s = medspheres.CheckScene()
    pose = np.eye(4)
    pose[:3, 3] = BOX_CENTRE
    s.add_box(2 * BOX_HALF, pose, name="box")
    s.add_points(CLOUD, name="cloud")
    assert len(s) == 2
    return s


def configurations(n, seed):
    return np.random.default_rng(seed).uniform(-3.2, 3.2, (n, 2))


def test_check_matches_brute_force(robot_file):
    checker = medspheres.RobotChecker(robot_file, scene(), margin=0.01)
    assert checker.joint_names == ["j1", "j2"]
    assert checker.links == ["base", "link1", "link2"]
    q = configurations(500, 1)
    verdicts = checker.check(q)
    assert verdicts.dtype == np.uint8 and verdicts.shape == (500,)
    expected = np.array([brute_force(x, 0.01) for x in q])
    assert np.array_equal(verdicts, expected)
    assert 25 < expected.sum() < 475


def test_threads_and_simd_paths_agree(robot_file):
    q = configurations(1001, 2)
    one = medspheres.RobotChecker(robot_file, scene(), simd="scalar").check(q, mode="bounds")
    checker = medspheres.RobotChecker(robot_file, scene())
    assert np.array_equal(checker.check(q, mode="bounds", threads=2), one)
    # Two Python threads at once (the GIL released): the same answers.
    with ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda _: checker.check(q, threads=1), range(4)))
    assert all(np.array_equal(r, results[0]) for r in results)


def test_edges_match_their_samples(robot_file):
    checker = medspheres.RobotChecker(robot_file, scene())
    q = configurations(61, 4)
    q0, q1 = q[:-1], q[1:]
    verdicts, checked = checker.check_edges(q0, q1, 0.05, threads=2)
    assert checked >= len(q0)
    assert_edges_match_samples(checker, q0, q1, 0.05, verdicts)
    assert 0 < verdicts.sum() < len(verdicts)


def test_any_colliding_matches_brute_force(robot_file):
    checker = medspheres.RobotChecker(robot_file, scene(), margin=0.01)
    q = configurations(400, 5)
    expected = np.array([brute_force(x, 0.01) for x in q])
    seen = set()
    for first in range(0, 380, 3):
        for count in (0, 1, 8, 9, 17):
            window = q[first:first + count]
            truth = bool(expected[first:first + count].any())
            assert checker.any_colliding(window) == truth
            seen.add(truth)
    assert seen == {True, False}
    with pytest.raises(ValueError, match="j1"):
        checker.any_colliding(np.array([[np.inf, 0.0]]))


def test_with_scene_matches_a_new_checker(robot_file):
    first = medspheres.RobotChecker(robot_file, medspheres.CheckScene(), margin=0.01)
    moved = first.with_scene(scene())
    q = configurations(300, 6)
    expected = np.array([brute_force(x, 0.01) for x in q])
    assert np.array_equal(moved.check(q), expected)
    assert 25 < expected.sum() < 275
    # The first checker still has its own (empty) scene: only self-collision is left there.
    alone = medspheres.RobotChecker(robot_file, medspheres.CheckScene(), margin=0.01)
    assert np.array_equal(first.check(q), alone.check(q))
    assert first.check(q).sum() < expected.sum()


def test_bad_input(robot_file):
    checker = medspheres.RobotChecker(robot_file)
    with pytest.raises(ValueError, match="q"):
        checker.check(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="j2"):
        checker.check(np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match="mode"):
        checker.check(np.zeros((1, 2)), mode="mesh")
    with pytest.raises(ValueError, match="margin"):
        medspheres.RobotChecker(robot_file, margin=-1.0)
    with pytest.raises(ValueError, match="crate"):
        medspheres.CheckScene().add_box([1, -1, 1], name="crate")
