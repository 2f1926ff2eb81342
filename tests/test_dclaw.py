"""The ROBEL D'Claw checked against numbers: fingertip forward kinematics against the
URDF's joint origins chained here, its masses and joint ranges, ManiSkill's joint and
action order and drives, the keyframe held, random actions in every mode, and a
three-fingertip pinch of a cube whose contact forces carry its weight."""

from __future__ import annotations

import dataclasses

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_holds, check_random_actions
from robot_agents.robots.robel.dclaw import (
    ACTION_JOINTS,
    CLOSED,
    DCLAW_HAND,
    GRASP_CUBE_EDGE,
    JOINTS,
    MOUNT,
    OPEN,
    POWER_GRASP,
    TIP_LINKS,
    DClaw,
)
from robot_agents.robots.servo_arms.servos import XM430_W350
from robot_agents.tuning.claims import Penetration
from robot_agents.tuning.grasp_claim import grasp_claim
from tests.chain_check import axis_rotation, transform

UID = "dclaw"

# ---------------------------------------------------------------- independent kinematics
# ManiSkill's dclaw_gripper_glb.urdf (ROBEL's D'Claw), written out here, not read from our
# model: base_joint's rpy, then per finger the first joint's origin (xyz, roll about x)
# and the three joints' axes, the origins of joints 1 and 2 and the tip's offset.
X = (1.0, 0.0, 0.0)
BASE_PITCH = -1.57079
FINGER_ORIGINS = {
    1: ((0.013836, 0.026467, 0.054269), 2.618),
    2: ((0.0138355526615453, 0.033321641905068, -0.0509719115789127), -2.61799387799149),
    3: ((0.0138355526615456, -0.05963321136, 0.00022432666062458), 1.5707963267949),
}
FINGER_AXES = {
    1: (
        (0, -0.0015509, -1),
        (-0.00794039679013064, 0.999967271990909, -0.00155082103229942),
        (0.00794039679012981, -0.999967271990909, 0.00155082103230192),
    ),
    2: (
        (0, -0.00155086992413278, -0.999998797400516),
        (-0.014343581886071, 0.999895923061994, -0.00155071037926452),
        (0.0143435818860688, -0.999895923061994, 0.0015507103792663),
    ),
    3: (
        (0, -0.00155086992413289, -0.999998797400516),
        (-0.0101468979551261, 0.99994731636822, -0.0015507900836953),
        (-0.010147, 0.99995, -0.0015508),
    ),
}
LINK_ORIGINS = {
    1: (
        (0.068497840506843, -0.00447059066166425, -0.00069480419720909),
        (0.0684925346596223, 0.000542552150630676, -0.000853424316918899),
    ),
    2: (
        (0.0684929530993347, 0.00359252558891102, -0.000174342974942968),
        (0.0684929345007509, 0.000982455622303688, -5.20041001613319e-05),
    ),
    3: ((0.0684964735450448, 0.000745917286560926, -0.000209448841640203), (0.068496, 0.00069546, 0.00025837)),
}
TIP_OFFSET = (0.084, 0.0, 0.0)


def unit(axis: tuple[float, ...]) -> np.ndarray:
    vector = np.asarray(axis, dtype=np.float64)
    unit_axis: np.ndarray = vector / np.linalg.norm(vector)
    return unit_axis


def tip_in_base(finger: int, q: np.ndarray) -> np.ndarray:
    """The fingertip's end (``link_fN_head``) in ``base`` (m) at the finger's 3 angles."""
    pose = transform(axis_rotation((0.0, 1.0, 0.0), BASE_PITCH), np.zeros(3))
    origin, roll = FINGER_ORIGINS[finger]
    pose = pose @ transform(axis_rotation(X, roll), np.array(origin))
    axes = FINGER_AXES[finger]
    pose = pose @ transform(axis_rotation(unit(axes[0]), float(q[0])), np.zeros(3))
    for offset, axis, angle in zip(LINK_ORIGINS[finger], axes[1:], q[1:], strict=True):
        pose = (
            pose
            @ transform(np.eye(3), np.array(offset))
            @ transform(axis_rotation(unit(axis), float(angle)), np.zeros(3))
        )
    tip: np.ndarray = (pose @ np.array([*TIP_OFFSET, 1.0]))[:3]
    return tip


@pytest.mark.parametrize("pose", ["keyframe", "closed", "random"])
def test_fingertips_match_the_urdf_chain(pose: str) -> None:
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    if pose == "keyframe":
        q = agent.keyframe_qpos("rest")
    elif pose == "closed":
        q = np.zeros(9)
        q[[JOINTS.index(j) for j in ACTION_JOINTS]] = CLOSED  # the part's order -> qpos
    else:
        low, high = scene.model.jnt_range.T  # the robot's 9 joints, nothing else in the scene
        q = np.random.default_rng(5).uniform(low, high)
    for finger in (1, 2, 3):
        joints = [JOINTS.index(f"joint_f{finger}_{k}") for k in range(3)]
        measured = agent.frame_pose(f"link_f{finger}_head", q, relative_to="root")[0, :3]
        np.testing.assert_allclose(measured, tip_in_base(finger, q[joints]), atol=1e-6)
    if pose == "keyframe":
        # the stretched fingers point straight down from the mount, their ends 0.2348 m below it
        for name in TIP_LINKS:
            tip = agent.frame_pose(name, q)[0, :3]
            assert tip[2] == pytest.approx(MOUNT[2] - 0.2348, abs=2e-4)
            assert 0.059 < np.hypot(tip[0], tip[1]) < 0.062
    scene.close()


def test_the_chain_check_can_fail() -> None:
    """A 1 mm change in one origin of the chain written here moves the tip 1 mm."""
    q = np.zeros(3)
    saved = dict(FINGER_ORIGINS)
    base = tip_in_base(3, q)
    FINGER_ORIGINS[3] = ((0.0148355526615456, -0.05963321136, 0.00022432666062458), 1.5707963267949)
    try:
        assert np.linalg.norm(tip_in_base(3, q) - base) == pytest.approx(0.001)
    finally:
        FINGER_ORIGINS.update(saved)


# ---------------------------------------------------------------- data
#: The URDF's masses (kg) and joint ranges (rad).
MASSES = {"base_link": 0.23695}
for f in (1, 2, 3):
    MASSES |= {f"link_f{f}_1": 0.0500997884944, f"link_f{f}_2": 0.0500997884944, f"link_f{f}_3": 0.0260028967}
RANGES = {"joint_f1_0": (-0.524, 1.32), "joint_f2_0": (-1.32, 0.524), "joint_f3_0": (-1.32, 0.524)}


def test_masses_ranges_and_order_match_the_sources() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    for body, mass in MASSES.items():
        assert model.body(f"{agent.prefix}{body}").mass[0] == pytest.approx(mass, abs=1e-9), body
    assert sum(MASSES.values()) == pytest.approx(0.6156, abs=1e-4)
    # the URDF's proximal link inertia (kg*m^2): its principal moments
    inertia = model.body(f"{agent.prefix}link_f1_1").inertia
    assert sorted(inertia) == pytest.approx(sorted([8.46910e-06, 1.16900e-05, 1.27968e-05]), rel=1e-3)
    assert agent.joint_names == JOINTS
    for name in JOINTS:
        expected = RANGES.get(name, (-1.57, 1.57))
        np.testing.assert_allclose(model.joint(f"{agent.prefix}{name}").range, expected, atol=1e-12)
    # ManiSkill's action order: the base joints, the middle joints, the distal joints
    assert agent.part_joints["hand"] == (
        "joint_f1_0", "joint_f2_0", "joint_f3_0", "joint_f1_1", "joint_f2_1", "joint_f3_1",
        "joint_f1_2", "joint_f2_2", "joint_f3_2",
    )  # fmt: skip
    assert TIP_LINKS == ("link_f1_head", "link_f2_head", "link_f3_head")
    scene.close()


def test_drives_are_maniskills_gains_within_the_servos_limits() -> None:
    scene = ra.Scene(UID)
    model = scene.model
    agent = scene.agents[0]
    kp = model.actuator_gainprm[: len(JOINTS), 0]
    assert np.all(kp == 100.0)  # ManiSkill's joint_stiffness
    forces = model.actuator_forcerange[: len(JOINTS)]
    np.testing.assert_allclose(forces, [[-XM430_W350.stall_torque, XM430_W350.stall_torque]] * len(JOINTS))
    dofs = [int(model.joint(f"{agent.prefix}{n}").dofadr[0]) for n in JOINTS]
    np.testing.assert_allclose(model.dof_armature[dofs], XM430_W350.armature)
    assert set(DClaw.modes()) >= {"pd_joint_delta_pos", "pd_joint_pos", "pd_joint_target_delta_pos"}
    assert DClaw.default_mode() == "pd_joint_delta_pos"
    scene.close()


def test_keyframe_holds_and_random_actions_stay_stable() -> None:
    held = check_holds(ra.get_agent(UID), seconds=2.0)
    assert held.passed, held.detail
    random = check_random_actions(ra.get_agent(UID), seconds=10.0)
    assert random.passed, random.detail


# ---------------------------------------------------------------- the pinch
CUBE_HALF = 0.5 * GRASP_CUBE_EDGE
CUBE_MASS = 0.064  # 4 cm of water
GRAVITY = 9.81


def cube_world(scene: ra.Scene) -> np.ndarray:
    """The declared grasp's cube centre in the world (m): below the mount, on its axis."""
    agent = scene.agents[0]
    base = agent.frame_pose("base_link")[0]
    rotation = np.empty(9)
    mujoco.mju_quat2Mat(rotation, base[3:])
    centre: np.ndarray = base[:3] + rotation.reshape(3, 3) @ np.array(POWER_GRASP.cube_centre)
    return centre


def pinch_scene() -> tuple[ra.Scene, int]:
    """The claw open, a 4 cm, 64 g cube floating (weight cancelled) where the pinch holds it."""
    cube = ra.Prop("cube", "box", (CUBE_HALF,) * 3, pos=(0.3, 0.0, CUBE_HALF), mass=CUBE_MASS)
    scene = ra.Scene(UID, props=[cube], control_modes="pd_joint_pos")
    scene.reset()
    model = scene.model
    joint = int(model.body("cube").jntadr[0])
    qpos_adr = np.arange(7) + int(model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(model.jnt_dofadr[joint])
    pose = np.array([[*cube_world(scene), 1.0, 0.0, 0.0, 0.0]])
    scene.world.write_joint_state([0], qpos_adr, pose, dof_adr, np.zeros((1, 6)))
    body = int(model.body("cube").id)
    scene.world.datas[0].xfrc_applied[body, :3] = (0.0, 0.0, CUBE_MASS * GRAVITY)
    return scene, body


def act(scene: ra.Scene, action: np.ndarray | tuple[float, ...], steps: int) -> None:
    for _ in range(steps):
        scene.agents[0].set_action(np.asarray(action, dtype=np.float64))
        scene.step()


def contact_forces_on(scene: ra.Scene, body: int) -> dict[str, np.ndarray]:
    """Total contact force (N, world) on ``body`` from each other body touching it."""
    model, data = scene.model, scene.world.datas[0]
    forces: dict[str, np.ndarray] = {}
    wrench = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        bodies = (int(model.geom_bodyid[contact.geom1]), int(model.geom_bodyid[contact.geom2]))
        if body not in bodies:
            continue
        mujoco.mj_contactForce(model, data, i, wrench)
        force = contact.frame.reshape(3, 3).T @ wrench[:3]  # on geom2, world axes
        other = bodies[0] if bodies[1] == body else bodies[1]
        name = model.body(other).name
        forces[name] = forces.get(name, np.zeros(3)) + (force if bodies[1] == body else -force)
    return forces


def test_three_fingertips_pinch_a_cube_and_their_forces_carry_its_weight() -> None:
    scene, body = pinch_scene()
    agent = scene.agents[0]
    act(scene, OPEN, 5)
    assert agent.is_gripper_open()[0]
    assert not agent.is_grasping("cube")[0]
    act(scene, CLOSED, 40)  # 2 s, the cube weightless
    assert agent.is_grasping("cube")[0]
    scene.world.datas[0].xfrc_applied[body, :3] = 0.0  # its weight on the fingertips
    start = scene.body_pose("cube")[0, :3].copy()
    act(scene, CLOSED, 40)
    moved = float(np.linalg.norm(scene.body_pose("cube")[0, :3] - start))
    assert moved < 0.002, f"the cube moved {moved * 1000:.2f} mm"
    assert agent.is_grasping("cube")[0]
    forces = contact_forces_on(scene, body)
    prefix = agent.prefix
    # only the three fingertips touch it, each pressing (over 5 N) ...
    assert set(forces) == {f"{prefix}link_f{f}_3" for f in (1, 2, 3)}
    assert all(np.linalg.norm(force) > 5.0 for force in forces.values())
    # ... and together they carry its weight, nothing more (at rest: 0.628 N up)
    total = sum(forces.values(), np.zeros(3))
    np.testing.assert_allclose(total, (0.0, 0.0, CUBE_MASS * GRAVITY), atol=1e-3)
    act(scene, OPEN, 20)  # opened, it falls out
    assert not agent.is_grasping("cube")[0]
    assert scene.body_pose("cube")[0, 2] < start[2] - 0.05
    scene.close()


def test_the_pinch_check_can_fail() -> None:
    """The claw left open: the cube, given its weight, falls (more than 5 cm in 1 s)."""
    scene, body = pinch_scene()
    act(scene, OPEN, 10)
    start = scene.body_pose("cube")[0, :3].copy()
    scene.world.datas[0].xfrc_applied[body, :3] = 0.0
    act(scene, OPEN, 20)
    assert not scene.agents[0].is_grasping("cube")[0]
    assert scene.body_pose("cube")[0, 2] < start[2] - 0.05
    scene.close()


# ---------------------------------------------------------------- the sweep's grasp claim
def test_the_sweeps_grasp_claim_holds_the_declared_pinch() -> None:
    """The time-step sweep's grasp claim for a hand: the declared 4 cm cube (water's
    density, 64 g) held against a 1 g pull away from the mount, at the default step."""
    claim = grasp_claim(DClaw, DClaw.sim_freq or 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert "not opposed" not in claim.detail


class _NeverCloses(DClaw):
    """The D'Claw whose pinch is its open pose: the fingers never close."""

    parts = (dataclasses.replace(DCLAW_HAND, closed=OPEN),)


def test_the_sweeps_grasp_claim_fails_when_the_claw_does_not_close() -> None:
    claim = grasp_claim(_NeverCloses, DClaw.sim_freq or 500, 20, Penetration())
    assert claim is not None and not claim.passed
    assert claim.value > 0.01 and "not opposed" in claim.detail
