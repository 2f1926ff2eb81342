"""The batched world's reads and its instability test (``num_envs > 1``) give, bit for
bit, what the per-env definitions give: poses of bodies and sites, the gathered joint
state, and the flag ``time < start + advance or not qvel @ qvel <= MAX_SPEED**2`` at
speeds around the screen that skips the exact norm and around the limit itself.
(That a step ending with NaN speeds is flagged in a batch is test_reliability's.)"""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.limits import MAX_SPEED
from robot_agents.sim.world import BatchedWorld

#: Free-spinning wheels on hinges to the world (no gravity, damping or contact): each
#: joint keeps the speed it is given, so the stepped speeds are the ones set.
NV = 6
SPINNERS = (
    "<mujoco><option gravity='0 0 0'/><worldbody>"
    + "".join(
        f"<body pos='{i} 0 0' euler='{10 * i} {20 * i} 0'><joint type='hinge' axis='0 0 1'/>"
        f"<geom type='sphere' size='.1' contype='0' conaffinity='0'/><site name='s{i}' pos='.05 .02 0'"
        f" euler='0 {15 * i} 30'/></body>"
        for i in range(NV)
    )
    + "</worldbody></mujoco>"
)


def _bits(array: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(array).view(np.uint8)


def _world(num_envs: int) -> BatchedWorld:
    return BatchedWorld(mujoco.MjModel.from_xml_string(SPINNERS), num_envs=num_envs, substeps=2, num_threads=1)


def test_instability_flags_equal_the_per_env_norm_test() -> None:
    """Speeds whose norm is far below the limit (the screen passes), just past half its
    square (the exact norm is taken), one ulp either side of the limit, spread over all
    joints or on one, and NaN / inf: each env's flag is the per-env definition's."""
    limit = MAX_SPEED
    spread = limit / math.sqrt(NV)  # every joint at this speed: the norm is the limit
    rows = [
        np.full(NV, 0.1),
        np.full(NV, spread * math.sqrt(0.5) * 1.0001),  # past the screen, below the limit
        np.full(NV, np.nextafter(spread, 0.0)),
        np.full(NV, np.nextafter(spread, np.inf)),
        np.r_[np.nextafter(limit, 0.0), np.zeros(NV - 1)],
        np.r_[np.nextafter(limit, np.inf), np.zeros(NV - 1)],
        np.r_[limit, np.zeros(NV - 1)],
        np.r_[np.nan, np.zeros(NV - 1)],  # (MuJoCo resets these two)
        np.r_[np.zeros(NV - 1), -np.inf],
        np.zeros(NV),
    ]
    world = _world(len(rows))
    for data, row in zip(world.datas, rows, strict=True):
        data.qvel[:] = row
    started = world.time.copy()
    with pytest.warns(RuntimeWarning, match="BatchedWorld.step: MuJoCo: Nan, Inf or huge value in QVEL"):
        world.step()
    advance = (world.substeps - 0.5) * world.model.opt.timestep
    expected = [
        bool(data.time < start + advance or not data.qvel @ data.qvel <= MAX_SPEED**2)
        for data, start in zip(world.datas, started, strict=True)
    ]
    np.testing.assert_array_equal(world.last_step_unstable, expected)
    # both sides of the limit are hit (NaN / inf are reset by MuJoCo within the step: a
    # step ending with NaN speeds is test_reliability's)
    assert expected == [False, False, False, True, False, True, False, False, False, False]
    np.testing.assert_array_equal(world.unstable_steps, np.array(expected, dtype=np.int64))
    world.close()


def test_batched_reads_equal_the_per_env_arrays() -> None:
    """``qpos`` / ``qvel`` (kept from the instability test or gathered), body and site
    poses of several ids (repeated, unordered) equal each env's MjData arrays and
    MuJoCo's ``mju_mat2Quat``, bit for bit; the reads are new arrays the caller may keep."""
    world = _world(3)
    rng = np.random.default_rng(0)
    for data in world.datas:
        data.qvel[:] = rng.normal(size=NV)
    world.step()
    for name in ("qpos", "qvel"):
        read = getattr(world, name)
        assert not read.flags.writeable
        assert np.array_equal(_bits(read), _bits(np.stack([getattr(d, name) for d in world.datas])))
    bodies, sites = [3, 1, 3, 6], [5, 0, 2, 0]
    body_poses, site_poses = world.body_poses(bodies), world.site_poses(sites)
    one_body = world.body_poses(2)
    for env, data in enumerate(world.datas):
        expected = np.array([np.r_[data.xpos[b], data.xquat[b]] for b in bodies])
        assert np.array_equal(_bits(body_poses[env]), _bits(expected))
        assert np.array_equal(_bits(one_body[env, 0]), _bits(np.r_[data.xpos[2], data.xquat[2]]))
        for k, site in enumerate(sites):
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, data.site_xmat[site])
            assert np.array_equal(_bits(site_poses[env, k]), _bits(np.r_[data.site_xpos[site], quat]))
    kept = world.body_poses(bodies)
    world.step()
    assert np.array_equal(_bits(kept), _bits(body_poses))  # a read is not changed by later steps
    assert not np.array_equal(world.body_poses(bodies), body_poses)
    world.close()


def test_batched_base_velocity_targets_equal_the_one_env_arithmetic() -> None:
    """The base velocity controller's batched ``apply`` (NumPy on ``(num_envs,)``
    arrays) gives each env the targets of its one-env arithmetic on Python floats, bit
    for bit: turning, not turning (``0.0`` and ``-0.0``: the heading is the yaw), and
    driving without a turn."""
    env = ra.make_env("Empty-v1", robot_uids="fetch", num_envs=4, max_episode_steps=None).unwrapped
    env.reset(seed=[3, 3, 3, 3])  # one yaw in every env: the one-env path reads env 0's
    env.step(np.tile(env.single_action_space.high * 0.5, (4, 1)))  # a yaw that is not 0
    controller = next(c for c in env.agent.controller.parts.values() if type(c).__name__ == "PDBaseVelController")
    world = env.scene.world
    raw = np.array([[0.4, 1.3], [0.4, 0.0], [-0.7, -0.0], [0.0, -2.1]])
    controller.apply(raw, world)
    batched = controller.target_qvel.copy()
    assert np.all(world.qpos[:, controller._yaw_adr] == world.qpos[0, controller._yaw_adr])
    for env_id, row in enumerate(raw):
        controller._apply_single(row[None], world)
        assert np.array_equal(_bits(controller.target_qvel[0]), _bits(batched[env_id])), env_id
    env.close()
