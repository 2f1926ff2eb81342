"""The robots' cameras against their sources: the optical frame chained from the source's
numbers (1e-9), the intrinsic matrix, resolution and clipping planes, and in the image a
point placed off the optical axis lands at the pixel the source's camera predicts.

Conventions. MuJoCo (and our ``cam2world_gl``) cameras look along their -z with +y up;
ROS optical frames and OpenCV look along +z with +y down (``CV_TO_GL`` turns one into the
other); SAPIEN (ManiSkill) cameras are given in ROS body axes, x forward, y left, z up,
whose optical frame is the URDF optical joint's rpy (-pi/2, 0, -pi/2) (``ROS_TO_CV``).
Pixels: ours are OpenCV's, pixel centres at integers (a centred ``W``-wide camera has
``cx = (W - 1) / 2``); SAPIEN's principal point counts from the image's edge (its
default ``cx`` is ``W / 2``, and its projection puts ``cx = W / 2`` on the image's
centre line: SAPIEN ``camera_component.cpp``), so a SAPIEN ``cx`` is our ``cx + 0.5``.

The mount links' forward kinematics against the same sources are tested in each robot's
test module; these tests chain the fixed camera transforms from the link the source
names."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics.rotations import matrix_to_quat
from robot_agents.robots.widowx.widowx250s import WidowX250S
from tests.chain_check import axis_rotation, transform

#: OpenCV / ROS optical axes -> MuJoCo camera axes (x kept, y and z flipped).
CV_TO_GL = np.diag([1.0, -1.0, -1.0])


def rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll-pitch-yaw: Rz(yaw) Ry(pitch) Rx(roll)."""
    x, y, z = np.eye(3)
    return axis_rotation(z, yaw) @ axis_rotation(y, pitch) @ axis_rotation(x, roll)


#: A ROS body frame (x forward, y left, z up; SAPIEN's camera axes) -> its optical frame.
ROS_TO_CV = rpy(-math.pi / 2, 0.0, -math.pi / 2)


def sapien_quat(w: float, x: float, y: float, z: float) -> np.ndarray:
    """Rotation matrix of a SAPIEN ``(w, x, y, z)`` quaternion (Hamilton, as written in
    the source), computed here rather than with the library's converter."""
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def centred(fovy: float, width: int, height: int) -> np.ndarray:
    """OpenCV ``K`` of a centred camera with vertical field of view ``fovy`` (rad)."""
    focal = height / 2 / math.tan(fovy / 2)
    return np.array([[focal, 0.0, (width - 1) / 2], [0.0, focal, (height - 1) / 2], [0.0, 0.0, 1.0]])


def habitat_k(hfov: float, width: int, height: int) -> np.ndarray:
    """OpenCV ``K`` of a Habitat-sim pinhole camera: ``hfov`` (rad) spans the image's
    width, pixels square, centred (Habitat-sim ``CameraSensor.cpp``)."""
    focal = width / 2 / math.tan(hfov / 2)
    return np.array([[focal, 0.0, (width - 1) / 2], [0.0, focal, (height - 1) / 2], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class Source:
    """A robot camera as its source gives it.

    Attributes:
        robot, camera: our robot uid and camera uid.
        parent: the link the source chains the camera from.
        optical: ``(4, 4)`` the source's optical frame (OpenCV axes) in ``parent``.
        intrinsic: ``(3, 3)`` the source's ``K`` in our (OpenCV) pixel convention at
            ``size``.
        size: ``(width, height)`` in pixels.
        near, far: clipping planes (m).
        point: a point in the optical frame (m, +z ahead) that the camera sees unblocked
            at the robot's default reset; ``tolerance`` (pixels) for its image.
        pose_atol: tolerance of the pose (1e-9 unless the model holds a rounded number).
    """

    robot: str
    camera: str
    parent: str
    optical: np.ndarray
    intrinsic: np.ndarray
    size: tuple[int, int]
    near: float
    far: float
    point: tuple[float, float, float]
    tolerance: float = 0.25
    pose_atol: float = 1e-9


def maniskill(parent_to_mount: np.ndarray, p: tuple[float, float, float], q: tuple[float, ...]) -> np.ndarray:
    """ManiSkill's ``CameraConfig(pose=Pose(p, q))`` on a mount link (the mount given in
    ``parent``), as the optical frame in ``parent``."""
    return parent_to_mount @ transform(sapien_quat(*q) @ ROS_TO_CV, np.array(p))


IDENTITY = (1.0, 0.0, 0.0, 0.0)
#: ManiSkill's ``fov=2`` (fetch.py) and ``fov=np.pi / 2`` (widowxai_wristcam.py,
#: xarm6_*.py): SAPIEN's vertical field of view, rad.
FETCH_FOV, WRIST_FOV = 2.0, math.pi / 2
#: SimplerEnv's (ManiSkill2_real2sim ``GoogleRobotManualTunedIntrinsicConfig``, and
#: ManiSkill 3.0.1 ``googlerobot.py``) overhead camera: 640 x 512, SAPIEN ``K``.
GOOGLE_K_SAPIEN = np.array([[425.0, 0.0, 305.0], [0.0, 413.1, 233.0], [0.0, 0.0, 1.0]])


def google_k(scale: float) -> np.ndarray:
    """SimplerEnv's ``K`` at ``scale`` x 640 x 512 in our convention: SAPIEN's principal
    point counts from the edge, so it scales as is; ours is half a pixel less."""
    k = GOOGLE_K_SAPIEN * np.array([[scale], [scale], [1.0]])
    k[:2, 2] -= 0.5
    return k


SOURCES = [
    # fetch_ros fetch.urdf (ManiSkill 3.0.1's copy): head_camera_joint (0.055, 0, 0.0225)
    # on head_tilt_link; ManiSkill 3.0.1 fetch.py: fetch_head at Pose([0, 0, 0], [1, 0, 0, 0])
    # on head_camera_link, 128 x 128, fov 2, near 0.01, far 100.
    Source(
        "fetch",
        "fetch_head",
        "head_tilt_link",
        maniskill(transform(np.eye(3), np.array([0.055, 0.0, 0.0225])), (0.0, 0.0, 0.0), IDENTITY),
        centred(FETCH_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (-1.2, -0.6, 2.0),
    ),
    # ManiSkill 3.0.1 fetch.py: fetch_hand at Pose([-0.1, 0, 0.1], [1, 0, 0, 0]) on gripper_link.
    Source(
        "fetch",
        "fetch_hand",
        "gripper_link",
        maniskill(np.eye(4), (-0.1, 0.0, 0.1), IDENTITY),
        centred(FETCH_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.2, -0.3, 0.8),
    ),
    # Trossen / Menagerie wxai: the D405 mount 0.012 m along link_6's x, camera_link at
    # (0.04665, 0.009, 0.054272) on it pitched 20 deg about y; ManiSkill 3.0.1
    # widowxai_wristcam.py: wrist_camera at Pose([0, 0, 0], [1, 0, 0, 0]) on camera_link,
    # 128 x 128, fov pi / 2, near 0.01, far 100. Our camera_link holds Menagerie's 6-digit
    # quaternion of the 20 deg pitch (0.984808, 0, 0.173648, 0): 4e-7 off.
    Source(
        "widowxai_wristcam",
        "wrist_camera",
        "link_6",
        maniskill(
            transform(rpy(0.0, math.radians(20.0), 0.0), np.array([0.012 + 0.04665, 0.009, 0.054272])),
            (0.0, 0.0, 0.0),
            IDENTITY,
        ),
        centred(WRIST_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.03, -0.03, 0.12),
        pose_atol=1e-6,
    ),
    # ManiSkill's xarm6_nogripper.urdf (ManiSkill-XArm6 v0.1.1, 438e7e4; tests/test_peer_assets.py):
    # camera_link at (0.05, 0, 0), rpy (pi, 0, pi/2) on link6; ManiSkill 3.0.1 xarm6_nogripper.py: hand_camera at Pose([0, 0, -0.05],
    # [0.70710678, 0, 0.70710678, 0]) on camera_link, 128 x 128, fov pi / 2, near 0.01, far 100.
    Source(
        "xarm6_nogripper_wristcam",
        "hand_camera",
        "link6",
        maniskill(
            transform(rpy(math.pi, 0.0, math.pi / 2), np.array([0.05, 0.0, 0.0])),
            (0.0, 0.0, -0.05),
            (0.70710678, 0.0, 0.70710678, 0.0),
        ),
        centred(WRIST_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.1, 0.05, 0.2),
        pose_atol=1e-8,  # the source's 8-digit quaternion
    ),
    # UFactory xarm_description/urdf/camera/realsense_d435i.urdf.xacro: camera_link at
    # (0.06746, -0.0175, 0.0237), rpy (pi, -pi/2, 0) on link_eef; camera_color_frame on
    # it unturned, camera_color_optical_frame at rpy (-pi/2, 0, -pi/2). Projection:
    # ManiSkill 3.0.1 xarm6_robotiq.py's hand_camera (128 x 128, fov pi / 2, 0.01, 100).
    Source(
        "xarm6_robotiq_wristcam",
        "hand_camera",
        "link_eef",
        transform(rpy(math.pi, -math.pi / 2, 0.0), np.array([0.06746, -0.0175, 0.0237]))
        @ transform(ROS_TO_CV, np.zeros(3)),
        centred(WRIST_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.05, 0.05, 0.25),
    ),
    # Habitat-lab spot_robot.py (articulated_agent_arm_rgb / _depth): on link 6
    # (arm0.link_wr1), orientation rotation_y(-1.571) rotation_z(-90 deg) in Habitat's
    # camera axes (MuJoCo's: -z ahead, +y up), here with -pi/2 for its -1.571; its offset
    # (0.166, 0.023, 0.03) m lies inside our primitive jaw's sweep, so the position
    # (0.101, 0, -0.03) m, at the housing's face, is ours. Image: Habitat-lab
    # sensor_setups/spot_agent.yaml arm_rgb_sensor, 640 x 480, hfov 47 (Habitat-sim's
    # horizontal angle); planes Habitat-sim's defaults (VisualSensor.h), 0.01 / 1000 m.
    Source(
        "spot",
        "hand_camera",
        "arm_link_wr1",
        transform(rpy(0.0, -math.pi / 2, 0.0) @ rpy(0.0, 0.0, -math.pi / 2) @ CV_TO_GL, np.array([0.101, 0.0, -0.03])),
        habitat_k(math.radians(47.0), 160, 120),  # Habitat's view rendered at 160 x 120
        (160, 120),
        0.01,
        1000.0,
        (0.03, 0.04, 0.25),
    ),
    # SimplerEnv google_robot_meta_sim_fix_fingertip.urdf: joint_camera_mount (0.10488, 0, 0),
    # rpy (-pi/2, 0, -pi/2) on link_head_tilt (link_camera is an optical frame);
    # overhead_camera at p [0, 0, 0], q [0.5, 0.5, -0.5, 0.5] on link_camera, 640 x 512,
    # K GOOGLE_K_SAPIEN; here at a quarter of the resolution; ManiSkill 3.0.1's near 0.01, far 100.
    Source(
        "google_robot",
        "overhead_camera",
        "link_head_tilt",
        maniskill(
            transform(rpy(-math.pi / 2, 0.0, -math.pi / 2), np.array([0.10488, 0.0, 0.0])),
            (0.0, 0.0, 0.0),
            (0.5, 0.5, -0.5, 0.5),
        ),
        google_k(0.25),
        (160, 128),
        0.01,
        100.0,
        (0.02, 0.01, 1.0),
    ),
    # ManiSkill 3.0.1 g1_upper_body.py: head_camera at Pose([0.05, 0, 0.46],
    # euler2quat(0, pi / 6, 0)) on head_link, 128 x 128, fov pi / 2, near 0.01, far 100
    # (euler2quat's (w, x, y, z) of a pi / 6 pitch written out here).
    Source(
        "unitree_g1_simplified_upper_body_with_head_camera",
        "head_camera",
        "head_link",
        maniskill(np.eye(4), (0.05, 0.0, 0.46), (math.cos(math.pi / 12), 0.0, math.sin(math.pi / 12), 0.0)),
        centred(WRIST_FOV, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.3, -0.3, 1.0),
    ),
    # ManiSkill 3.0.1 stompy.py: head_camera at Pose([0.12, 0, 0.02], euler2quat(-pi / 2,
    # 0, 0)) on link_head_1_head_1, 128 x 128, fov 1.57, near 0.01, far 100 (euler2quat's
    # (w, x, y, z) of a -pi / 2 roll written out here).
    Source(
        "stompy",
        "head_camera",
        "link_head_1_head_1",
        maniskill(np.eye(4), (0.12, 0.0, 0.02), (math.cos(-math.pi / 4), math.sin(-math.pi / 4), 0.0, 0.0)),
        centred(1.57, 128, 128),
        (128, 128),
        0.01,
        100.0,
        (0.3, -0.3, 1.0),
    ),
    # Vector-Wangel/ManiSkill-XLeRobot v0.2.1 xlerobot.urdf: head_camera_joint (0.055, 0,
    # 0.0225) on head_tilt_link, Right_Arm_Camera_joint / Left_Arm_Camera_joint (0, -0.02,
    # 0.05), rpy (1.5708, 0, -1.5708) on Fixed_Jaw / Fixed_Jaw_2; ManiSkill 3.0.1
    # xlerobot.py: fetch_head at Pose([0, 0, 0], [1, 0, 0, 0]) on head_camera_link, 256 x 256,
    # fov 1.6; the arm cameras at the identity on their links, 128 x 128, fov 1.3; near
    # 0.01, far 100.
    Source(
        "xlerobot",
        "fetch_head",
        "head_tilt_link",
        maniskill(transform(np.eye(3), np.array([0.055, 0.0, 0.0225])), (0.0, 0.0, 0.0), IDENTITY),
        centred(1.6, 256, 256),
        (256, 256),
        0.01,
        100.0,
        (0.3, -0.2, 2.0),
    ),
    *(
        Source(
            "xlerobot",
            camera,
            jaw,
            maniskill(transform(rpy(1.5708, 0.0, -1.5708), np.array([0.0, -0.02, 0.05])), (0.0, 0.0, 0.0), IDENTITY),
            centred(1.3, 128, 128),
            (128, 128),
            0.01,
            100.0,
            (-0.1, 0.05, 0.8),
        )
        for camera, jaw in (("fetch_right_arm_camera", "Fixed_Jaw"), ("fetch_left_arm_camera", "Fixed_Jaw_2"))
    ),
]


def link_pose(scene: ra.Scene, name: str) -> np.ndarray:
    """``(4, 4)`` world pose of the robot's link ``name`` after the last forward pass."""
    agent = scene.agents[0]
    body = agent.index.body_id(name, "test")
    data = scene.world.datas[0]
    return transform(data.xmat[body].reshape(3, 3), data.xpos[body].copy())


def source_pose(scene: ra.Scene, source: Source) -> np.ndarray:
    """The source's optical frame in the world, ``(4, 4)``, OpenCV axes."""
    return link_pose(scene, source.parent) @ source.optical


@pytest.mark.parametrize("source", SOURCES, ids=lambda s: f"{s.robot}-{s.camera}")
def test_camera_is_the_sources_optical_frame_and_projection(source: Source) -> None:
    """cam2world_gl is the source's optical frame in MuJoCo's axes (1e-9), the intrinsic
    matrix the source's (1e-9, our pixel convention), and the image size and clipping
    planes are the source's."""
    scene = ra.Scene(source.robot)
    scene.reset()
    params = scene.cameras.params(scene.world)[source.camera]
    expected = source_pose(scene, source)
    expected[:3, :3] = expected[:3, :3] @ CV_TO_GL
    np.testing.assert_allclose(params["cam2world_gl"][0], expected, atol=source.pose_atol)
    np.testing.assert_allclose(params["intrinsic_cv"][0], source.intrinsic, atol=1e-9)
    config = next(c for c in type(scene.agents[0]).cameras if c.uid == source.camera)
    assert (config.width, config.height, config.near, config.far) == (*source.size, source.near, source.far)
    scene.close()


def seen_at(source: Source, optical: np.ndarray, point: np.ndarray, radius: float) -> tuple[np.ndarray, int]:
    """Centroid ``(u, v)`` (pixels) of a thin disc of ``radius`` (m) centred on ``point``
    (optical frame, m) and facing the camera (parallel to the image plane, so its image is
    a circle centred on the point's projection) in the camera's segmentation image at the
    robot's default reset, and its pixel count. ``optical``: the optical frame in the world."""
    centre = optical[:3, :3] @ point + optical[:3, 3]
    disc = ra.Prop(
        "disc",
        "cylinder",  # its axis along the optical axis
        size=(radius, 0.0005),
        pos=tuple(float(v) for v in centre),
        quat=tuple(float(v) for v in matrix_to_quat(optical[:3, :3])),
        mass=None,
    )
    scene = ra.Scene(source.robot, props=[disc])
    scene.reset()
    seg = scene.cameras.capture(scene.world, ("segmentation",))[source.camera]["segmentation"][0, :, :, 0]
    rows, columns = np.nonzero(seg == scene.model.body("disc").id)
    scene.close()
    return np.array([columns.mean(), rows.mean()]) if rows.size else np.full(2, np.nan), int(rows.size)


@pytest.mark.parametrize("source", SOURCES, ids=lambda s: f"{s.robot}-{s.camera}")
def test_a_point_lands_at_the_pixel_the_source_predicts(source: Source) -> None:
    """A disc centred on a point off the optical axis (in the source's optical frame, in
    a part of the image the robot does not cover) shows where the source's K puts that
    point: its centroid within ``tolerance`` pixels (a 10-pixel-radius disc, so the
    centroid is sub-pixel). A camera rolled by 180 deg, mirrored, shifted by a few mm or
    by half a pixel would miss."""
    scene = ra.Scene(source.robot)
    scene.reset()
    optical = source_pose(scene, source)
    scene.close()
    point = np.array(source.point)
    predicted = (source.intrinsic @ point)[:2] / point[2]
    centroid, count = seen_at(source, optical, point, 10.0 * point[2] / source.intrinsic[1, 1])
    assert count > 300, f"the disc is not seen whole ({count} pixels of about 314)"
    np.testing.assert_allclose(centroid, predicted, atol=source.tolerance)


def test_fetch_head_camera_is_the_urdf_head_camera_link_not_its_rgb_optical_frame() -> None:
    """ManiSkill mounts fetch_head on head_camera_link; fetch.urdf's colour camera,
    head_camera_rgb_optical_frame, is head_camera_link + (0, 0.02, 0) turned by rpy
    (-pi/2, 0, -pi/2): the same orientation (1e-9), 0.02 m to the image's left (the
    robot's +y); its depth optical frame 0.045 m. Kept at ManiSkill's mount: a 0.4-pixel
    shift at 2 m in the 128-pixel, 2 rad image."""
    scene = ra.Scene("fetch")
    scene.reset()
    pose = scene.cameras.params(scene.world)["fetch_head"]["cam2world_gl"][0]
    rgb_frame = transform(np.eye(3), np.array([0.055, 0.0, 0.0225])) @ transform(np.eye(3), np.array([0.0, 0.02, 0.0]))
    optical = link_pose(scene, "head_tilt_link") @ rgb_frame @ transform(ROS_TO_CV, np.zeros(3))
    np.testing.assert_allclose(pose[:3, :3], optical[:3, :3] @ CV_TO_GL, atol=1e-9)
    image_left = -pose[:3, 0]
    np.testing.assert_allclose(optical[:3, 3] - pose[:3, 3], 0.02 * image_left, atol=1e-9)
    # head_camera_depth_frame: (0, 0.045, 0) on head_camera_link, the same optical turn.
    depth_frame = transform(np.eye(3), np.array([0.055, 0.045, 0.0225])) @ transform(ROS_TO_CV, np.zeros(3))
    depth_optical = link_pose(scene, "head_tilt_link") @ depth_frame
    np.testing.assert_allclose(depth_optical[:3, :3], optical[:3, :3], atol=1e-9)
    np.testing.assert_allclose(depth_optical[:3, 3] - pose[:3, 3], 0.045 * image_left, atol=1e-9)
    scene.close()


def test_widowx250s_declares_no_camera_as_maniskill() -> None:
    """ManiSkill 3.0.1's WidowX250S agent (widowx.py) declares no sensor; only its Bridge
    dataset variants carry the 3rd-view camera (tests/test_widowx.py). Ours neither."""
    assert WidowX250S.cameras == ()
    scene = ra.Scene("widowx250s")
    assert scene.cameras.params(scene.world) == {}
    scene.close()
