"""A two-line arm gets end-effector modes: the task space measured on the arm
(robot_agents.agent.derived_task_space), checked against the written arm's geometry and
by reaching targets."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.actuators.gains import gains_from_inertia
from robot_agents.agent.derived_drives import drive_configurations
from robot_agents.checks import check_random_actions
from robot_agents.controllers.rules import EE_MODES
from robot_agents.controllers.task_space import delta_action
from robot_agents.envs.tasks.layout import STRETCHED_SHARE, UPRIGHT_AHEAD, table_top_layout
from robot_agents.kinematics.ik_config import POSITION_IK
from robot_agents.kinematics.rotations import quat_angle
from robot_agents.model.robot_spec import STOP_SOLREF
from robot_agents.sim.scene import DEFAULT_SIM_FREQ
from tests.conftest import make_pendulum_class
from tests.ik_check import assert_ik_reaches_random_targets

#: Joints of the written arm: name, axis, limit (rad), the next link's length along z (m).
JOINTS = (
    ("yaw", "0 0 1", 2.8, 0.30),
    ("shoulder", "0 1 0", 1.7, 0.30),
    ("elbow", "0 1 0", 2.5, 0.25),
    ("forearm_roll", "0 0 1", 2.8, 0.08),
    ("wrist", "0 1 0", 1.7, 0.08),
    ("flange_roll", "0 0 1", 2.8, 0.06),
)
BASE_HEIGHT = 0.1
MOTOR_INERTIA = 0.01  # kg*m^2 each link adds about every axis (see arm_urdf)


def arm_urdf(
    joints: int,
    elbow: tuple[float, float] | None = None,
    shoulder: tuple[float, float] | None = None,
    motor: float = MOTOR_INERTIA,
    effort: float = 100.0,
) -> str:
    """A serial arm of the first ``joints`` of :data:`JOINTS`: each link a box along z
    of its length (1 kg per metre) carrying the next joint's motor (``motor`` kg*m^2
    about every axis: a housing and rotor, as a URDF's links give no armature), each
    joint at the top of the previous link with an ``effort`` limit (N*m; 0: none);
    ``elbow`` / ``shoulder``: those joints' limits (rad) instead of the table's."""
    links = [
        '<link name="base"><inertial><mass value="2"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
        f'<collision><origin xyz="0 0 {BASE_HEIGHT / 2}"/><geometry><box size="0.1 0.1 {BASE_HEIGHT}"/></geometry></collision></link>'
    ]
    parts, parent, offset = [], "base", BASE_HEIGHT
    for name, axis, limit, length in JOINTS[:joints]:
        child = f"{name}_link"
        given = {"elbow": elbow, "shoulder": shoulder}.get(name)
        low, high = given if given is not None else (-limit, limit)
        mass = max(length, 0.05)
        inertia = mass * length**2 / 12 + motor
        links.append(
            f'<link name="{child}"><inertial><origin xyz="0 0 {length / 2}"/><mass value="{mass}"/>'
            f'<inertia ixx="{inertia}" iyy="{inertia}" izz="{motor}" ixy="0" ixz="0" iyz="0"/></inertial>'
            f'<collision><origin xyz="0 0 {length / 2}"/><geometry><box size="0.04 0.04 {length * 0.8}"/></geometry>'
            "</collision></link>"
        )
        parts.append(
            f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="0 0 {offset}"/><axis xyz="{axis}"/>'
            f'<limit lower="{low}" upper="{high}" effort="{effort}" velocity="3"/></joint>'
        )
        parent, offset = child, length
    return f'<robot name="arm{joints}">{"".join(links)}{"".join(parts)}</robot>'


def two_line(
    tmp_path: Path,
    joints: int,
    elbow: tuple[float, float] | None = None,
    shoulder: tuple[float, float] | None = None,
    motor: float = MOTOR_INERTIA,
    effort: float = 100.0,
) -> type[ra.Agent]:
    path = tmp_path / f"arm{joints}.urdf"
    path.write_text(arm_urdf(joints, elbow, shoulder, motor, effort))
    return type(f"Arm{joints}", (ra.Agent,), {"uid": f"derived_arm{joints}", "urdf_path": path})


def test_a_six_joint_arm_gets_every_end_effector_mode(tmp_path: Path) -> None:
    checked = two_line(tmp_path, 6).check()
    arm = checked.parts[0]
    assert isinstance(arm, ra.Arm) and arm.task_space is not None
    assert set(EE_MODES) <= set(checked.modes)
    assert checked.default_mode == "pd_joint_delta_pos"  # unchanged
    # reach from the shoulder (the first joint, 0.1 m up) to the last body's origin: at
    # most the stretched chain above the shoulder's anchor, nearly all of it over 1024 draws
    stretched = 0.30 + 0.30 + 0.25 + 0.08 + 0.08  # yaw link (shoulder above the yaw axis) .. wrist
    space = arm.task_space
    reach = space.max_translation / 0.1
    assert 0.85 * stretched <= reach <= stretched + 0.001
    lower, upper = np.array(space.position_bounds.lower), np.array(space.position_bounds.upper)
    # the box covers the arm's sweep about the base: symmetric in x and y, up to the top
    np.testing.assert_allclose(lower[:2], -upper[:2], atol=0.05 * reach)
    assert upper[2] > BASE_HEIGHT + 0.9 * stretched


def test_a_five_joint_arm_gets_the_position_modes(tmp_path: Path) -> None:
    checked = two_line(tmp_path, 5).check()
    arm = checked.parts[0]
    assert isinstance(arm, ra.Arm) and arm.task_space is not None
    assert arm.task_space.ik == POSITION_IK
    assert {m for m in checked.modes if m.startswith("pd_ee")} == {"pd_ee_delta_pos", "pd_ee_target_delta_pos"}


def test_fewer_than_three_joints_get_none(tmp_path: Path) -> None:
    checked = two_line(tmp_path, 2).check()
    assert not [m for m in checked.modes if m.startswith("pd_ee")]


def _one_step_targets(
    scene: ra.Scene, space: ra.TaskSpace, count: int, seed: int, rotation: bool
) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """``count`` (start qpos, action, target tool pose in the root frame): a random
    configuration within 80 % of the joint ranges, and the tool pose of one 0.15 rad
    (at most, per joint) away, so the target is reachable and near; kept when one
    normalized delta action reaches it (:func:`delta_action`)."""
    agent = scene.agents[0]
    rng = np.random.default_rng(seed)
    low, high = agent.qpos_limits[:, 0], agent.qpos_limits[:, 1]
    middle, half = (low + high) / 2, 0.4 * (high - low)
    out: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    while len(out) < count:
        start = rng.uniform(middle - half, middle + half)
        goal = np.clip(start + rng.uniform(-0.15, 0.15, len(start)), low, high)
        before = agent.frame_pose("ee", qpos=start, relative_to="root")[0]
        after = agent.frame_pose("ee", qpos=goal, relative_to="root")[0]
        action = delta_action(space, before, after, rotation)
        if action is not None:
            out.append((start, action, after))
    return out


@pytest.mark.parametrize(("joints", "mode"), [(6, "pd_ee_target_delta_pose"), (5, "pd_ee_target_delta_pos")])
def test_one_delta_action_lands_on_a_reachable_target(tmp_path: Path, joints: int, mode: str) -> None:
    """From 20 random configurations, one delta action to a reachable pose near by, then
    its target held 1 s: within 1 mm (and 1 deg for the 6-joint arm's pose). (With bare
    links, 1e-4 kg*m^2 about their axes, and the drives derived at the default keyframe
    alone, 7 and 17 of 40 landed, 2026-11-28; the gains over the ranges and the motors'
    inertia each make them land.)"""
    cls = two_line(tmp_path, joints)
    space = cls.check().parts[0].task_space  # type: ignore[union-attr]
    assert space is not None
    scene = ra.Scene(cls, control_modes=mode, floor=False)
    agent = scene.agents[0]
    rotation = joints >= 6
    misses = []
    for start, action, target in _one_step_targets(scene, space, 20, seed=3, rotation=rotation):
        agent.reset(qpos=start)
        agent.set_action(action[None])
        scene.step()
        for _ in range(scene.control_freq):
            agent.set_action(np.zeros((1, len(action))))
            scene.step()
        pose = agent.frame_pose("ee", relative_to="root")[0]
        position = float(np.linalg.norm(pose[:3] - target[:3]))
        angle = math.degrees(float(quat_angle(pose[3:], target[3:]))) if rotation else 0.0
        if position > 1e-3 or angle > 1.0:
            misses.append((position, angle))
    assert not misses, misses


def test_derived_drives_hold_over_the_whole_range(tmp_path: Path) -> None:
    """Bare links (1e-4 kg*m^2 about their axes) and no effort limit: the first joint's
    inertia at the default keyframe (pointing up) is a few hundredths of what it carries
    stretched out; a 0.03 rad step there settles within 1 mrad in 0.5 s (at the
    keyframe's gains alone, 2.4 N*m/rad, it swung 9 mrad off after 0.5 s)."""
    cls = two_line(tmp_path, 6, motor=1e-4, effort=0.0)
    scene = ra.Scene(cls, control_modes="pd_joint_pos", floor=False)
    agent = scene.agents[0]
    stretched = np.array([0.0, 1.5, 0.0, 0.0, 0.0, 0.0])  # the arm held out sideways
    agent.reset(qpos=stretched)
    target = stretched + np.array([0.03, 0, 0, 0, 0, 0])
    for _ in range(scene.control_freq // 2):
        agent.set_action(target[None])
        scene.step()
    assert abs(agent.qpos[0, 0] - target[0]) < 1e-3, agent.qpos[0]


def test_clamped_drives_keep_their_damping_explicitly_stable(tmp_path: Path) -> None:
    """With effort limits, a clamped drive's damping is integrated explicitly: derived
    gains keep ``kv dt / I`` within 1 (half the bound 2) at each joint's smallest
    inertia over its ranges, as damped as that lets them be at the largest (critical
    where it can; a stiffness that bound cannot damp falls back to the keyframe's: the
    two-line Panda of the mani-skill wheel cycled its first joint at 3.6 rad/s under
    random position+velocity targets without the bound: the sweep's settle claim)."""
    cls = two_line(tmp_path, 6, motor=1e-4)
    checked = cls.check()
    model, joints = checked.index.model, [d.joint for d in checked.drives]
    full = model.qpos0.copy()
    full[checked.index.qpos_adr] = checked.keyframes["default"].qpos
    configurations = drive_configurations(model, checked.index, joints, full)
    each = [gains_from_inertia(model, joints, q) for q in configurations]
    least, largest = np.min([g.inertia for g in each], axis=0), np.max([g.inertia for g in each], axis=0)
    first = each[0]
    assert checked.derived_gains is not None
    dt = 1.0 / DEFAULT_SIM_FREQ
    for i, joint in enumerate(joints):
        kp, kv, _ = checked.derived_gains[joint]
        bound = max(least[i] / dt, first.damping[i])  # never below the keyframe's own gains
        assert kv <= bound * (1 + 1e-9), (joint, kv, least[i] / dt)
        # as damped as the bound lets it be at the largest inertia (critical there where it can)
        wanted = min(2.0 * math.sqrt(kp * largest[i]), bound)
        assert kv == pytest.approx(max(wanted, first.damping[i]), rel=1e-6), (joint, kp, kv)


def test_ik_reaches_random_targets_of_the_derived_arm(tmp_path: Path) -> None:
    scene = ra.Scene(two_line(tmp_path, 6), floor=False)
    agent = scene.agents[0]
    assert_ik_reaches_random_targets(scene, agent.part_joints["arm"], "flange_roll_link", 50, seed=4, margin=0.1)


@pytest.mark.parametrize("joints", [5, 6])
def test_random_actions_in_every_derived_mode_stay_stable(tmp_path: Path, joints: int) -> None:
    result = check_random_actions(two_line(tmp_path, joints), seconds=3.0)
    assert result.passed, result.detail


def test_a_default_outside_the_limits_lands_inside_them(tmp_path: Path) -> None:
    """An elbow whose range excludes the file's zero pose ([-2.5, -0.1], as a Panda's
    fourth joint): the default keyframe puts it a tenth of the range inside the nearer
    stop (-0.34 rad), not on it (where the arm is stretched straight)."""
    checked = two_line(tmp_path, 6, elbow=(-2.5, -0.1)).check()
    default = checked.keyframes["default"].qpos
    elbow = checked.index.joint_names.index("elbow")
    assert default[elbow] == pytest.approx(-0.1 - 0.1 * 2.4)
    assert np.count_nonzero(default) == 1  # the joints whose zero lies inside stay at zero


def declaring_its_rest(cls: type[ra.Agent]) -> type[ra.Agent]:
    """``cls`` with the pose it rests in (its default keyframe) declared as its keyframe."""
    rest = cls.check().keyframes["default"].qpos
    names = cls.check().index.joint_names
    keyframe = ra.Keyframe(qpos={re.escape(n): float(v) for n, v in zip(names, rest, strict=True)})
    return type(cls.__name__, (cls,), {"uid": f"{cls.uid}_declared", "keyframes": {"rest": keyframe}})


def test_an_upright_arm_faces_a_workspace_ahead_of_it(tmp_path: Path) -> None:
    """The task layout of an arm whose keyframe holds its tool up (the written arm,
    every joint at zero, declared): the workspace centre 0.5 reach ahead of the
    shoulder, where the arm reaches down to the table (the built-in arms keep theirs:
    tests/test_tasks.py). Declaring no keyframe, it rests as its file draws it, which
    says nothing of where it works: its centre goes to the middle of where its flange
    points down, nearer (PushCube 7 -> 12 of 20, benchmarks/two_line_tasks.py)."""
    cls = two_line(tmp_path, 6)
    layout = table_top_layout(declaring_its_rest(cls))
    shoulder_x = layout.robot_pose[0]  # the shoulder is on the root's vertical axis
    assert layout.rest_tcp[0] == pytest.approx(shoulder_x, abs=1e-6)  # the tool straight above it
    assert 0.0 - shoulder_x == pytest.approx(UPRIGHT_AHEAD * layout.reach, rel=1e-9)  # centre at the origin
    drawn = table_top_layout(cls)
    assert drawn.reach == layout.reach
    assert 0.2 * drawn.reach < -drawn.robot_pose[0] < UPRIGHT_AHEAD * drawn.reach - 0.1


def test_a_stretched_arm_faces_a_workspace_within_reach(tmp_path: Path) -> None:
    """An arm whose keyframe holds it stretched out near the horizontal (its shoulder's
    range [1.5, 1.7] rad excludes zero: 1.52 rad by default, as the Koch's file lies
    stretched out; declared): the workspace centre 0.5 reach ahead too, not under the
    tool at the end of its reach."""
    layout = table_top_layout(declaring_its_rest(two_line(tmp_path, 6, shoulder=(1.5, 1.7))))
    shoulder_x = layout.robot_pose[0]
    assert layout.rest_tcp[0] - shoulder_x > STRETCHED_SHARE * layout.reach
    assert 0.0 - shoulder_x == pytest.approx(UPRIGHT_AHEAD * layout.reach, rel=1e-9)


def test_delta_action_refuses_what_one_step_cannot_do() -> None:
    space = ra.TaskSpace(
        position_bounds=ra.WorkspaceBox((-1, -1, -1), (1, 1, 1)), max_translation=0.1, max_rotation=0.1
    )
    here = np.array([0.3, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0])
    there = here.copy()
    there[:3] += (0.05, -0.1, 0.0)
    np.testing.assert_allclose(delta_action(space, here, there, rotation=False), [0.5, -1.0, 0.0])
    there[0] += 0.06  # 0.11 m along x
    assert delta_action(space, here, there) is None
    turned = here.copy()
    turned[3:] = (math.cos(0.04), 0.0, 0.0, math.sin(0.04))  # 0.08 rad about z
    np.testing.assert_allclose(delta_action(space, here, turned), [0, 0, 0, 0, 0, 0.8], atol=1e-12)
    turned[3:] = (math.cos(0.04), math.sin(0.04) / math.sqrt(2), 0.0, math.sin(0.04) / math.sqrt(2))
    assert delta_action(space, here, turned) is not None  # 0.08 rad about a diagonal: inside the ellipsoid
    turned[3:] = (math.cos(0.06), math.sin(0.06) / math.sqrt(2), 0.0, math.sin(0.06) / math.sqrt(2))
    assert delta_action(space, here, turned) is None  # 0.12 rad: each axis 0.085, the norm past 0.1


def test_a_derived_robot_gets_stiff_joint_stops(tmp_path: Path, pendulum_file: Path) -> None:
    """A robot with derived drives: every limited joint gets ``robot_spec.STOP_SOLREF``
    (the two-line Panda's joint 5 passed its stop by 0.51 rad under random targets at
    MuJoCo's default 20 ms, 0.12 rad with it: the sweep's random claim); a robot that
    declares its drives keeps the file's stops."""
    scene = ra.Scene(two_line(tmp_path, 6), floor=False)
    model = scene.model
    limited = [j for j in range(model.njnt) if model.jnt_limited[j]]
    assert len(limited) == 6
    for j in limited:
        np.testing.assert_array_equal(model.jnt_solref[j], STOP_SOLREF)
    declared = ra.Scene(make_pendulum_class(pendulum_file), floor=False).model
    for j in range(declared.njnt):
        np.testing.assert_array_equal(declared.jnt_solref[j], [0.02, 1.0])


#: A telescoping arm: a turret, a boom whose slide has no stops ({limits}), a forearm
#: and a wrist.
TELESCOPE = """<mujoco>
  <worldbody>
    <body name="base" pos="0 0 0.1">
      <geom type="cylinder" size="0.05 0.05" mass="2"/>
      <body name="turret" pos="0 0 0.05">
        <joint name="yaw" axis="0 0 1" range="-170 170"/>
        <geom type="capsule" fromto="0 0 0 0 0 0.2" size="0.03" mass="1"/>
        <body name="boom" pos="0 0 0.2">
          <joint name="extend" type="slide" axis="1 0 0" {limits}/>
          <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.025" mass="0.5"/>
          <body name="fore" pos="0.3 0 0">
            <joint name="pitch" axis="0 1 0" range="-100 100"/>
            <geom type="capsule" fromto="0 0 0 0.2 0 0" size="0.02" mass="0.3"/>
            <body name="hand" pos="0.2 0 0">
              <joint name="wrist" axis="0 1 0" range="-100 100"/>
              <geom type="box" size="0.03 0.03 0.03" mass="0.1"/>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def test_an_arm_with_an_unlimited_slide_gets_end_effector_modes_with_a_note(tmp_path: Path) -> None:
    # a slide without limits in the arm: no end-effector mode, and no word why
    path = tmp_path / "telescope.xml"
    path.write_text(TELESCOPE.format(limits=""))
    cls = type("Telescope", (ra.Agent,), {"uid": "telescope", "mjcf_path": path})
    with pytest.warns(RuntimeWarning, match=r"slide joint\(s\) \['extend'\] without limits: .*held at the keyframe"):
        checked = cls.check()
    space = checked.parts[0].task_space  # type: ignore[union-attr]
    assert space is not None
    assert {m for m in checked.modes if m.startswith("pd_ee")} == {"pd_ee_delta_pos", "pd_ee_target_delta_pos"}
    # the box: what the other joints reach with the boom at its keyframe (the hand 0.3 +
    # 0.2 m out, 0.2 m above the yaw joint), grown by 5 % of that reach
    assert space.position_bounds.upper[0] == pytest.approx(0.5 + 0.05 * math.hypot(0.5, 0.2), abs=0.005)
    # the delta modes carry the tool along the slide past that box
    scene = ra.Scene(cls, control_modes="pd_ee_delta_pos", floor=False)
    agent = scene.agents[0]
    scene.reset()
    for _ in range(40):
        agent.set_action(np.array([[1.0, 0.0, 0.0]]))
        scene.step()
    tool = agent.frame_pose("ee", relative_to="root")[0]
    assert tool[0] > space.position_bounds.upper[0] + 0.2
    assert agent.qpos[0, 1] > 0.2  # the boom extended
    scene.close()
    result = check_random_actions(cls, seconds=2.0)
    assert result.passed, result.detail
