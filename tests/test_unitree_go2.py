"""Unitree Go2: it stands on its own legs under PD control (free root, full gravity), its
masses, inertias, joint ranges and foot kinematics match the public model, its actions
follow ManiSkill's joint order, and random actions in every mode stay finite."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.cli import main
from robot_agents.robots.unitree.go2 import (
    ACTION_JOINTS,
    LEG_JOINTS,
    STANDING_HEIGHT,
    STANDING_LEG,
    TOUCHING_HEIGHT,
)
from tests.chain_check import axis_rotation, transform

UID = "unitree_go2"
LEGS = ("FL", "FR", "RL", "RR")
#: Menagerie's unitree_go2/go2.xml (kg): link masses; the feet are part of the calves.
LINK_MASSES = {"base": 6.921, "hip": 0.678, "thigh": 1.152, "calf": 0.241352}
LINK_INERTIAS = {
    "base": (0.107027, 0.0980771, 0.0244531),
    "hip": (0.00088403, 0.000596003, 0.000479967),
    "thigh": (0.00594973, 0.00584149, 0.000878787),
    "calf": (0.0014901, 0.00146356, 5.31397e-05),
}
TOTAL_MASS = 15.206408
#: Menagerie's joint ranges (rad).
RANGES = {
    "hip": (-1.0472, 1.0472),
    "front_thigh": (-1.5708, 3.4907),
    "rear_thigh": (-0.5236, 4.5379),
    "calf": (-2.7227, -0.83776),
}
#: Joint origins (Menagerie): hip in the base, thigh in the hip (y outwards), calf in
#: the thigh, foot in the calf; the foot sphere's centre in the foot; its radius.
HIP = {"FL": (0.1934, 0.0465), "FR": (0.1934, -0.0465), "RL": (-0.1934, 0.0465), "RR": (-0.1934, -0.0465)}
THIGH_Y = 0.0955
SEGMENT = 0.213
SOLE = (-0.002, 0.0, 0.0)
FOOT_RADIUS = 0.022
STANDING_QPOS = np.tile(STANDING_LEG, 4)
#: ManiSkill's standing qpos, in its action order (hips, thighs, calves).
MANISKILL_STANDING = np.array([0.0] * 4 + [0.9] * 4 + [-1.8] * 4)


def foot_chain(base: np.ndarray, leg: str, q: np.ndarray) -> np.ndarray:
    """The foot sphere's centre (world) from the base pose (4x4) and the leg's (hip, thigh,
    calf) angles, chained from the joint origins above."""
    x, y = HIP[leg]
    side = 1.0 if y > 0 else -1.0
    pose = base @ transform(axis_rotation((1, 0, 0), q[0]), np.array([x, y, 0.0]))
    pose = pose @ transform(axis_rotation((0, 1, 0), q[1]), np.array([0.0, side * THIGH_Y, 0.0]))
    pose = pose @ transform(axis_rotation((0, 1, 0), q[2]), np.array([0.0, 0.0, -SEGMENT]))
    pose = pose @ transform(np.eye(3), np.array([0.0, 0.0, -SEGMENT]))
    return (pose @ np.array([*SOLE, 1.0]))[:3]


def base_matrix(pose: np.ndarray) -> np.ndarray:
    w, x, y, z = pose[3:]
    rotation = np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
    return transform(rotation, pose[:3])


def tilt_degrees(quat: np.ndarray) -> float:
    """Angle between the base's z axis and the world's (deg)."""
    _, x, y, _ = quat
    return math.degrees(math.acos(min(1.0, max(-1.0, 1 - 2 * (x * x + y * y)))))


def foot_geoms(scene: ra.Scene) -> list[int]:
    prefix = scene.agents[0].prefix
    return [scene.model.geom(prefix + leg).id for leg in LEGS]


def floor_contacts(scene: ra.Scene) -> set[int]:
    """The robot geoms touching the floor in env 0."""
    data = scene.world.datas[0]
    floor = scene.model.geom("floor").id
    touching = set()
    for c in data.contact[: data.ncon]:
        if floor in (c.geom1, c.geom2):
            touching.add(int(c.geom2 if c.geom1 == floor else c.geom1))
    return touching


# ---------------------------------------------------------------- standing
def test_stands_at_the_standing_keyframe_for_5_s_in_the_default_mode() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    assert agent.control_mode == "pd_joint_pos"
    scene.reset(keyframes="standing")
    np.testing.assert_allclose(agent.base_pose[0, :3], (0.0, 0.0, STANDING_HEIGHT))
    hold = hold_action(agent)  # the keyframe's targets, repeated
    np.testing.assert_array_equal(hold, MANISKILL_STANDING)  # ManiSkill's action order
    heights, tilts, sag = [], [], 0.0
    feet = set(foot_geoms(scene))
    for _ in range(5 * scene.control_freq):
        agent.set_action(hold)
        scene.step()
        heights.append(float(agent.base_pose[0, 2]))
        tilts.append(tilt_degrees(agent.base_pose[0, 3:]))
        sag = max(sag, float(np.max(np.abs(agent.qpos[0] - STANDING_QPOS))))
        assert floor_contacts(scene) <= feet  # nothing but the feet touches the floor
    last = np.array(heights[scene.control_freq :])
    assert np.ptp(last) < 0.01  # settled: within 1 cm over the last 4 s (measured < 1e-6 m)
    assert max(tilts) < 2.0
    assert floor_contacts(scene) == feet  # all four feet carry it
    # Sag under the 15.2 kg at Unitree's stand gains (kp 60): the knees give 0.124 rad,
    # lowering the base 2.6 cm below the height at which the rigid feet would just touch.
    assert 0.1 < sag < 0.15
    assert TOUCHING_HEIGHT - 0.035 < last[-1] < TOUCHING_HEIGHT - 0.02
    assert np.all(agent.is_static())
    assert np.all(agent.is_standing()) and not np.any(agent.is_fallen())
    scene.close()


def test_every_keyframe_stands_on_four_feet() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    feet = set(foot_geoms(scene))
    assert next(iter(agent.keyframes)) == "rest"
    for name in agent.keyframes:
        scene.reset(keyframes=name)
        np.testing.assert_array_equal(agent.qpos[0], STANDING_QPOS)
        hold = hold_action(agent)
        for _ in range(2 * scene.control_freq):
            agent.set_action(hold)
            scene.step()
        assert floor_contacts(scene) == feet, name
        assert tilt_degrees(agent.base_pose[0, 3:]) < 2.0, name
    scene.close()


def test_target_deltas_stand_and_maniskills_zero_deltas_sink() -> None:
    """Zero ``pd_joint_target_delta_pos`` deltas keep the targets: the robot stands. Zero
    ``pd_joint_delta_pos`` deltas (ManiSkill's default mode) retarget the measured pose
    every control step, so the load walks the legs down by the drives' steady-state error
    each step (why the default mode is ``pd_joint_pos``)."""
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    heights = {}
    for mode in ("pd_joint_target_delta_pos", "pd_joint_delta_pos"):
        agent.set_control_mode(mode)
        scene.reset(keyframes="standing")
        for _ in range(3 * scene.control_freq):
            agent.set_action(np.zeros(12))
            scene.step()
        heights[mode] = float(agent.base_pose[0, 2])
        if mode == "pd_joint_target_delta_pos":  # the stand's sag (0.124 rad), no more
            assert np.max(np.abs(agent.qpos[0] - STANDING_QPOS)) < 0.15 and np.all(agent.is_standing())
    assert heights["pd_joint_target_delta_pos"] - heights["pd_joint_delta_pos"] > 0.02  # sunk > 2 cm in 3 s
    scene.close()


# ---------------------------------------------------------------- model data
def test_masses_inertias_and_joint_ranges_match_the_public_model() -> None:
    scene = ra.Scene(UID)
    agent = scene.agents[0]
    model = scene.model
    bodies = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    assert float(sum(model.body_mass[b] for b in bodies)) == pytest.approx(TOTAL_MASS, abs=1e-9)
    for link, mass in LINK_MASSES.items():
        names = ["base"] if link == "base" else [f"{leg}_{link}" for leg in LEGS]
        for name in names:
            body = model.body(agent.prefix + name)
            assert body.mass[0] == pytest.approx(mass, abs=1e-9), name
            np.testing.assert_allclose(np.sort(body.inertia), np.sort(LINK_INERTIAS[link]), rtol=1e-6, err_msg=name)
    for leg in LEGS:
        assert model.body(agent.prefix + f"{leg}_foot").mass[0] == 0.0
    for joint in LEG_JOINTS:
        kind = joint.split("_")[1]
        if kind == "thigh":
            kind = "front_thigh" if joint.startswith("F") else "rear_thigh"
        np.testing.assert_allclose(model.joint(agent.prefix + joint).range, RANGES[kind], err_msg=joint)
    assert agent.joint_names == LEG_JOINTS
    scene.close()


def test_drives_gains_limits_and_armature() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    prefix = scene.agents[0].prefix
    for joint in LEG_JOINTS:
        jid = model.joint(prefix + joint).id
        act = next(a for a in range(model.nu) if model.actuator_trnid[a, 0] == jid)
        limit = 45.43 if "calf" in joint else 23.7
        assert model.actuator_gainprm[act, 0] == 60.0  # unitree_sdk2's go2_stand_example.cpp
        assert -model.actuator_biasprm[act, 2] == 5.0
        np.testing.assert_allclose(model.actuator_forcerange[act], (-limit, limit))
        dof = model.jnt_dofadr[jid]
        assert model.dof_armature[dof] == 0.01
        assert model.dof_frictionloss[dof] == 0.2
        assert model.dof_damping[dof] == 2.0
    assert float(np.sum(model.body_gravcomp)) == 0.0
    scene.close()


def test_foot_positions_match_the_joint_origins_chained_independently() -> None:
    yaw = 0.4
    scene = ra.Scene(UID, robot_poses=[(0.3, -0.2, 0.1, math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))])
    agent = scene.agents[0]
    data = scene.world.datas[0]
    feet = foot_geoms(scene)
    rng = np.random.default_rng(0)
    limits = agent.qpos_limits
    poses = [STANDING_QPOS] + [rng.uniform(limits[:, 0], limits[:, 1]) for _ in range(5)]
    for q in poses:
        agent.reset(qpos=q)
        base = base_matrix(agent.base_pose[0])
        for k, leg in enumerate(LEGS):
            expected = foot_chain(base, leg, q[3 * k : 3 * k + 3])
            np.testing.assert_allclose(data.geom_xpos[feet[k]], expected, atol=1e-6, err_msg=leg)
    # At the standing pose each sole is 0.288372 m below the base, under its hip.
    agent.reset(qpos=STANDING_QPOS)
    inverse = np.linalg.inv(base_matrix(agent.base_pose[0]))
    local = (inverse @ np.c_[data.geom_xpos[feet], np.ones(4)].T).T[:, :3]
    np.testing.assert_allclose(local[:, 2] - FOOT_RADIUS, -0.288372, atol=1e-6)
    np.testing.assert_allclose(local[:, 1], (0.142, -0.142, 0.142, -0.142), atol=1e-9)
    np.testing.assert_allclose(local[:, 0], (0.192157, 0.192157, -0.194643, -0.194643), atol=1e-6)
    scene.close()


# ---------------------------------------------------------------- actions
def test_actions_follow_maniskills_joint_order() -> None:
    """Action entry i drives ManiSkill's i-th active joint (hips, thighs, calves of FL, FR,
    RL, RR): raising one entry of the absolute standing targets moves that joint."""
    assert ACTION_JOINTS[:4] == ("FL_hip_joint", "FR_hip_joint", "RL_hip_joint", "RR_hip_joint")
    scene = ra.Scene(UID, control_modes="pd_joint_pos")
    agent = scene.agents[0]

    def pose_after(action: np.ndarray) -> np.ndarray:
        scene.reset(keyframes="standing")
        for _ in range(5):
            agent.set_action(action)
            scene.step()
        return agent.qpos[0]

    standing = pose_after(MANISKILL_STANDING)  # the legs give under the load alike
    for entry in (1, 5, 10):
        action = MANISKILL_STANDING.copy()
        action[entry] += 0.2
        moved = np.abs(pose_after(action) - standing)
        assert agent.joint_names[int(np.argmax(moved))] == ACTION_JOINTS[entry]
        assert moved.max() > 0.1
    scene.close()


@pytest.mark.parametrize("mode", ra.get_agent(UID).modes())
def test_random_actions_for_10_s_stay_finite_in_every_mode(mode: str) -> None:
    scene = ra.Scene(UID, control_modes=mode)
    agent = scene.agents[0]
    scene.reset()
    rng = np.random.default_rng(1)
    space = agent.single_action_space
    fell = False
    for _ in range(10 * scene.control_freq):
        agent.set_action(rng.uniform(space.low, space.high))
        scene.step()
        assert np.all(np.isfinite(agent.qpos)) and np.all(np.isfinite(agent.base_pose))
        assert np.max(np.abs(agent.qvel)) < 200.0  # rad/s: no blow-up
        assert abs(agent.base_pose[0, 2]) < 1.0 and np.max(np.abs(agent.base_pose[0, :2])) < 3.0
        fell = fell or bool(agent.is_fallen()[0])
    assert not np.any(scene.world.instability_counts())
    if mode == "pd_joint_pos":  # random targets over the whole joint ranges fold it up
        assert fell
    scene.close()


def test_cli_info_shows_a_free_root_and_the_default_mode() -> None:
    out = io.StringIO()
    assert main(["info", UID], out=out) == 0
    text = out.getvalue()
    assert "root: free" in text
    assert "pd_joint_pos (default)     12" in text
    assert "rest: qpos = [0.0000, 0.9000, -1.8000" in text
