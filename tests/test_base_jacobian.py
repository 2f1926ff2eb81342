"""``Agent.frame_jacobian(..., include_base=True)``: the free base's six velocity dofs
(MuJoCo's free joint: linear in world axes, angular in the base's own axes) then the
joints, against central differences of ``frame_pose``."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.errors import ConfigError
from robot_agents.kinematics import finite_difference_jacobian
from robot_agents.robot_source import robot_from_file
from tests.test_derived_stance import quadruped, write

TOLERANCE = 1e-6


def base_and_joints(scene: ra.Scene, seed: int) -> tuple[ra.Agent, np.ndarray]:
    """The scene's robot with its base turned and lifted off the origin and its joints
    at random within their ranges; returns the agent and the model's qpos ``(nq,)``."""
    agent = scene.agents[0]
    free = agent.index.free_joint
    assert free is not None
    rng = np.random.default_rng(seed)
    qpos = np.array(scene.world.qpos[0], dtype=np.float64)
    quat = rng.normal(size=4)
    qpos[free.qpos_adr : free.qpos_adr + 7] = (*rng.uniform(-0.5, 0.5, 3), *(quat / np.linalg.norm(quat)))
    model = scene.model
    for adr, joint in zip(agent.index.qpos_adr, (j for j in range(model.njnt) if j != free.id), strict=False):
        low, high = model.jnt_range[joint] if model.jnt_limited[joint] else (-1.0, 1.0)
        qpos[adr] = rng.uniform(low, high)
    return agent, qpos


def put(scene: ra.Scene, qpos: np.ndarray) -> None:
    """Set the scene's (one env's) whole configuration ``(nq,)`` through its state
    (MuJoCo's integration state: time, then qpos)."""
    state = scene.world.get_state()
    state[0, 1 : 1 + scene.model.nq] = qpos
    scene.world.set_state(state)


def numeric(scene: ra.Scene, agent: ra.Agent, qpos: np.ndarray, name: str, relative_to: str) -> np.ndarray:
    """Central differences over (base position, base rotation vector in the base's own
    axes, joints): the base's rotation parameter ``r`` gives the quaternion
    ``q0 * exp(r)``, whose rate at ``r = 0`` is the body-frame angular velocity."""
    free = agent.index.free_joint
    assert free is not None
    q0 = qpos[free.qpos_adr + 3 : free.qpos_adr + 7]

    def pose(params: np.ndarray) -> np.ndarray:
        out = []
        for row in params:
            full = qpos.copy()
            full[free.qpos_adr : free.qpos_adr + 3] = row[:3]
            angle = float(np.linalg.norm(row[3:6]))
            axis = row[3:6] / angle if angle > 0 else np.zeros(3)
            turn = np.array([np.cos(angle / 2), *(np.sin(angle / 2) * axis)])
            quat = np.empty(4)
            mujoco.mju_mulQuat(quat, q0, turn)
            full[free.qpos_adr + 3 : free.qpos_adr + 7] = quat
            full[agent.index.qpos_adr] = row[6:]
            put(scene, full)  # the measured base: frame_pose reads the base from the state
            out.append(agent.frame_pose(name, full[agent.index.qpos_adr], relative_to=relative_to)[0])
        return np.array(out)

    params = np.concatenate([qpos[free.qpos_adr : free.qpos_adr + 3], np.zeros(3), qpos[agent.index.qpos_adr]])
    return finite_difference_jacobian(pose, params[None])


def check(scene: ra.Scene, name: str, seed: int) -> None:
    agent, qpos = base_and_joints(scene, seed)
    for relative_to in ("world", "root"):
        expected = numeric(scene, agent, qpos, name, relative_to)
        put(scene, qpos)
        joints = qpos[agent.index.qpos_adr]
        full = agent.frame_jacobian(name, joints, relative_to=relative_to, include_base=True)
        assert full.shape == (1, 6, 6 + len(agent.index.dof_adr))
        np.testing.assert_allclose(full, expected, atol=TOLERANCE)
        # the default is unchanged: the joints' columns alone
        np.testing.assert_array_equal(full[:, :, 6:], agent.frame_jacobian(name, joints, relative_to=relative_to))
    # the base's columns are not trivial (a turned base: body-frame angular columns)
    world = agent.frame_jacobian(name, qpos[agent.index.qpos_adr], include_base=True)
    assert not np.allclose(world[0, 3:, 3:6], np.eye(3), atol=1e-3)


@pytest.mark.parametrize("seed", [0, 1])
def test_go2_foot_jacobian_with_the_base(seed: int) -> None:
    scene = ra.Scene("unitree_go2")
    scene.reset()
    check(scene, "FL_calf", seed)


def test_file_robot_floating_jacobian_with_the_base(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_jacobian", quadruped()), floating=True)
    scene = ra.Scene(cls)
    scene.reset()
    check(scene, "fr_shin", 2)


def test_a_fixed_base_has_no_base_columns() -> None:
    scene = ra.Scene("panda")
    scene.reset()
    agent = scene.agents[0]
    before = scene.world.get_state()
    with pytest.raises(ConfigError, match="include_base=True needs a free-floating base"):
        agent.frame_jacobian("panda_hand_tcp", include_base=True)
    np.testing.assert_array_equal(scene.world.get_state(), before)
