"""The floating grippers' ``pd_ee_pose`` box covers every tool position their mount
reaches, and no more than it: computed on the compiled model when the robot is built
(``FloatingMountTaskSpace``, robot_agents.agent.mount_task_space), for the built-in
floating grippers and for a user's (another gripper on the same mount, a mount with
other slide travels); mounts it cannot bound are refused, saying why."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.controllers.task_space import FloatingMountTaskSpace
from robot_agents.robots.floating_mount import MOUNT_JOINTS, SLIDE_TRAVEL, mount_arm

UIDS = ("floating_panda_gripper", "floating_robotiq_2f_85_gripper")
#: How close (m) the box's faces are to the farthest sampled tool points.
TIGHTNESS = 0.005  # measured gaps: at most 1.9 mm (Franka Hand), 0.66 mm (2F-85)
PANDA_MOUNT = Path(ra.__file__).parent / "robots" / "panda" / "assets" / "floating_mount.xml"
#: The WidowX 250 S gripper piece's TCP out of its mount (m; tests/test_widowx_piece.py).
WIDOWX_TCP_OUT = 0.093575
#: Where a user's gripper sits on the mount's root (m), and turned pi about x (pointing down).
USER_POS, DOWN = (0.01, 0.02, 0.03), (0.0, 1.0, 0.0, 0.0)


class FloatingWidowXGripper(ra.Agent):
    """A user's floating gripper: the WidowX 250 S gripper piece on the Franka Hand's
    floating mount file, off the hinges' common point by ``USER_POS``."""

    mjcf_path = PANDA_MOUNT
    attachments = (ra.Attachment(ra.get_piece("widowx250s_gripper"), at="root", pos=USER_POS, quat=DOWN),)
    actuators = (ra.PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2),)
    parts = (mount_arm("ee_gripper_link"),)
    keyframes = {"rest": ra.Keyframe(qpos={"root_.*": 0.0})}


def bounds(agent: ra.Agent) -> tuple[np.ndarray, np.ndarray]:
    """The pd_ee_pose box the built robot has (its arm's task space, computed at build)."""
    box = type(agent).check().parts[0].task_space.position_bounds
    return np.asarray(box.lower), np.asarray(box.upper)


def test_a_users_floating_gripper_gets_the_box_of_its_own_tool() -> None:
    """The WidowX gripper 1-3 cm off the hinges' point, turned down: its TCP is
    (0.01, 0.02, 0.03 - 0.093575) m from that point, and the box is +-1 m grown by that
    distance (from the geometry, not the model); the pd_ee_pose mode's actions span it."""
    offset = math.dist((*USER_POS[:2], USER_POS[2] - WIDOWX_TCP_OUT), (0.0, 0.0, 0.0))
    box = FloatingWidowXGripper.check().parts[0].task_space.position_bounds
    np.testing.assert_allclose(box.upper, [SLIDE_TRAVEL + offset] * 3, atol=1e-12)
    np.testing.assert_allclose(box.lower, [-(SLIDE_TRAVEL + offset)] * 3, atol=1e-12)
    scene = ra.Scene(FloatingWidowXGripper, control_modes="pd_ee_pose")
    scene.reset()
    space = scene.agents[0].single_action_space  # (float32)
    np.testing.assert_array_equal(space.low[:3], np.float32(box.lower))
    np.testing.assert_array_equal(space.high[:3], np.float32(box.upper))
    scene.close()


MOUNT_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="root" pos="0 0 0.5">
      {joints}
      <geom type="sphere" size="0.01" mass="0.1" contype="0" conaffinity="0"/>
      <body name="hand" pos="{hand}">
        {inner}
        <geom type="box" size="0.02 0.02 0.02" mass="0.5" contype="0" conaffinity="0"/>
        <site name="tool" pos="0 0 -0.1"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""
SLIDES = (
    '<joint name="root_x_axis_joint" type="slide" axis="1 0 0" range="-0.5 0.8"/>'
    '<joint name="root_y_axis_joint" type="slide" axis="0 1 0" range="-1 1"/>'
    '<joint name="root_z_axis_joint" type="slide" axis="0 0 1" range="0 0.6"/>'
)
HINGES = (
    '<joint name="root_x_rot_joint" type="hinge" axis="1 0 0" range="-3.14159 3.14159"/>'
    '<joint name="root_y_rot_joint" type="hinge" axis="0 1 0" range="-3.14159 3.14159"/>'
    '<joint name="root_z_rot_joint" type="hinge" axis="0 0 1" range="-3.14159 3.14159"/>'
)


def mount_robot(tmp_path: Path, joints: str, inner: str = "", hand: str = "0 0 0") -> type[ra.Agent]:
    path = tmp_path / "mount.xml"
    path.write_text(MOUNT_MJCF.format(joints=joints, inner=inner, hand=hand))

    class Mount(ra.Agent):
        mjcf_path = path
        actuators = (ra.PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2),)
        parts = (mount_arm("tool"),)

    return Mount


def test_the_box_reads_the_slides_travel_from_the_model(tmp_path: Path) -> None:
    """Slides of -0.5..0.8, -1..1 and 0..0.6 m, hinges at the root, the tool 0.1 m and
    a hand 0.05 m along x from the hinges' point: the box is the slides' travel grown by
    |(0.05, 0, -0.1)| m on every side."""
    robot = mount_robot(tmp_path, SLIDES + HINGES, hand="0.05 0 0")
    offset = math.hypot(0.05, 0.1)
    box = robot.check().parts[0].task_space.position_bounds
    np.testing.assert_allclose(box.lower, np.array([-0.5, -1.0, 0.0]) - offset, atol=1e-12)
    np.testing.assert_allclose(box.upper, np.array([0.8, 1.0, 0.6]) + offset, atol=1e-12)


@pytest.mark.parametrize(
    ("joints", "inner", "says"),
    [
        (HINGES + SLIDES, "", r"slides then hinges .*'root_x_rot_joint \(hinge\)'"),
        (SLIDES.replace(' range="-1 1"', ""), HINGES, r"slide joint\(s\) \['root_y_axis_joint'\] have no range"),
        (
            SLIDES + HINGES[: HINGES.index("<joint", 1)],
            HINGES[HINGES.index("<joint", 1) :],
            r"do not meet at one point \(one passes \d+(\.\d+)? mm",
        ),
    ],
    ids=["hinges-first", "unlimited-slide", "apart"],
)
def test_a_mount_it_cannot_bound_is_refused(tmp_path: Path, joints: str, inner: str, says: str) -> None:
    """Hinges before the slides, a slide without a range, and hinges whose axes miss
    each other (two of them on a hand 5 cm along y) raise ConfigError naming the arm."""
    robot = mount_robot(tmp_path, joints, inner, hand="0 0.05 0" if inner else "0 0 0")
    with pytest.raises(ra.ConfigError, match=r"Mount.parts\['arm'\]: FloatingMountTaskSpace\(\): " + f".*{says}"):
        robot.check()


def test_a_command_frame_moving_with_the_mount_is_refused(tmp_path: Path) -> None:
    """Tool commands in the hand's frame, which the mount carries: no box bounds them."""
    path = tmp_path / "mount.xml"
    path.write_text(MOUNT_MJCF.format(joints=SLIDES + HINGES, inner="", hand="0 0 0"))

    class Mount(ra.Agent):
        mjcf_path = path
        actuators = (ra.PDActuator(joints=MOUNT_JOINTS, stiffness=1e3, damping=1e2),)
        parts = (
            ra.Arm(
                name="arm",
                joints=MOUNT_JOINTS,
                end_effectors=(ra.EndEffector("tool", name="tcp", command_frame="hand"),),
                task_space=FloatingMountTaskSpace(),
            ),
        )

    with pytest.raises(ra.ConfigError, match=r"command frame 'hand' moves with the mount's joints"):
        Mount.check()


def test_the_declaration_is_checked() -> None:
    assert ra.FloatingMountTaskSpace is FloatingMountTaskSpace
    assert FloatingMountTaskSpace().modes == ("pd_ee_delta_pose", "pd_ee_pose")
    with pytest.raises(ra.ConfigError, match=r"FloatingMountTaskSpace.modes: expected .* got 'pd_ee_pose'"):
        FloatingMountTaskSpace(modes="pd_ee_pose")  # type: ignore[arg-type]


@pytest.mark.parametrize("uid", UIDS)
def test_the_tool_offset_is_the_models(uid: str) -> None:
    scene = ra.Scene(uid)
    scene.reset()
    agent = scene.agents[0]
    q = np.asarray(agent.keyframe_qpos("rest"), dtype=np.float64).copy()
    q[:6] = 0.0
    offset = float(np.linalg.norm(agent.frame_pose("tcp", q, relative_to="root")[0, :3]))
    lower, upper = bounds(agent)
    np.testing.assert_allclose(upper, SLIDE_TRAVEL + offset, atol=1e-9)
    np.testing.assert_allclose(lower, -(SLIDE_TRAVEL + offset), atol=1e-9)


@pytest.mark.parametrize("uid", [*UIDS, FloatingWidowXGripper], ids=[*UIDS, "user-widowx"])
def test_every_reachable_tool_position_is_inside_and_the_box_is_tight(uid: str | type[ra.Agent]) -> None:
    scene = ra.Scene(uid)
    scene.reset()
    agent = scene.agents[0]
    rest = np.asarray(agent.keyframe_qpos("rest"), dtype=np.float64)
    low, high = scene.model.jnt_range[:6].T  # the mount's slides then hinges
    rng = np.random.default_rng(0)
    n = 4000
    q = np.tile(rest, (n, 1))
    q[:, :6] = rng.uniform(low, high, size=(n, 6))
    # and the corners with the tool turned along each axis: the faces' points
    signs = rng.choice([-1.0, 1.0], size=(n // 4, 3))
    q[: n // 4, :3] = signs * high[:3]
    points = np.vstack([agent.frame_pose("tcp", row, relative_to="root")[0, :3] for row in q])
    lower, upper = bounds(agent)
    assert np.all(points >= lower - 1e-9) and np.all(points <= upper + 1e-9)
    # tight: on every face some sampled point lies within TIGHTNESS of it
    assert np.all(upper - points.max(axis=0) < TIGHTNESS), (upper, points.max(axis=0))
    assert np.all(points.min(axis=0) - lower < TIGHTNESS), (lower, points.min(axis=0))
    # the old +-1 m box missed some of them
    assert np.any(np.abs(points) > SLIDE_TRAVEL)
