"""medspheres: medial sphere sets of meshes and robots, their fit, and fast queries.

Everything here is the C++ library (the same calls as the ``medspheres`` command line),
bound with pybind11; arrays are numpy float64 with the shapes the docstrings give.

>>> import medspheres
>>> s = medspheres.bake("part.stl", max_spheres=64)
>>> s.spheres.shape            # (n, 4): x, y, z, r in the mesh's frame and units
>>> s.stats["nerr"]
"""

from ._medspheres import (  # noqa: F401
    BoundedGeometry,
    CertifiedChecker,
    CheckScene,
    InputError,
    RobotBake,
    RobotBounds,
    RobotChecker,
    SphereDocument,
    SphereSet,
    SphereTree,
    __version__,
    bake,
    bake_robot,
    collide_bounds,
    convert,
    distance_bounds,
    evaluate,
    evaluate_robot,
    load,
    load_mesh,
    load_spheres,
)

__all__ = [
    "BoundedGeometry",
    "CertifiedChecker",
    "CheckScene",
    "InputError",
    "RobotBake",
    "RobotBounds",
    "RobotChecker",
    "SphereDocument",
    "SphereSet",
    "SphereTree",
    "bake",
    "bake_robot",
    "collide_bounds",
    "convert",
    "distance_bounds",
    "evaluate",
    "evaluate_robot",
    "load",
    "load_mesh",
    "load_spheres",
]
