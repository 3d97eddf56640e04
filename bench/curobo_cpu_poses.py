"""Pose products for cuRobo's loaders on the CPU, where cuRobo runs them as warp kernels.

cuRobo (v1 and v2) folds locked joints (a gripper's fingers) into fixed transforms with
Pose.multiply, Pose.inverse and Pose.get_matrix, whose products are warp kernels; the
import-only warp stub of ../shared/clients/curobo leaves them uncomputed. install() puts the
same products, in NumPy, in place of the names a cuRobo pose module imports. Used by
curobo_v1_check.py and curobo_v2_check.py; local checks, not tests (CI has no cuRobo)."""
import numpy as np
import torch
from scipy.spatial.transform import Rotation


def as_matrices(p, q):
    """4 x 4 matrices of positions p (..., 3) and quaternions q (..., 4), real part first."""
    p = p.detach().cpu().numpy().reshape(-1, 3).astype(float)
    q = q.detach().cpu().numpy().reshape(-1, 4).astype(float)
    T = np.tile(np.eye(4), (len(p), 1, 1))
    T[:, :3, :3] = Rotation.from_quat(q[:, [1, 2, 3, 0]]).as_matrix()
    T[:, :3, 3] = p
    return T


def as_pose(T, like):
    """The positions and quaternions (real part first) of matrices T, shaped and typed like
    the position tensor `like`."""
    xyzw = Rotation.from_matrix(T[:, :3, :3]).as_quat()
    t = lambda a, n: torch.as_tensor(np.ascontiguousarray(a), dtype=like.dtype).reshape(*like.shape[:-1], n)
    return t(T[:, :3, 3], 3), t(xyzw[:, [3, 0, 1, 2]], 4)


def install(module):
    """Replaces pose_multiply, pose_inverse, pose_to_matrix and, where the module has them,
    pose_to_affine_matrix, matrix_to_quaternion and normalize_quaternion in the namespace of
    `module` (curobo.types.math in v1, curobo._src.types.pose in v2)."""
    module.pose_multiply = lambda p1, q1, p2, q2, *rest: as_pose(
        as_matrices(p1, q1) @ as_matrices(p2, q2), p1 if p1.numel() >= p2.numel() else p2)
    module.pose_inverse = lambda p, q, *rest: as_pose(np.linalg.inv(as_matrices(p, q)), p)
    module.pose_to_matrix = lambda p, q, out=None: torch.as_tensor(
        as_matrices(p, q), dtype=p.dtype).reshape(*p.shape[:-1], 4, 4)
    if hasattr(module, "pose_to_affine_matrix"):
        module.pose_to_affine_matrix = lambda p, q, out=None: torch.as_tensor(
            as_matrices(p, q)[:, :3, :], dtype=p.dtype).reshape(*p.shape[:-1], 3, 4)
    if hasattr(module, "normalize_quaternion"):
        module.normalize_quaternion = lambda q, *rest: q / torch.linalg.norm(q, dim=-1, keepdim=True)
    if hasattr(module, "matrix_to_quaternion"):
        module.matrix_to_quaternion = lambda R, *rest: torch.as_tensor(np.ascontiguousarray(
            Rotation.from_matrix(R.detach().cpu().numpy().reshape(-1, 3, 3)).as_quat()[:, [3, 0, 1, 2]]),
            dtype=R.dtype).reshape(*R.shape[:-2], 4)
