"""cuRobo v1's own loaders (NVlabs/curobo d64c4b0) on what `medspheres robot` writes, on the CPU.

A local check, not a test (CI has no copy of cuRobo): the v1 YAML loads as written by
CudaRobotModelConfig.from_robot_yaml_file and RobotConfig.from_dict, the XRDF by
from_robot_yaml_file; then v1's link poses at the YAML's retract_config are compared with
yourdfpy's, and the sphere pairs v1's self-collision matrix checks (with its offsets) are
counted, penetrating or not, at that configuration. v1's CUDA modules are stood in for: the
loaders import them but call only the kinematics, to fold locked joints into fixed
transforms, which cpu_kinematics below computes instead; the pose products of that fold,
which v1 runs as warp kernels, come from curobo_cpu_poses.py.

Set-up: ../shared/clients/curobo/setup.sh (it unpacks v1 beside v2 and writes env_v1.sh).
Usage: . /tmp/curobo_client/env_v1.sh && /usr/bin/python3 bench/curobo_v1_check.py OUTDIR URDF
(GROW=0.01 grows every sphere by 1 cm: the count then shows that the check can fire.)"""
import glob, os, sys, types
import numpy as np, torch
from scipy.spatial.transform import Rotation
torch.set_num_threads(1)
for n in ['kinematics_fused_cu', 'geom_cu', 'lbfgs_step_cu', 'line_search_cu', 'tensor_step_cu']:
    sys.modules['curobo.curobolib.' + n] = types.ModuleType(n)  # CUDA kernels, stood in below
out, urdf = sys.argv[1], sys.argv[2]


def joint(t, x):
    T = np.eye(4)
    if t < 0:
        return T
    axis, kind = t % 3, (t % 6) // 3  # kind 0 prismatic, 1 revolute; t >= 6: negative axis
    x = -x if t >= 6 else x
    if kind == 0:
        T[axis, 3] = x
        return T
    T[:3, :3] = Rotation.from_rotvec(x * np.eye(3)[axis]).as_matrix()
    return T


def fk(ft, lm, jm, jt, jo, q):
    """v1's link transforms (as its kernel chains them) at q, in link_map order."""
    ft = np.asarray(ft, float).reshape(-1, 4, 4); jo = np.asarray(jo, float).reshape(-1, 2)
    W = []
    for k in range(len(lm)):
        x = jo[k, 0] * q[jm[k]] + jo[k, 1] if (jt[k] >= 0 and jm[k] >= 0) else 0.0
        W.append((W[lm[k]] if k > 0 else np.eye(4)) @ ft[k] @ joint(int(jt[k]), x))
    return W


import curobo.cuda_robot_model.cuda_robot_generator as gen


def cpu_kinematics(link_pos, link_quat, spheres, cumul, q, fixed, link_spheres, link_map, joint_map,
                   joint_map_type, store_link_map, sphere_idx, chain, joint_offset, grad, use_cumul=True):
    """A stand-in for v1's CUDA kinematics call (link poses only), which v1 makes to fold
    locked joints into fixed transforms."""
    c = lambda t: t.cpu().numpy()
    W = fk(c(fixed), c(link_map), c(joint_map), c(joint_map_type), c(joint_offset), c(q).reshape(-1).astype(float))
    for s, k in enumerate(c(store_link_map)):
        link_pos[0, s] = torch.as_tensor(W[int(k)][:3, 3])
        xyzw = Rotation.from_matrix(W[int(k)][:3, :3]).as_quat()
        link_quat[0, s] = torch.as_tensor([xyzw[3], xyzw[0], xyzw[1], xyzw[2]])
    return link_pos, link_quat, spheres


gen.get_cuda_kinematics = cpu_kinematics

import curobo.types.math
import curobo_cpu_poses
curobo_cpu_poses.install(curobo.types.math)  # the fold's pose products (warp kernels in v1)
from curobo.types.base import TensorDeviceType
from curobo.cuda_robot_model.cuda_robot_model import CudaRobotModelConfig
from curobo.types.robot import RobotConfig
from curobo.util_file import load_yaml

tensor_args = TensorDeviceType(device=torch.device("cpu"))
# An extra link's (an XRDF's add_frame) fixed transform goes through a default device, CUDA
# (kinematics_parser.py:65); here the CPU.
import curobo.cuda_robot_model.kinematics_parser as kinematics_parser
kinematics_parser.TensorDeviceType = lambda: tensor_args
path = glob.glob(os.path.join(out, "*.curobo_v1.yml"))[0]
cfg = CudaRobotModelConfig.from_robot_yaml_file(path, urdf_path=urdf, tensor_args=tensor_args)
print("from_robot_yaml_file, the v1 YAML as written: OK")
for xrdf in glob.glob(os.path.join(out, "*.xrdf")) or [None]:
    if xrdf is None:  # a robot without an actuated joint has none
        print("no XRDF")
        continue
    CudaRobotModelConfig.from_robot_yaml_file(xrdf, urdf_path=urdf, tensor_args=tensor_args)
    print("from_robot_yaml_file, the XRDF as written: OK")
data = load_yaml(path)["robot_cfg"]
RobotConfig.from_dict(data, tensor_args)
print("RobotConfig.from_dict, the v1 YAML as written: OK")
# Again with v1's slower self-collision kernel, whose matrix of the sphere pairs it checks
# stays on the config (the faster one keeps thread data instead); the pairs are the same.
data["kinematics"]["debug"] = {"self_collision_experimental": False}
rc = RobotConfig.from_dict(data, tensor_args)
kc, sc = rc.kinematics.kinematics_config, rc.kinematics.self_collision_config
q0 = kc.cspace.retract_config.cpu().numpy().astype(float)
W = fk(kc.fixed_transforms.cpu().numpy(), kc.link_map.cpu().numpy(), kc.joint_map.cpu().numpy(),
       kc.joint_map_type.cpu().numpy(), kc.joint_offset_map.cpu().numpy(), q0)
import yourdfpy
u = yourdfpy.URDF.load(urdf, build_scene_graph=True, load_meshes=False)
cspace = data["kinematics"]["cspace"]  # the locked joints too, at the values v1 folds them at
u.update_cfg({**dict(zip(cspace["joint_names"], cspace["retract_config"])), **dict(zip(kc.joint_names, q0))})
worst = max(np.abs(W[int(k)] - u.get_transform(n)).max() for n, k in kc.link_name_to_idx_map.items())
print("v1 link poses at retract_config vs yourdfpy: %d links, max |difference| %.3g"
      % (len(kc.link_name_to_idx_map), worst))
spheres = kc.link_spheres.cpu().numpy().astype(float); idx = kc.link_sphere_idx_map.cpu().numpy()
centres = np.array([(W[int(idx[i])] @ np.r_[spheres[i, :3], 1.0])[:3] for i in range(len(spheres))])
rad = spheres[:, 3] + sc.offset.cpu().numpy().astype(float) + float(os.environ.get("GROW", "0"))
m = sc.collision_matrix.cpu().numpy().reshape(len(spheres), len(spheres)) > 0
d = np.linalg.norm(centres[:, None] - centres[None], axis=2)
live = spheres[:, 3] > 0
pen = np.triu(m & (d < rad[:, None] + rad[None]) & live[:, None] & live[None], 1)
print("v1: %d spheres, %d sphere pairs checked, %d penetrating at retract_config"
      % (len(spheres), int(np.triu(m, 1).sum()), int(pen.sum())))
