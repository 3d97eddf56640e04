"""cuRobo v2's loaders on the CPU for robots with locked joints: ../shared's check_outputs.py,
run after the stand-ins that folding locked joints needs there.

v2 folds locked joints (a gripper's fingers) into fixed transforms with its CUDA kinematics
(KinematicsLoader._get_link_poses refuses a CPU tensor) and warp pose products. Here the link
poses come from cuRobo's own NumPy reference joint transform (its tests' rnea reference, as
check_outputs.py computes them) and the products from curobo_cpu_poses.py; nothing else of the
loaders changes. A local check, not a test (CI has no copy of cuRobo).

Set-up: ../shared/clients/curobo/setup.sh. Usage, from the repository root:
  . /tmp/curobo_client/env.sh && /usr/bin/python3 bench/curobo_v2_check.py URDF OUTDIR
(CUROBO_CLIENT names another client folder.)"""
import importlib.util, os, runpy, sys
import numpy as np, torch

client = os.environ.get("CUROBO_CLIENT", "/tmp/curobo_client")
sys.path.insert(0, client)
import cpu_shim  # noqa: F401  (the client's CPU redirects)
import curobo._src.types.pose as pose_module
from curobo._src.robot.loader.kinematics_loader import KinematicsLoader
from curobo._src.types.pose import Pose
import curobo_cpu_poses

spec = importlib.util.spec_from_file_location(
    "rnea_reference", client + "/curobo/tests/_src/robot/dynamics/rnea_numpy_reference.py")
reference = importlib.util.module_from_spec(spec); spec.loader.exec_module(reference)


def link_poses(self, q, query_link_names, kc):
    """World poses of `query_link_names` at q (1 x dof), chained as v2's kernel chains them."""
    c = lambda t: t.detach().cpu().numpy()
    ft, lm, jm, jt = c(kc.fixed_transforms).astype(float), c(kc.link_map), c(kc.joint_map), c(kc.joint_map_type)
    jo, q = c(kc.joint_offset_map).reshape(-1, 2), c(q).reshape(-1).astype(float)
    W = []
    for k in range(len(lm)):
        x = jo[k, 0] * q[jm[k]] + jo[k, 1] if (jt[k] != -1 and jm[k] >= 0) else 0.0
        R, p = reference.build_joint_transform(ft[k], int(jt[k]), x)
        T = np.eye(4); T[:3, :3] = R; T[:3, 3] = p
        W.append(T if (lm[k] < 0 or lm[k] == k) else W[lm[k]] @ T)
    T = np.stack([W[self._name_to_idx_map[n]] for n in query_link_names])
    like = torch.zeros((1, len(query_link_names), 3), dtype=self.device_cfg.dtype)
    position, quaternion = curobo_cpu_poses.as_pose(T, like)
    return Pose(position=position, quaternion=quaternion)


curobo_cpu_poses.install(pose_module)
KinematicsLoader._get_link_poses = link_poses
sys.argv = [client + "/check_outputs.py"] + sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
