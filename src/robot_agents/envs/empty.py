"""``Empty-v1``: the robot alone on a floor; no reward, never terminates.

For trying control modes, benchmarking and demos.
"""

from __future__ import annotations

from collections.abc import Sequence

from robot_agents.envs.base_env import RobotEnv
from robot_agents.sensors.camera import CameraConfig

#: The task camera: 128 x 128, 90 deg, in front of the robot looking back at it and at
#: the floor before it (world frame, m).
BASE_CAMERA = CameraConfig.look_at("base_camera", eye=(1.0, 0.0, 0.8), target=(0.3, 0.0, 0.25))


class EmptyEnv(RobotEnv):
    """A robot on an empty floor. Observation: proprioception and tool pose (and, in
    camera modes, the robot's cameras and ``base_camera``)."""

    def _scene_cameras(self) -> Sequence[CameraConfig]:
        return (BASE_CAMERA,)
