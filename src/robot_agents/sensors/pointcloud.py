"""Point clouds: depth images back-projected into the world frame and fused over cameras.

Layout (ManiSkill's): ``xyzw`` ``(N, P, 4)`` float32 world coordinates (m) with ``w = 1``
for pixels that see something and ``w = 0`` (and ``xyz = 0``) for those that see
nothing (depth at the far plane); ``rgb`` ``(N, P, 3)`` uint8; ``segmentation``
``(N, P, 1)`` int16 segmentation ids. ``P`` is the sum of ``H * W`` over the cameras, in camera
order, each camera's pixels row by row.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import numpy.typing as npt

from robot_agents.kinematics.rotations import GL_TO_CV

FloatArray = npt.NDArray[np.float64]


def pixel_rays(intrinsic: FloatArray, width: int, height: int) -> FloatArray:
    """OpenCV camera-frame rays ``((u - cx) / fx, (v - cy) / fy, 1)`` of every pixel,
    shape ``(H * W, 3)``, row by row; a point at depth ``z`` is ``z * ray``."""
    v, u = np.mgrid[0:height, 0:width]
    rays = np.empty((height * width, 3))
    rays[:, 0] = (u.reshape(-1) - intrinsic[0, 2]) / intrinsic[0, 0]
    rays[:, 1] = (v.reshape(-1) - intrinsic[1, 2]) / intrinsic[1, 1]
    rays[:, 2] = 1.0
    return rays


def world_points(depth: npt.NDArray[np.float32], rays: FloatArray, cam2world_gl: FloatArray) -> FloatArray:
    """World coordinates (m) of every pixel, shape ``(N, H * W, 3)``, from depth
    ``(N, H, W, 1)``, :func:`pixel_rays` and camera poses ``(N, 4, 4)``."""
    n = depth.shape[0]
    camera_points = rays[None] * depth.reshape(n, -1, 1).astype(np.float64)
    rotation = cam2world_gl[:, :3, :3] @ GL_TO_CV  # OpenCV camera axes to world
    points: FloatArray = np.einsum("nij,npj->npi", rotation, camera_points) + cam2world_gl[:, None, :3, 3]
    return points


def fuse(
    images: Mapping[str, Mapping[str, npt.NDArray[np.generic]]],
    rays: Mapping[str, FloatArray],
    poses: Mapping[str, FloatArray],
    far: Mapping[str, float],
) -> dict[str, npt.NDArray[np.generic]]:
    """Fuse every camera's ``rgb``, ``depth`` and ``segmentation`` (from
    ``CameraRig.capture``) into one world-frame point cloud (layout above).

    ``rays``, ``poses`` (``cam2world_gl``, ``(N, 4, 4)``) and ``far`` are keyed by camera."""
    xyzw, rgb, seg = [], [], []
    for key, texture in images.items():
        depth = np.asarray(texture["depth"])
        n = depth.shape[0]
        points = world_points(depth, rays[key], poses[key])
        valid = (depth.reshape(n, -1) < far[key]).astype(np.float64)
        xyzw.append(np.concatenate([points * valid[..., None], valid[..., None]], axis=2))
        rgb.append(np.asarray(texture["rgb"]).reshape(n, -1, 3))
        seg.append(np.asarray(texture["segmentation"]).reshape(n, -1, 1))
    return {
        "xyzw": np.concatenate(xyzw, axis=1).astype(np.float32),
        "rgb": np.concatenate(rgb, axis=1),
        "segmentation": np.concatenate(seg, axis=1),
    }
