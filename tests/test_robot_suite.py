"""One suite for every registered robot and every control mode."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.agent import Agent
from robot_agents.controllers import PDEEController
from robot_agents.kinematics.rotations import quat_to_rotvec

ROBOTS = ra.list_agents()
CASES = [(uid, mode) for uid in ROBOTS for mode in ra.get_agent(uid).control_modes]


def hold_action(agent: Agent) -> np.ndarray:
    """The action that asks the robot to stay where it is, in any mode."""
    parts = []
    for controller in agent.controller.parts.values():
        cfg = controller.config
        if isinstance(cfg, ra.PDJointPosConfig) and not cfg.use_delta:
            index = [agent.joint_names.index(j) for j in cfg.joint_names][: controller.action_dim]
            raw = agent.qpos[0, index]
            if isinstance(controller, ra.controllers.joint.PDJointPosVelController):
                raw = np.concatenate([raw, np.zeros(len(index))])
        elif isinstance(controller, PDEEController) and not cfg.use_delta:
            pose = controller.target_pose[0]  # the measured tool pose (root frame) since the reset
            rotation = pose[3:] if controller.quaternion_input else quat_to_rotvec(pose[3:])
            raw = np.concatenate([pose[:3], rotation]) if controller.rotation else pose[:3]
        else:
            raw = np.zeros(controller.action_dim)  # zero delta / zero velocity (symmetric bounds)
        if cfg.normalize_action and isinstance(cfg, ra.PDJointPosConfig) and not cfg.use_delta:
            raw = 2 * (raw - controller.raw_low) / (controller.raw_high - controller.raw_low) - 1
        parts.append(raw)
    return np.concatenate(parts) if parts else np.zeros(0)


def assert_stable(scene: ra.Scene) -> None:
    """MuJoCo resets an env that blows up (and only warns), so NaN checks are not enough."""
    assert not np.any(scene.world.instability_counts()), "MuJoCo found NaN/inf/huge values and reset an env"


@pytest.fixture(scope="module", params=ROBOTS)
def scene(request: pytest.FixtureRequest) -> ra.Scene:
    scene = ra.Scene(request.param, num_envs=2)
    yield scene
    scene.close()


def test_loads_with_consistent_model(scene: ra.Scene) -> None:
    agent = scene.agents[0]
    cls = type(agent)
    assert agent.dof == len(agent.joint_names) > 0
    assert agent.qpos.shape == (2, agent.dof)
    assert agent.qvel.shape == (2, agent.dof)
    robot_bodies = [b for b in range(scene.model.nbody) if scene.model.body(b).name.startswith(agent.prefix)]
    assert all(scene.model.body_mass[b] > 0 for b in robot_bodies if scene.model.body_jntnum[b] > 0)
    gravcomp = scene.model.body_gravcomp[robot_bodies]
    assert np.all(gravcomp == (1.0 if cls.fix_root_link else 0.0))
    for joint in cls.controlled_joints():
        assert joint in agent.joint_names


def test_keyframes_within_limits(scene: ra.Scene) -> None:
    agent = scene.agents[0]
    assert agent.keyframes, "every built-in robot declares at least one keyframe"
    for name, frame in agent.keyframes.items():
        qpos = frame.qpos_array()
        assert qpos.shape == (agent.dof,), name
        assert np.all(qpos >= agent.qpos_limits[:, 0]) and np.all(qpos <= agent.qpos_limits[:, 1]), name


def test_keyframe_pose_has_no_contacts(scene: ra.Scene) -> None:
    """At every keyframe the robot touches nothing (no self-collision, no floor)."""
    agent = scene.agents[0]
    for name in agent.keyframes:
        scene.reset(keyframes=name)
        data = scene.world.datas[0]
        assert data.ncon == 0, (
            f"{name}: {[(scene.model.geom(c.geom1).name, scene.model.geom(c.geom2).name) for c in data.contact]}"
        )


@pytest.mark.parametrize(("uid", "mode"), CASES)
def test_every_mode(uid: str, mode: str) -> None:
    """Action space matches the controller; random actions keep the state finite;
    the hold action keeps the robot at its keyframe; the same actions replay bit-identically."""
    scene = ra.Scene(uid, num_envs=2, control_modes=mode)
    agent = scene.agents[0]
    space = agent.action_space
    dim = sum(c.action_dim for c in agent.controller.parts.values())
    assert space.shape == (2, dim) and agent.single_action_space.shape == (dim,)
    assert space.dtype == np.float32
    for part, controller in agent.controller.parts.items():
        sl = agent.controller.slices[part]
        if controller.config.normalize_action:
            assert np.all(space.low[:, sl] == -1) and np.all(space.high[:, sl] == 1)
        else:
            np.testing.assert_allclose(space.low[0, sl], controller.raw_low.astype(np.float32))

    # Hold: the robot stays at its rest keyframe for 1 s (5 s for the default mode: see below).
    scene.reset()
    start = agent.qpos
    for _ in range(scene.control_freq):
        agent.set_action(hold_action(agent))
        scene.step()
    assert np.max(np.abs(agent.qpos - start)) < 0.01

    # Random actions: finite, deterministic.
    # Random actions over the whole space (absolute targets anywhere within the joint
    # limits): finite, stable, deterministic.
    rng = np.random.default_rng(0)
    actions = [rng.uniform(space.low, space.high).astype(np.float32) for _ in range(20)]
    trajectories = []
    for _ in range(2):
        scene.reset()
        states = []
        for action in actions:
            agent.set_action(action)
            scene.step()
            states.append(scene.world.get_state())
        trajectories.append(np.stack(states))
    assert np.all(np.isfinite(trajectories[0]))
    assert_stable(scene)
    assert np.array_equal(trajectories[0], trajectories[1])
    scene.close()


@pytest.mark.parametrize("uid", ROBOTS)
def test_default_mode_holds_keyframe_for_five_seconds(uid: str) -> None:
    scene = ra.Scene(uid)
    agent = scene.agents[0]
    scene.reset()
    start = agent.qpos
    worst = 0.0
    for _ in range(5 * scene.control_freq):
        agent.set_action(hold_action(agent))
        scene.step()
        worst = max(worst, float(np.max(np.abs(agent.qpos - start))))
    assert worst < 0.01, f"{uid} drifted {worst:.4f} rad/m from its rest keyframe"
    assert np.all(agent.is_static())
    scene.close()
