"""Inverse kinematics by damped least squares (DLS), batched over envs.

One iteration, per env, at joint positions ``q`` of the chain:

    e  = [p_target - p(q),  w * rotvec(R_target R(q)^T)]            (6,)
    e  = e scaled down to a norm of at most max_task_step
    J  = [J_p(q); w * J_r(q)]                                        (6, n)
    dq = J^T (J J^T + lambda^2 I)^-1 e   (+ null-space pull, see below)
    q  = clip(q + dq scaled to max_step, joint limits)

A joint at a limit that ``dq`` pushes further is taken out of the step (its column of
``J`` zeroed) and ``dq`` solved again, until no such joint is left: otherwise the clip
undoes that joint's share and the others never make it up (an arm resting on its limits,
such as the SO-100 at ``rest``, stalls).

It stops when both errors are within tolerance (small end-effector steps from a
controller take 2-3 iterations). A far target can lie beyond a joint limit from the
seed's side; ``restarts`` then retries from random configurations.

With ``null_space_gain > 0`` a redundant arm is also pulled toward ``rest_qpos`` in
the null space of the task, ``(I - J^+ J) k (q_rest - q)`` with the exact (undamped)
pseudo-inverse ``J^+``, which changes joint positions without moving the end effector
(to first order); joints taken out of the step at a limit are not pulled (the others'
step assumes they stay).

Unlimited hinges (continuous joints) count modulo ``2 pi``: a solution is taken to the
turn nearest its seed (the same pose; :meth:`IKSolver.solve` with restarts, to the turn
of the caller's seed), and the pull aims at the turn of the rest angle nearest the joint.

Only the chain's joints move; every other joint (fingers, other robots, objects)
stays at the value given in ``context_qpos``, except followers of a chain joint through
linear joint equalities (``follower = c0 + c1 * leader``, possibly through a chain of
them, e.g. the telescoping segments of Stretch's arm): they move with their leader, and
the leader's Jacobian column includes ``c1`` times theirs. The solver keeps the best
iterate, so a target it cannot reach still yields the closest configuration it found,
and it reports per env whether the tolerances were met.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.clipping import clip_ufunc, one_pass_clip_exact
from robot_agents.errors import ConfigError, StateError
from robot_agents.indexing import index_selector
from robot_agents.kinematics.forward import BoundFrame, FrameRef, Kinematics
from robot_agents.kinematics.ik_config import IKConfig, IKResult
from robot_agents.kinematics.rotations import quat_angle

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]

_TURN = 2 * np.pi
#: Smallest pivot of the Cholesky factor of ``J J^T + lambda^2 I`` (m^2): only binds
#: without damping (``damping=0``) at a singularity, where a zero pivot made the step
#: NaN (a NumPy warning and a wasted iteration); with damping every pivot is at least
#: ``lambda^2``.
_MIN_PIVOT = 1e-12
#: Singular values of the Jacobian below this fraction of the largest count as zero in
#: the null-space projector (their directions then take the pull as it is).
_NULL_SPACE_RCOND = 1e-10


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

    Attributes:
        lower / upper: the chain's joint limits ``(n,)`` (read-only arrays: the solver
            keeps their Python floats for its limit tests).
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
        # The limits never change (read-only), so their Python floats are taken once
        # (:func:`_strictly_within`'s tests).
        self.lower.flags.writeable = self.upper.flags.writeable = False
        self._limit_lists = (self.lower.tolist(), self.upper.tolist())
        #: Whether each iteration's clip to the limits takes NumPy's one-pass clip (the
        #: same bits as ``np.minimum(np.maximum(...))`` where no limit is zero).
        self._one_pass_clip = one_pass_clip_exact(self.lower, self.upper)
        model = kinematics.model
        for adr in self.dof_adr:
            joint = int(model.dof_jntid[adr])
            if int(model.jnt_type[joint]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                raise ConfigError(
                    f"IKSolver({frame.name}): joint {model.joint(joint).name!r} is not a hinge or slide; "
                    "IK chains take 1-DoF joints only."
                )
        if rest_qpos is None:
            bounded = np.isfinite(self.lower) & np.isfinite(self.upper)  # an unlimited joint rests at 0
            self.rest_qpos = np.where(
                bounded, 0.5 * (np.where(bounded, self.lower, 0.0) + np.where(bounded, self.upper, 0.0)), 0.0
            )
        else:
            self.rest_qpos = np.asarray(rest_qpos, dtype=np.float64).reshape(-1)
            if self.rest_qpos.shape != (n,):
                raise ConfigError(
                    f"IKSolver({frame.name}): expected rest_qpos of {n} values, got {self.rest_qpos.size}."
                )
        hinge = np.array([int(model.jnt_type[int(model.dof_jntid[adr])]) for adr in self.dof_adr]) == int(
            mujoco.mjtJoint.mjJNT_HINGE
        )
        periodic = hinge & ~np.isfinite(self.lower) & ~np.isfinite(self.upper)
        #: Unlimited hinges (continuous joints), whose angles are only defined modulo
        #: ``2 pi``: solutions are taken to the turn nearest the seed, and the null-space
        #: pull aims at the turn of ``rest_qpos`` nearest the joint (``None``: none).
        self.periodic: IntArray | None = np.flatnonzero(periodic) if periodic.any() else None
        self._qpos_sel = index_selector(self.qpos_adr)
        self._dof_sel = index_selector(self.dof_adr)
        self._followers = linear_followers(model, self.dof_adr)
        # Scratch buffers of the per-env descent, and views of them made once (per rows:
        # 3 for position-only solves, 6 with orientation).
        self._pose = np.empty(7)
        #: The pose at the seed and the best iterate's (a failed solve's check reads them).
        self._start_pose, self._best_pose = np.empty(7), np.empty(7)
        self._error = np.empty(6)
        self._error_position, self._error_rotation = self._error[:3], self._error[3:]
        self._difference = np.empty(4)
        self._systems = {3: np.empty((3, 3)), 6: np.empty((6, 6))}
        self._damping = {rows: self.config.damping**2 * np.eye(rows) for rows in (3, 6)}
        self._solution = np.empty(6)
        self._solutions = {rows: self._solution[:rows] for rows in (3, 6)}
        self._jacobian = np.empty((6, n))
        self._jacobians = {rows: self._jacobian[:rows] for rows in (3, 6)}
        self._transposes = {rows: self._jacobian[:rows].T for rows in (3, 6)}
        self._jacobian_position, self._jacobian_rotation = self._jacobian[:3], self._jacobian[3:]
        self._buffers = {
            rows: (
                self._systems[rows],
                self._solutions[rows],
                self._damping[rows],
                self._jacobians[rows],
                self._transposes[rows],
            )
            for rows in (3, 6)
        }
        self._bound = BoundFrame(kinematics, frame)
        self._scratch_qpos = kinematics.data.qpos
        # The chain's Jacobian columns as views when the dofs are consecutive (else taken):
        # both halves' (one copy of the 6 rows) and the translational half's.
        self._chain_jac = self._bound.jacobians[:, self._dof_sel] if isinstance(self._dof_sel, slice) else None
        self._chain_jacp = self._bound.jacp[:, self._dof_sel] if isinstance(self._dof_sel, slice) else None
        #: What :meth:`solve_one` reads each call, in one tuple (unpacked at once: cheaper
        #: than the attribute lookups; every entry is made once and never replaced).
        self._hot = (
            self._scratch_qpos,
            kinematics.model,
            kinematics.data,
            self._bound,
            self._bound.pose,
            self._bound.position,
            self._bound.quat,
            self._error,
            self._error_position,
            self._error_rotation,
            self._difference,
            self._jacobian_position,
            self._jacobian_rotation,
            self._chain_jac,
            self._chain_jacp,
            self._qpos_sel,
            self._followers,
            self._limit_lists,
        )

    @property
    def size(self) -> int:
        """How many joints the solver moves (the length of its ``qpos_adr``)."""
        return len(self.qpos_adr)

    @property
    def frame_bound(self) -> BoundFrame:
        """The solved frame bound to the scratch kinematics, whose pose :meth:`solve_one`
        reads (a caller that computes the frame's pose at the seed through it passes
        ``posed``)."""
        return self._bound

    @property
    def followers(self) -> bool:
        """Whether joints outside the chain follow it (:func:`linear_followers`)."""
        return bool(self._followers)

    def move_followers(self, qpos: FloatArray, q: FloatArray) -> None:
        """Followers of chain joints take ``c0 + c1 * leader`` in the configuration
        ``qpos`` ``(nq,)`` (linear joint couplings), the chain at ``q`` ``(n,)``."""
        for qadr, _, column, offset, slope in self._followers:
            qpos[qadr] = offset + slope * q[column]

    def solve(
        self,
        context_qpos: npt.ArrayLike,
        target: npt.ArrayLike,
        seed: npt.ArrayLike,
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
                generator, the same sequence for every env, so results are
                deterministic and each env's does not depend on the rest of the
                batch). Use it for global targets;
                controllers use 0, since another IK branch means a large motion.

        Raises:
            StateError: an argument of the wrong shape (one env's ``(nq,)``, ``(7,)``,
                ``(n,)`` are taken as a batch of one), with NaN or inf, or a target
                whose quaternion is zero (where ``position_only`` is false).
        """
        context_qpos, target, seed = self._checked(context_qpos, target, seed, position_only)
        num_envs = len(seed)
        result = IKResult(
            qpos=np.empty((num_envs, self.size)),
            success=np.empty(num_envs, dtype=bool),
            position_error=np.empty(num_envs),
            rotation_error=np.empty(num_envs),
            iterations=np.zeros(num_envs, dtype=np.int64),
        )
        low = np.where(np.isfinite(self.lower), self.lower, -np.pi)
        high = np.where(np.isfinite(self.upper), self.upper, np.pi)
        periodic = self.periodic
        for env in range(num_envs):
            self.solve_one(context_qpos[env], target[env], seed[env], result, env, position_only, max_iterations)
            best = (result.qpos[env].copy(), result.position_error[env], result.rotation_error[env])
            # Each env's restarts draw the same fixed-seed sequence, so an env's answer
            # does not depend on the other envs of the batch (which of them needed
            # restarts, and how many): a batch solves each env as a batch of one would.
            rng: np.random.Generator | None = None
            for _ in range(restarts if not result.success[env] else 0):
                rng = rng or np.random.default_rng(0)
                used = result.iterations[env]
                self.solve_one(
                    context_qpos[env], target[env], rng.uniform(low, high), result, env, position_only, max_iterations
                )
                result.iterations[env] += used
                if result.success[env]:
                    break
                # Keep the closest failure, by the descent's own measure: the larger of
                # the errors in units of their tolerances (by position alone it kept a
                # 0 mm / 88 deg answer over a 70 mm / 1 deg one).
                if self._cost(result.position_error[env], result.rotation_error[env]) >= self._cost(best[1], best[2]):
                    result.qpos[env], result.position_error[env], result.rotation_error[env] = best
                else:
                    best = (result.qpos[env].copy(), result.position_error[env], result.rotation_error[env])
            if periodic is not None:  # a restart's solution lies near its random seed: back to the caller's turn
                row = result.qpos[env]
                row[periodic] = _nearest_turn(row[periodic], seed[env][periodic])
        return result

    def _cost(self, position_error: float, rotation_error: float) -> float:
        """How far a solve is from its target: the larger of the errors (m, rad) in units
        of their tolerances (1 or less: solved)."""
        cfg = self.config
        return max(float(position_error) / cfg.position_tolerance, float(rotation_error) / cfg.rotation_tolerance)

    def _checked(
        self, context_qpos: npt.ArrayLike, target: npt.ArrayLike, seed: npt.ArrayLike, position_only: bool
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """:meth:`solve`'s arguments as float arrays ``(num_envs, ...)``, checked."""
        where = f"IKSolver({self.frame.name}).solve"
        arrays = []
        for name, value, width in (
            ("context_qpos", context_qpos, self.kinematics.model.nq),
            ("target", target, 7),
            ("seed", seed, self.size),
        ):
            try:
                array = np.asarray(value, dtype=np.float64)
            except (TypeError, ValueError):
                raise StateError(f"{where}: expected {name} as numbers, got {type(value).__name__}.") from None
            array = array[None] if array.ndim == 1 else array
            if array.ndim != 2 or array.shape[1] != width:
                raise StateError(f"{where}: expected {name} of shape (num_envs, {width}), got {np.shape(value)}.")
            if not np.all(np.isfinite(array)):
                raise StateError(f"{where}: {name} contains NaN or inf.")
            arrays.append(array)
        context, goal, start = arrays
        if not (len(context) == len(goal) == len(start)):
            raise StateError(
                f"{where}: expected context_qpos, target and seed for the same number of envs, got "
                f"{len(context)}, {len(goal)} and {len(start)}."
            )
        if not position_only:
            norms = np.linalg.norm(goal[:, 3:], axis=1)
            if np.any(norms < 1e-9):
                env = int(np.argmin(norms))
                raise StateError(
                    f"{where}: expected a non-zero target quaternion (w, x, y, z), got {goal[env, 3:].tolist()} "
                    f"in env {env}."
                )
        return context, goal, start

    def solve_one(
        self,
        context: FloatArray,
        target: FloatArray,
        seed: FloatArray,
        out: IKResult,
        row: int,
        position_only: bool = False,
        max_iterations: int | None = None,
        loaded: bool = False,
        posed: bool = False,
    ) -> None:
        """One DLS descent for one env, written into row ``row`` of ``out``.

        ``context`` ``(nq,)``, ``target`` ``(7,)`` world pose, ``seed`` ``(n,)``. With
        ``loaded``, the kinematics' scratch data already holds ``context`` (whose chain
        joints equal ``seed``) with positions computed, and the first forward pass is
        skipped; with ``posed`` too, :attr:`frame_bound`'s pose was updated there (read
        as it is). Runs per env with MuJoCo's C helpers: on problems this small numpy's
        per-call overhead, not arithmetic, dominates, and per-env results do not depend
        on the batch size.
        """
        cfg = self.config
        iterations = cfg.max_iterations if max_iterations is None else int(max_iterations)
        lower, upper = self.lower, self.upper
        (
            scratch_qpos,
            model,
            data,
            bound,
            pose,
            pose_position,
            pose_quat,
            error,
            error_position,
            error_rotation,
            difference,
            jacobian_position,
            jacobian_rotation,
            chain_jac,
            chain_jacp,
            qpos_sel,
            followers,
            (lower_list, upper_list),
        ) = self._hot
        if not loaded:
            scratch_qpos[:] = context
        rows = 3 if position_only else 6
        # A seed strictly inside the limits is its own clip (np.minimum(np.maximum(seed,
        # lower), upper) gives back its values, bit for bit): the seed itself (never
        # written here: every later q is a new array); at or past a limit, the clip.
        seed_values = seed.tolist()
        if _strictly_within(seed_values, lower_list, upper_list):
            q = seed
        else:
            q = np.minimum(np.maximum(seed, lower), upper)
            # (np.any(q != seed) on Python floats: the same != )
            if loaded and q.tolist() != seed_values:  # a seed past a (soft) limit was clipped
                loaded = False
                scratch_qpos[:] = context
        best_q, best_cost, best_position, best_rotation = q, math.inf, math.inf, math.inf
        start_pose = best_pose = self._start_pose
        system, solution, damping, jacobian, transpose = self._buffers[rows]
        task = error_position if position_only else error
        target_position, target_quat = target[:3], target[3:]
        weight, max_task = cfg.rotation_weight, cfg.max_task_step
        tol_position, tol_rotation = cfg.position_tolerance, cfg.rotation_tolerance
        # ``a.dot(b)`` is ``a @ b`` (the same BLAS call, ddot / dgemv, so the same bits)
        # without matmul's per-call dispatch.
        done = 0
        for iteration in range(iterations + 1):
            # Positions and orientations (mj_kinematics) for the errors; mj_comPos, which
            # only the Jacobian needs, just before it (not on the iteration that stops).
            centred = loaded and not iteration
            if not centred:
                scratch_qpos[qpos_sel] = q
                if followers:
                    self.move_followers(scratch_qpos, q)
                mujoco.mj_kinematics(model, data)
            if not (centred and posed):
                bound.update()
            np.subtract(target_position, pose_position, out=error_position)
            position_norm = math.sqrt(error_position.dot(error_position))
            if position_only:
                rotation_norm = 0.0
            else:
                # The rotation vector turning the pose's orientation into the target's
                # (rotation_error_into inlined).
                mujoco.mju_negQuat(difference, pose_quat)
                mujoco.mju_mulQuat(difference, target_quat, difference)
                mujoco.mju_quat2Vel(error_rotation, difference, 1.0)
                rotation_norm = math.sqrt(error_rotation.dot(error_rotation))
            cost = max(position_norm / tol_position, rotation_norm / tol_rotation)
            if iteration == 0:
                start_q = q
                start_pose[...] = pose
            if cost < best_cost:
                best_q, best_cost, best_position, best_rotation = q, cost, position_norm, rotation_norm
                if iteration:  # the pose of iteration 0 is start_pose (neither is written later)
                    best_pose = pose  # (the frame's own buffer: copied below if the descent goes on)
            if cost <= 1.0 or iteration == iterations:
                break
            if best_pose is pose:  # the next forward pass rewrites the frame's pose
                best_pose = self._best_pose
                best_pose[...] = pose
            if not centred:
                mujoco.mj_comPos(model, data)
            jacp, jacr = bound.jacobian(updated=True)
            if chain_jac is not None and chain_jacp is not None:
                if position_only:
                    jacobian_position[...] = chain_jacp
                else:  # both halves in one copy, then the rotational rows weighted in place (the same products)
                    jacobian[...] = chain_jac
                    np.multiply(jacobian_rotation, weight, out=jacobian_rotation)
            else:
                jacobian_position[...] = jacp[:, self._dof_sel]
                if not position_only:
                    np.multiply(jacr[:, self._dof_sel], weight, out=jacobian_rotation)
            if not position_only:
                error_rotation *= weight
            for _, dof, column, _, slope in followers:  # coupled joints move with their leader
                jacobian[:3, column] += slope * jacp[:, dof]
                if not position_only:
                    jacobian[3:, column] += (slope * weight) * jacr[:, dof]
            size = math.sqrt(task.dot(task))
            if size > max_task:
                task *= max_task / size
            np.matmul(jacobian, transpose, out=system)
            system += damping
            mujoco.mju_cholFactor(system, _MIN_PIVOT)
            mujoco.mju_cholSolve(solution, system, task)
            step = transpose.dot(solution)
            # Joints at a limit that the step pushes further are taken out of the
            # problem (their columns zeroed) and the rest solved again: the clip would
            # undo their share, and the others would never make it up (an arm resting
            # on its limits stalls otherwise). No joint at a limit: nothing to take out.
            # (The tests on Python floats: the comparisons NumPy makes, without its per-call cost.)
            held: list[bool] | None = None
            values = q.tolist()
            if not _strictly_within(values, lower_list, upper_list):  # a joint at (or past) a limit
                at_lower = [value <= low for value, low in zip(values, lower_list, strict=True)]
                at_upper = [value >= high for value, high in zip(values, upper_list, strict=True)]
                for _ in range(len(q)):
                    pushed = _pushed_further(at_lower, at_upper, step.tolist())
                    if not any(pushed):
                        break
                    held = pushed if held is None else [a or b for a, b in zip(held, pushed, strict=True)]
                    for column, push in enumerate(pushed):  # (jacobian[:, pushed] = 0.0, column by column)
                        if push:
                            jacobian[:, column] = 0.0
                    np.matmul(jacobian, transpose, out=system)
                    system += damping
                    mujoco.mju_cholFactor(system, _MIN_PIVOT)
                    mujoco.mju_cholSolve(solution, system, task)
                    step = transpose.dot(solution)
            if cfg.null_space_gain > 0:
                rest = self.rest_qpos
                if self.periodic is not None:  # an unlimited hinge rests at the turn of its rest angle nearest it
                    rest = rest.copy()
                    rest[self.periodic] = _nearest_turn(rest[self.periodic], q[self.periodic])
                pull = cfg.null_space_gain * (rest - q)
                if held is not None:  # out of the task step: the others count on them staying
                    pull[np.array(held, dtype=bool)] = 0.0
                # The exact null space (I - J^+ J), not the damped one: the damped
                # projector leaks lambda^2 (J J^T + lambda^2)^-1 J pull into the task every
                # iteration, an error the task step then chases (a Panda with a pull of 0.3
                # never got within 1e-5 m).
                step += pull - np.linalg.pinv(jacobian, rcond=_NULL_SPACE_RCOND) @ (jacobian @ pull)
            largest = _largest_magnitude(step)
            if largest > cfg.max_step:
                step *= cfg.max_step / largest
            q = q + step  # (a new array: best_q may hold the last one)
            if self._one_pass_clip:
                clip_ufunc(q, lower, upper, out=q)
            else:
                np.minimum(np.maximum(q, lower), upper, out=q)
            done += 1
        success = best_position <= tol_position and (position_only or best_rotation <= tol_rotation)
        if self.periodic is not None:
            # An unlimited hinge's angle matters modulo 2 pi: the solution's turn nearest
            # the seed (the same pose), so the joint never goes more than half a turn.
            periodic = self.periodic
            wrapped = _nearest_turn(best_q[periodic], seed[periodic])
            if np.any(wrapped != best_q[periodic]):
                best_q = best_q.copy()
                best_q[periodic] = wrapped
        if not success and best_q is not start_q:
            best_q, best_position, best_rotation = self._no_farther_than_asked(
                start_q, start_pose, best_q, best_pose, best_position, best_rotation, target, position_only
            )
        out.qpos[row] = best_q
        out.position_error[row] = best_position
        out.rotation_error[row] = 0.0 if position_only else best_rotation
        out.success[row] = success
        out.iterations[row] = done

    def _no_farther_than_asked(
        self,
        start_q: FloatArray,
        start_pose: FloatArray,
        best_q: FloatArray,
        best_pose: FloatArray,
        best_position: float,
        best_rotation: float,
        target: FloatArray,
        position_only: bool,
    ) -> tuple[FloatArray, float, float]:
        """A failed solve must not move the frame farther than the target is from the
        start: near a singularity the lowest-error iterate can be a large swing of the arm
        for a marginal gain. Such a solution is pulled back along the joint path toward
        the start (halving up to 5 times, else the start itself). Returns the joints and
        their position / rotation errors (m, rad)."""
        cfg = self.config
        asked_position = _distance(target[:3], start_pose[:3]) + cfg.position_tolerance
        asked_rotation = float(quat_angle(target[3:], start_pose[3:])) + cfg.rotation_tolerance

        def within(pose: FloatArray) -> bool:
            return _distance(pose[:3], start_pose[:3]) <= asked_position and (
                position_only or float(quat_angle(pose[3:], start_pose[3:])) <= asked_rotation
            )

        if within(best_pose):
            return best_q, best_position, best_rotation
        kinematics, data, pose = self.kinematics, self.kinematics.data, self._pose
        fraction = 1.0
        for _ in range(5):
            fraction *= 0.5
            q = start_q + fraction * (best_q - start_q)
            data.qpos[self._qpos_sel] = q
            self.move_followers(data.qpos, q)
            mujoco.mj_kinematics(kinematics.model, data)
            kinematics.loaded_pose(self.frame, pose)
            if within(pose):
                return q, _distance(target[:3], pose[:3]), float(quat_angle(target[3:], pose[3:]))
        return start_q, _distance(target[:3], start_pose[:3]), float(quat_angle(target[3:], start_pose[3:]))


def linear_followers(model: mujoco.MjModel, chain_dofs: IntArray) -> list[tuple[int, int, int, float, float]]:
    """Joints outside the chain (``chain_dofs``: its dof addresses) that follow a chain
    joint through active linear joint equalities (directly or through other followers,
    e.g. Stretch's telescope segments): ``(qpos adr, dof adr, chain column, c0, c1)``
    with ``follower = c0 + c1 * chain joint``, model addresses. Nonlinear couplings are
    left out (the follower then keeps its context value). Forward kinematics at a given
    ``qpos`` moves only the joints it sets; an IK moves these with their leader and adds
    ``c1`` times a follower's Jacobian column to its leader's."""
    column_of = {int(model.dof_jntid[dof]): k for k, dof in enumerate(chain_dofs)}
    leader_of: dict[int, tuple[int, float, float]] = {}
    for eq in range(model.neq):
        if int(model.eq_type[eq]) != int(mujoco.mjtEq.mjEQ_JOINT) or not bool(model.eq_active0[eq]):
            continue
        follower, leader = int(model.eq_obj1id[eq]), int(model.eq_obj2id[eq])
        coef = model.eq_data[eq, :5]
        if leader < 0 or np.any(coef[2:] != 0.0) or follower in column_of:
            continue
        leader_of[follower] = (leader, float(coef[0]), float(coef[1]))
    out = []
    for follower in leader_of:
        offset, slope, joint = 0.0, 1.0, follower
        for _ in range(len(leader_of)):
            if joint not in leader_of:
                break
            leader, c0, c1 = leader_of[joint]
            offset, slope, joint = offset + slope * c0, slope * c1, leader
            if joint in column_of:
                out.append(
                    (int(model.jnt_qposadr[follower]), int(model.jnt_dofadr[follower]), column_of[joint], offset, slope)
                )
                break
    return out


@dataclass(frozen=True)
class LinearFollowers:
    """:func:`linear_followers` as arrays ``(k,)``, to fill a batch of configurations
    or joint writes: each follower's model ``qpos`` and dof address, its leader's chain
    column, and ``c0`` (rad / m), ``c1`` of ``follower = c0 + c1 * leader``."""

    qpos_adr: IntArray
    dof_adr: IntArray
    leader: IntArray
    offset: FloatArray
    slope: FloatArray

    @classmethod
    def of(cls, model: mujoco.MjModel, chain_dofs: IntArray) -> LinearFollowers:
        """The followers of the chain with dof addresses ``chain_dofs`` ``(n,)``."""
        found = linear_followers(model, chain_dofs)
        return cls(
            qpos_adr=np.array([f[0] for f in found], dtype=np.int64),
            dof_adr=np.array([f[1] for f in found], dtype=np.int64),
            leader=np.array([f[2] for f in found], dtype=np.int64),
            offset=np.array([f[3] for f in found], dtype=np.float64),
            slope=np.array([f[4] for f in found], dtype=np.float64),
        )

    def positions(self, q: FloatArray) -> FloatArray:
        """The followers' positions ``(..., k)`` (rad / m) with the chain at ``q``
        ``(..., n)``."""
        values: FloatArray = self.offset + self.slope * q[..., self.leader]
        return values

    def velocities(self, qd: FloatArray) -> FloatArray:
        """The followers' velocities ``(..., k)`` (rad/s / m/s) with the chain moving at
        ``qd`` ``(..., n)``."""
        values: FloatArray = self.slope * qd[..., self.leader]
        return values


def _strictly_within(values: list[float], lower: list[float], upper: list[float]) -> bool:
    """Whether every ``lower[i] < values[i] < upper[i]`` (Python floats: the comparisons
    NumPy's ``<`` makes; a NaN value is not within): ``not np.any((q <= lower) | (q >= upper))``
    for a ``q`` without NaN, without NumPy's per-call cost on a few joints."""
    for value, low, high in zip(values, lower, upper, strict=True):  # noqa: SIM110 (a loop: half all()'s generator cost)
        if not low < value < high:
            return False
    return True


def _pushed_further(at_lower: list[bool], at_upper: list[bool], step: list[float]) -> list[bool]:
    """Per joint, whether a step ``step`` (Python floats) pushes it further past the limit
    it is at: ``(at_lower & (step < 0.0)) | (at_upper & (step > 0.0))`` as a list (a NaN
    step pushes nowhere, as in NumPy)."""
    return [
        (low and value < 0.0) or (high and value > 0.0)
        for low, high, value in zip(at_lower, at_upper, step, strict=True)
    ]


def _largest_magnitude(values: FloatArray) -> float:
    """``float(np.abs(values).max())``: the largest magnitude, picked in Python (exact: a
    maximum selects one of the values); numpy's answer where a NaN may be present (a NaN
    or ``inf - inf`` sum), since Python's ``max`` does not propagate NaN."""
    entries: list[float] = values.tolist()
    total = sum(entries)
    if total != total:
        return float(np.abs(values).max())
    return max(map(abs, entries))


def _nearest_turn(angles: FloatArray, reference: FloatArray) -> FloatArray:
    """``angles`` (rad) shifted by whole turns to the values nearest ``reference``: the
    arithmetic of :func:`robot_agents.controllers.joint.nearest_turn`, a new array."""
    shifted: FloatArray = angles + _TURN * np.round((reference - angles) / _TURN)
    return shifted


def _distance(a: FloatArray, b: FloatArray) -> float:
    difference = a - b
    return math.sqrt(difference @ difference)
