#!/usr/bin/python3
"""Python module vs C++: the vectorised point query on 10^6 points, side by side.

Bakes a sphere set (examples/data/knot1.off and eight.off by default), draws N points
uniformly in its box grown by 20%, and times in one run, alternating, the C++ call
point_distances (bench_point_query, a subprocess on the same files) and the module's
SphereTree.point_distance on the same tree shape and points, best of --repeat each. Prints a
table: the ratio Python / C++ is the figure (target: at most 1.2).

  PYTHONPATH=build/python /usr/bin/python3 bench/python_point_query.py --build build
"""

import argparse
import pathlib
import subprocess
import tempfile
import time

import numpy as np

import medspheres

ROOT = pathlib.Path(__file__).resolve().parent.parent


def cxx_time(exe, spheres, points, repeat, out):
    args = [exe, "--spheres", spheres, "--points", points, "--repeat", str(repeat), "--out", out]
    text = subprocess.run(args, check=True, capture_output=True, text=True).stdout.split()
    return float(dict(zip(text[::2], text[1::2]))["seconds"]), np.fromfile(out)


def python_time(tree, points, repeat):
    best, d = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        d = tree.point_distance(points)
        best = min(best, time.perf_counter() - t0)
    return best, d


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"), help="the CMake build folder")
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5, help="calls per round; the best counts")
    ap.add_argument("--rounds", type=int, default=3, help="alternating C++ / Python rounds")
    ap.add_argument("--resolution", type=int, default=28)
    ap.add_argument("meshes", nargs="*",
                    default=[str(ROOT / "examples/data/knot1.off"),
                             str(ROOT / "examples/data/eight.off")])
    a = ap.parse_args()
    exe = str(pathlib.Path(a.build) / "bin" / "bench_point_query")
    rng = np.random.default_rng(1)
    print(f"{'mesh':<12} {'spheres':>8} {'points':>9} {'C++ s':>9} {'Python s':>9} {'ratio':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for mesh in a.meshes:
            s = medspheres.bake(mesh, resolution=a.resolution)
            spheres = pathlib.Path(tmp) / "s.json"
            s.save(spheres)
            lo = (s.spheres[:, :3] - s.spheres[:, 3:]).min(axis=0)
            hi = (s.spheres[:, :3] + s.spheres[:, 3:]).max(axis=0)
            grow = 0.2 * (hi - lo)
            points = rng.uniform(lo - grow, hi + grow, size=(a.points, 3))
            points_file = pathlib.Path(tmp) / "p.bin"
            points.tofile(points_file)
            tree = medspheres.SphereTree(medspheres.load_spheres(spheres))
            cxx, py = float("inf"), float("inf")
            for _ in range(a.rounds):
                t, cxx_d = cxx_time(exe, str(spheres), str(points_file), a.repeat,
                                    str(pathlib.Path(tmp) / "d.bin"))
                cxx = min(cxx, t)
                t, py_d = python_time(tree, points, a.repeat)
                py = min(py, t)
            if cxx_d.tobytes() != py_d.tobytes():
                raise SystemExit(f"{mesh}: the C++ and Python distances differ")
            name = pathlib.Path(mesh).name
            print(f"{name:<12} {len(s):>8} {a.points:>9} {cxx:>9.4f} {py:>9.4f} {py / cxx:>6.3f}")


if __name__ == "__main__":
    main()
