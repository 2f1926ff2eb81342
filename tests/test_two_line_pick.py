"""A model file in two lines picks a cube: a written six-joint arm with a hand and two
sliding fingers (URDF, no actuators), its gripper, pads, drives, task space and table
layout all derived, solved by the scripted solver of ``examples/scripted_pick.py``."""

from __future__ import annotations

import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.envs.tasks.layout import (
    SPAWN_HALF_SIZE,
    TABLE_CLEARANCE,
    UPRIGHT_AHEAD,
    _pressing,
    table_top_layout,
)
from tests.test_derived_task_space import BASE_HEIGHT, JOINTS, arm_urdf
from tests.test_scripted_solvers import load_solver

#: The fingers: stroke (m) and effort limit (N) each, written in the file.
STROKE, FINGER_EFFORT = 0.04, 20.0


def _link(name: str, mass: float, com: str, box: str, inertia: float) -> str:
    return (
        f'<link name="{name}"><inertial><origin xyz="{com}"/><mass value="{mass}"/>'
        f'<inertia ixx="{inertia}" iyy="{inertia}" izz="{inertia}" ixy="0" ixz="0" iyz="0"/></inertial>'
        f'<collision><origin xyz="{com}"/><geometry><box size="{box}"/></geometry></collision></link>'
    )


def arm_with_gripper_urdf() -> str:
    """``arm_urdf(6)`` (upright at zero: 0.3, 0.3, 0.25 m links, then a short wrist) with
    a 0.4 kg hand on its flange and two 30 g fingers sliding apart across it (0 closed,
    ``STROKE`` open, 4 cm pads, 2 mm apart when closed)."""
    parts = _link("hand", 0.4, "0 0 0.02", "0.04 0.12 0.04", 4e-4)
    parts += (
        '<joint name="hand_mount" type="fixed"><parent link="flange_roll_link"/><child link="hand"/>'
        f'<origin xyz="0 0 {JOINTS[-1][3]}"/></joint>'
    )
    for side, sign in (("left", 1), ("right", -1)):
        parts += _link(f"{side}_finger", 0.03, "0 0 0.03", "0.02 0.01 0.04", 1e-5)
        parts += (
            f'<joint name="{side}_finger_joint" type="prismatic"><parent link="hand"/><child link="{side}_finger"/>'
            f'<origin xyz="0 {sign * 0.006} 0.04"/><axis xyz="0 {sign} 0"/>'
            f'<limit lower="0" upper="{STROKE}" effort="{FINGER_EFFORT}" velocity="0.2"/></joint>'
        )
    return arm_urdf(6).replace("</robot>", parts + "</robot>")


@pytest.fixture
def two_line_arm(tmp_path: Path) -> Iterator[type[ra.Agent]]:
    path = tmp_path / "arm_gripper.urdf"
    path.write_text(arm_with_gripper_urdf())
    cls = type("TwoLineArm", (ra.Agent,), {"uid": "two_line_gripper_arm", "urdf_path": path})
    ra.register_agent(cls, override=True)
    yield cls
    ra.unregister_agent(cls.uid)  # (the solver suites list every registered robot)


def test_an_upright_arm_gets_its_workspace_where_it_grasps_pointing_down(two_line_arm: type[ra.Agent]) -> None:
    """The arm rests upright (every joint at zero); pointing its fingers down it reaches
    at most 0.62 m ahead of its shoulder (probed with IK when the rule was written), so
    the workspace centre comes nearer than ``UPRIGHT_AHEAD`` reach (0.57 m: a third of
    the cubes lay beyond, PickCube 14/20), with every cube drawn within that reach."""
    layout = table_top_layout(two_line_arm)
    ahead = -layout.robot_pose[0]  # the shoulder's axis is the root's vertical; the centre is the origin
    assert ahead < UPRIGHT_AHEAD * layout.reach
    assert ahead + SPAWN_HALF_SIZE * layout.reach < 0.62
    assert ahead > 0.2  # not at the arm's foot


def test_the_two_line_arm_picks_the_cube(two_line_arm: type[ra.Agent]) -> None:
    solver = load_solver()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        successes, _ = solver.success_rate("PickCube-v1", two_line_arm.uid, 20)
    assert successes >= 18, successes
    env = ra.make_env("PickCube-v1", robot_uids=two_line_arm.uid).unwrapped
    try:
        agent = env.agents[0]
        assert [type(p).__name__ for p in agent.parts_by_name.values()] == ["Arm", "Gripper"]
        assert np.all(np.isfinite(agent.qpos))
    finally:
        env.close()


def folded_arm(tmp_path: Path, keyframes: dict[str, ra.Keyframe] | None = None) -> type[ra.Agent]:
    """The arm with a gripper, its file drawing the forearm bent 1.2 rad forward at zero
    (as the xArm7's file folds its tool in near its base); ``keyframes``: declared."""
    elbow = '<child link="elbow_link"/><origin xyz="0 0 0.3"/>'
    text = arm_with_gripper_urdf()
    if elbow not in text:
        raise AssertionError("the written arm's elbow moved")
    path = tmp_path / "folded.urdf"
    path.write_text(text.replace(elbow, elbow.replace('"/>', '" rpy="0 1.2 0"/>')))
    attrs: dict[str, object] = {"uid": "folded_arm", "urdf_path": path}
    if keyframes is not None:
        attrs["keyframes"] = keyframes
    return type("FoldedArm", (ra.Agent,), attrs)


def test_an_arm_resting_as_its_file_draws_it_gets_its_workspace_where_it_points_down(tmp_path: Path) -> None:
    """Declaring no keyframe, the arm rests as its file draws it, which says nothing of
    where it works: its centre goes in the middle of where its fingers point down
    (0.35 m ahead). Declaring that same pose as its keyframe, the centre stays under
    its tool (0.50 m), as for every built-in robot."""
    drawn = table_top_layout(folded_arm(tmp_path))
    declared = table_top_layout(folded_arm(tmp_path, {"rest": ra.Keyframe(qpos={".*": 0.0})}))
    assert drawn.reach == declared.reach
    rest_ahead = declared.rest_tcp[0] - declared.robot_pose[0]  # the rest tool, from the root
    assert -declared.robot_pose[0] == pytest.approx(rest_ahead, abs=0.01)  # the centre under it
    assert -drawn.robot_pose[0] == pytest.approx(0.35, abs=0.03)


def test_poses_pressing_into_the_table_or_the_arm_itself_do_not_count(two_line_arm: type[ra.Agent]) -> None:
    """The pointing-down measure leaves out configurations in which the robot touches
    itself or the floor it stands on (the table top) deeper than 1 mm."""
    scene = ra.Scene(two_line_arm)
    try:
        agent, model = scene.agents[0], scene.model
        robot = set(agent.index.subtree_bodies(agent.index.root_body_id))
        data = mujoco.MjData(model)
        qpos = scene.world.qpos[0].copy()
        shoulder, elbow, wrist = (agent.index.joint(j, "test").qpos_start for j in ("shoulder", "elbow", "wrist"))
        assert not _pressing(model, data, qpos, robot)  # upright
        into_table = qpos.copy()
        into_table[shoulder] = 1.7  # leaning forward down to its stop: the arm's tip reaches below its foot
        into_table[elbow] = 1.0
        assert _pressing(model, data, into_table, robot)
        onto_itself = qpos.copy()
        onto_itself[elbow], onto_itself[wrist] = 2.5, 1.7  # folded back: the fingers into its foot
        assert _pressing(model, data, onto_itself, robot)
    finally:
        scene.close()


def test_the_solver_ik_takes_another_solution_where_one_is_refused(two_line_arm: type[ra.Agent]) -> None:
    """``Arm.solve(..., refuse=...)`` (the scripted pick refuses a pose above the cube
    from which the descent would press the arm into the table): refusing the elbow's
    side of the first solution, the restarts find one bent the other way that still
    puts the tool on the target."""
    solver = load_solver()
    env = ra.make_env("PickCube-v1", robot_uids=two_line_arm.uid, num_envs=4).unwrapped
    try:
        env.reset(seed=0)
        arm = solver.Arm(env)
        elbow = list(arm.agent.part_joints["arm"]).index("elbow")
        target = env.body_pose("cube")[:, :3] + np.array([0.0, 0.0, 0.15])
        first = arm.solve(target, None)
        assert np.linalg.norm(arm.tool_at(first) - target, axis=1).max() < 0.01
        side = np.sign(first[:, elbow])

        def same_side(q: np.ndarray) -> np.ndarray:
            return np.asarray(np.sign(q[:, elbow]) == side)

        other = arm.solve(target, None, refuse=same_side)
        assert not same_side(other).any()
        assert np.linalg.norm(arm.tool_at(other) - target, axis=1).max() < 0.01
    finally:
        env.close()


@contextmanager
def registered(cls: type[ra.Agent]) -> Iterator[None]:
    """``cls`` registered under its uid for the block (the solvers make envs by uid)."""
    ra.register_agent(cls, override=True)
    try:
        yield
    finally:
        ra.unregister_agent(cls.uid)


def scripted_successes(task: str, uid: str, seeds: int) -> int:
    """Successes of the scripted solver of ``task`` over seeds ``0 .. seeds - 1``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        successes, _ = load_solver().success_rate(task, uid, seeds)
    return int(successes)


#: The pedestal the arm stands on in its file (m): tall enough that its tool cannot get
#: down to the floor under it (gymnasium-robotics' Franka kitchen stands its Panda 1.8 m up).
PEDESTAL_HEIGHT, PEDESTAL_WIDTH = 1.5, 0.2


def arm_on_a_block(
    tmp_path: Path, name: str, height: float, width: float, mass: float, inertia: float
) -> type[ra.Agent]:
    """A two-line robot of ``arm_with_gripper_urdf`` standing on a fixed box link ``name``
    ``width`` x ``width`` x ``height`` (m) of ``mass`` (kg) and diagonal ``inertia``
    (kg*m^2), its base on the box's top."""
    block = (
        _link(name, mass, f"0 0 {height / 2}", f"{width} {width} {height}", inertia)
        + f'<joint name="on_{name}" type="fixed"><parent link="{name}"/><child link="base"/>'
        f'<origin xyz="0 0 {height}"/></joint>'
    )
    path = tmp_path / f"on_{name}.urdf"
    path.write_text(arm_with_gripper_urdf().replace("<link ", block + "<link ", 1))
    title = name.capitalize()
    return type(f"{title}Arm", (ra.Agent,), {"uid": f"{name}_arm", "urdf_path": path})


def test_an_arm_on_a_pedestal_of_its_own_gets_a_table_it_reaches(tmp_path: Path) -> None:
    """The arm with a gripper on a 1.5 m pedestal (the file's root link): its tool gets
    no lower than 1.32 m over the floor, so the robot stands on the floor and the table
    top rises to where the heights of cubes and goals centre on the median height at
    which its tool points down (1.39 m: between that lowest point and the shoulder's yaw
    axis, 1.6 m), the table starting clear of the pedestal with every cube drawn on it;
    the scripted solver picks. (Before, the pedestal stood on the table and every cube
    lay out of reach: the kitchen's Franka picked 0 of 20.)"""
    cls = arm_on_a_block(tmp_path, "pedestal", PEDESTAL_HEIGHT, PEDESTAL_WIDTH, 50.0, 10.0)
    layout = table_top_layout(cls)
    root_x, reach, edge = layout.robot_pose[0], layout.reach, 2.0 * layout.cube_half_size
    assert layout.robot_pose[2] == pytest.approx(0.0, abs=1e-9)  # on the floor
    assert 1.35 < layout.table_height < 1.45 < PEDESTAL_HEIGHT + BASE_HEIGHT
    back = layout.table_center[0] - layout.table_half_size[0]
    assert back >= root_x + 0.5 * PEDESTAL_WIDTH + TABLE_CLEARANCE * reach - 1e-9  # clear of the pedestal
    nearest_cube = -layout.spawn_half_size - np.sqrt(2.0) * 0.5 * edge  # from the workspace centre (x = 0)
    assert nearest_cube > back
    assert layout.pedestal
    with registered(cls):
        successes = scripted_successes("PickCube-v1", cls.uid, 10)
        assert successes >= 9, successes
        env = ra.make_env("PickCube-v1", robot_uids=cls.uid).unwrapped
        try:  # the render camera frames the arm over its table, not the pedestal's 1.5 m
            lower, upper = env._render_bounds()
            assert layout.table_height - 0.1 < lower[2] <= layout.table_height < upper[2]
        finally:
            env.close()


def test_an_arm_hanging_from_above_gets_a_table_under_its_rest_pose(tmp_path: Path) -> None:
    """The arm with a gripper hung upside down 1.6 m up (``mount_pose``; its file's rest
    hangs it straight down): its tool cannot get down to the floor's cubes, so it is laid
    out as a robot on a pedestal, but the table top stays under what of it moves as it
    rests (the fingertips, 0.34 m up), and with nothing of it fixed below that top the
    table spans under it as under a table-top robot; ReachPose is solved."""
    path = tmp_path / "hanging.urdf"
    path.write_text(arm_with_gripper_urdf())
    cls = type(
        "HangingArm", (ra.Agent,), {"uid": "hanging_arm", "urdf_path": path, "mount_pose": (0, 0, 1.6, 0, 1, 0, 0)}
    )
    layout = table_top_layout(cls)
    assert layout.pedestal and layout.robot_pose[2] == pytest.approx(1.6)
    assert layout.gripper is not None
    assert layout.table_height < layout.rest_tcp[2] - layout.gripper.tip_reach  # the resting fingertips above it
    back = layout.table_center[0] - layout.table_half_size[0]
    assert back < layout.robot_pose[0]  # under the arm: nothing fixed of it stands below the top
    with registered(cls):
        successes = scripted_successes("ReachPose-v1", cls.uid, 10)
    assert successes >= 9, successes


#: A column the arm stands on in its file (m): short enough that its tool gets down to
#: the floor under it, tall enough that pointing down it reaches the floor only over a
#: narrow band of distances (gymnasium-robotics' Fetch: its shoulder 0.80 m over its base).
COLUMN_HEIGHT, COLUMN_WIDTH = 0.3, 0.12


def test_a_tall_arm_stands_on_the_floor_next_to_a_risen_table(tmp_path: Path) -> None:
    """The arm with a gripper on a 0.3 m column (the file's root link): its fingers
    point down at the floor it stands on only over a band of distances narrower than
    ``NARROW_BAND`` reach, so it stands on the floor and the table top rises to where
    the heights of cubes and goals centre on the median height at which it points down
    (0.19 m), the table starting clear of the column with every cube drawn on it. Before,
    the arm stood on the table and picked 0 of 20 (and pushed 0 of 20); now 20 of 20
    (and 13 of 20: ``/tmp`` scratch runs of the scripted solvers, 2026-11-29 10:16 UTC)."""
    cls = arm_on_a_block(tmp_path, "column", COLUMN_HEIGHT, COLUMN_WIDTH, 20.0, 1.0)
    layout = table_top_layout(cls)
    root_x, reach, edge = layout.robot_pose[0], layout.reach, 2.0 * layout.cube_half_size
    assert layout.lowered and not layout.pedestal
    assert layout.robot_pose[2] == pytest.approx(0.0, abs=1e-9)  # on the floor
    assert 0.1 < layout.table_height < COLUMN_HEIGHT + BASE_HEIGHT  # risen, below the shoulder
    back = layout.table_center[0] - layout.table_half_size[0]
    assert back >= root_x + 0.5 * COLUMN_WIDTH + TABLE_CLEARANCE * reach - 1e-9  # clear of the column
    assert -layout.spawn_half_size - np.sqrt(2.0) * 0.5 * edge > back  # every cube on the table
    with registered(cls):
        successes = scripted_successes("PickCube-v1", cls.uid, 10)
    assert successes >= 9, successes


def _turn(uid: str, settle: int) -> tuple[int, np.ndarray]:
    """The scripted solvers' turn to a ReachPose goal (4 envs, seed 0) with at most
    ``settle`` steps of waiting: the steps it took and each env's largest joint lag (rad)."""
    solver = load_solver()
    solver.SETTLE_STEPS = settle
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        env = ra.make_env("ReachPose-v1", robot_uids=uid, num_envs=4).unwrapped
    try:
        env.reset(seed=0)
        arm = solver.Arm(env)
        goal = arm.solve(env.goal_pose[:, :3], None)
        steps = 0

        def step(action: np.ndarray) -> None:
            nonlocal steps
            steps += 1
            env.step(action)

        arm.ramp(step, goal, 30, np.ones(4, dtype=bool))
        lag = np.abs(arm.agent.qpos[:, arm.q_index] - arm.nearest_turns(goal, arm.agent.qpos[:, arm.q_index]))
        return steps, lag.max(axis=1)
    finally:
        env.close()


def test_the_turn_waits_for_drives_slower_than_its_ramp(tmp_path: Path, two_line_arm: type[ra.Agent]) -> None:
    """An arm whose file's position servos turn its joints at most 1.25 rad/s (a 5 N*m
    force limit over 4 N*m*s/rad of joint damping, as gymnasium-robotics' Franka kitchen
    writes its Panda's: 0.87 and 1.2 rad/s) ends the 1.5 s ramp short of the turn's goal;
    the solver holds the goal until it has arrived. Drives that keep up take no extra step."""
    from tests.test_model_files_wild import MOCAP_ARM

    text = MOCAP_ARM.replace('<equality><weld body1="mocap" body2="hand"/></equality>', "")
    text = text.replace('range="-2 2"/>', 'range="-2 2" damping="4"/>')
    servos = "".join(
        f'<position joint="{joint}" kp="50" forcerange="-5 5" ctrlrange="-2 2"/>'
        for joint in ("shoulder", "elbow", "wrist")
    )
    path = tmp_path / "slow_arm.xml"
    path.write_text(text.replace("<actuator>", "<actuator>" + servos))
    slow = type("SlowArm", (ra.Agent,), {"uid": "slow_servo_arm", "mjcf_path": path})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # (its fingers touch its forearm at rest: a note)
        slow.check()
    with registered(slow), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        steps, lag = _turn("slow_servo_arm", 0)
        assert steps == 30 and lag.max() > 0.15, lag  # measured: 0.21 rad short
        steps, lag = _turn("slow_servo_arm", 20)
        assert steps > 30 and lag.max() < load_solver().ARRIVED, (steps, lag)
    steps, lag = _turn(two_line_arm.uid, 20)
    assert steps == 30 and lag.max() < 0.05, (steps, lag)


def arm_with_one_jaw_urdf() -> str:
    """``arm_urdf(6)`` with a 0.4 kg hand on its flange, a fixed jaw welded to it (a 6 cm
    plate 3 cm to one side) and a moving jaw (a 6 cm plate hinged 3 cm to the other side,
    4 cm up) that turns onto the fixed jaw (-0.6 rad open, 1.0 closed, its tip then at
    the fixed jaw), as the SO-100's and the Unitree Z1's files: closed, both jaws stand
    beside the middle of the open mouth, the grasp point (1.6 cm from the nearer)."""
    parts = _link("hand", 0.4, "0 0 0.02", "0.04 0.1 0.04", 4e-4)
    parts += (
        '<joint name="hand_mount" type="fixed"><parent link="flange_roll_link"/><child link="hand"/>'
        f'<origin xyz="0 0 {JOINTS[-1][3]}"/></joint>'
    )
    parts += _link("fixed_jaw", 0.03, "0 0.03 0.07", "0.03 0.01 0.06", 1e-5)
    parts += '<joint name="fixed_jaw_weld" type="fixed"><parent link="hand"/><child link="fixed_jaw"/></joint>'
    parts += _link("moving_jaw", 0.03, "0 0 0.03", "0.03 0.01 0.06", 1e-5)
    parts += (
        '<joint name="jaw_joint" type="revolute"><parent link="hand"/><child link="moving_jaw"/>'
        '<origin xyz="0 -0.03 0.04"/><axis xyz="-1 0 0"/>'
        '<limit lower="-0.6" upper="1.0" effort="5" velocity="3"/></joint>'
    )
    return arm_urdf(6).replace("</robot>", parts + "</robot>")


def test_a_one_jaw_gripper_pushes_with_its_closed_jaws(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The arm with one moving jaw: its grasp point lies farther than half the cube's edge
    from both closed jaws, so the push aims the closed jaws' point instead. Aimed so, the
    jaws move the cube more than 1 cm in at least 6 of 20 envs (measured: 8); aimed with
    the grasp point, as before, the closed jaws pass beside the cube and touch it in none."""
    path = tmp_path / "one_jaw_arm.urdf"
    path.write_text(arm_with_one_jaw_urdf())
    cls = type("OneJawArm", (ra.Agent,), {"uid": "one_jaw_arm", "urdf_path": path})
    solver = load_solver()
    with registered(cls), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        layout = table_top_layout(cls)
        geometry = layout.gripper
        assert geometry is not None and geometry.closed_clearance > layout.cube_half_size
        moved = []
        for aim in (solver.push_point, lambda geometry, half: np.array(geometry.grasp_point)):
            monkeypatch.setattr(solver, "push_point", aim)
            env = ra.make_env("PushCube-v1", robot_uids=cls.uid, num_envs=20).unwrapped
            try:
                env.reset(seed=0)
                start = env.body_pose("cube")[:, :2].copy()
                solver.solve_push(env, 0)
                moved.append(int(np.sum(np.linalg.norm(env.body_pose("cube")[:, :2] - start, axis=1) > 0.01)))
            finally:
                env.close()
    assert moved[0] >= 6 and moved[1] == 0, moved
