"""Camera parameters per env, in ManiSkill's layout and conventions.

- ``cam2world_gl`` (4x4): the camera's pose in the world, axes in the OpenGL / MuJoCo
  camera convention (x right, y up, looking along -z).
- ``extrinsic_cv`` (3x4): world-to-camera ``[R | t]`` in the OpenCV convention (x
  right, y down, looking along +z): ``x_cam = R @ x_world + t``.
- ``intrinsic_cv`` (3x3): ``K``, pixels; ``K @ x_cam`` projects to ``(u, v)`` with
  pixel centres at integers.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from robot_agents.kinematics.rotations import GL_TO_CV

if TYPE_CHECKING:
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]


def extrinsic_cv(cam2world: FloatArray) -> FloatArray:
    """World-to-camera ``[R | t]`` in the OpenCV convention, shape ``(num_envs, 3, 4)``,
    from ``cam2world_gl`` poses ``(num_envs, 4, 4)``."""
    rot_cv = cam2world[:, :3, :3] @ GL_TO_CV  # camera-to-world rotation, OpenCV axes
    world_to_cam = np.transpose(rot_cv, (0, 2, 1))
    translation = -np.einsum("nij,nj->ni", world_to_cam, cam2world[:, :3, 3])
    return np.concatenate([world_to_cam, translation[:, :, None]], axis=2)


def camera_params(world: SimBackend, camera_id: int, intrinsic: FloatArray) -> dict[str, FloatArray]:
    """``intrinsic_cv`` ``(num_envs, 3, 3)``, ``extrinsic_cv`` ``(num_envs, 3, 4)`` and
    ``cam2world_gl`` ``(num_envs, 4, 4)`` of one camera (float64); the pose is MuJoCo's
    ``cam_xpos`` / ``cam_xmat`` after the last physics step."""
    pose = world.camera_poses(camera_id)
    return {
        "extrinsic_cv": extrinsic_cv(pose),
        "cam2world_gl": pose,
        "intrinsic_cv": np.broadcast_to(intrinsic, (len(pose), 3, 3)).copy(),
    }
