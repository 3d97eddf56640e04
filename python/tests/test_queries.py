"""Queries against brute force over every ball; the same answers from many threads."""

import concurrent.futures

import numpy as np
import pytest

import medspheres


def random_balls(rng, n, spread=1.0):
    return np.column_stack([rng.normal(scale=spread, size=(n, 3)), rng.uniform(0.02, 0.2, n)])


def pose(rng, shift):
    """A random rigid transform (rotation from a QR decomposition, det +1)."""
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    x = np.eye(4)
    x[:3, :3], x[:3, 3] = q, shift
    return x


def world(balls, x):
    return np.column_stack([balls[:, :3] @ x[:3, :3].T + x[:3, 3], balls[:, 3]])


def brute_point(balls, points):
    d = np.linalg.norm(points[:, None, :] - balls[None, :, :3], axis=2) - balls[None, :, 3]
    return d.min(axis=1), d.argmin(axis=1)


def brute_pair(a, b):
    d = np.linalg.norm(a[:, None, :3] - b[None, :, :3], axis=2) - a[:, None, 3] - b[None, :, 3]
    return d.min()


def test_point_distance_against_brute_force():
    rng = np.random.default_rng(11)
    balls = random_balls(rng, 300)
    x = pose(rng, [0.5, -1.0, 2.0])
    tree = medspheres.SphereTree(balls)
    points = rng.normal(scale=2.0, size=(2000, 3)) + x[:3, 3]
    d, index = tree.point_distance(points, x, return_index=True)
    assert d.shape == (2000,) and d.dtype == np.float64
    assert index.shape == (2000,) and index.dtype == np.intp
    expected, _ = brute_point(world(balls, x), points)
    assert np.allclose(d, expected, rtol=0, atol=1e-12)
    # the ball reported realises the distance
    realised = np.linalg.norm(points - world(balls, x)[index, :3], axis=1) - balls[index, 3]
    assert np.allclose(realised, d, rtol=0, atol=1e-12)
    # a list of points and a Fortran-ordered array give the same
    assert np.array_equal(tree.point_distance(points.tolist(), x), d)
    assert np.array_equal(tree.point_distance(np.asfortranarray(points), x), d)
    assert tree.point_distance(np.zeros((0, 3))).shape == (0,)


def test_pair_distance_and_collision_against_brute_force():
    rng = np.random.default_rng(5)
    a_balls, b_balls = random_balls(rng, 120, 0.3), random_balls(rng, 80, 0.3)
    a, b = medspheres.SphereTree(a_balls), medspheres.SphereTree(b_balls, kind="ball")
    for shift in np.linspace(0.0, 3.0, 13):
        xa, xb = pose(rng, [0, 0, 0]), pose(rng, [shift, 0.2, 0])
        wa, wb = world(a_balls, xa), world(b_balls, xb)
        expected = brute_pair(wa, wb)
        r = a.distance(b, xa, xb)
        assert a.collide(b, xa, xb) == (expected <= 0)
        if expected > 0:
            assert r["distance"] == pytest.approx(expected, abs=1e-12)
            pa, pb = np.array(r["point_a"]), np.array(r["point_b"])
            assert np.linalg.norm(pa - pb) == pytest.approx(expected, abs=1e-12)
            assert r["sphere_a"] >= 0 and r["sphere_b"] >= 0
        else:
            assert r["distance"] <= 0
            deepest = a.distance(b, xa, xb, signed=True)["distance"]
            assert deepest == pytest.approx(expected, abs=1e-12)


def test_queries_from_many_threads_agree():
    rng = np.random.default_rng(2)
    balls = random_balls(rng, 2000)
    tree = medspheres.SphereTree(medspheres.SphereSet(balls))
    points = rng.normal(scale=2.0, size=(20000, 3))
    poses = [pose(rng, rng.normal(size=3)) for _ in range(16)]
    other = medspheres.SphereTree(random_balls(rng, 500))
    serial = [(tree.point_distance(points, x), tree.distance(other, x)) for x in poses]
    with concurrent.futures.ThreadPoolExecutor(max_workers=8) as pool:
        parallel = list(pool.map(lambda x: (tree.point_distance(points, x), tree.distance(other, x)),
                                 poses))
    for (d1, p1), (d2, p2) in zip(serial, parallel):
        assert d1.tobytes() == d2.tobytes() and p1 == p2


def test_bounds_of_baked_sets(eight):
    inner = medspheres.bake(eight, resolution=16)
    outer = medspheres.bake(eight, method="cover", max_spheres=30)
    assert outer.stats["certified"] is True
    g = medspheres.BoundedGeometry(inner, outer, name="eight")
    assert g.certified
    wi, wo = inner.spheres, outer.spheres
    for shift in (0.0, 0.3, 0.6, 1.2):
        xb = np.eye(4)
        xb[0, 3] = shift
        lower, upper, certified = medspheres.distance_bounds(g, g, None, xb)
        assert certified
        inner_d = max(0.0, brute_pair(wi, world(wi, xb)))
        outer_d = max(0.0, brute_pair(wo, world(wo, xb)))
        # the bounds are the outer and the inner sets' distances (to a rounding allowance)
        assert lower <= outer_d <= lower + 1e-9 and upper - 1e-9 <= inner_d <= upper
        assert lower <= upper
        for margin in (0.0, 0.05):
            c = medspheres.collide_bounds(g, g, None, xb, margin=margin)
            expected = ("free" if outer_d > margin else
                        "colliding" if inner_d <= margin else "undecided")
            assert c["verdict"] == expected, (shift, margin)
    with pytest.raises(medspheres.InputError):
        medspheres.BoundedGeometry(inner, inner)  # an inner set is no certified cover


def test_bad_query_input_raises():
    tree = medspheres.SphereTree(np.array([[0, 0, 0, 1.0]]))
    with pytest.raises(ValueError):
        tree.point_distance(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        tree.point_distance(np.array([[0, 0, np.nan]]))
    with pytest.raises(ValueError):
        tree.point_distance(np.zeros((1, 3)), np.eye(3))
    bad = np.eye(4)
    bad[3, 0] = 1
    with pytest.raises(ValueError):
        tree.distance(tree, bad)
    with pytest.raises(ValueError):
        tree.distance(tree, np.diag([2.0, 1.0, 1.0, 1.0]))  # not a rotation
    with pytest.raises(ValueError):
        medspheres.SphereTree(np.array([[0, 0, 0, 1.0]]), kind="box")
