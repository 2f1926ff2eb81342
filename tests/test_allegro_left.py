"""The left Allegro Hand checked against numbers: fingertip forward kinematics against
Wonik's left description's joint origins chained here, the mirror image of the right
hand at every configuration, where ManiSkill's left URDF differs (by how much), the
right hand's masses and ranges; and :func:`robot_agents.model.mirror.mirror_spec` on its
own. Its physics claims (keyframes, random actions, power grasp) run in
tests/test_allegro.py with the right hand's."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.errors import ModelError
from robot_agents.model.mirror import mirror_spec
from robot_agents.robots.wonik.allegro import AllegroHandRight
from robot_agents.robots.wonik.allegro_left import SPREAD_JOINTS, AllegroHandLeft
from tests.chain_check import axis_rotation, transform
from tests.random_actions import after_random_actions
from tests.test_allegro import FINGER_RANGES, MASSES, THUMB_RANGES, rpy_matrix
from tests.test_allegro import tip_in_base as right_tip_in_base

UID = "allegro_hand_left"

# ---------------------------------------------------------------- independent kinematics
# Wonik's left description (allegro_hand_ros2 v4 allegro_hand_description_left.xacro;
# allegro_hand_ros allegro_hand_description_left.urdf: the same numbers), written out
# here, not read from our model or mirrored by code: per finger, the first joint's
# origin (position, rpy) in the palm frame, its axis, the following joints' offsets and
# axes, and the tip's offset along the last link's z.
X, Y, Z = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
MINUS_Z = (0.0, 0.0, -1.0)
WONIK_LEFT = {
    "index": ((0.0, -0.0435, -0.001542), (0.08726646255, 0.0, 0.0)),
    "middle": ((0.0, 0.0, 0.0007), (0.0, 0.0, 0.0)),
    "ring": ((0.0, 0.0435, -0.001542), (-0.08726646255, 0.0, 0.0)),
    "thumb": ((-0.0182, -0.019333, -0.045987), (0.0, -1.65806278845, 1.5707963259)),
}
FINGER_LINKS = [((0.0, 0.0, 0.0164), Y), ((0.0, 0.0, 0.054), Y), ((0.0, 0.0, 0.0384), Y)]
WONIK_LEFT_THUMB_LINKS = [((-0.027, -0.005, 0.0399), MINUS_Z), ((0.0, 0.0, 0.0177), Y), ((0.0, 0.0, 0.0514), Y)]
TIP_OFFSET = {"index": 0.0267, "middle": 0.0267, "ring": 0.0267, "thumb": 0.0423}
FIRST_AXIS = {"index": Z, "middle": Z, "ring": Z, "thumb": X}
FINGER_JOINTS = {"index": range(0, 4), "middle": range(4, 8), "ring": range(8, 12), "thumb": range(12, 16)}
FINGER_TIPS = {"index": "link_3.0_tip", "middle": "link_7.0_tip", "ring": "link_11.0_tip", "thumb": "link_15.0_tip"}
#: ManiSkill 3.0.1's allegro_hand_left.urdf where it differs from Wonik's: its fingers
#: keep the right hand's places, its thumb's proximal joint the right hand's offset.
MANISKILL_LEFT = dict(WONIK_LEFT)
MANISKILL_LEFT |= {
    "index": ((0.0, 0.0435, -0.001542), (-0.08726646255, 0.0, 0.0)),
    "ring": ((0.0, -0.0435, -0.001542), (0.08726646255, 0.0, 0.0)),
}
MANISKILL_LEFT_THUMB_LINKS = [((-0.027, 0.005, 0.0399), MINUS_Z), *WONIK_LEFT_THUMB_LINKS[1:]]


def tip_in_palm(
    finger: str,
    q: np.ndarray,
    origins: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = WONIK_LEFT,
    thumb_links: list[tuple[tuple[float, float, float], tuple[float, float, float]]] = WONIK_LEFT_THUMB_LINKS,
) -> np.ndarray:
    """The fingertip's position in the palm frame (m) at the finger's 4 joint angles."""
    origin, rpy = origins[finger]
    pose = transform(rpy_matrix(*rpy), np.array(origin))
    pose = pose @ transform(axis_rotation(FIRST_AXIS[finger], float(q[0])), np.zeros(3))
    links = thumb_links if finger == "thumb" else FINGER_LINKS
    for (offset, axis), angle in zip(links, q[1:], strict=True):
        pose = pose @ transform(axis_rotation(axis, float(angle)), np.array(offset))
    tip: np.ndarray = (pose @ np.array([0.0, 0.0, TIP_OFFSET[finger], 1.0]))[:3]
    return tip


def configurations(agent: ra.Agent, model: mujoco.MjModel) -> list[np.ndarray]:
    """The keyframe, the power grasp's closed pose and 5 random configurations in range."""
    low, high = model.jnt_range.T
    rng = np.random.default_rng(7)
    return [
        agent.keyframe_qpos("palm_side"),
        np.asarray(agent.gripper().closed, dtype=np.float64),
        *(rng.uniform(low, high) for _ in range(5)),
    ]


def test_fingertips_match_wonik_s_left_description() -> None:
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    for q in configurations(agent, scene.model):
        for finger, joints in FINGER_JOINTS.items():
            measured = agent.frame_pose(FINGER_TIPS[finger], q, relative_to="root")[0, :3]
            np.testing.assert_allclose(measured, tip_in_palm(finger, q[list(joints)]), atol=1e-6)
    # the index finger is on the thumb's side (-y), the ring finger across the palm
    q = agent.keyframe_qpos("palm_side")
    assert agent.frame_pose("link_3.0_tip", q, relative_to="root")[0, 1] == pytest.approx(-0.0553, abs=1e-4)
    assert agent.frame_pose("link_15.0_tip", q, relative_to="root")[0, 1] < -0.1
    scene.close()


def test_the_left_hand_is_the_right_hand_mirrored() -> None:
    """At any configuration each left fingertip is the right one's mirror image (y
    negated), with the spread angles negated (Wonik keeps the spread axes at +z); the
    thumb's spread-free chain mirrors as it is."""
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    mirror = np.array([1.0, -1.0, 1.0])
    for q in configurations(agent, scene.model):
        for finger, joints in FINGER_JOINTS.items():
            right_q = q[list(joints)].copy()
            if finger != "thumb":
                right_q[0] = -right_q[0]
            left = agent.frame_pose(FINGER_TIPS[finger], q, relative_to="root")[0, :3]
            np.testing.assert_allclose(left, mirror * right_tip_in_base(finger, right_q), atol=1e-6)
    scene.close()


def test_where_maniskill_s_left_urdf_differs() -> None:
    """ManiSkill's left URDF keeps the right hand's finger places and thumb proximal
    offset: its finger 0-3 is our ring finger (8-11) joint for joint, and its thumb tip
    is 10 mm from ours at every configuration (the offset moved along the thumb base's
    y); the thumb's base frame and axes are ours."""
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    for q in configurations(agent, scene.model):
        ours = {f: agent.frame_pose(FINGER_TIPS[f], q, relative_to="root")[0, :3] for f in FINGER_TIPS}
        theirs = {
            f: tip_in_palm(f, q[list(j)], MANISKILL_LEFT, MANISKILL_LEFT_THUMB_LINKS) for f, j in FINGER_JOINTS.items()
        }
        index_q, ring_q = q[0:4], q[8:12]
        np.testing.assert_allclose(theirs["index"], tip_in_palm("ring", index_q), atol=1e-12)
        np.testing.assert_allclose(ours["ring"], tip_in_palm("ring", ring_q), atol=1e-6)
        np.testing.assert_allclose(theirs["middle"], ours["middle"], atol=1e-6)
        assert np.linalg.norm(theirs["thumb"] - ours["thumb"]) == pytest.approx(0.010, abs=1e-6)
    model = scene.model
    thumb_base = model.body(f"{agent.prefix}link_12.0")
    np.testing.assert_allclose(thumb_base.pos, MANISKILL_LEFT["thumb"][0], atol=1e-9)
    expected = np.zeros(4)
    mujoco.mju_mat2Quat(expected, rpy_matrix(*MANISKILL_LEFT["thumb"][1]).ravel())
    np.testing.assert_allclose(thumb_base.quat * np.sign(thumb_base.quat @ expected), expected, atol=1e-6)
    scene.close()


def test_masses_ranges_and_axes() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    for body, mass in MASSES.items():
        assert model.body(f"{agent.prefix}{body}").mass[0] == pytest.approx(mass, abs=1e-9), body
    ranges = np.array([model.joint(f"{agent.prefix}{name}").range for name in agent.joint_names])
    np.testing.assert_allclose(ranges, FINGER_RANGES * 3 + THUMB_RANGES, atol=1e-12)
    axes = {name: model.joint(f"{agent.prefix}{name}").axis for name in agent.joint_names}
    for name in SPREAD_JOINTS:
        np.testing.assert_allclose(axes[name], Z, atol=1e-12)
    np.testing.assert_allclose(axes["joint_12.0"], X, atol=1e-12)
    np.testing.assert_allclose(axes["joint_13.0"], MINUS_Z, atol=1e-12)
    # the inertias are the right hand's mirrored: the same principal moments
    right = ra.Scene("allegro_hand_right")
    for body in MASSES:
        np.testing.assert_allclose(
            model.body(f"{agent.prefix}{body}").inertia,
            right.model.body(f"{right.agents[0].prefix}{body}").inertia,
            rtol=1e-12,
        )
    right.close()
    scene.close()


def test_keyframes_and_modes_are_maniskill_s() -> None:
    cls = ra.get_agent(UID)
    assert cls is AllegroHandLeft
    assert list(cls.keyframes) == ["palm_side", "palm_up", "rest"]
    modes = set(cls.modes())
    assert {"pd_joint_delta_pos", "pd_joint_pos", "pd_joint_target_delta_pos"} <= modes
    assert cls.default_control_mode == "pd_joint_delta_pos"


class _PureMirror(AllegroHandRight):
    """The right hand's file mirrored with nothing kept: the spread axes turned too."""

    @classmethod
    def edit_model(cls, spec: mujoco.MjSpec, where: str) -> None:
        mirror_spec(spec, where)


def test_a_mirrored_hand_moves_as_the_right_one_and_wonik_s_spread_axes_make_the_difference() -> None:
    """The right hand's file mirrored whole moves, under the same random actions (the
    sweep's 10 s of ``pd_joint_pos_vel``, seed 1, 160 Hz), through the same joint angles as the
    right hand (to 1e-9 rad: the mirror image, contacts and all); the left hand, whose
    spread axes Wonik keeps, does not once fingers touch (its spread joints turn the
    fingers the other way: without contacts the joint motion is the same)."""
    finals = {}
    for cls in (AllegroHandRight, _PureMirror, AllegroHandLeft):
        scene = after_random_actions(cls, "pd_joint_pos_vel", 160, seed=1)
        finals[cls] = scene.agents[0].qpos[0].copy()
        scene.close()
    np.testing.assert_allclose(finals[_PureMirror], finals[AllegroHandRight], atol=1e-9)
    assert np.max(np.abs(finals[AllegroHandLeft] - finals[AllegroHandRight])) > 0.01


def test_a_mounted_left_hand_is_mirrored_as_a_piece_too() -> None:
    """``edit_model`` applies where the class is mounted on another robot: the left hand
    on an xArm6's flange has its thumb at -y of its palm."""
    from robot_agents.robots.ufactory.xarm6 import XArm6NoGripper

    class ArmWithLeftHand(XArm6NoGripper):
        uid = "arm_with_left_allegro_test"
        attachments = (ra.Attachment(AllegroHandLeft, at="link_eef", prefix="hand/", pos=(0.0, 0.0, 0.1)),)

    model = ArmWithLeftHand.build_spec().compile()
    np.testing.assert_allclose(model.body("hand/link_12.0").pos, WONIK_LEFT["thumb"][0], atol=1e-12)
    np.testing.assert_allclose(model.joint("hand/joint_13.0").axis, MINUS_Z, atol=1e-12)


def test_one_file_read_once_serves_both_hands() -> None:
    """Within one read scope the right hand's file is parsed once and handed out as
    copies: the left hand's mirror edits its copy only (the right hand built after it in
    the same scope, and a right hand mounted beside a left one, keep the thumb at +y)."""
    from robot_agents.model.load_scope import one_read_per_file

    class BothHands(AllegroHandRight):
        uid = "both_allegro_hands_test"
        attachments = (ra.Attachment(AllegroHandLeft, at="base_link", prefix="left/", pos=(0.0, 0.5, 0.0)),)

    with one_read_per_file():
        left = AllegroHandLeft.build_spec().compile()
        right = AllegroHandRight.build_spec().compile()
        both = BothHands.build_spec().compile()
    assert left.body("link_12.0").pos[1] == pytest.approx(-0.019333)
    assert right.body("link_12.0").pos[1] == pytest.approx(0.019333)
    assert both.body("link_12.0").pos[1] == pytest.approx(0.019333)
    assert both.body("left/link_12.0").pos[1] == pytest.approx(-0.019333)


# ---------------------------------------------------------------- mirror_spec on its own
MIRROR_MJCF = """
<mujoco>
  <worldbody>
    <body name="a" pos="0.1 0.2 0.3" quat="0.9 0.1 0.3 0.2">
      <joint name="hinge" type="hinge" axis="0.2 0.5 0.8" pos="0 0.01 0"/>
      <geom name="box" type="box" size="0.01 0.02 0.03" pos="0.01 0.02 0.03" quat="0.8 0.2 0.1 0.4"/>
      <site name="s" pos="0.02 0.03 0.04"/>
      <camera name="c" pos="0.01 0.02 0.03" quat="0.9 0.1 0.2 0.3"/>
      <body name="b" pos="0.05 -0.04 0.02" quat="0.7 -0.2 0.5 0.1">
        <joint name="slide" type="slide" axis="0.3 0.4 0.5"/>
        <geom name="stick" type="capsule" fromto="0 0 0 0.03 0.05 0.02" size="0.005"/>
        <light name="l" pos="0.1 0.2 0.3" dir="0.3 0.4 -0.8"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def world_frames(spec: mujoco.MjSpec, qpos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Site, geom, camera and light world positions (m) and the light's direction; geom
    and camera rotation matrices at ``qpos``."""
    model = spec.compile()
    data = mujoco.MjData(model)
    data.qpos[:] = qpos
    mujoco.mj_kinematics(model, data)
    mujoco.mj_camlight(model, data)
    points = np.concatenate([data.site_xpos, data.geom_xpos, data.cam_xpos, data.light_xpos, data.light_xdir])
    frames = np.concatenate([data.geom_xmat, data.cam_xmat]).reshape(-1, 3, 3).copy()
    return points, frames


def test_mirror_spec_reflects_every_frame_at_every_configuration() -> None:
    """The mirrored model at any ``qpos`` is the original's reflection (y -> -y): points
    mirrored, frames ``M R M``, joint values keeping their meaning."""
    mirror = np.diag([1.0, -1.0, 1.0])
    for qpos in (np.array([0.0, 0.0]), np.array([0.7, 0.02]), np.array([-1.3, -0.05])):
        original = mujoco.MjSpec.from_string(MIRROR_MJCF)
        mirrored = mujoco.MjSpec.from_string(MIRROR_MJCF)
        mirror_spec(mirrored, "test")
        points, frames = world_frames(original, qpos)
        points_m, frames_m = world_frames(mirrored, qpos)
        np.testing.assert_allclose(points_m, points @ mirror, atol=1e-12)
        np.testing.assert_allclose(frames_m, mirror @ frames @ mirror, atol=1e-12)


def test_mirror_spec_refuses_what_it_cannot_mirror(tmp_path: Path) -> None:
    ball = MIRROR_MJCF.replace('type="hinge" axis="0.2 0.5 0.8"', 'type="ball"')
    spec = mujoco.MjSpec.from_string(ball)
    before = spec.to_xml()
    with pytest.raises(ModelError, match="where: joint 'hinge' is a ball joint"):
        mirror_spec(spec, "where")
    assert spec.to_xml() == before  # nothing changed
    mesh = MIRROR_MJCF.replace(
        "<worldbody>", '<asset><mesh name="tetra" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset><worldbody>'
    )
    mesh = mesh.replace(
        '<geom name="box" type="box" size="0.01 0.02 0.03"', '<geom name="box" type="mesh" mesh="tetra"'
    )
    spec = mujoco.MjSpec.from_string(mesh)
    before = spec.to_xml()
    with pytest.raises(ModelError, match="geom 'box' is a mjGEOM_MESH"):
        mirror_spec(spec, "where")
    assert spec.to_xml() == before
    euler = MIRROR_MJCF.replace('<site name="s" pos="0.02 0.03 0.04"/>', '<site name="s" euler="0.1 0.2 0.3"/>')
    spec = mujoco.MjSpec.from_string(euler)
    before = spec.to_xml()
    with pytest.raises(ModelError, match="site 's' has its orientation written as mjORIENTATION_EULER"):
        mirror_spec(spec, "where")
    assert spec.to_xml() == before
