"""Type stubs of the medspheres module (the C++ extension medspheres._medspheres)."""

import os
from typing import Any, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = Union[str, os.PathLike[str]]
#: (vertices n x 3 float, triangles m x 3 int)
MeshArrays = Tuple[npt.ArrayLike, npt.ArrayLike]
Mesh = Union[PathLike, MeshArrays]
#: a 4 x 4 homogeneous rigid transform, or None for the identity
Pose = Optional[npt.ArrayLike]
#: a length in the mesh's units (metres for a robot), or text such as "0.003L" (a multiple of
#: the box's largest side)
Length = Union[float, str]
Spheres = Union["SphereSet", npt.ArrayLike]

class InputError(ValueError):
    """Bad input: the command line's message, options named as the keywords."""

    kind: str
    file: str
    field: str
    value: str
    problem: str

class SphereSet:
    """Balls in the mesh's frame and units, with provenance and statistics."""

    def __init__(self, spheres: npt.ArrayLike, metadata: Optional[Mapping[str, Any]] = ...) -> None: ...
    @property
    def spheres(self) -> npt.NDArray[np.float64]:
        """n x 4 (x, y, z, r), a read-only view of the set's memory."""
    @property
    def metadata(self) -> dict[str, Any]: ...
    @property
    def stats(self) -> dict[str, Any]: ...
    def __len__(self) -> int: ...
    def to_json(self) -> str: ...
    def save(
        self,
        path: PathLike,
        format: Optional[str] = ...,
        link: str = ...,
        urdf: Optional[str] = ...,
        name: str = ...,
    ) -> None: ...

class SphereDocument:
    """What a sphere file held: one set, or spheres per link."""

    @property
    def set(self) -> Optional[SphereSet]: ...
    @property
    def links(self) -> dict[str, npt.NDArray[np.float64]]: ...
    @property
    def robot_name(self) -> str: ...
    @property
    def is_robot_file(self) -> bool: ...
    def save(
        self,
        path: PathLike,
        format: Optional[str] = ...,
        link: str = ...,
        urdf: Optional[str] = ...,
        name: str = ...,
    ) -> None: ...

class RobotBake:
    """A baked robot: per-link inner and outer sets in link frames (metres)."""

    @property
    def links(self) -> dict[str, dict[Literal["inner", "outer"], npt.NDArray[np.float64]]]: ...
    @property
    def stats(self) -> list[dict[str, Any]]: ...
    @property
    def seconds(self) -> float: ...
    @property
    def name(self) -> str: ...
    @property
    def self_collision_estimate(self) -> Optional[dict[str, Any]]: ...
    def to_json(self) -> str: ...
    def save(self, output: PathLike, formats: Sequence[str] = ..., set: str = ...) -> None: ...

class SphereTree:
    """A hierarchy over a sphere set for distance and collision queries (thread-safe)."""

    def __init__(self, spheres: Spheres, kind: Literal["rss", "ball"] = ..., max_leaf_size: int = ...) -> None: ...
    def __len__(self) -> int: ...
    def distance(
        self, other: SphereTree, pose: Pose = ..., other_pose: Pose = ..., signed: bool = ...
    ) -> dict[str, Any]: ...
    def collide(self, other: SphereTree, pose: Pose = ..., other_pose: Pose = ...) -> bool: ...
    @overload
    def point_distance(
        self, points: npt.ArrayLike, pose: Pose = ..., return_index: Literal[False] = ...
    ) -> npt.NDArray[np.float64]: ...
    @overload
    def point_distance(
        self, points: npt.ArrayLike, pose: Pose = ..., *, return_index: Literal[True]
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.intp]]: ...

class BoundedGeometry:
    """A solid as an inner set and a certified outer (covering) set."""

    def __init__(
        self, inner: Spheres, outer: Spheres, name: str = ..., allow_uncertified: bool = ...
    ) -> None: ...
    @property
    def certified(self) -> bool: ...

class CheckScene:
    """Obstacles for a RobotChecker in the world frame (metres): FCL's primitives, meshes
    (surfaces), point clouds and octomap cells. Each add_* returns the object's index."""

    def __init__(self) -> None: ...
    def add_sphere(self, center: npt.ArrayLike, radius: float, name: str = ...) -> int: ...
    def add_box(self, size: npt.ArrayLike, pose: Pose = ..., name: str = ...) -> int: ...
    def add_capsule(self, radius: float, length: float, pose: Pose = ..., name: str = ...) -> int: ...
    def add_cylinder(self, radius: float, length: float, pose: Pose = ..., name: str = ...) -> int: ...
    def add_mesh(self, mesh: MeshArrays, pose: Pose = ..., name: str = ...) -> int: ...
    def add_points(self, points: npt.ArrayLike, name: str = ...) -> int: ...
    def add_cells(self, centres: npt.ArrayLike, side: float, name: str = ...) -> int: ...
    def __len__(self) -> int: ...

class RobotChecker:
    """Collision checks of a robot file's spheres for arrays of configurations and edges
    (verdicts: 0 free, 1 colliding, 2 undecided); the GIL is released while they run."""

    def __init__(
        self,
        robot_file: PathLike,
        scene: CheckScene = ...,
        *,
        fine: Optional[PathLike] = ...,
        margin: float = ...,
        disabled: Sequence[Tuple[str, str]] = ...,
        self_collision: bool = ...,
        base_pose: Pose = ...,
        simd: Literal["auto", "scalar", "avx2"] = ...,
    ) -> None: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def links(self) -> list[str]: ...
    @property
    def uses_avx2(self) -> bool: ...
    @property
    def allowance(self) -> float: ...
    def check(
        self, q: npt.ArrayLike, mode: Literal["spheres", "bounds"] = ..., threads: int = ...
    ) -> npt.NDArray[np.uint8]: ...
    def check_edges(
        self,
        q0: npt.ArrayLike,
        q1: npt.ArrayLike,
        resolution: float,
        mode: Literal["spheres", "bounds"] = ...,
        threads: int = ...,
    ) -> Tuple[npt.NDArray[np.uint8], int]: ...

class CertifiedChecker:
    """Certified collision checks of a robot for arrays of configurations and edges: the
    robot file's spheres, then its URDF's exact meshes for the pairs they leave undecided
    (verdicts: 0 free, 1 colliding, 2 undecided only without a mesh); the GIL is released."""

    def __init__(
        self,
        urdf: PathLike,
        robot_file: PathLike,
        scene: CheckScene = ...,
        *,
        fine: Optional[PathLike] = ...,
        trees: Optional[PathLike] = ...,
        packages: Mapping[str, str] = ...,
        margin: float = ...,
        disabled: Sequence[Tuple[str, str]] = ...,
        self_collision: bool = ...,
        base_pose: Pose = ...,
        simd: Literal["auto", "scalar", "avx2"] = ...,
        order_samples: int = ...,
        seed: int = ...,
        table_cells: int = ...,
        table_pairs: int = ...,
        table_store: str = ...,
    ) -> None: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def links(self) -> list[str]: ...
    @overload
    def check(
        self, q: npt.ArrayLike, threads: int = ..., stats: Literal[False] = ...
    ) -> npt.NDArray[np.uint8]: ...
    @overload
    def check(
        self, q: npt.ArrayLike, threads: int = ..., *, stats: Literal[True]
    ) -> Tuple[npt.NDArray[np.uint8], dict[str, int]]: ...
    def check_edges(
        self, q0: npt.ArrayLike, q1: npt.ArrayLike, resolution: float, threads: int = ...
    ) -> Tuple[npt.NDArray[np.uint8], int]: ...

class RobotBounds:
    """A robot file's links as inner and certified outer sets, for certified queries."""

    def __init__(
        self,
        robot_file: PathLike,
        disabled: Sequence[Tuple[str, str]] = ...,
        allow_uncertified: bool = ...,
        order_samples: int = ...,
        order_margin: float = ...,
        seed: int = ...,
    ) -> None: ...
    @property
    def joint_names(self) -> list[str]: ...
    @property
    def witnesses(self) -> int: ...
    def bounds(
        self,
        q: npt.ArrayLike,
        scene: Sequence[Tuple[Spheres, Pose]] = ...,
        include_self: bool = ...,
        base_pose: Pose = ...,
    ) -> Tuple[float, float, bool]: ...
    def collide(
        self,
        q: npt.ArrayLike,
        scene: Sequence[Tuple[Spheres, Pose]] = ...,
        include_self: bool = ...,
        margin: float = ...,
        base_pose: Pose = ...,
    ) -> dict[str, Any]: ...

def bake(
    mesh: Mesh,
    *,
    method: Literal["medial", "cover"] = ...,
    resolution: int = ...,
    object_angle: float = ...,
    medial_tolerance: float = ...,
    max_spheres: Optional[int] = ...,
    target_error: Optional[float] = ...,
    dilate: bool = ...,
    vertex_tolerance: Optional[Length] = ...,
    max_protrusion: Optional[Length] = ...,
    cover: Optional[Length] = ...,
    seed: int = ...,
    threads: int = ...,
    solid: Literal["auto", "winding", "robust"] = ...,
    robust_resolution: int = ...,
    robust_thickness: Optional[Length] = ...,
    cover_start: Optional[Spheres] = ...,
    protrusion_allowance: float = ...,
    protrusion_restarts: int = ...,
    balance_rounds: int = ...,
    name: str = ...,
) -> SphereSet: ...
def evaluate(
    mesh: Mesh,
    spheres: Union[Spheres, PathLike],
    *,
    samples: int = ...,
    surface_samples: int = ...,
    seed: int = ...,
    threads: int = ...,
    solid: Literal["auto", "winding", "robust"] = ...,
    robust_resolution: int = ...,
    robust_thickness: Optional[Length] = ...,
) -> dict[str, Any]: ...
def evaluate_robot(
    urdf: PathLike,
    spheres: Union[PathLike, Mapping[str, Spheres]],
    *,
    packages: Mapping[str, str] = ...,
    samples: int = ...,
    surface_samples: int = ...,
    seed: int = ...,
    threads: int = ...,
) -> list[dict[str, Any]]: ...
def load_mesh(path: PathLike) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int32]]: ...
def load(path: PathLike, format: Optional[str] = ..., set: str = ..., level: int = ...) -> SphereDocument: ...
def load_spheres(path: PathLike) -> SphereSet: ...
def convert(
    src: PathLike,
    dst: PathLike,
    from_format: Optional[str] = ...,
    to_format: Optional[str] = ...,
    link: str = ...,
    urdf: Optional[str] = ...,
    set: str = ...,
    level: int = ...,
    name: str = ...,
) -> None: ...
def bake_robot(
    urdf: PathLike,
    output: Optional[PathLike] = ...,
    *,
    formats: Sequence[str] = ...,
    set: Literal["auto", "inner", "outer"] = ...,
    packages: Mapping[str, str] = ...,
    from_visual: bool = ...,
    spheres_per_link: Optional[int] = ...,
    budget: Optional[int] = ...,
    links: Mapping[str, int] = ...,
    jobs: int = ...,
    resolution: Optional[int] = ...,
    object_angle: float = ...,
    target_error: Optional[float] = ...,
    dilate: bool = ...,
    vertex_tolerance: Optional[Length] = ...,
    max_protrusion: Optional[Length] = ...,
    cover: Optional[Length] = ...,
    seed: int = ...,
    solid: Literal["auto", "winding", "robust"] = ...,
    robust_resolution: int = ...,
    robust_thickness: Optional[Length] = ...,
    measure: bool = ...,
    outer: bool = ...,
    cover_start: Optional[Union[PathLike, Mapping[str, Any]]] = ...,
    fill: bool = ...,
    fill_covers: bool = ...,
    protrusion_allowance: float = ...,
    protrusion_restarts: int = ...,
    balance_rounds: int = ...,
    tool_frames: Sequence[str] = ...,
    free_joints: Sequence[str] = ...,
    srdf: Optional[PathLike] = ...,
    self_collision: bool = ...,
    self_collision_samples: int = ...,
    self_collision_seed: int = ...,
    self_collision_threshold: float = ...,
    self_collision_margin: float = ...,
    self_collision_estimate: int = ...,
) -> RobotBake: ...
def distance_bounds(
    a: BoundedGeometry, b: BoundedGeometry, pose_a: Pose = ..., pose_b: Pose = ...
) -> Tuple[float, float, bool]: ...
def collide_bounds(
    a: BoundedGeometry, b: BoundedGeometry, pose_a: Pose = ..., pose_b: Pose = ..., margin: float = ...
) -> dict[str, Any]: ...
