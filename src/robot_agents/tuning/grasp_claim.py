"""The grasp claim of the time-step sweep (:mod:`.claims`): a robot with a two-finger
gripper closes it on a cube of the table-top tasks' size, lifts it and holds it; the
claim is the cube's largest movement relative to the tool frame over the hold. A hand
that declares its power grasp (:class:`~robot_agents.parts.declaration.PowerGrasp`)
closes on the declared cube instead, and the cube is pulled away from the palm (its
movement relative to the palm counts)."""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from robot_agents.agent import Agent
from robot_agents.checks import hold_action, raw_hold, standing_leg_joints
from robot_agents.controllers.ee import PDEEController
from robot_agents.controllers.joint import PDJointPosController
from robot_agents.errors import ConfigError
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.parts.declaration import Hand, is_jaw_gripper
from robot_agents.sim.scene import Scene
from robot_agents.tuning.claims import ClaimResult, Penetration, claim_scene, ee_mode

#: Grasp claim: seconds the fingers close on the weightless cube, the lift (in cube
#: edges, over seconds) and the hold after it.
CLOSE_SECONDS = 1.0
LIFT_EDGES = 2.0
LIFT_SECONDS = 1.0
GRASP_HOLD_SECONDS = 2.0
#: Largest movement of the grasped cube relative to the tool frame over the hold (m).
SLIP_BOUND = 0.002
#: How far towards the wrist from the grasp point the cube's centre sits, in cube
#: edges, tried in order until the cube holds: first the scripted PickCube solver's
#: grasp depth (the fingers reach past its middle), then deeper (a jaw whose grasp
#: point lies near its tips, the Koch's, holds the cube only deeper in).
GRASP_DEPTHS = (0.2, 0.4, 0.6)
#: A finger that travels less than this share of the other's when the gripper closes
#: counts as fixed (the SO-100's and Koch's jaws).
FIXED_FINGER_SHARE = 0.25
#: Hands: seconds the fingers close on the weightless cube (a hand's fingers travel
#: further than a gripper's jaws), and the pull away from the palm over the hold, in
#: units of the cube's weight (its weight cancelled and this much again: 1 g net, as if
#: the palm were turned down).
HAND_CLOSE_SECONDS = 2.0
HAND_PULL = 1.0
#: The mode a hand's grasp runs in: absolute joint targets (the ``closed`` pose).
HAND_MODE = "pd_joint_pos"


def grasp_claim(cls: type[Agent], sim_freq: int, control_freq: int, depth: Penetration) -> ClaimResult | None:
    """Close the gripper on a weightless cube between its open fingers, give the cube its
    weight, lift it and hold it (see the module doc); the cube's largest movement
    relative to the tool frame over the hold, at the first of :data:`GRASP_DEPTHS` where
    it holds (else the least). ``None``: the robot has no gripper with two fingers (or
    no end effector)."""
    from robot_agents.envs.tasks.layout import table_top_layout

    hand = next((p for p in cls.check().parts if isinstance(p, Hand) and p.power_grasp is not None), None)
    if hand is not None:
        return _hand_grasp(cls, hand, sim_freq, control_freq, depth)
    mode = ee_mode(cls)
    # a hand without a declared power grasp makes no grasp claim (a file's derived hand)
    grippers = [p for p in cls.check().parts if is_jaw_gripper(p) and p.finger_links]
    if mode is None or not grippers:
        return None
    if table_top_layout(cls).gripper is None:
        return None
    attempts: list[tuple[float, str, Penetration]] = []
    for edges in GRASP_DEPTHS:
        held = Penetration()
        attempts.append((*_grasp_at(cls, sim_freq, control_freq, mode, edges, held), held))
        if attempts[-1][0] <= SLIP_BOUND:
            break
    slip, detail, held = min(attempts, key=lambda attempt: attempt[0])
    if held.depth > depth.depth:
        depth.depth, depth.where = held.depth, held.where
    return ClaimResult("grasp", slip <= SLIP_BOUND, slip, SLIP_BOUND, detail)


def _grasp_at(
    cls: type[Agent], sim_freq: int, control_freq: int, mode: str, edges: float, depth: Penetration
) -> tuple[float, str]:
    """One grasp with the cube's centre ``edges`` cube edges from the grasp point towards
    the wrist: the slip over the hold (m) and a description."""
    from robot_agents.envs.tasks.layout import table_top_layout, tool_arm
    from robot_agents.envs.tasks.table_top import cube_prop

    layout = table_top_layout(cls)
    geometry = layout.gripper
    if geometry is None:
        raise ConfigError(f"sweep_timestep: {cls.__name__}'s gripper geometry could not be measured.")
    cube = cube_prop("sweep_cube", layout, (0.8, 0.2, 0.2, 1.0))
    scene = claim_scene(cls, sim_freq, control_freq, mode, props=[cube], floor=False)
    scene.reset()
    agent = scene.agents[0]
    gripper = agent.gripper()
    names = agent.part_joints[gripper.name]
    opened, shut = gripper.positions(len(names))
    qpos = _with_joints(agent, agent.qpos[0], names, opened)
    agent.reset(qpos=qpos)
    ee = tool_arm(agent, "sweep_timestep").end_effectors[0].name

    # The cube between the open fingers, faces square to the closing axis: in the
    # middle of the gap, or 1 mm off a finger that does not move (a jaw against a fixed
    # finger would push a weightless cube out otherwise).
    approach, closing = np.array(geometry.approach_axis), np.array(geometry.closing_axis)
    edge = 2.0 * layout.cube_half_size
    centre = np.array(geometry.grasp_point) - edges * edge * approach
    closed_q = _with_joints(agent, qpos, names, shut)
    travel = []  # how far each finger's first link moves as the gripper closes (turns x the opening)
    for finger in gripper.finger_links[:2]:
        before, after = agent.frame_pose(finger[0], qpos, ee)[0], agent.frame_pose(finger[0], closed_q, ee)[0]
        turn = 2.0 * np.arccos(min(1.0, abs(float(before[3:] @ after[3:]))))
        travel.append(float(np.linalg.norm(after[:3] - before[:3])) + turn * geometry.opening)
    if min(travel) < FIXED_FINGER_SHARE * max(travel):
        side = -1.0 if travel[0] < travel[1] else 1.0  # towards the fixed finger
        centre += side * (0.5 * geometry.opening - 0.5 * edge - 0.001) * closing
    tool = agent.frame_pose(ee)[0]
    rotation = quat_to_matrix(tool[3:])
    axes = rotation @ np.stack([approach, closing, np.cross(approach, closing)], axis=1)
    body, _ = _place_weightless_cube(scene, tool[:3] + rotation @ centre, axes)
    data = scene.world.datas[0]

    # The gripper's slice of the action: fully closed (-1 in every gripper's action: its
    # command past ``closed``, whichever way the joints close).
    slot, close = None, None
    for part_name, controller in agent.controller.parts.items():
        if set(names) & set(controller.config.joint_names):
            slot, close = agent.controller.slices[part_name], controller.from_raw(controller.unit_low)
    ee_controller = next(c for c in agent.controller.parts.values() if isinstance(c, PDEEController))
    ee_slot = next(agent.controller.slices[n] for n, c in agent.controller.parts.items() if c is ee_controller)

    impact = Penetration()  # the fingers' impact on the cube while closing: not judged

    def act(lift: float = 0.0, measured: Penetration = impact) -> None:
        action = hold_action(agent)
        if lift:
            raw = raw_hold(ee_controller, action[ee_slot])
            raw[2] += lift
            action[ee_slot] = ee_controller.from_raw(raw)
        if slot is not None and close is not None:
            action[slot] = close
        agent.set_action(action)
        scene.step()
        measured.measure(scene)

    def in_tool() -> np.ndarray:
        tool = agent.frame_pose(ee)[0]
        return np.asarray(quat_to_matrix(tool[3:]).T @ (scene.body_pose("sweep_cube")[0, :3] - tool[:3]))

    for _ in range(round(CLOSE_SECONDS * control_freq)):  # weightless while the fingers close
        act()
    data.xfrc_applied[body, :3] = 0.0
    lift_steps = round(LIFT_SECONDS * control_freq)
    for _ in range(lift_steps):
        act(LIFT_EDGES * edge / lift_steps)
    start = in_tool()
    slip = 0.0
    for _ in range(round(GRASP_HOLD_SECONDS * control_freq)):
        act(measured=depth)
        slip = max(slip, float(np.linalg.norm(in_tool() - start)))
    # (Held in the air under its weight, a cube that moved less than the bound is held;
    # whether the finger forces also pass ``is_grasping``'s opposing-force test is reported.)
    opposed = bool(agent.is_grasping("sweep_cube")[0])
    scene.close()
    detail = f"{edge * 1000:.1f} mm cube {edges:g} edge in, {mode}" + ("" if opposed else ", finger forces not opposed")
    if slip > edge:  # farther than its own edge: the cube has left the grasp (however far it fell)
        slip, detail = edge, detail + ", cube lost"
    return slip, detail


def _hand_grasp(
    cls: type[Agent], hand: Hand, sim_freq: int, control_freq: int, depth: Penetration
) -> ClaimResult | None:
    """A hand's grasp claim (module doc): the declared cube, weightless, between the open
    fingers; the hand closes to ``closed``; then the cube's weight is cancelled and
    :data:`HAND_PULL` times it pulls the cube along the palm's outward direction for
    :data:`GRASP_HOLD_SECONDS`. The cube's largest movement relative to the palm link
    over that hold. ``None``: the robot has no :data:`HAND_MODE`."""
    from robot_agents.envs.tasks.table_top import free_cube

    grasp = hand.power_grasp
    if grasp is None or HAND_MODE not in cls.modes():
        return None
    cube = free_cube("sweep_cube", 0.5 * grasp.cube_edge, (0.8, 0.2, 0.2, 1.0))
    # a robot whose legs carry it stands on the floor (without one it would fall with the hand)
    scene = claim_scene(cls, sim_freq, control_freq, HAND_MODE, props=[cube], floor=bool(standing_leg_joints(cls)))
    scene.reset()
    agent = scene.agents[0]
    names = agent.part_joints[hand.name]
    opened, shut = hand.positions(len(names))
    closed = dict(zip(names, shut, strict=True))
    agent.reset(qpos=_with_joints(agent, agent.qpos[0], names, opened))

    # The hand's slice of the action: its ``closed`` pose; every other part holds. A hand
    # that takes deltas in this mode (a hand riding on an arm) is given, at every step,
    # the change from its targets (or measured pose) to ``closed``, clipped to its bounds.
    hold = hold_action(agent)
    stepped: list[tuple[str, PDJointPosController]] = []
    for part_name, controller in agent.controller.parts.items():
        joints = controller.config.joint_names
        if set(joints) & set(names):
            raw = np.array([closed.get(j, agent.qpos[0, agent.joint_names.index(j)]) for j in joints])
            if isinstance(controller, PDJointPosController) and controller.config.use_delta:
                stepped.append((part_name, controller))
                continue
            hold[agent.controller.slices[part_name]] = controller.from_raw(raw[: controller.action_dim])

    def closing() -> np.ndarray:
        """The action that moves the hand's targets to ``closed``."""
        if not stepped:
            return hold
        action: np.ndarray = hold.copy()
        for part_name, controller in stepped:
            joints = controller.config.joint_names
            goal = np.array([closed[j] for j in joints])
            base = (
                controller.target_qpos[0]
                if controller.config.use_target
                else agent.qpos[0, [agent.joint_names.index(j) for j in joints]]
            )
            action[agent.controller.slices[part_name]] = controller.from_raw(goal - base)
        return action

    def palm() -> tuple[np.ndarray, np.ndarray]:
        pose = agent.frame_pose(grasp.link)[0]
        return pose[:3], quat_to_matrix(pose[3:])

    origin, rotation = palm()
    body, weight = _place_weightless_cube(scene, origin + rotation @ np.array(grasp.cube_centre), rotation)
    data = scene.world.datas[0]

    def in_palm() -> np.ndarray:
        origin, rotation = palm()
        return np.asarray(rotation.T @ (scene.body_pose("sweep_cube")[0, :3] - origin))

    for _ in range(round(HAND_CLOSE_SECONDS * control_freq)):  # weightless while the fingers close
        agent.set_action(closing())
        scene.step()
    start = in_palm()
    pull = HAND_PULL * float(np.linalg.norm(weight)) * np.array(grasp.outward)  # in the palm's axes
    slip = 0.0
    for _ in range(round(GRASP_HOLD_SECONDS * control_freq)):
        _, rotation = palm()  # (a hand on an arm: the palm may turn)
        data.xfrc_applied[body, :3] = weight + rotation @ pull
        agent.set_action(closing())
        scene.step()
        depth.measure(scene)
        slip = max(slip, float(np.linalg.norm(in_palm() - start)))
    opposed = bool(agent.is_grasping("sweep_cube")[0])
    scene.close()
    detail = f"{grasp.cube_edge * 1000:.1f} mm cube in the palm, {HAND_PULL:g} g pull away from it, {HAND_MODE}"
    detail += "" if opposed else ", finger forces not opposed"
    if slip > grasp.cube_edge:
        slip, detail = grasp.cube_edge, detail + ", cube lost"
    return ClaimResult("grasp", slip <= SLIP_BOUND, slip, SLIP_BOUND, detail)


def _place_weightless_cube(scene: Scene, position: np.ndarray, axes: np.ndarray) -> tuple[int, np.ndarray]:
    """Put the claim's cube (``sweep_cube``) at rest at ``position`` (world, m) with its
    faces along the columns of ``axes`` (a rotation matrix), its weight cancelled by an
    applied force; its body id and its weight (N, world axes)."""
    quat = np.empty(4)
    mujoco.mju_mat2Quat(quat, np.ascontiguousarray(axes).reshape(-1))
    body = scene.model.body("sweep_cube")
    joint = int(body.jntadr[0])
    qpos_adr = np.arange(7) + int(scene.model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(scene.model.jnt_dofadr[joint])
    pose = np.concatenate([position, quat])[None]
    scene.world.write_joint_state([0], qpos_adr, pose, dof_adr, np.zeros((1, 6)))
    weight: np.ndarray = -float(scene.model.body_subtreemass[body.id]) * scene.model.opt.gravity
    scene.world.datas[0].xfrc_applied[body.id, :3] = weight
    return int(body.id), weight


def _with_joints(agent: Agent, qpos: np.ndarray, names: Sequence[str], values: np.ndarray) -> np.ndarray:
    """A copy of the robot's ``qpos`` ``(nq,)`` with the joints ``names`` at ``values``."""
    out: np.ndarray = qpos.copy()
    for name, value in zip(names, values, strict=True):
        out[agent.joint_names.index(name)] = value
    return out
