"""Inverse kinematics by damped least squares (DLS), batched over envs.

One iteration, per env, at joint positions ``q`` of the chain:

    e  = [p_target - p(q),  w * rotvec(R_target R(q)^T)]            (6,)
    e  = e scaled down to a norm of at most max_task_step
    J  = [J_p(q); w * J_r(q)]                                        (6, n)
    dq = J^T (J J^T + lambda^2 I)^-1 e   (+ null-space pull, see below)
    q  = clip(q + dq scaled to max_step, joint limits)

It stops when both errors are within tolerance (small end-effector steps from a
controller take 2-3 iterations). A far target can lie beyond a joint limit from the
seed's side; ``restarts`` then retries from random configurations.

With ``null_space_gain > 0`` a redundant arm is also pulled toward ``rest_qpos`` in
the null space of the task, ``(I - J^+ J) k (q_rest - q)``, which changes joint
positions without moving the end effector (to first order).

Only the chain's joints move; every other joint (fingers, other robots, objects)
stays at the value given in ``context_qpos``. The solver keeps the best iterate, so a
target it cannot reach still yields the closest configuration it found, and it
reports per env whether the tolerances were met.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError
from robot_agents.kinematics.forward import FrameRef, Kinematics
from robot_agents.kinematics.rotations import rotation_error

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]


@dataclass(frozen=True)
class IKConfig:
    """Settings of the damped-least-squares solver.

    Attributes:
        damping: ``lambda`` of DLS (m); larger is more robust near singularities and
            joint limits, smaller converges faster.
        max_iterations: iterations per solve (each costs one forward kinematics per env).
        position_tolerance: success threshold on the position error (m).
        rotation_tolerance: success threshold on the rotation error (rad).
        rotation_weight: metres per radian when position and rotation errors share one
            least-squares problem.
        max_step: largest change of any joint in one iteration (rad or m).
        max_task_step: largest weighted task-space error one iteration tries to remove
            (m); far targets are approached in straight steps of this size.
        null_space_gain: pull toward the rest posture per iteration (0 disables it).
    """

    damping: float = 0.01
    max_iterations: int = 10
    position_tolerance: float = 1e-3
    rotation_tolerance: float = math.radians(1.0)
    rotation_weight: float = 0.5
    max_step: float = 0.3
    max_task_step: float = 0.2
    null_space_gain: float = 0.0

    def __post_init__(self) -> None:
        positive = {
            "position_tolerance": self.position_tolerance,
            "rotation_tolerance": self.rotation_tolerance,
            "rotation_weight": self.rotation_weight,
            "max_step": self.max_step,
            "max_task_step": self.max_task_step,
        }
        for name, value in positive.items():
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"IKConfig.{name}: expected a finite value > 0, got {value!r}.")
        if not (math.isfinite(self.damping) and self.damping >= 0):
            raise ConfigError(f"IKConfig.damping: expected a finite value >= 0, got {self.damping!r}.")
        if not (math.isfinite(self.null_space_gain) and 0 <= self.null_space_gain <= 1):
            raise ConfigError(f"IKConfig.null_space_gain: expected a value in [0, 1], got {self.null_space_gain!r}.")
        if not (isinstance(self.max_iterations, int) and self.max_iterations >= 1):
            raise ConfigError(f"IKConfig.max_iterations: expected an int >= 1, got {self.max_iterations!r}.")


@dataclass(frozen=True)
class IKResult:
    """What a solve returns, per env.

    Attributes:
        qpos: the chain's joint positions ``(num_envs, n)`` (the best iterate).
        success: both tolerances met ``(num_envs,)``.
        position_error: remaining position error (m) ``(num_envs,)``.
        rotation_error: remaining rotation error (rad) ``(num_envs,)``; 0 for
            position-only solves.
        iterations: DLS updates made ``(num_envs,)``.
    """

    qpos: FloatArray
    success: BoolArray
    position_error: FloatArray
    rotation_error: FloatArray
    iterations: IntArray


class IKSolver:
    """DLS inverse kinematics of one frame over one serial chain of hinge / slide joints.

    Args:
        kinematics: the scratch kinematics of the compiled model.
        frame: the controlled body or site (e.g. the tool centre point).
        qpos_adr / dof_adr: the chain's joints in ``qpos`` / ``qvel``, shape ``(n,)``.
        qpos_limits: joint limits ``(n, 2)`` (``-inf`` / ``inf`` when unlimited).
        config: solver settings.
        rest_qpos: posture ``(n,)`` of the null-space pull (default: mid-range, or 0
            for unlimited joints).
    """

    def __init__(
        self,
        kinematics: Kinematics,
        frame: FrameRef,
        qpos_adr: IntArray,
        dof_adr: IntArray,
        qpos_limits: FloatArray,
        config: IKConfig | None = None,
        rest_qpos: npt.ArrayLike | None = None,
    ) -> None:
        self.kinematics = kinematics
        self.frame = frame
        self.qpos_adr = np.asarray(qpos_adr, dtype=np.int64)
        self.dof_adr = np.asarray(dof_adr, dtype=np.int64)
        self.config = config or IKConfig()
        n = len(self.qpos_adr)
        self.lower = np.asarray(qpos_limits, dtype=np.float64)[:, 0].copy()
        self.upper = np.asarray(qpos_limits, dtype=np.float64)[:, 1].copy()
        model = kinematics.model
        for adr in self.dof_adr:
            joint = int(model.dof_jntid[adr])
            if int(model.jnt_type[joint]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                raise ConfigError(
                    f"IKSolver({frame.name}): joint {model.joint(joint).name!r} is not a hinge or slide; "
                    "IK chains take 1-DoF joints only."
                )
        if rest_qpos is None:
            middle = 0.5 * (self.lower + self.upper)
            self.rest_qpos = np.where(np.isfinite(middle), middle, 0.0)
        else:
            self.rest_qpos = np.asarray(rest_qpos, dtype=np.float64).reshape(-1)
            if self.rest_qpos.shape != (n,):
                raise ConfigError(
                    f"IKSolver({frame.name}): expected rest_qpos of {n} values, got {self.rest_qpos.size}."
                )
        self._pose = np.empty(7)

    @property
    def size(self) -> int:
        return len(self.qpos_adr)

    def solve(
        self,
        context_qpos: FloatArray,
        target: FloatArray,
        seed: FloatArray,
        position_only: bool = False,
        max_iterations: int | None = None,
        restarts: int = 0,
    ) -> IKResult:
        """Joint positions that put the frame at ``target``.

        Args:
            context_qpos: full configurations ``(num_envs, nq)``; joints outside the chain
                keep these values.
            target: world poses ``(num_envs, 7)`` (position, quaternion w-x-y-z).
            seed: initial chain positions ``(num_envs, n)``.
            position_only: ignore the orientation of ``target``.
            max_iterations: overrides ``config.max_iterations`` (per attempt).
            restarts: envs that fail try again this many times from random
                configurations within the joint limits (drawn from a fixed-seed
                generator, so results are deterministic). Use it for global targets;
                controllers use 0, since another IK branch means a large motion.
        """
        result = self._solve_local(context_qpos, target, seed, position_only, max_iterations)
        if restarts <= 0 or result.success.all():
            return result
        rng = np.random.default_rng(0)
        low = np.where(np.isfinite(self.lower), self.lower, -np.pi)
        high = np.where(np.isfinite(self.upper), self.upper, np.pi)
        qpos, success = result.qpos.copy(), result.success.copy()
        position_error, rotation_error_ = result.position_error.copy(), result.rotation_error.copy()
        iterations = result.iterations.copy()
        for _ in range(restarts):
            failed = np.flatnonzero(~success)
            if len(failed) == 0:
                break
            random_seed = rng.uniform(low, high, (len(failed), self.size))
            retry = self._solve_local(context_qpos[failed], target[failed], random_seed, position_only, max_iterations)
            iterations[failed] += retry.iterations
            better = retry.success | (retry.position_error < position_error[failed]) & ~success[failed]
            chosen = failed[better]
            qpos[chosen] = retry.qpos[better]
            success[chosen] = retry.success[better]
            position_error[chosen] = retry.position_error[better]
            rotation_error_[chosen] = retry.rotation_error[better]
        return IKResult(qpos, success, position_error, rotation_error_, iterations)

    def _solve_local(
        self,
        context_qpos: FloatArray,
        target: FloatArray,
        seed: FloatArray,
        position_only: bool,
        max_iterations: int | None,
    ) -> IKResult:
        """One DLS descent from ``seed`` (see :meth:`solve`)."""
        cfg = self.config
        iterations_allowed = cfg.max_iterations if max_iterations is None else int(max_iterations)
        num_envs, n = seed.shape[0], self.size
        rows = 3 if position_only else 6
        q = np.clip(np.asarray(seed, dtype=np.float64), self.lower, self.upper)
        best_q = q.copy()
        best_cost = np.full(num_envs, np.inf)
        best_position_error = np.full(num_envs, np.inf)
        best_rotation_error = np.full(num_envs, np.inf)
        iterations = np.zeros(num_envs, dtype=np.int64)
        active = np.ones(num_envs, dtype=bool)
        configuration = np.array(context_qpos, dtype=np.float64)
        poses = np.empty((num_envs, 7))
        jacobian = np.zeros((num_envs, 6, n))
        target_position, target_quat = target[:, :3], target[:, 3:]
        weight = cfg.rotation_weight
        damping_sq = cfg.damping**2
        kinematics, frame, qpos_adr, dof_adr = self.kinematics, self.frame, self.qpos_adr, self.dof_adr
        for iteration in range(iterations_allowed + 1):
            envs = np.flatnonzero(active)
            for env in envs:
                row = configuration[env]
                row[qpos_adr] = q[env]
                kinematics.load(row)
                kinematics.loaded_pose(frame, poses[env])
                jacp, jacr = kinematics.loaded_jacobian(frame)
                jacobian[env, :3] = jacp[:, dof_adr]
                jacobian[env, 3:] = jacr[:, dof_adr]
            position_error = target_position[envs] - poses[envs, :3]
            position_norm = np.linalg.norm(position_error, axis=1)
            if position_only:
                rotation_vec = np.zeros((len(envs), 3))
                rotation_norm = np.zeros(len(envs))
            else:
                rotation_vec = rotation_error(target_quat[envs], poses[envs, 3:])
                rotation_norm = np.linalg.norm(rotation_vec, axis=1)
            cost = np.maximum(position_norm / cfg.position_tolerance, rotation_norm / cfg.rotation_tolerance)
            better = cost < best_cost[envs]
            improved = envs[better]
            best_cost[improved] = cost[better]
            best_q[improved] = q[improved]
            best_position_error[improved] = position_norm[better]
            best_rotation_error[improved] = rotation_norm[better]
            converged = cost <= 1.0
            active[envs[converged]] = False
            if iteration == iterations_allowed or not active.any():
                break
            keep = ~converged
            envs = envs[keep]
            error = np.concatenate((position_error[keep], weight * rotation_vec[keep]), axis=1)[:, :rows]
            size = np.linalg.norm(error, axis=1, keepdims=True)
            error *= np.minimum(1.0, cfg.max_task_step / np.maximum(size, 1e-300))
            jac = jacobian[envs, :rows].copy()
            if not position_only:
                jac[:, 3:] *= weight
            jac_t = np.swapaxes(jac, 1, 2)
            system = jac @ jac_t + damping_sq * np.eye(rows)
            step = (jac_t @ np.linalg.solve(system, error[..., None]))[..., 0]
            if cfg.null_space_gain > 0:
                pull = cfg.null_space_gain * (self.rest_qpos - q[envs])
                projected = jac_t @ np.linalg.solve(system, (jac @ pull[..., None]))
                step += pull - projected[..., 0]
            largest = np.max(np.abs(step), axis=1, keepdims=True)
            step *= np.minimum(1.0, cfg.max_step / np.maximum(largest, 1e-300))
            q[envs] = np.clip(q[envs] + step, self.lower, self.upper)
            iterations[envs] += 1
        success = (best_position_error <= cfg.position_tolerance) & (
            position_only | (best_rotation_error <= cfg.rotation_tolerance)
        )
        if position_only:
            best_rotation_error = np.zeros(num_envs)
        return IKResult(best_q, success, best_position_error, best_rotation_error, iterations)
