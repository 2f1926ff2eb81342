"""One suite for every registered robot and every control mode."""

from __future__ import annotations

import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import LOAD_SETTLE_SECONDS, hold_drift, keeps_targets, standing_leg_joints
from robot_agents.controllers.base import ControllerConfig
from robot_agents.controllers.joint import UNBOUNDED_TARGET

ROBOTS = ra.list_agents()
CASES = [(uid, mode) for uid in ROBOTS for mode in ra.get_agent(uid).modes()]


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
    model = scene.model
    joints = [j for j in range(model.njnt) if model.joint(j).name.startswith(agent.prefix)]
    moving = [j for j in joints if model.jnt_type[j] != 0]  # a free root is the base pose
    sizes = {1: (4, 3), 2: (1, 1), 3: (1, 1)}
    assert agent.qpos.shape == (2, sum(sizes[int(model.jnt_type[j])][0] for j in moving))
    assert agent.qvel.shape == (2, sum(sizes[int(model.jnt_type[j])][1] for j in moving))
    robot_bodies = [b for b in range(model.nbody) if model.body(b).name.startswith(agent.prefix)]
    assert all(model.body_mass[b] > 0 for b in robot_bodies if model.body_jntnum[b] > 0)
    gravcomp = model.body_gravcomp[robot_bodies]
    assert np.all(gravcomp == (1.0 if cls.fix_root_link else 0.0))
    # Every joint a control mode commands has exactly one actuator on it in the compiled
    # scene (never a duplicate beside the file's own), and every part's joints exist.
    driving = [int(model.actuator_trnid[a, 0]) for a in range(model.nu) if model.actuator_trntype[a] == 0]
    for mode in cls.modes():
        for config in cls.mode_parts(mode).values():
            for joint in config.joint_names:
                joint_id = model.joint(agent.prefix + joint).id
                assert driving.count(joint_id) == 1, (mode, joint)
    for part, names in agent.part_joints.items():
        assert names and all(n in agent.joint_names for n in names), part


@pytest.mark.parametrize("uid", ROBOTS)
def test_every_robot_has_a_rest_keyframe(uid: str) -> None:
    """Tasks may reset any robot to ``rest``."""
    assert "rest" in ra.get_agent(uid).keyframes


def test_keyframes_within_limits(scene: ra.Scene) -> None:
    agent = scene.agents[0]
    assert agent.keyframes, "every built-in robot declares at least one keyframe"
    model = scene.model
    for name in agent.keyframes:
        qpos = agent.keyframe_qpos(name)
        assert qpos.shape == (agent.nq,), name
        for joint, value in zip(agent.joint_names, qpos, strict=True):  # hinge and slide joints
            low, high = model.jnt_range[model.joint(agent.prefix + joint).id]
            assert low - 1e-9 <= value <= high + 1e-9, (name, joint)
        scene.reset(keyframes=name)
        np.testing.assert_array_equal(agent.qpos[0], qpos)


def test_keyframe_pose_has_no_contacts(scene: ra.Scene) -> None:
    """At every keyframe the robot touches nothing (no self-collision, no floor) but,
    for a robot standing on its legs, its feet on the floor."""
    agent = scene.agents[0]
    model = scene.model
    feet = agent.legs.feet  # empty unless the robot stands on its legs
    for name in agent.keyframes:
        scene.reset(keyframes=name)
        data = scene.world.datas[0]
        touching = [
            (model.geom(c.geom1).name, model.geom(c.geom2).name)
            for c in data.contact
            if not (
                {int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2])} & feet
                and 0 in (int(model.geom_bodyid[c.geom1]), int(model.geom_bodyid[c.geom2]))
            )
        ]
        assert not touching, f"{name}: {touching}"


def assert_gripper_action_closes_at_minus_one(agent: ra.Agent) -> None:
    """Every gripper, in every mode: a normalized -1 commands its leader joint to (or past)
    the closed position, +1 to (or past) the open one, whichever way its joints close."""
    for part in agent.grippers.parts.values():
        if isinstance(part, ra.Hand):
            continue
        joints = list(agent.part_joints[part.name])
        opened, closed = part.positions(len(joints))
        for controller in agent.controller.parts.values():
            leader = controller.config.joint_names[0]
            if leader not in joints or not controller.config.normalize_action:
                continue
            k = joints.index(leader)
            at_minus, at_plus = controller.to_raw(np.array([[-1.0], [1.0]]))[:, 0]
            closing = np.sign(closed[k] - opened[k])
            assert closing * (at_minus - closed[k]) >= -1e-12, f"{part.name}: -1 -> {at_minus}, closed {closed[k]}"
            assert closing * (at_plus - opened[k]) <= 1e-12, f"{part.name}: +1 -> {at_plus}, open {opened[k]}"


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
        cfg = controller.config
        if cfg.normalize_action:
            assert np.all(space.low[:, sl] == -1) and np.all(space.high[:, sl] == 1)
        elif isinstance(cfg, ra.PDJointPosConfig) and cfg.lower is None:
            # absolute joint targets: bounded by the joint limits in the compiled model
            ranges = [scene.model.jnt_range[scene.model.joint(agent.prefix + j).id] for j in cfg.joint_names]
            # (joints turning more than a turn either way take targets within one turn)
            limits = np.clip(np.array(ranges[: len(range(sl.start, sl.stop))]), -UNBOUNDED_TARGET, UNBOUNDED_TARGET)
            n = len(cfg.joint_names) if not isinstance(cfg, ra.PDJointPosMimicConfig) else 1
            np.testing.assert_allclose(space.low[0, sl.start : sl.start + n], limits[:n, 0].astype(np.float32))
            np.testing.assert_allclose(space.high[0, sl.start : sl.start + n], limits[:n, 1].astype(np.float32))

    assert_gripper_action_closes_at_minus_one(agent)

    # Hold: the robot stays at its rest keyframe for 1 s (5 s for the default mode: see
    # below); a robot on its legs is first given a second to settle onto them, in the
    # modes whose hold keeps its targets.
    scene.reset()
    legged = bool(standing_leg_joints(type(agent)))
    if not legged or keeps_targets(agent):
        settle = round(LOAD_SETTLE_SECONDS * scene.control_freq) if legged else 0
        drift, _ = hold_drift(scene, agent, 1.0, settle)
        assert drift < 0.01

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


@pytest.mark.parametrize(("uid", "keyframe"), [(u, k) for u in ROBOTS for k in ra.get_agent(u).keyframes])
def test_default_mode_holds_every_keyframe_for_five_seconds(uid: str, keyframe: str) -> None:
    scene = ra.Scene(uid)
    agent = scene.agents[0]
    scene.reset(keyframes=keyframe)
    # the keyframe's own targets, repeated; a robot on its legs settles onto them first
    settle = round(LOAD_SETTLE_SECONDS * scene.control_freq) if standing_leg_joints(ra.get_agent(uid)) else 0
    worst, _ = hold_drift(scene, agent, 5.0, settle)
    assert worst < 0.01, f"{uid} drifted {worst:.4f} rad/m from keyframe {keyframe!r}"
    assert np.all(agent.is_static())
    scene.close()


@pytest.mark.parametrize(
    ("config", "keeps"),
    [
        (ra.PDJointPosConfig(joint_names=("j",)), True),
        (ra.PDJointPosConfig(joint_names=("j",), use_delta=True, lower=-0.1, upper=0.1), False),
        (ra.PDJointPosConfig(joint_names=("j",), use_delta=True, use_target=True, lower=-0.1, upper=0.1), True),
        (ra.PDJointPosVelConfig(joint_names=("j",), use_delta=True, lower=-0.1, upper=0.1), False),
        (ra.PDJointVelConfig(joint_names=("j",)), False),
        (ra.JointEffortConfig(joint_names=("j",)), True),
    ],
)
def test_each_config_says_whether_its_hold_keeps_the_targets(config: ControllerConfig, keeps: bool) -> None:
    """``keeps_targets`` (what the standing claims ask of a legged robot's mode) is each
    config's answer: a delta from the measured pose or a zero velocity lets a loaded joint
    give; absolute, target-delta and effort modes (and the base's velocity) do not."""
    assert config.keeps_targets is keeps


def test_keeps_targets_asks_every_part_of_the_mode() -> None:
    env = ra.make_env("Empty-v1", robot_uids="anymal_c").unwrapped
    env.agent.set_control_mode("pd_joint_target_delta_pos")
    assert keeps_targets(env.agent)
    env.agent.set_control_mode("pd_joint_delta_pos")
    assert not keeps_targets(env.agent)
    env.close()
