"""Our robots against the robot assets ManiSkill 3.0.1 downloads at first use (the
repositories and tags its ``mani_skill/utils/assets/data.py`` names), with the numbers
written out here as read from those files:

- ``haosulab/ManiSkill-XArm6`` v0.1.1 (commit 438e7e4), ``xarm6_nogripper.urdf`` (the
  arm and ``camera_link`` of ``xarm6_robotiq.urdf`` are the same);
- ``haosulab/ManiSkill-WidowX250S`` v0.2.0 (commit 6a12bb7), ``wx250s.urdf``;
- ``TrossenRobotics/ManiSkill-WidowX_AI`` v0.1.0 (commit 0d55894), ``wxai_follower.urdf``
  (its arm is ``wxai_base.urdf``'s);
- ``haosulab/ManiSkill-UR10e`` v0.1.0 (commit 734bc91), ``ur10e.xml`` (MuJoCo Menagerie's
  model with a smaller shoulder capsule);
- ``haosulab/ManiSkill-Robotiq_2F`` v0.1.0 (commit fc8d5e0), ``floating_robotiq_2f_85.urdf``.

Where ours differs from the peer's file on purpose, the test states what ours follows
(docs/notes/robot-facts-audit.md, 2026-11-29 section). The Google Robot's URDF there
(``haosulab/ManiSkill-GoogleRobot`` v0.1.0) is byte for byte ManiSkill2_real2sim's, which
tests/test_google_robot.py already chains.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

import robot_agents as ra
from tests.chain_check import axis_rotation, transform

X, Y, Z = np.eye(3)
TURN = 2 * math.pi


def rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """URDF's fixed-axis roll-pitch-yaw: Rz(yaw) Ry(pitch) Rx(roll)."""
    return axis_rotation(Z, yaw) @ axis_rotation(Y, pitch) @ axis_rotation(X, roll)


def mj_quat(w: float, x: float, y: float, z: float) -> np.ndarray:
    """Rotation matrix of an MJCF ``quat`` as written (normalised here, as MuJoCo does)."""
    q = np.array([w, x, y, z]) / math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


#: A joint of a source file: (origin xyz in the parent link, origin rotation, axis).
Joint = tuple[tuple[float, float, float], np.ndarray, np.ndarray]


def source_chain(joints: list[Joint], q: np.ndarray) -> np.ndarray:
    """The child link of the last joint in the first joint's parent, ``(4, 4)``."""
    pose = np.eye(4)
    for (xyz, rotation, axis), angle in zip(joints, q, strict=True):
        pose = pose @ transform(rotation, np.array(xyz)) @ transform(axis_rotation(axis, float(angle)), np.zeros(3))
    return pose


class Model:
    """Our compiled robot with a data of its own, posed by its joint vector."""

    def __init__(self, uid: str) -> None:
        self.scene = ra.Scene(uid)
        self.agent = self.scene.agents[0]
        self.model = self.scene.model
        self.data = mujoco.MjData(self.model)

    def pose(self, q: np.ndarray, body: str, relative_to: str) -> np.ndarray:
        """``body`` in ``relative_to`` at the robot's joint vector ``q``, ``(4, 4)``."""
        self.data.qpos[self.agent.qpos_adr] = q
        mujoco.mj_kinematics(self.model, self.data)
        frames = []
        for name in (body, relative_to):
            i = self.model.body(self.agent.prefix + name).id
            frames.append(transform(self.data.xmat[i].reshape(3, 3).copy(), self.data.xpos[i].copy()))
        return np.linalg.inv(frames[1]) @ frames[0]

    def body_names(self) -> list[str]:
        n = len(self.agent.prefix)
        return [self.model.body(i).name[n:] for i in range(1, self.model.nbody)]

    def close(self) -> None:
        self.scene.close()


# ManiSkill-XArm6 xarm6_nogripper.urdf: joint1..joint6 (every axis z; the quarter turns
# written as 1.5708 rad), then camera_link_joint on link6.
QUARTER = 1.5708
XARM6_JOINTS: list[Joint] = [
    ((0.0, 0.0, 0.267), rpy(0.0, 0.0, 0.0), Z),
    ((0.0, 0.0, 0.0), rpy(-QUARTER, 0.0, 0.0), Z),
    ((0.0535, -0.2845, 0.0), rpy(0.0, 0.0, 0.0), Z),
    ((0.0775, 0.3425, 0.0), rpy(-QUARTER, 0.0, 0.0), Z),
    ((0.0, 0.0, 0.0), rpy(QUARTER, 0.0, 0.0), Z),
    ((0.076, 0.097, 0.0), rpy(-QUARTER, 0.0, 0.0), Z),
]
XARM6_CAMERA_LINK = transform(rpy(3.141592653589793, -0.0, 1.5707963267948966), np.array([0.05, 0.0, 0.0]))
XARM6_LIMITS = [
    (-6.28318530718, 6.28318530718),
    (-2.059, 2.0944),
    (-3.8, 0.19198),
    (-6.28318530718, 6.28318530718),
    (-1.69297, 3.14159265359),
    (-6.28318530718, 6.28318530718),
]


def test_xarm6_flange_and_camera_link_are_the_peers_urdf() -> None:
    """link6 through the peer URDF's joint origins at 20 random configurations (3e-5: the
    file's 1.5708 rad quarter turns are 3.7e-6 rad off; 1.4e-5 at most over 200
    configurations), and ``camera_link`` on link6 as
    the file places it (1e-9)."""
    ours = Model("xarm6_nogripper_wristcam")
    rng = np.random.default_rng(0)
    limits = ours.agent.qpos_limits
    for _ in range(20):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        expected = source_chain(XARM6_JOINTS, q)
        np.testing.assert_allclose(ours.pose(q, "link6", "link_base"), expected, atol=3e-5)
        np.testing.assert_allclose(ours.pose(q, "camera_link", "link6"), XARM6_CAMERA_LINK, atol=1e-9)
    ours.close()


def test_xarm6_joint_ranges_against_the_peers_urdf() -> None:
    """Every range equal to the peer's (1e-8: ours written to eight decimals) but joint
    3's lower end: ours is the datasheet's -225 deg (-3.927 rad, as UFactory's
    xarm_description ``xarm6.urdf.xacro``), the peer's file -3.8 rad (-217.7 deg)."""
    ours = Model("xarm6_nogripper")
    limits = ours.agent.qpos_limits
    for j, (lower, upper) in enumerate(XARM6_LIMITS):
        assert abs(limits[j, 1] - upper) < 1e-8, j
        if j != 2:
            assert abs(limits[j, 0] - lower) < 1e-8, j
    assert limits[2, 0] == -3.927
    assert abs(math.degrees(limits[2, 0]) + 225.0) < 0.01
    ours.close()


# ManiSkill-WidowX250S wx250s.urdf: the joints waist .. wrist_rotate (origins, no
# rotations), then the fixed ee_arm, gripper_bar, ee_bar and ee_gripper to ee_gripper_link.
WX250S_JOINTS: list[Joint] = [
    ((0.0, 0.0, 0.072), np.eye(3), Z),
    ((0.0, 0.0, 0.03865), np.eye(3), Y),
    ((0.04975, 0.0, 0.25), np.eye(3), Y),
    ((0.175, 0.0, 0.0), np.eye(3), X),
    ((0.075, 0.0, 0.0), np.eye(3), Y),
    ((0.065, 0.0, 0.0), np.eye(3), X),
]
WX250S_TOOL = transform(np.eye(3), np.array([0.043 + 0.0 + 0.023 + 0.027575, 0.0, 0.0]))
WX250S_LIMITS = [
    (-3.141592653589793, 3.141592653589793),
    (-1.8849555921538759, 1.9896753472735358),
    (-2.1467549799530254, 1.6057029118347832),
    (-3.141582653589793, 3.141582653589793),
    (-1.7453292519943295, 2.1467549799530254),
    (-3.141582653589793, 3.141582653589793),
]
WX250S_LINKS = [
    "base_link",
    "shoulder_link",
    "upper_arm_link",
    "upper_forearm_link",
    "lower_forearm_link",
    "wrist_link",
    "gripper_link",
    "ee_arm_link",
    "gripper_prop_link",
    "gripper_bar_link",
    "fingers_link",
    "left_finger_link",
    "right_finger_link",
    "ee_gripper_link",
]


def test_widowx250s_links_chain_and_ranges_against_the_peers_urdf() -> None:
    """The peer's 14 link names are our bodies; ee_gripper_link through its joint origins
    (1e-9); the arm's ranges within 5e-6 rad of the file's (ours are written to five
    decimals) but the waist's, which the peer opens to +-pi where Interbotix's xacro (our
    source) has +-(pi - 1e-5), as for forearm_roll and wrist_rotate; the fingers'
    0.015 .. 0.037 m (the peer's right finger slides along -y, ours along +y with the
    range negated: the same positions)."""
    ours = Model("widowx250s")
    assert ours.body_names() == WX250S_LINKS
    limits = ours.agent.qpos_limits
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        expected = source_chain(WX250S_JOINTS, q[:6]) @ WX250S_TOOL
        np.testing.assert_allclose(ours.pose(q, "ee_gripper_link", "base_link"), expected, atol=1e-9)
    for j, (lower, upper) in enumerate(WX250S_LIMITS[1:], start=1):
        np.testing.assert_allclose(limits[j], [lower, upper], atol=5e-6)
    np.testing.assert_allclose(limits[0], [-(math.pi - 1e-5), math.pi - 1e-5], atol=3e-6)
    assert limits[0, 1] < WX250S_LIMITS[0][1] - 1e-5
    np.testing.assert_allclose(limits[6], [0.015, 0.037])
    np.testing.assert_allclose(-limits[7, ::-1], [0.015, 0.037])
    axes = [ours.model.jnt_axis[ours.model.joint(ours.agent.prefix + n).id] for n in ("left_finger", "right_finger")]
    np.testing.assert_array_equal(axes, [Y, Y])
    ours.close()


# ManiSkill-WidowX_AI wxai_follower.urdf: joint_0 .. joint_5 (origins, no rotations),
# ee_gripper to ee_gripper_link, the carriages, and the D405's chain to camera_link:
# camera_mount_joint, camera_joint (pitched 0.3490658503988659 rad), camera_link_joint.
WXAI_JOINTS: list[Joint] = [
    ((0.0, 0.0, 0.05725), np.eye(3), Z),
    ((0.02, 0.0, 0.04625), np.eye(3), Y),
    ((-0.264, 0.0, 0.0), np.eye(3), -Y),
    ((0.245, 0.0, 0.06), np.eye(3), -Y),
    ((0.06775, 0.0, 0.0455), np.eye(3), -Z),
    ((0.02895, 0.0, -0.0455), np.eye(3), X),
]
WXAI_TOOL = transform(np.eye(3), np.array([0.156062, 0.0, 0.0]))
WXAI_CAMERA_LINK = (
    transform(np.eye(3), np.array([0.012, 0.0, 0.0]))
    @ transform(rpy(0.0, 0.3490658503988659, 0.0), np.array([0.02927207801, 0.0, 0.03824951197]))
    @ transform(np.eye(3), np.array([0.01085, 0.009, 0.021]))
)
WXAI_RANGES = [
    (-3.0543261909900767, 3.0543261909900767),
    (0.0, 3.141592653589793),
    (0.0, 2.356194490192345),
    (-1.5707963267948966, 1.5707963267948966),
    (-1.5707963267948966, 1.5707963267948966),
    (-3.141592653589793, 3.141592653589793),
    (0.0, 0.044),
    (0.0, 0.044),
]
WXAI_CARRIAGES = [("right_carriage_joint", (0.0865, -0.023, 0.0), -Y), ("left_carriage_joint", (0.0865, 0.023, 0.0), Y)]


def test_widowxai_chain_ranges_and_camera_link_against_the_peers_urdf() -> None:
    """Joint names and axes as the file's; ``ee_gripper_link`` through its joint
    origins (1e-9); ranges within 5e-6 (ours are Menagerie's, written to five or six
    digits); the carriages' origins and axes; ``camera_link`` on ``link_6`` through the
    D405 mount's three fixed joints (1e-6: ours holds Menagerie's 6-digit numbers)."""
    ours = Model("widowxai_wristcam")
    names = [f"joint_{i}" for i in range(6)] + [name for name, _, _ in WXAI_CARRIAGES]
    assert list(ours.agent.joint_names) == names
    limits = ours.agent.qpos_limits
    np.testing.assert_allclose(limits, WXAI_RANGES, atol=5e-6)
    rng = np.random.default_rng(3)
    for _ in range(20):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        expected = source_chain(WXAI_JOINTS, q[:6]) @ WXAI_TOOL
        np.testing.assert_allclose(ours.pose(q, "ee_gripper_link", "base_link"), expected, atol=1e-9)
        np.testing.assert_allclose(ours.pose(q, "camera_link", "link_6"), WXAI_CAMERA_LINK, atol=1e-6)
    for name, origin, axis in WXAI_CARRIAGES:
        j = ours.model.joint(ours.agent.prefix + name).id
        np.testing.assert_array_equal(ours.model.jnt_axis[j], axis)
        carriage = "carriage_right" if name.startswith("right") else "carriage_left"
        q = np.zeros(8)
        np.testing.assert_allclose(ours.pose(q, carriage, "link_6")[:3, 3], origin, atol=1e-9)
    ours.close()


# ManiSkill-UR10e ur10e.xml (Menagerie's body frames, lengths to the mm): base quat
# (1, 0, 0, 1) in the world, then each body's pos / quat and its joint's axis.
UR10E_BASE = mj_quat(1.0, 0.0, 0.0, 1.0)
UR10E_JOINTS: list[Joint] = [
    ((0.0, 0.0, 0.181), np.eye(3), Z),
    ((0.0, 0.176, 0.0), mj_quat(1.0, 0.0, 1.0, 0.0), Y),
    ((0.0, -0.137, 0.613), np.eye(3), Y),
    ((0.0, 0.0, 0.571), mj_quat(1.0, 0.0, 1.0, 0.0), Y),
    ((0.0, 0.135, 0.0), np.eye(3), Z),
    ((0.0, 0.0, 0.12), np.eye(3), Y),
]
UR10E_NAMES = [
    ("shoulder_link", "shoulder_pan_joint"),
    ("upper_arm_link", "shoulder_lift_joint"),
    ("forearm_link", "elbow_joint"),
    ("wrist_1_link", "wrist_1_joint"),
    ("wrist_2_link", "wrist_2_joint"),
    ("wrist_3_link", "wrist_3_joint"),
]


def test_ur10e_is_the_peers_model_turned_a_quarter_about_z() -> None:
    """Same joint and link names in the same order; the peer's wrist_3_link, chained from
    its file, is ours turned -90 deg about z (the peer's base is Menagerie's, yawed 90 deg
    from UR's controller base frame, which is ours): orientations to 1e-9, positions to
    2 mm (the file's lengths are rounded to the mm: 0.181 for d1 0.1807, ...). Ranges:
    the file's +-6.28319 and elbow +-3.1415 are 2 pi and pi rounded (ours exact, 1e-4)."""
    ours = Model("ur_10e")
    assert list(ours.agent.joint_names) == [joint for _, joint in UR10E_NAMES]
    assert ours.body_names()[1:7] == [link for link, _ in UR10E_NAMES]
    turn = transform(axis_rotation(Z, -math.pi / 2), np.zeros(3))
    rng = np.random.default_rng(2)
    limits = ours.agent.qpos_limits
    for _ in range(20):
        q = rng.uniform(limits[:, 0], limits[:, 1])
        peer = transform(UR10E_BASE, np.zeros(3)) @ source_chain(UR10E_JOINTS, q)
        mine = turn @ ours.pose(q, "wrist_3_link", "base")
        np.testing.assert_allclose(mine[:3, :3], peer[:3, :3], atol=1e-9)
        np.testing.assert_allclose(mine[:3, 3], peer[:3, 3], atol=2e-3)
    np.testing.assert_allclose(
        limits, [[-6.28319, 6.28319]] * 2 + [[-3.1415, 3.1415]] + [[-6.28319, 6.28319]] * 3, atol=1e-4
    )
    ours.close()


# ManiSkill-Robotiq_2F floating_robotiq_2f_85.urdf: the mount's joints in order (three
# prismatic then three revolute, axes x, y, z twice); its ranges are +-20 (m, rad).
MOUNT = [
    ("root_x_axis_joint", mujoco.mjtJoint.mjJNT_SLIDE, X),
    ("root_y_axis_joint", mujoco.mjtJoint.mjJNT_SLIDE, Y),
    ("root_z_axis_joint", mujoco.mjtJoint.mjJNT_SLIDE, Z),
    ("root_x_rot_joint", mujoco.mjtJoint.mjJNT_HINGE, X),
    ("root_y_rot_joint", mujoco.mjtJoint.mjJNT_HINGE, Y),
    ("root_z_rot_joint", mujoco.mjtJoint.mjJNT_HINGE, Z),
]


def test_floating_robotiq_mount_joints_are_the_peers() -> None:
    """The mount's six joints: the peer's names, order, kinds and axes. Their ranges are
    ours (+-1 m, +-pi; the peer's file: +-20), the gripper linkage Menagerie's (its module)."""
    ours = Model("floating_robotiq_2f_85_gripper")
    assert list(ours.agent.joint_names[:6]) == [name for name, _, _ in MOUNT]
    for name, kind, axis in MOUNT:
        j = ours.model.joint(ours.agent.prefix + name).id
        assert ours.model.jnt_type[j] == kind, name
        np.testing.assert_array_equal(ours.model.jnt_axis[j], axis)
    np.testing.assert_allclose(ours.agent.qpos_limits[:6], [[-1.0, 1.0]] * 3 + [[-math.pi, math.pi]] * 3, atol=1e-8)
    ours.close()
