"""The IK's and the one-env end-effector step's cheaper forms against the arithmetic they
replace, bit for bit: ``IKSolver.solve_one`` against a plain NumPy descent (the solver's
operations in their order, without the Python-float tests, the one-block Jacobian copy
and the skipped clip of a seed inside the limits), the limit tests on Python floats
against NumPy's comparisons, ``BoundFrame.update`` against ``_pose_into``, and the
one-env end-effector call with the drives' columns taken by index."""

from __future__ import annotations

import math
from dataclasses import replace

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.controllers import PDEEController
from robot_agents.kinematics import FrameRef, IKResult, IKSolver, Kinematics
from robot_agents.kinematics.forward import BoundFrame, FrameKind
from robot_agents.kinematics.ik import _nearest_turn, _pushed_further, _strictly_within
from robot_agents.kinematics.rotations import rotation_error_into

from .test_single_env_ee_step import assert_same_controllers
from .test_single_env_step import actions, make


def dls_step(jacobian: np.ndarray, damping: np.ndarray, task: np.ndarray) -> np.ndarray:
    """``J^T (J J^T + lambda^2 I)^-1 e`` with the solver's calls (MuJoCo's Cholesky)."""
    system, solution = np.matmul(jacobian, jacobian.T), np.empty(len(task))
    system += damping
    mujoco.mju_cholFactor(system, 1e-12)
    mujoco.mju_cholSolve(solution, system, task)
    step: np.ndarray = jacobian.T.dot(solution)
    return step


def reference_solve_one(
    solver: IKSolver, context: np.ndarray, target: np.ndarray, seed: np.ndarray, position_only: bool
) -> tuple[np.ndarray, float, float, bool, int]:
    """One DLS descent as the solver made it before its Python-float shortcuts, every
    step on NumPy arrays: joints, position and rotation errors, success, iterations."""
    cfg, kinematics = solver.config, solver.kinematics
    model, data = kinematics.model, kinematics.data
    bound = BoundFrame(kinematics, solver.frame)
    lower, upper = solver.lower, solver.upper
    rows, n = (3 if position_only else 6), solver.size
    data.qpos[:] = context
    q = np.minimum(np.maximum(seed, lower), upper)
    best_q, best_cost, best_position, best_rotation = q, math.inf, math.inf, math.inf
    start_pose, best_buffer, pose = np.empty(7), np.empty(7), np.empty(7)
    best_pose = start_pose
    error, difference = np.empty(6), np.empty(4)
    task = error[:3] if position_only else error
    jacobian = np.empty((rows, n))
    damping = cfg.damping**2 * np.eye(rows)
    weight, done, start_q = cfg.rotation_weight, 0, q
    for iteration in range(cfg.max_iterations + 1):
        data.qpos[solver._qpos_sel] = q
        solver.move_followers(data.qpos, q)
        mujoco.mj_kinematics(model, data)
        bound._pose_into(pose[:3], pose[3:])
        np.subtract(target[:3], pose[:3], out=error[:3])
        position_norm = math.sqrt(error[:3].dot(error[:3]))
        rotation_norm = 0.0
        if not position_only:
            rotation_error_into(error[3:], target[3:], pose[3:], difference)
            rotation_norm = math.sqrt(error[3:].dot(error[3:]))
        cost = max(position_norm / cfg.position_tolerance, rotation_norm / cfg.rotation_tolerance)
        if iteration == 0:
            start_q = q
            start_pose[...] = pose
        if cost < best_cost:
            best_q, best_cost, best_position, best_rotation = q, cost, position_norm, rotation_norm
            if iteration:
                best_pose = best_buffer
                best_pose[...] = pose
        if cost <= 1.0 or iteration == cfg.max_iterations:
            break
        mujoco.mj_comPos(model, data)
        jacp, jacr = bound.jacobian()
        jacobian[:3] = jacp[:, solver._dof_sel]
        if not position_only:
            np.multiply(jacr[:, solver._dof_sel], weight, out=jacobian[3:])
            error[3:] *= weight
        for _, dof, column, _, slope in solver._followers:
            jacobian[:3, column] += slope * jacp[:, dof]
            if not position_only:
                jacobian[3:, column] += (slope * weight) * jacr[:, dof]
        size = math.sqrt(task.dot(task))
        if size > cfg.max_task_step:
            task *= cfg.max_task_step / size
        step = dls_step(jacobian, damping, task)
        at_lower, at_upper = q <= lower, q >= upper
        held = None
        if np.count_nonzero(at_lower) or np.count_nonzero(at_upper):
            for _ in range(n):
                blocked = (at_lower & (step < 0.0)) | (at_upper & (step > 0.0))
                if not blocked.any():
                    break
                held = blocked if held is None else held | blocked
                jacobian[:, blocked] = 0.0
                step = dls_step(jacobian, damping, task)
        if cfg.null_space_gain > 0:
            pull = cfg.null_space_gain * (solver.rest_qpos - q)
            if held is not None:
                pull[held] = 0.0
            step += pull - np.linalg.pinv(jacobian, rcond=1e-10) @ (jacobian @ pull)
        largest = float(np.abs(step).max())
        if largest > cfg.max_step:
            step *= cfg.max_step / largest
        q = np.minimum(np.maximum(q + step, lower), upper)
        done += 1
    success = best_position <= cfg.position_tolerance and (position_only or best_rotation <= cfg.rotation_tolerance)
    if solver.periodic is not None:
        best_q = best_q.copy()
        best_q[solver.periodic] = _nearest_turn(best_q[solver.periodic], seed[solver.periodic])
    if not success and best_q is not start_q:
        best_q, best_position, best_rotation = solver._no_farther_than_asked(
            start_q, start_pose, best_q, best_pose, best_position, best_rotation, target, position_only
        )
    return best_q, best_position, 0.0 if position_only else best_rotation, success, done


#: (robot, mode, null-space gain or None): a plain body frame (Panda, UR10e), one with an
#: offset (SO-100, resting on its limits), a site (Google Robot), followers (Stretch),
#: a position-only solve, and the null-space pull with joints held at a limit.
SOLVER_CASES = [
    ("panda", "pd_ee_delta_pose", None),
    ("panda", "pd_ee_delta_pose", 0.3),
    ("so100", "pd_ee_delta_pos", None),
    ("ur_10e", "pd_ee_delta_pose", None),
    ("google_robot", "pd_ee_delta_pose", None),
    ("stretch", "pd_ee_delta_pos", None),
]


def test_the_cases_cover_both_clips_of_the_descent() -> None:
    """The descent clips each iterate to the limits in one pass (NumPy's clip ufunc)
    where no limit is zero, else in two (``np.minimum(np.maximum(...))``, which the plain
    descent below uses): :data:`SOLVER_CASES` holds arms of both kinds."""
    one_pass = {}
    for uid, mode, _ in SOLVER_CASES:
        env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None)
        agent = env.unwrapped.agents[0]
        ee = next(c for c in agent.control.active.parts.values() if isinstance(c, PDEEController))
        one_pass[uid] = ee.solver._one_pass_clip
        env.close()
    assert one_pass["panda"] and one_pass["ur_10e"] and not one_pass["stretch"], one_pass


@pytest.mark.parametrize(("uid", "mode", "gain"), SOLVER_CASES)
def test_solve_one_matches_the_plain_numpy_descent_bit_for_bit(uid: str, mode: str, gain: float | None) -> None:
    env = ra.make_env("Empty-v1", robot_uids=uid, control_mode=mode, max_episode_steps=None)
    env.reset(seed=0)
    agent = env.unwrapped.agents[0]
    ee = next(c for c in agent.control.active.parts.values() if isinstance(c, PDEEController))
    solver = ee.solver
    if gain is not None:
        solver = IKSolver(
            solver.kinematics,
            solver.frame,
            solver.qpos_adr,
            solver.dof_adr,
            np.stack([solver.lower, solver.upper], axis=1),
            replace(solver.config, null_space_gain=gain),
        )
    position_only = ee._position_only
    rng = np.random.default_rng(3)
    context = env.unwrapped.scene.world.datas[0].qpos.copy()
    low = np.where(np.isfinite(solver.lower), solver.lower, -np.pi)
    high = np.where(np.isfinite(solver.upper), solver.upper, np.pi)
    out = IKResult(np.empty((1, solver.size)), np.empty(1, bool), np.empty(1), np.empty(1), np.empty(1, np.int64))
    kinds = {"inside": 0, "at a limit": 0, "past a limit": 0, "failed": 0, "blocked": 0}
    for trial in range(60):
        seed = rng.uniform(low, high)
        if trial % 3 == 1:  # some joints exactly at a limit (the SO-100 rests on its own)
            pick = rng.random(solver.size) < 0.4
            seed[pick] = np.where(rng.random(pick.sum()) < 0.5, low[pick], high[pick])
        elif trial % 3 == 2:  # some past a limit (a seed the solver clips)
            pick = rng.random(solver.size) < 0.3
            seed[pick] = np.where(rng.random(pick.sum()) < 0.5, low[pick] - 0.05, high[pick] + 0.05)
        goal_q = np.clip(seed + rng.normal(0.0, 0.15 if trial % 4 else 0.6, solver.size), low, high)
        configuration = context.copy()
        configuration[solver.qpos_adr] = goal_q
        solver.move_followers(configuration, goal_q)
        target = solver.kinematics.pose(configuration, solver.frame)[0]
        if trial % 5 == 4:  # out of reach: a failed solve pulled back toward its start
            target[:3] += rng.normal(0.0, 1.0, 3)
        for loaded, posed in ((False, False), (True, False), (True, True)):
            start = context.copy()
            if loaded:  # the controllers' call: the scratch data holds the context at the seed
                start[solver.qpos_adr] = seed
                solver.move_followers(start, seed)
                solver.kinematics.load(start)
                if posed:  # and the frame's pose there (a clipped seed: computed again)
                    solver.frame_bound.update()
            solver.solve_one(start, target, seed, out, 0, position_only, None, loaded, posed)
            q, position, rotation, success, done = reference_solve_one(solver, start, target, seed, position_only)
            assert out.qpos[0].tobytes() == q.tobytes(), (trial, loaded)
            assert (out.position_error[0], out.rotation_error[0]) == (position, rotation)
            assert (bool(out.success[0]), int(out.iterations[0])) == (success, done)
        inside = _strictly_within(seed.tolist(), solver.lower.tolist(), solver.upper.tolist())
        clipped = np.minimum(np.maximum(seed, solver.lower), solver.upper)
        kinds["inside" if inside else "past a limit" if np.any(clipped != seed) else "at a limit"] += 1
        kinds["failed"] += int(not out.success[0])
        kinds["blocked"] += int(not _strictly_within(q.tolist(), solver.lower.tolist(), solver.upper.tolist()))
    limited = np.isfinite(solver.lower).any()
    assert kinds["inside"] and kinds["failed"], kinds
    if limited:
        assert kinds["at a limit"] and kinds["past a limit"] and kinds["blocked"], kinds
    env.close()


def test_the_limit_tests_on_python_floats_are_numpys_comparisons() -> None:
    rng = np.random.default_rng(0)
    special = [0.0, -0.0, 1.0, -1.0, math.inf, -math.inf, math.nan]
    for _ in range(3000):
        n = int(rng.integers(1, 8))
        lower = rng.choice([-1.0, 0.0, -0.0, -math.inf, -0.5], n)
        upper = rng.choice([1.0, 0.0, -0.0, math.inf, 0.5], n)
        q = np.where(rng.random(n) < 0.5, rng.uniform(-1.5, 1.5, n), rng.choice([*special, 0.5, -0.5], n))
        step = np.where(rng.random(n) < 0.7, rng.normal(0.0, 1.0, n), rng.choice(special, n))
        with np.errstate(invalid="ignore"):
            inside = not np.any((q <= lower) | (q >= upper)) and not np.isnan(q).any()
            clip = np.minimum(np.maximum(q, lower), upper)
        assert _strictly_within(q.tolist(), lower.tolist(), upper.tolist()) == inside
        if inside:  # the seed stands for its clip: the same bits
            assert clip.tobytes() == q.tobytes()
        at_lower, at_upper = q <= lower, q >= upper
        expected = (at_lower & (step < 0.0)) | (at_upper & (step > 0.0))
        pushed = _pushed_further(at_lower.tolist(), at_upper.tolist(), step.tolist())
        assert np.array(pushed, dtype=bool).tolist() == expected.tolist()


MODEL = """
<mujoco>
  <worldbody>
    <body name="base" pos="0.1 0.2 0.3" quat="0.9 0.1 0.3 0.2">
      <joint name="a" type="hinge" axis="0 0 1"/>
      <geom type="sphere" size="0.05"/>
      <body name="link" pos="0.3 0 0.1">
        <joint name="b" type="hinge" axis="0 1 0"/>
        <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02"/>
        <site name="tip" pos="0.3 0.01 0" quat="0.7 0.7 0.1 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("kind", ["body", "body with offset", "site", "site with offset"])
def test_bound_frame_update_is_pose_into_bit_for_bit(kind: str) -> None:
    model = mujoco.MjModel.from_xml_string(MODEL)
    kinematics = Kinematics(model)
    offset = (0.01, -0.02, 0.05, 0.8, 0.1, -0.5, 0.3) if "offset" in kind else None
    if kind.startswith("body"):
        frame = FrameRef(FrameKind.BODY, model.body("link").id, "link", offset)
    else:
        frame = FrameRef(FrameKind.SITE, model.site("tip").id, "tip", offset)
    bound, reference = BoundFrame(kinematics, frame), np.empty(7)
    rng = np.random.default_rng(1)
    for _ in range(50):
        kinematics.load(rng.uniform(-3.0, 3.0, model.nq))
        bound._pose_into(reference[:3], reference[3:])
        assert bound.update().tobytes() == reference.tobytes()
        jacp, jacr = bound.jacobian()
        assert np.shares_memory(jacp, bound.jacobians) and np.shares_memory(jacr, bound.jacobians)
        assert bound.jacobians[:3].tobytes() == jacp.tobytes() and bound.jacobians[3:].tobytes() == jacr.tobytes()


@pytest.mark.parametrize("mode", ["pd_ee_delta_pose", "pd_ee_target_delta_pose", "pd_ee_delta_pos"])
def test_the_one_env_ee_call_with_drive_columns_by_index_matches_the_general_path(mode: str) -> None:
    """Drive columns the controller takes by index (no built-in robot has them apart):
    the feed-forward targets go through the scratch rows instead of the drives' views."""
    fast, general = make("panda", mode), make("panda", mode)
    for env in (fast, general):
        for part in env.agent.controller.parts.values():
            if isinstance(part, PDEEController):
                columns = part._columns
                assert isinstance(columns, slice)
                part._columns = np.arange(columns.start or 0, columns.stop)
    slow_controller = general.agent.controller
    slow_controller._single_sim, slow_controller._single_plan = general.scene.world, None
    for action in actions(fast, 20):
        obs_fast, *_ = fast.step(action)
        obs_slow, *_ = general.step(action)
        assert obs_fast.tobytes() == obs_slow.tobytes()
        assert fast.scene.world.ctrl.tobytes() == general.scene.world.ctrl.tobytes()
        assert_same_controllers(fast.agent, general.agent)
    assert fast.agent.controller._single_plan is not None
    fast.close()
    general.close()


def test_the_one_env_ee_call_sees_a_root_moved_between_steps() -> None:
    """The root's inverse pose is kept while the root's pose bits stay the same: a root
    body moved in the model between steps (a user placing the robot) is taken up, as on
    the general path."""
    fast, general = make("panda", "pd_ee_delta_pose"), make("panda", "pd_ee_delta_pose")
    slow_controller = general.agent.controller
    slow_controller._single_sim, slow_controller._single_plan = general.scene.world, None
    root = fast.agent.root_body_id
    assert fast.model is not general.model and fast.agent.kinematics.model is fast.model
    for step, action in enumerate(actions(fast, 16)):
        if step in (5, 11):
            for env in (fast, general):
                env.model.body_pos[root] += (0.05, -0.02, 0.01)
        obs_fast, *_ = fast.step(action)
        obs_slow, *_ = general.step(action)
        assert obs_fast.tobytes() == obs_slow.tobytes()
        assert fast.scene.world.ctrl.tobytes() == general.scene.world.ctrl.tobytes()
        assert_same_controllers(fast.agent, general.agent)
    fast.close()
    general.close()
