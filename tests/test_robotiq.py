"""The Robotiq 2F-85 checked against numbers: the linkage against the public model's
joint origins (a parallel grip), the datasheet's stroke, grip force and closing speed,
one action driving the whole linkage, a grasp with the floating gripper, the floating
gripper's keyframes, and the piece mounted on another robot's flange."""

from __future__ import annotations

import math
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.kinematics import IKSolver, resolve_frame
from robot_agents.kinematics.rotations import rotation_error
from robot_agents.robots.robotiq.robotiq import Robotiq2F85, linkage_qpos
from robot_agents.tuning.claims import ClaimResult, Penetration, _random
from robot_agents.tuning.cycles import drive_cycle_bounds

# The right side's linkage in the base frame (y, z), from Menagerie's robotiq_2f85:
# driver hinge A, coupler on the driver at A + C_ON_DRIVER, spring link hinge B, the
# follower's origin (where the loop closes) at B + E_ON_SPRING. Pad faces 0.0189 +
# 0.0066 m inwards of the follower's origin; the base 0.0108 m above the coupling face.
A = np.array([0.0306011, 0.054904])
C_ON_DRIVER = np.array([0.0315, -0.0041])
B = np.array([0.0132, 0.0609])
E_ON_SPRING = np.array([0.055, 0.0375])
PAD_FACE_INWARD = 0.0189 + 0.0066
PAD_CENTRE = np.array([-0.0189 - 0.0026, 0.01352 + 0.01875])  # in the follower frame (y, z)
BASE_HEIGHT = 0.0108
# Datasheet: stroke 85 mm, grip force 20-235 N, closing speed 20-150 mm/s, 925 g.
STROKE, FORCE_RANGE, SPEED_RANGE, MASS = 0.085, (20.0, 235.0), (0.020, 0.150), 0.925


def rotate(v: np.ndarray, angle: float) -> np.ndarray:
    """Turn a (y, z) vector by ``angle`` about +x."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def follower_origin(driver: float) -> np.ndarray:
    """Where the right follower's origin is (y, z in the base frame) with the driver at
    ``driver`` (the hinge turns about +x, closing is positive)."""
    e0 = B + E_ON_SPRING
    return A + rotate(e0 - A, driver)


def action_for(driver: float) -> np.ndarray:
    """The normalized gripper action whose target is ``driver`` (-1: closed + 0.1 rad, +1: open)."""
    return np.array([1.0 - 2.0 * driver / 0.9])


def pad_faces(agent: ra.Agent, prefix: str = "") -> tuple[np.ndarray, np.ndarray]:
    """The inner face centres of the right and left pads in the base frame (m)."""
    faces = []
    for side in ("right", "left"):
        pose = agent.frame_pose(f"{prefix}{side}_pad", relative_to=f"{prefix}base")[0]
        rotation = np.zeros(9)
        mujoco.mju_quat2Mat(rotation, pose[3:])
        faces.append(pose[:3] + rotation.reshape(3, 3) @ [0.0, -0.0066, 0.01875])
    return faces[0], faces[1]


def pad_tilt(agent: ra.Agent, side: str) -> float:
    """Angle between a pad's z axis and the palm's (deg)."""
    quat = agent.frame_pose(f"{side}_pad", relative_to="base")[0, 3:]
    rotation = np.zeros(9)
    mujoco.mju_quat2Mat(rotation, quat)
    return math.degrees(math.acos(min(1.0, rotation[8])))


def loop_gap(scene: ra.Scene, agent: ra.Agent, side: str) -> float:
    """How far (m) the follower's origin is from its pin on the coupler."""
    data = scene.world.physics_sources([0])[0]
    coupler = scene.model.body(f"{agent.prefix}{side}_coupler").id
    follower = scene.model.body(f"{agent.prefix}{side}_follower").id
    pin = (B + E_ON_SPRING) - (A + C_ON_DRIVER)  # the pin in the coupler frame (y, z)
    world_pin = data.xpos[coupler] + data.xmat[coupler].reshape(3, 3) @ [0.0, pin[0], pin[1]]
    return float(np.linalg.norm(world_pin - data.xpos[follower]))


def settle(scene: ra.Scene, action: np.ndarray, steps: int) -> None:
    for _ in range(steps):
        scene.agents[0].set_action(action)
        scene.step()


def test_linkage_follows_the_public_geometry_with_parallel_pads_and_an_85_mm_stroke() -> None:
    scene = ra.Scene(Robotiq2F85)
    agent = scene.agents[0]
    scene.reset()
    gaps = []
    for target in np.linspace(0.0, 0.8, 10):
        settle(scene, action_for(0.9) if target == 0.8 else action_for(target), 8)
        driver = agent.qpos[0, 0]
        assert driver == pytest.approx(target, abs=0.01)
        right, left = pad_faces(agent)
        # The pad follows the four-bar of the cited joint origins, parallel to the palm.
        expected = follower_origin(driver) + np.array([-PAD_FACE_INWARD, PAD_CENTRE[1]])
        np.testing.assert_allclose(right[1:], expected, atol=2e-4)
        np.testing.assert_allclose(left[1:], [-expected[0], expected[1]], atol=2e-4)
        assert pad_tilt(agent, "right") < 2.0 and pad_tilt(agent, "left") < 2.0
        gaps.append(right[1] - left[1])
    assert gaps[0] == pytest.approx(0.0854, abs=2e-4)  # the pads' faces, fully open
    assert gaps[0] - gaps[-1] == pytest.approx(STROKE, abs=0.002)
    assert 0.0 < gaps[-1] < 0.001  # closed: the joint limits stop the pads just short of each other
    assert np.all(np.diff(gaps) < 0)
    scene.close()


def test_one_action_drives_the_whole_linkage() -> None:
    scene = ra.Scene(Robotiq2F85)
    agent = scene.agents[0]
    model = scene.model
    # Two actuators, on the drivers; the spring links and followers are passive.
    driven = {model.joint(int(model.actuator_trnid[a, 0])).name[len(agent.prefix) :] for a in range(model.nu)}
    assert driven == {"right_driver_joint", "left_driver_joint"}
    assert agent.single_action_space.shape == (1,)
    scene.reset()
    settle(scene, action_for(0.45), 10)
    q = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    for side in ("right", "left"):
        assert q[f"{side}_driver_joint"] == pytest.approx(0.45, abs=0.01)
        # the parallelogram: the spring link turns with the driver, the follower back
        assert q[f"{side}_spring_link_joint"] == pytest.approx(q[f"{side}_driver_joint"], abs=1e-3)
        assert q[f"{side}_follower_joint"] == pytest.approx(-q[f"{side}_driver_joint"], abs=1e-3)
        assert loop_gap(scene, agent, side) < 2e-5
    assert agent.gripper_opening()[0] == pytest.approx(0.4375, abs=0.02)
    scene.close()


def test_closing_speed_matches_the_datasheet() -> None:
    scene = ra.Scene(Robotiq2F85)
    agent = scene.agents[0]
    scene.reset()
    gaps = [float(np.subtract(*pad_faces(agent))[1])]
    for _ in range(16):  # 0.8 s
        settle(scene, np.array([-1.0]), 1)
        gaps.append(float(np.subtract(*pad_faces(agent))[1]))
    speeds = -np.diff(gaps) * scene.control_freq  # m/s, averaged over each 50 ms step
    assert np.max(speeds) <= SPEED_RANGE[1] * 1.01
    assert np.max(speeds) >= 0.9 * SPEED_RANGE[1]  # the full speed setting
    closed_at = next(i for i, gap in enumerate(gaps) if gap < 0.001) / scene.control_freq
    assert STROKE / SPEED_RANGE[1] < closed_at < 0.8  # a full stroke in ~0.6 s
    scene.close()


def test_floating_gripper_grasps_lifts_and_holds_a_cube() -> None:
    """A 4 cm, 150 g cube on the floor, grasped from above: grip force within the
    datasheet's range, the weight carried by the pads, held for 2 s 10 cm up."""
    cube = ra.Prop(name="cube", shape="box", size=(0.02,) * 3, pos=(0.0, 0.0, 0.0201), mass=0.15)
    scene = ra.Scene("floating_robotiq_2f_85_gripper", props=[cube], control_modes="pd_joint_pos")
    agent = scene.agents[0]
    scene.reset(keyframes="open_facing_down")
    mount = agent.keyframe_qpos("open_facing_down")[:6]
    above = mount.copy()
    above[2] += 0.035 - agent.tcp_pose[0, 2]  # the TCP 3.5 cm up: the open fingertips clear the floor
    for i in range(20):
        settle(scene, np.r_[mount + min(1.0, (i + 1) / 10) * (above - mount), 1.0], 1)
    assert not agent.is_grasping("cube")[0]
    settle(scene, np.r_[above, -1.0], 20)
    assert agent.is_grasping("cube")[0]

    body = lambda name: mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_BODY, name)  # noqa: E731
    fingers = [[body(f"{agent.prefix}{side}_{link}") for link in ("follower", "pad")] for side in ("right", "left")]
    lifted = above.copy()
    lifted[2] += 0.1
    cube_z0 = scene.body_pose("cube")[0, 2]
    for i in range(60):  # lift over 1 s, hold 2 s
        settle(scene, np.r_[above + min(1.0, (i + 1) / 20) * (lifted - above), -1.0], 1)
        if i >= 20:
            assert agent.is_grasping("cube")[0]
    assert scene.body_pose("cube")[0, 2] - cube_z0 > 0.095
    right, left = scene.world.contact_forces(fingers, body("cube"))[0]
    for force in (right, left):
        assert FORCE_RANGE[0] < abs(force[1]) < FORCE_RANGE[1]  # squeezing along the closing axis
    assert abs(right[1] + left[1]) < 0.5
    np.testing.assert_allclose((right + left)[2], 0.15 * 9.81, rtol=0.05)  # the pads carry the weight
    assert max(loop_gap(scene, agent, side) for side in ("right", "left")) < 5e-5  # under ~110 N
    settle(scene, np.r_[lifted, 1.0], 10)
    assert not agent.is_grasping("cube")[0]
    scene.close()


@pytest.mark.parametrize(
    ("keyframe", "rotation"),
    [
        ("open_facing_down", np.diag([1.0, -1.0, -1.0])),  # half a turn about x
        ("open_facing_up", np.eye(3)),
        ("open_facing_side", np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])),  # pi/2 about y
    ],
)
def test_keyframes_face_down_up_and_side(keyframe: str, rotation: np.ndarray) -> None:
    scene = ra.Scene("floating_robotiq_2f_85_gripper")
    agent = scene.agents[0]
    scene.reset(keyframes=keyframe)
    tcp = agent.tcp_pose[0]
    measured = np.zeros(9)
    mujoco.mju_quat2Mat(measured, tcp[3:])
    np.testing.assert_allclose(measured.reshape(3, 3), rotation, atol=1e-9)
    # The TCP lies 0.1553 m along the approach (the rotation's z column) from the mount at 0.5 m.
    np.testing.assert_allclose(tcp[:3], [0.0, 0.0, 0.5] + 0.1553 * rotation[:, 2], atol=2e-4)
    scene.close()


def axis_rotation(axis: int, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    i, j = (axis + 1) % 3, (axis + 2) % 3
    out = np.eye(3)
    out[i, i], out[i, j], out[j, i], out[j, j] = c, -s, s, c
    return out


def test_floating_mount_kinematics_and_ik() -> None:
    """FK at 20 random mount configurations against the chain written out (slides, then
    hinges about x, y, z, then the gripper turned -pi/2 about x and its TCP 0.1553 m
    out); IK reaches 100 random reachable TCP poses within 1 mm / 1 deg."""
    scene = ra.Scene("floating_robotiq_2f_85_gripper")
    agent = scene.agents[0]
    scene.reset()
    rng = np.random.default_rng(0)
    limits = agent.qpos_limits[:6]
    for _ in range(20):
        q = agent.keyframe_qpos("open_facing_down")
        q[:6] = rng.uniform(limits[:, 0], limits[:, 1])
        agent.reset(qpos=q)
        rotation = (
            axis_rotation(0, q[3]) @ axis_rotation(1, q[4]) @ axis_rotation(2, q[5]) @ axis_rotation(0, -math.pi / 2)
        )
        tcp = agent.tcp_pose[0]
        np.testing.assert_allclose(tcp[:3], [q[0], q[1], 0.5 + q[2]] + 0.1553 * rotation[:, 2], atol=2e-4)
        measured = np.zeros(9)
        mujoco.mju_quat2Mat(measured, tcp[3:])
        np.testing.assert_allclose(measured.reshape(3, 3), rotation, atol=1e-9)
    mount = np.arange(6)
    frame = resolve_frame(scene.model, "robotiq_tcp", agent.prefix)
    solver = IKSolver(agent.kinematics, frame, agent.qpos_adr[mount], agent.dof_adr[mount], limits)
    scene.reset(keyframes="open_facing_down")
    context = np.repeat(scene.world.qpos, 100, axis=0)
    goals = context.copy()
    goals[:, agent.qpos_adr[mount]] = rng.uniform(0.9 * limits[:, 0], 0.9 * limits[:, 1], (100, 6))
    targets = agent.kinematics.pose(goals, solver.frame)
    seed = np.repeat(agent.qpos[:, :6], 100, axis=0)
    result = solver.solve(context, targets, seed, max_iterations=100, restarts=20)
    assert result.success.all(), np.flatnonzero(~result.success)
    goals[:, agent.qpos_adr[mount]] = result.qpos
    reached = agent.kinematics.pose(goals, solver.frame)
    assert np.max(np.linalg.norm(reached[:, :3] - targets[:, :3], axis=1)) < 1e-3
    assert np.max(np.linalg.norm(rotation_error(reached[:, 3:], targets[:, 3:]), axis=1)) < math.radians(1)
    scene.close()


FLANGE_MJCF = """
<mujoco>
  <compiler angle="radian"/>
  <worldbody>
    <body name="link" pos="0 0 0.4">
      <joint name="wrist" axis="0 0 1" range="-3 3"/>
      <geom type="cylinder" size="0.04 0.05" mass="1"/>
      <body name="flange" pos="0 0 -0.06" quat="0 1 0 0"/>
    </body>
  </worldbody>
</mujoco>
"""


def test_the_piece_mounts_on_a_flange(tmp_path: Path) -> None:
    """Another robot mounts the gripper at its flange (with a prefix), points its arm's
    end effector at the gripper's TCP and closes it in a keyframe by naming the linkage."""
    path = tmp_path / "wrist.xml"
    path.write_text(FLANGE_MJCF)

    class Wrist(ra.Agent):
        mjcf_path = path
        actuators = (ra.PDActuator(joints="wrist", stiffness=50.0, damping=5.0),)
        attachments = (
            ra.Attachment(Robotiq2F85, at="flange", prefix="rq/", quat=(math.sqrt(0.5), 0, 0, math.sqrt(0.5))),
        )
        parts = (ra.Arm(name="arm", joints="wrist", end_effectors=(ra.EndEffector("rq/robotiq_tcp", name="tcp"),)),)
        keyframes = {
            "home": ra.Keyframe(qpos={"wrist": 0.3}),
            "closed": ra.Keyframe(qpos={"wrist": 0.3, **linkage_qpos(0.8, prefix="rq/")}),
        }

    scene = ra.Scene(Wrist)
    agent = scene.agents[0]
    assert set(agent.part_joints) == {"arm", "rq_gripper"}
    assert agent.controller.slices == {"arm": slice(0, 1), "rq_gripper": slice(1, 2)}
    model = scene.model
    robotiq = [b for b in range(model.nbody) if model.body(b).name.startswith(f"{agent.prefix}rq/")]
    assert sum(model.body_mass[b] for b in robotiq) == pytest.approx(MASS, abs=1e-4)
    flange = model.body(f"{agent.prefix}flange").id
    for keyframe, driver, gap in (("home", 0.0, 0.0854), ("closed", 0.8, 0.0002)):
        scene.reset(keyframes=keyframe)
        np.testing.assert_allclose(agent.qpos[0, 1:], [driver, driver, -driver] * 2, atol=1e-12)
        assert max(loop_gap(scene, agent, side) for side in ("rq/right", "rq/left")) < 1e-6
        assert scene.world.datas[0].ncon == 0
        right, left = pad_faces(agent, prefix="rq/")
        assert right[1] - left[1] == pytest.approx(gap, abs=2e-4)
        data = scene.world.physics_sources([0])[0]
        approach = data.xmat[flange].reshape(3, 3)[:, 2]
        np.testing.assert_allclose(agent.tcp_pose[0, :3], data.xpos[flange] + 0.1553 * approach, atol=2e-4)
    scene.close()


def settle_claim_at_200_hz(cls: type[ra.Agent]) -> ClaimResult:
    """The sweep's settle claim at 200 Hz with the random-action seeds that left the
    former mount's hinges cycling (1 and 2, in ``pd_joint_vel``)."""
    return next(r for r in _random(cls, 200, 20, (1, 2), Penetration()) if r.name == "settle")


def test_the_mounts_hinges_cannot_cycle_at_the_default_step(tmp_path: Path) -> None:
    """The mount's hinges (100 N*m, kv 100) carry 0.3 kg*m^2 of armature so that no
    torque-limit cycle exists at the robot's 200 Hz (docs/timestep.md, "The 2F-85 mount's
    armature"): they settle after random actions, where with the former 0.1 kg*m^2 a
    hinge was left flipping between its limits every step."""
    robot = ra.get_agent("floating_robotiq_2f_85_gripper")
    assert robot.sim_freq == 200
    hinges = [b for b in drive_cycle_bounds(robot) if b.joint.endswith("_rot_joint")]
    assert len(hinges) == 3
    for bound in hinges:
        assert bound.inertia == pytest.approx(0.3, abs=0.01)  # armature + the gripper's own
        assert bound.cycle_free_above < robot.sim_freq
    settle = settle_claim_at_200_hz(robot)
    assert settle.passed, settle

    source = Path(robot.mjcf_path).read_text()
    assert source.count('type="hinge" armature="0.3"') == 3
    former_file = tmp_path / "floating_mount.xml"
    former_file.write_text(source.replace('type="hinge" armature="0.3"', 'type="hinge" armature="0.1"'))

    class FormerMount(robot):  # type: ignore[valid-type,misc]
        uid = ""
        mjcf_path = former_file

    former = settle_claim_at_200_hz(FormerMount)
    assert not former.passed and former.value > 1.0 and "_rot_joint" in former.detail, former
