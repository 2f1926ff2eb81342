"""The two-line robot: ``uid`` plus a model file (plus ``fix_root_link=False`` for a
floating robot) gives a working robot, with parts, a keyframe, drives and control modes
derived from the model. Checked on gymnasium's MuJoCo models and files written here."""

from __future__ import annotations

import io
import math
import re
import warnings
from pathlib import Path

import gymnasium
import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.actuators.gains import gains_from_inertia
from robot_agents.checks import run_random_actions
from tests.conftest import PENDULUM_MJCF, TWO_LINK_URDF

GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"


def two_line(path: Path, **extra: object) -> type[ra.Agent]:
    return type(
        "TwoLine",
        (ra.Agent,),
        {"uid": "two_line", "mjcf_path" if path.suffix == ".xml" else "urdf_path": path, **extra},
    )


def scene_of(cls: type[ra.Agent], **kwargs: object) -> ra.Scene:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # files with extra bodies: a one-line note
        return ra.Scene(cls, **kwargs)  # type: ignore[arg-type]


def run_random(scene: ra.Scene, seconds: float, seed: int = 0) -> None:
    run_random_actions(scene, seconds, seed)
    assert not np.any(scene.world.instability_counts()), "MuJoCo reset an env (instability)"
    assert np.all(np.isfinite(scene.world.get_state()))


def test_urdf_arm_without_actuators_gets_derived_drives_and_holds(tmp_path: Path) -> None:
    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF)
    cls = two_line(path)
    checked = cls.check()
    assert checked.part_joints == {"arm": ("joint_a", "joint_b")}  # a serial chain: an arm
    assert [ee.link for ee in checked.parts[0].end_effectors] == ["tool"]  # type: ignore[attr-defined]
    assert checked.default_mode == "pd_joint_delta_pos"  # small, safe random actions
    assert list(checked.keyframes) == ["default"]
    # Drives: critically damped at 10 Hz from the inertia at the default pose, torques
    # bounded by the URDF's effort limits (50 and 20 N*m).
    assert checked.derived_gains is not None
    assert [d.effort_limit for d in checked.drives] == [50.0, 20.0]
    scene = scene_of(cls, num_envs=2)
    scene.reset()
    agent = scene.agents[0]
    start = agent.qpos
    for _ in range(2 * scene.control_freq):  # 2 s of zero deltas
        agent.set_action(np.zeros(2))
        scene.step()
    assert np.max(np.abs(agent.qpos - start)) < 0.01
    run_random(scene, 5.0)


def test_a_urdfs_speed_limits_bound_the_drives_and_the_velocity_modes(tmp_path: Path) -> None:
    # MuJoCo's URDF reader keeps `effort` and drops `velocity`; the drives read it:
    # pd_joint_vel spans the file's speeds (1 rad/s per joint before: no speed known)
    from robot_agents.cli import main as cli_main
    from robot_agents.model.loading import urdf_velocity_limits

    path = tmp_path / "two_link.urdf"
    path.write_text(TWO_LINK_URDF.replace('effort="20" velocity="2"', 'effort="20" velocity="0.75"'))
    assert urdf_velocity_limits(path) == {"joint_a": 2.0, "joint_b": 0.75}
    checked = two_line(path).check()
    assert [(d.effort_limit, d.velocity_limit) for d in checked.drives] == [(50.0, 2.0), (20.0, 0.75)]
    velocity = checked.modes["pd_joint_vel"]
    assert isinstance(velocity, ra.PDJointVelConfig)
    assert (velocity.lower, velocity.upper) == ((-2.0, -0.75), (2.0, 0.75))
    # a speed the robot states wins; `velocity="0"` (a URDF's "none") states none
    stated = two_line(path, actuators=(ra.DerivedActuators(velocity_limit=1.5),)).check()
    assert [d.velocity_limit for d in stated.drives] == [1.5, 1.5]
    unstated = tmp_path / "unstated.urdf"
    unstated.write_text(TWO_LINK_URDF.replace('velocity="2"', 'velocity="0"'))
    assert urdf_velocity_limits(unstated) == {}
    assert [d.velocity_limit for d in two_line(unstated).check().drives] == [math.inf, math.inf]
    assert urdf_velocity_limits(tmp_path / "missing.urdf") == {}
    # a placeholder (example-robot-data's quadruped: 1000 and 10000 rad/s) states none, noted
    placeholder = tmp_path / "placeholder.urdf"
    placeholder.write_text(TWO_LINK_URDF.replace('effort="50" velocity="2"', 'effort="50" velocity="1000"'))
    with pytest.warns(RuntimeWarning, match=r"joint speed limits taken as none.*: joint_a \(1000 rad/s\)"):
        assert urdf_velocity_limits(placeholder) == {"joint_b": 2.0}
    # `robot-agents info` lists each joint's limits
    out = io.StringIO()
    assert cli_main(["info", str(path)], out=out) == 0
    table = out.getvalue()
    assert re.search(r"joint_a +-3.0000 +3.0000 +50 +2\n", table) and re.search(r"joint_b .* 20 +0.75\n", table)


def test_suggested_gains_are_critically_damped_at_the_stated_bandwidth() -> None:
    # A 2 kg box on a slide: effective inertia 2 kg (+ 0.5 kg armature).
    model = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><body><joint name="s" type="slide" axis="1 0 0" armature="0.5"/>
        <geom type="box" size="0.1 0.1 0.1" mass="2"/></body></worldbody></mujoco>"""
    )
    gains = gains_from_inertia(model, ["s"], bandwidth_hz=5.0)
    omega = 2 * math.pi * 5.0
    np.testing.assert_allclose(gains.inertia, [2.5])
    np.testing.assert_allclose(gains.stiffness, [2.5 * omega**2])
    np.testing.assert_allclose(gains.damping, [2 * 2.5 * omega])
    with pytest.raises(ra.ConfigError, match="bandwidth"):
        gains_from_inertia(model, ["s"], bandwidth_hz=0.0)


def test_pendulum_mjcf_two_lines(tmp_path: Path) -> None:
    path = tmp_path / "pendulum.xml"
    path.write_text(PENDULUM_MJCF)
    scene = scene_of(two_line(path))
    scene.reset()
    agent = scene.agents[0]
    assert agent.control_mode == "pd_joint_delta_pos"
    assert list(agent.frames.end_effectors) == ["ee"]
    assert agent.frames.end_effectors["ee"][0].name.endswith("tip")
    run_random(scene, 5.0)


@pytest.mark.parametrize(("name", "joints", "motors"), [("ant.xml", 8, 8), ("humanoid.xml", 17, 17)])
def test_gymnasium_floating_robots_two_lines(name: str, joints: int, motors: int) -> None:
    cls = two_line(GYM / name, fix_root_link=False)
    scene = scene_of(cls)
    scene.reset()
    agent = scene.agents[0]
    assert agent.dof == joints and scene.model.nu == motors  # the file's motors, adopted
    assert agent.control_mode == "joint_effort"  # motors take efforts
    # The default keyframe rests the robot on the floor, not inside it: its lowest point
    # is 1 mm above z = 0 (contacts within the file's geom margins, none penetrating).
    model, data = scene.model, scene.world.physics_sources([0])[0]
    assert all(data.contact[i].dist > 0 for i in range(data.ncon))
    floor = model.geom("floor").id
    robot = [g for g in range(model.ngeom) if model.body_rootid[model.geom_bodyid[g]] != 0 and model.geom_contype[g]]
    gaps = [mujoco.mj_geomDistance(model, data, floor, g, 1.0, None) for g in robot]
    assert min(gaps) == pytest.approx(0.001, abs=2e-4)
    run_random(scene, 3.0)


def test_reacher_keeps_the_arm_and_drops_the_target_marker() -> None:
    cls = two_line(GYM / "reacher.xml")
    with (
        pytest.warns(RuntimeWarning, match=r"kept top-level body 'body0' as the robot and dropped \['target'\]"),
        pytest.warns(RuntimeWarning, match=r"drives 2 joint\(s\) with torque motors"),
    ):
        scene = ra.Scene(cls)
    assert scene.agents[0].joint_names == ("joint0", "joint1")
    assert scene.model.nu == 2
    # its two motors are PD drives within their torques, and joint_effort commands those
    assert {"pd_joint_delta_pos", "joint_effort"} <= set(cls.modes())
    chosen = two_line(GYM / "reacher.xml", root_body="target")
    # (the note no longer asks for the root_body it was given)
    with pytest.warns(RuntimeWarning, match=r"kept top-level body 'target' as the root_body chosen and dropped"):
        assert ra.Scene(chosen).agents[0].joint_names == ("target_x", "target_y")


def test_ambiguous_top_level_bodies_name_the_fix(tmp_path: Path) -> None:
    path = tmp_path / "twins.xml"
    path.write_text(
        """<mujoco><worldbody>
        <body name="left"><joint name="a"/><geom size="0.1"/></body>
        <body name="right" pos="1 0 0"><joint name="b"/><geom size="0.1"/></body>
        </worldbody></mujoco>"""
    )
    with pytest.raises(ra.ModelError, match=r"2 top-level bodies \['left', 'right'\].*set root_body = 'left'"):
        ra.Scene(two_line(path))


SUNKEN_ARM_MJCF = """<mujoco><worldbody><body name="base" pos="0 0 -0.05">
  <geom type="box" size="0.05 0.05 0.05" mass="1"/>
  <body name="link" pos="0 0 0.05"><joint name="hinge" axis="0 1 0" range="-1 1"/>
    <geom type="capsule" fromto="0 0 0 0 0 0.3" size="0.02" mass="0.5"/></body>
</body></worldbody></mujoco>"""


class _Unrelated:
    """A plain class after AgentDefinition in a robot's bases (a user's mixin)."""


def test_a_fixed_robot_reaching_into_the_floor_is_mounted_above_it_unless_it_declares_a_mount(tmp_path: Path) -> None:
    path = tmp_path / "sunken.xml"
    path.write_text(SUNKEN_ARM_MJCF)
    lifted = two_line(path).check().mount_pose[2]
    assert lifted == pytest.approx(0.1 + 0.001, abs=2e-4)  # the box's bottom 1 mm above z = 0
    # the automatic lift does not depend on where AgentDefinition sits in the class's MRO
    mixed = type("Mixed", (ra.Agent, _Unrelated), {"uid": "mixed", "mjcf_path": path})
    assert mixed.check().mount_pose[2] == pytest.approx(lifted)
    declared = two_line(path, mount_pose=(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0))
    assert declared.check().mount_pose[2] == 0.0


def test_a_fixed_robot_drawn_y_up_rests_on_the_floor_under_up_y(tmp_path: Path) -> None:
    # the sunken arm drawn y-up (turned -90 deg about x): `up="y"` declared only the turn
    # of the mount, and the arm stayed 0.1 m deep in the floor (`check`'s keyframe
    # contacts failed); it now rests as its z-up twin does
    from robot_agents.robot_source import robot_from_file

    z_up = tmp_path / "sunken.xml"
    z_up.write_text(SUNKEN_ARM_MJCF)
    y_up = tmp_path / "sunken_y_up.xml"
    y_up.write_text(
        SUNKEN_ARM_MJCF.replace('pos="0 0 -0.05"', 'pos="0 -0.05 0"')
        .replace('pos="0 0 0.05"', 'pos="0 0.05 0"')
        .replace('axis="0 1 0"', 'axis="0 0 -1"')
        .replace('fromto="0 0 0 0 0 0.3"', 'fromto="0 0 0 0 0.3 0"')
    )
    turned = robot_from_file(y_up, up="y")
    assert turned.check().mount_pose[2] == pytest.approx(robot_from_file(z_up).check().mount_pose[2], abs=1e-9)
    scenes = [scene_of(cls) for cls in (robot_from_file(z_up), turned)]
    for scene in scenes:
        scene.reset()
    for body in ("base", "link"):  # the same world positions
        places = [
            scene.body_pose(f"{name}-0/{body}")[0, :3]
            for scene, name in zip(scenes, ("sunken", "sunken_y_up"), strict=True)
        ]
        np.testing.assert_allclose(places[0], places[1], atol=1e-9)
    assert robot_from_file(y_up, up="y", floating=True).rest_on_floor is True
    with pytest.raises(ra.ConfigError, match=r"expected rest_on_floor to be a bool or None, got 1"):
        two_line(z_up, rest_on_floor=1).check()


FRICTION_WRIST_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base">
  <geom type="cylinder" size="0.04 0.02" mass="1"/>
  <body name="link" pos="0 0 0.03">
    <joint name="wrist" axis="0 0 1" range="-2 2" frictionloss="0.5" damping="0.5"/>
    <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01" mass="0.2"/>
  </body></body></worldbody></mujoco>"""


def test_derived_drives_overcome_the_files_dry_friction(tmp_path: Path) -> None:
    """A file's ``frictionloss`` stops a joint where the drive's pull falls below it:
    inertia gains (kp ~ 2.6 N*m/rad for this light link) left it 0.19 rad short of its
    target; the derived drive is stiffened to stop within FRICTION_STALL (0.005 rad),
    under the stability bound, and stays stable."""
    from robot_agents.actuators.gains import FRICTION_STALL, friction_gains

    path = tmp_path / "wrist.xml"
    path.write_text(FRICTION_WRIST_MJCF)
    cls = two_line(path)
    checked = cls.check()
    model = mujoco.MjModel.from_xml_path(str(path))
    plain = gains_from_inertia(model, ["wrist"])
    assert plain.stiffness[0] < 3.0 and plain.passive_friction is not None and plain.passive_friction[0] == 0.5
    stiff, capped = friction_gains(plain, 0.002)
    np.testing.assert_allclose(stiff.stiffness, [0.5 / FRICTION_STALL])
    np.testing.assert_allclose(stiff.damping, [2.0 * math.sqrt(100.0 * plain.inertia[0])])
    assert capped == ()
    assert checked.drives[0].stiffness == pytest.approx(100.0)
    scene = scene_of(cls)
    scene.reset()
    agent = scene.agents[0]
    agent.set_control_mode("pd_joint_pos")
    for _ in range(scene.control_freq):  # 1 s towards +0.3 rad
        agent.set_action(np.array([0.3]))
        scene.step()
    assert abs(agent.qpos[0, 0] - 0.3) <= FRICTION_STALL * 1.05
    run_random(scene, 3.0)
    # too light for the stiffness friction asks: capped by the step, and named
    heavy_friction, capped = friction_gains(plain, 0.002, stall=1e-4)
    assert capped == ("wrist",) and heavy_friction.stiffness[0] == pytest.approx(
        0.25 * 4.0 * plain.inertia[0] / 0.002**2
    )


FRICTION_FINGERTIP_MJCF = """<mujoco><compiler angle="radian"/><worldbody><body name="base">
  <geom type="cylinder" size="0.04 0.02" mass="1"/>
  <body name="finger" pos="0 0 0.05">
    <joint name="tip" axis="0 0 1" range="-1 1" frictionloss="0.5"/>
    <geom type="sphere" pos="0.01 0 0" size="0.004" mass="0.002"/>
  </body></body></worldbody></mujoco>"""


def test_a_derived_drive_whose_friction_floor_the_bound_caps_gets_a_load_note(tmp_path: Path) -> None:
    """A 2 g fingertip 1 cm from its axis (I ~ 2e-7 kg*m^2) with 0.5 N*m of dry friction:
    stopping within FRICTION_STALL asks kp = 100 N*m/rad, the stability bound at 2 ms
    allows I / dt^2 ~ 0.05; the drive gets the bound and the class check says so (which
    joint, the kp wanted and given, how far friction may stop it, why)."""
    from robot_agents.actuators.gains import FRICTION_STALL

    path = tmp_path / "fingertip.xml"
    path.write_text(FRICTION_FINGERTIP_MJCF)
    cls = two_line(path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        checked = cls.check()
    inertia = gains_from_inertia(mujoco.MjModel.from_xml_path(str(path)), ["tip"]).inertia[0]
    cap = 0.25 * 4.0 * inertia / 0.002**2
    assert checked.drives[0].stiffness == pytest.approx(cap)
    notes = [w for w in caught if "dry friction" in str(w.message)]
    assert len(notes) == 1 and issubclass(notes[0].category, RuntimeWarning)
    note = str(notes[0].message)
    assert "TwoLine" in note and "stability bound at the 0.002 s step" in note
    assert f"tip (frictionloss 0.5 N*m: kp {0.5 / FRICTION_STALL:.3g} N*m/rad wanted, {cap:.3g} given" in note
    assert f"up to {0.5 / cap:.3g} rad from its target" in note
    assert "raise sim_freq" in note
    # the friction test's wrist, heavy enough for its floor, gets no such note
    heavy = tmp_path / "wrist.xml"
    heavy.write_text(FRICTION_WRIST_MJCF)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        two_line(heavy).check()
    assert not [w for w in caught if "dry friction" in str(w.message)]


def _arm_with_fingers(fingers: int, joints_per_finger: int) -> str:
    """The written six-joint arm with a palm on its flange and ``fingers`` fingers of
    ``joints_per_finger`` hinges each (3 cm links)."""
    from tests.test_derived_task_space import JOINTS, arm_urdf

    def box_link(name: str, mass: float, size: str, z: float) -> str:
        return (
            f'<link name="{name}"><inertial><origin xyz="0 0 {z}"/><mass value="{mass}"/>'
            '<inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial>'
            f'<collision><origin xyz="0 0 {z}"/><geometry><box size="{size}"/></geometry></collision></link>'
        )

    parts = box_link("palm", 0.3, "0.08 0.08 0.02", 0.01)
    parts += (
        '<joint name="palm_mount" type="fixed"><parent link="flange_roll_link"/><child link="palm"/>'
        f'<origin xyz="0 0 {JOINTS[-1][3]}"/></joint>'
    )
    for f in range(fingers):
        parent, offset = "palm", f"{0.03 * (f - 1)} 0 0.02"
        for k in range(joints_per_finger):
            child = f"finger{f}_link{k}"
            parts += box_link(child, 0.02, "0.015 0.015 0.03", 0.015)
            parts += (
                f'<joint name="finger{f}_joint{k}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
                f'<origin xyz="{offset}"/><axis xyz="0 1 0"/><limit lower="0" upper="1.5" effort="1" velocity="2"/></joint>'
            )
            parent, offset = child, "0 0 0.03"
    return arm_urdf(6).replace("</robot>", parts + "</robot>")


@pytest.mark.parametrize(
    ("fingers", "per_finger", "parts"),
    [(3, 2, ["arm", "hand"]), (2, 5, ["arm", "hand"]), (1, 3, ["arm"]), (2, 6, ["body"])],
)
def test_an_arm_with_a_hand_at_its_end_is_an_arm_and_a_hand(
    tmp_path: Path, fingers: int, per_finger: int, parts: list[str]
) -> None:
    """A file of an arm with several fingers at its end (the mani-skill wheel's
    ``xarm7_ability_right_hand.urdf``): the serial start is the arm, its end effector
    the palm (so it gets end-effector modes), the fingers one ``Hand`` part. One finger
    continues the arm's chain (one arm, as before); branches longer than 5 joints (an
    arm and a head below a torso) stay one body."""
    path = tmp_path / "arm_hand.urdf"
    path.write_text(_arm_with_fingers(fingers, per_finger))
    checked = two_line(path).check()
    names = [p.name for p in checked.parts]
    assert names == parts
    if parts != ["arm", "hand"]:
        return
    assert names == ["arm", "hand"]
    assert checked.part_joints["arm"] == ("yaw", "shoulder", "elbow", "forearm_roll", "wrist", "flange_roll")
    assert len(checked.part_joints["hand"]) == fingers * per_finger
    hand = checked.parts[1]
    assert isinstance(hand, ra.Hand) and len(hand.finger_links) == fingers  # is_grasping's fingers
    # a derived hand declares no power grasp: the time-step sweep makes no grasp claim
    from robot_agents.tuning.claims import Penetration
    from robot_agents.tuning.grasp_claim import grasp_claim

    assert grasp_claim(two_line(path), 500, 20, Penetration()) is None
    arm = checked.parts[0]
    assert isinstance(arm, ra.Arm) and arm.end_effectors[0].link == "palm" and arm.task_space is not None
    assert {"pd_ee_delta_pose", "pd_joint_delta_pos"} <= set(checked.modes)


# A right hand standing up (palm face +x, fingers up +z): three fingers on the palm's top,
# each a spread about x and a flexion about y on its first body (two joints on one body,
# as MJCF allows), then two more flexions (positive curls towards +x, over the palm's
# face), and a thumb on its side with one flexion about z (positive folds it across the
# face).
HAND = """<mujoco>
  <compiler angle="radian"/>
  <default><geom type="capsule" size="0.008" mass="0.02"/></default>
  <worldbody>
    <body name="palm" pos="0 0 0.3">
      <geom type="box" size="0.01 0.04 0.05" mass="0.3"/>
      {fingers}
      <body name="thumb" pos="0 -0.045 -0.02">
        <joint name="thumb_flex" axis="0 0 1" range="-0.3 1.5"/>
        <geom fromto="0 0 0 0 -0.05 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>"""
FINGER = """<body name="f{k}_base" pos="0 {y} 0.05">
        <joint name="f{k}_spread" axis="1 0 0" range="-0.3 0.3"/>
        <joint name="f{k}_flex0" axis="0 1 0" range="-0.2 1.2"/>
        <geom fromto="0 0 0 0 0 0.04"/>
        <body name="f{k}_middle" pos="0 0 0.04">
          <joint name="f{k}_flex1" axis="0 1 0" range="-0.2 1.6"/>
          <geom fromto="0 0 0 0 0 0.03"/>
          <body name="f{k}_tip" pos="0 0 0.03">
            <joint name="f{k}_flex2" axis="0 1 0" range="-0.2 1.6"/>
            <geom fromto="0 0 0 0 0 0.025"/>
          </body>
        </body>
      </body>"""


def test_a_hand_file_is_a_hand_that_opens_and_closes(tmp_path: Path) -> None:
    """A file of a hand alone (the mani-skill wheel's Allegro and Ability hands): a
    ``Hand`` part, open at the default pose, closed with each finger curled in (its
    flexions at the end of their range that brings the tip nearer the palm), spreads
    left open; its fingers are ``is_grasping``'s."""
    path = tmp_path / "hand.xml"
    path.write_text(HAND.format(fingers="".join(FINGER.format(k=k, y=0.025 * (k - 1)) for k in range(3))))
    cls = two_line(path)
    checked = cls.check()
    (hand,) = checked.parts
    assert isinstance(hand, ra.Hand) and hand.name == "hand"
    joints = checked.part_joints["hand"]
    opened, closed = (dict(zip(joints, v, strict=True)) for v in hand.positions(len(joints)))
    assert set(opened.values()) == {0.0}
    for k in range(3):
        assert [closed[f"f{k}_{j}"] for j in ("spread", "flex0", "flex1", "flex2")] == [0.0, 1.2, 1.6, 1.6]
    assert closed["thumb_flex"] == 1.5
    assert hand.finger_links == (
        ("f0_base", "f0_middle", "f0_tip"),
        ("f1_base", "f1_middle", "f1_tip"),
        ("f2_base", "f2_middle", "f2_tip"),
        ("thumb",),
    )
    # driven to either pose in pd_joint_pos, the hand gets there; nothing held: not grasping
    scene = scene_of(cls, control_modes="pd_joint_pos")
    agent = scene.agents[0]
    scene.reset()
    for target in hand.positions(len(joints)):
        for _ in range(scene.control_freq):
            agent.set_action(np.asarray(target))
            scene.step()
        assert np.max(np.abs(agent.qpos[0] - target)) < 0.05
    assert not agent.is_grasping("world")[0]
    scene.close()
    # on a wrist of two joints (the Shadow hand's): the hand and a wrist part
    wrist = HAND.replace(
        '<body name="palm" pos="0 0 0.3">',
        '<body name="forearm" pos="0 0 0.2"><joint name="wrist_roll" axis="0 0 1" range="-1 1"/>'
        '<geom fromto="0 0 -0.05 0 0 0"/><body name="carpal" pos="0 0 0.02">'
        '<joint name="wrist_pitch" axis="0 1 0" range="-0.5 0.5"/><geom size="0.01" type="sphere"/>'
        '<body name="palm" pos="0 0 0.06">',
    ).replace("</worldbody>", "</body></body></worldbody>")
    path.write_text(wrist.format(fingers="".join(FINGER.format(k=k, y=0.025 * (k - 1)) for k in range(3))))
    parts = two_line(path).check().parts
    assert [(type(p), p.name) for p in parts] == [(ra.Hand, "hand"), (ra.Body, "wrist")]
    # fingers longer than MAX_FINGER_LENGTH are legs or arms (a quadruped's below its trunk)
    long = FINGER.replace('fromto="0 0 0 0 0 0.04"', 'fromto="0 0 0 0 0 0.3"').replace(
        'pos="0 0 0.04"', 'pos="0 0 0.3"'
    )
    path.write_text(HAND.format(fingers="".join(long.format(k=k, y=0.025 * (k - 1)) for k in range(3))))
    assert [type(p) for p in two_line(path).check().parts] == [ra.Body]


def test_a_files_free_root_fixed_by_the_default_gets_a_note(tmp_path: Path) -> None:
    # a file whose root has a <freejoint> (gymnasium's ant) hung fixed in the air with
    # two lines, silently: fix_root_link defaults to True
    from robot_agents.robot_source import robot_from_file

    path = tmp_path / "free_root.xml"
    path.write_text(
        PENDULUM_MJCF.replace('<body name="base" pos="0 0 1.0">', '<body name="base" pos="0 0 1.0"><freejoint/>')
    )
    with pytest.warns(
        RuntimeWarning, match=r"the file gives root body 'base' a free joint; the robot is fixed to the world"
    ):
        assert two_line(path).check().index.free_joint is None
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # declared: no note
        assert two_line(path, fix_root_link=True).check().index.free_joint is None
    assert robot_from_file(path, floating=True).check().index.free_joint is not None


def test_a_file_keyframe_outside_the_limits_is_moved_with_a_note(tmp_path: Path) -> None:
    # the default keyframe moved the file's 3.0 rad to 2.0 (a tenth of the range inside
    # the stop) without a word
    path = tmp_path / "key_outside.xml"
    path.write_text(PENDULUM_MJCF.replace("</mujoco>", '<keyframe><key name="home" qpos="3.0"/></keyframe></mujoco>'))
    with pytest.warns(RuntimeWarning, match=r"keyframe 'home' puts joints outside their limits; .*: shoulder 3 -> 2\b"):
        checked = two_line(path).check()
    assert checked.keyframes["default"].qpos[0] == pytest.approx(2.5 - 0.1 * 5.0)


def test_every_keyframe_of_a_file_is_kept_by_name(tmp_path: Path) -> None:
    # only the file's first keyframe was kept: reset(keyframes="ready") was an unknown name
    keys = (
        '<keyframe><key name="home" qpos="0.1 0.2"/><key name="ready" qpos="0.5 -0.4"/><key qpos="-0.3 0.6"/>'
        '<key name="default" qpos="3.0 0.7"/><key name="key2" qpos="0.2 0.2"/></keyframe>'
    )
    path = tmp_path / "keys.xml"
    path.write_text(PENDULUM_MJCF.replace("</mujoco>", keys + "</mujoco>"))
    # the note names the keyframe outside the limits, and only it
    with pytest.warns(
        RuntimeWarning, match=r"keyframe 'default' puts joints .*'default_3' keyframe .*shoulder 3 -> 2\b"
    ):
        checked = two_line(path).check()
    assert list(checked.keyframes) == ["default", "ready", "key2", "default_3", "key2_4"]
    np.testing.assert_allclose(checked.keyframes["default"].qpos, [0.1, 0.2])
    np.testing.assert_allclose(checked.keyframes["ready"].qpos, [0.5, -0.4])
    np.testing.assert_allclose(checked.keyframes["key2"].qpos, [-0.3, 0.6])
    np.testing.assert_allclose(checked.keyframes["default_3"].qpos, [2.0, 0.7])
    np.testing.assert_allclose(checked.keyframes["key2_4"].qpos, [0.2, 0.2])
    scene = scene_of(two_line(path), num_envs=2)
    scene.reset(keyframes="ready")
    scene.reset(env_ids=[1], keyframes="key2")
    np.testing.assert_allclose(scene.agents[0].qpos, [[0.5, -0.4], [-0.3, 0.6]])


def test_a_files_first_keyframe_answers_to_its_own_name_too(tmp_path: Path) -> None:
    # the first keyframe was reachable as "default" only: reset(keyframes="home") was refused,
    # listing 'default'
    keys = '<keyframe><key name="home" qpos="0.1 0.2"/><key name="ready" qpos="0.5 -0.4"/><key qpos="-0.3 0.6"/></keyframe>'
    path = tmp_path / "home.xml"
    path.write_text(PENDULUM_MJCF.replace("</mujoco>", keys + "</mujoco>"))
    cls = two_line(path)
    # listed once (sweeps over keyframes do not hold the same pose twice), the alias apart
    assert cls.keyframe_names() == ["default", "ready", "key2"]
    assert cls.keyframe_aliases() == {"home": "default"}
    scene = scene_of(cls, num_envs=2)
    agent = scene.agents[0]
    scene.reset(keyframes="ready")
    scene.reset(env_ids=[1], keyframes="home")
    np.testing.assert_allclose(agent.qpos, [[0.5, -0.4], [0.1, 0.2]])
    np.testing.assert_array_equal(agent.keyframe_qpos("home"), agent.keyframe_qpos("default"))
    agent.reset("home", env_ids=[0])
    np.testing.assert_allclose(agent.qpos, [[0.1, 0.2], [0.1, 0.2]])
    before = scene.get_state()
    for refused in (
        lambda: scene.reset(keyframes="hom"),
        lambda: agent.reset("hom"),
        lambda: agent.keyframe_qpos("hom"),
    ):
        with pytest.raises(ra.errors.UnknownNameError) as err:
            refused()
        assert "Did you mean 'home'?" in str(err.value)
        assert "Available: 'default', 'home' (= 'default'), 'key2', 'ready'." in str(err.value)
    np.testing.assert_array_equal(scene.get_state()["physics"], before["physics"])  # nothing written
    from robot_agents.real import SimulatedBus

    bus = SimulatedBus(cls, keyframe="home")  # a bus started at a keyframe takes the alias too
    np.testing.assert_allclose(bus.read()[0], [0.1, 0.2])
    bus.close()
    with pytest.raises(ra.errors.UnknownNameError, match=r"'home' \(= 'default'\)"):
        SimulatedBus(cls, keyframe="hom")
    out = io.StringIO()
    from robot_agents.cli import main as cli_main

    assert cli_main(["info", str(path)], out=out) == 0
    assert "  default (also 'home'): qpos = [0.1000, 0.2000]" in out.getvalue()
    # an unnamed first keyframe, or one named "default", has no other name; the first
    # keyframe's name is taken: a later unnamed key at its place gets "_<i>"
    for first, aliases in (('<key qpos="0.1 0.2"/>', {}), ('<key name="default" qpos="0.1 0.2"/>', {})):
        path.write_text(PENDULUM_MJCF.replace("</mujoco>", f"<keyframe>{first}</keyframe></mujoco>"))
        assert two_line(path).keyframe_aliases() == aliases
    path.write_text(
        PENDULUM_MJCF.replace("</mujoco>", '<keyframe><key name="key1" qpos="0.1 0.2"/><key/></keyframe></mujoco>')
    )
    assert two_line(path).keyframe_names() == ["default", "key1_1"]


def test_a_floating_files_keyframes_each_rest_on_the_floor_in_their_own_orientation(tmp_path: Path) -> None:
    from robot_agents.robot_source import robot_from_file

    keys = '<keyframe><key qpos="0 0 2 1 0 0 0 0.1 0.2"/><key name="side" qpos="0 0 2 0.7071068 0.7071068 0 0 0 0"/></keyframe>'
    path = tmp_path / "float_keys.xml"
    path.write_text(
        PENDULUM_MJCF.replace(
            '<body name="base" pos="0 0 1.0">', '<body name="base" pos="0 0 1.0"><freejoint/>'
        ).replace("</mujoco>", keys + "</mujoco>")
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        checked = robot_from_file(path, floating=True).check()
    assert list(checked.keyframes) == ["default", "side"]
    np.testing.assert_allclose(checked.keyframes["default"].base[3:], [1, 0, 0, 0])
    np.testing.assert_allclose(checked.keyframes["side"].base[3:], [0.7071068, 0.7071068, 0, 0], atol=1e-6)
    # each lowered to rest 1 mm above the floor: lying on its side it rests lower than hanging
    assert 0 < checked.keyframes["side"].base[2] < checked.keyframes["default"].base[2]


def test_a_files_keyframe_velocities_are_where_the_robot_starts(tmp_path: Path) -> None:
    # a file key's qvel was dropped: every derived keyframe started at rest
    keys = '<keyframe><key name="swing" qpos="0.1 0.2" qvel="0.5 -0.3"/><key name="still" qpos="0.5 -0.4"/></keyframe>'
    path = tmp_path / "swing.xml"
    path.write_text(PENDULUM_MJCF.replace("</mujoco>", keys + "</mujoco>"))
    cls = two_line(path)
    scene = scene_of(cls, num_envs=2)
    agent = scene.agents[0]
    scene.reset(keyframes="swing")
    np.testing.assert_array_equal(agent.qvel, [[0.5, -0.3], [0.5, -0.3]])
    scene.reset(env_ids=[1], keyframes="still")
    np.testing.assert_array_equal(agent.qvel, [[0.5, -0.3], [0.0, 0.0]])
    # the env's reset noise moves the positions and keeps the keyframe's velocities
    ra.register_agent(cls, override=True)
    try:
        env = ra.make_env("Empty-v1", robot_uids=cls.uid, num_envs=2).unwrapped
        assert env.robot_init_qpos_noise > 0
        env.reset(seed=0)  # the default keyframe: the file's first
        np.testing.assert_array_equal(env.agent.qvel, [[0.5, -0.3], [0.5, -0.3]])
        assert not np.array_equal(env.agent.qpos, [[0.1, 0.2], [0.1, 0.2]])  # the noise did move them
        env.reset(seed=0, options={"keyframe": "still"})
        np.testing.assert_array_equal(env.agent.qvel, 0.0)
        env.reset(seed=0, options={"keyframe": "swing"})  # the first keyframe by its file name
        np.testing.assert_array_equal(env.agent.qvel, [[0.5, -0.3], [0.5, -0.3]])
        env.close()
    finally:
        ra.unregister_agent(cls.uid)
    # a floating robot's root velocity too: linear in the world (turned by the mount),
    # angular in the root's own frame, as MuJoCo's free joint carries them
    keys = '<keyframe><key qpos="0 0 2 1 0 0 0 0.1 0.2" qvel="0.1 0.2 0.3 0.4 0.5 0.6 0.7 -0.8"/></keyframe>'
    path.write_text(
        PENDULUM_MJCF.replace(
            '<body name="base" pos="0 0 1.0">', '<body name="base" pos="0 0 1.0"><freejoint/>'
        ).replace("</mujoco>", keys + "</mujoco>")
    )
    half = math.sqrt(0.5)
    floating = scene_of(two_line(path, fix_root_link=False, mount_pose=(1.0, 0.0, 0.0, half, 0.0, 0.0, half)))
    floating.reset()
    free = floating.agents[0].index.free_joint
    assert free is not None
    np.testing.assert_array_equal(floating.agents[0].qvel, [[0.7, -0.8]])
    root = floating.world.qvel[0, free.dof_adr : free.dof_adr + 6]
    np.testing.assert_allclose(root, [-0.2, 0.1, 0.3, 0.4, 0.5, 0.6], atol=1e-15)  # 90 deg about z


def test_a_files_keyframe_activations_are_not_written_and_a_note_says_so(tmp_path: Path) -> None:
    servo = '<general joint="{}" dyntype="filter" dynprm="0.05" gainprm="10" biastype="affine" biasprm="0 -10 -1"/>'
    extra = (
        f"<actuator>{servo.format('shoulder')}{servo.format('elbow')}</actuator>"
        '<keyframe><key name="home" qpos="0.1 0.2" act="0.1 0.2"/></keyframe>'
    )
    path = tmp_path / "filtered.xml"
    path.write_text(PENDULUM_MJCF.replace("</mujoco>", extra + "</mujoco>"))
    cls = two_line(path)
    with pytest.warns(RuntimeWarning, match=r"keyframe\(s\) 'home' set actuator activations \(act\); a reset does not"):
        cls.check()
    scene = scene_of(cls)
    scene.reset(keyframes="home")
    np.testing.assert_array_equal(scene.world.physics_sources([0])[0].act, [0.0, 0.0])
    np.testing.assert_allclose(scene.agents[0].qpos, [[0.1, 0.2]])
