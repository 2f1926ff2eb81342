"""End-effector (task-space) control: poses commanded in the robot's root frame,
turned into joint targets by damped-least-squares IK, tracked by the joint PD actuators.

One control step of an end-effector controller, per env:

1. the *base pose* is the measured tool pose (``pd_ee_delta_*``) or the previous
   target (``pd_ee_target_delta_*``), both in the root frame;
2. the action moves it: a translation ``d`` in the root frame (``p + d``) or the tool
   frame (``p + R d``), and a rotation vector ``r`` about root-aligned axes through the
   tool point (``R' = exp(r) R``) or about the tool's own axes (``R' = R exp(r)``);
   absolute modes (``pd_ee_pose``) give the pose itself; position-only modes hold the
   orientation the controller had at its last reset;
3. the target position is clipped to the optional workspace box;
4. IK solves for the arm's joints (a few DLS iterations, warm-started) and the PD
   actuators track the solution. Delta modes add velocity feed-forward: the joints
   are driven along the straight path from where they start to the solution, at the
   speed that covers it in one control step, so a constant command moves the tool at
   the commanded rate instead of lagging behind it;
5. whether IK met its tolerances, and the residual errors, are kept per env and
   reported in the env's ``info``. A failed solve still applies the closest
   configuration found.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.controllers.base import (
    Controller,
    ControllerContext,
    FloatArray,
    IntArray,
    JointBinding,
    SimView,
)
from robot_agents.controllers.ee_config import (
    CommandFrame,
    PDEEPosConfig,
    PDEEPoseConfig,
    PerAxis,
    RotationFormat,
    per_axis,
)
from robot_agents.errors import ConfigError, UnknownNameError
from robot_agents.kinematics.forward import BoundFrame, FrameKind, FrameRef
from robot_agents.kinematics.ik import IKSolver
from robot_agents.kinematics.ik_config import IKResult
from robot_agents.kinematics.rotations import quat_to_euler, quat_to_rotvec, rotvec_to_quat_into

BoolArray = npt.NDArray[np.bool_]

__all__ = ["CommandFrame", "PDEEController", "PDEEPosConfig", "PDEEPoseConfig", "PerAxis", "RotationFormat"]


class PDEEController(Controller):
    """Controller of :class:`PDEEPosConfig` and :class:`PDEEPoseConfig` (see the module doc)."""

    config: PDEEPosConfig

    def __init__(self, config: PDEEPosConfig, binding: JointBinding, context: ControllerContext) -> None:
        self.config = config
        self.binding = binding
        owner = f"{context.owner} {type(config).__name__}"
        if config.ee_link:
            frame, command = context.resolve_frame(config.ee_link, owner), context.root_frame
        elif config.end_effector is not None:
            if config.end_effector not in context.end_effectors:
                raise UnknownNameError(owner, "end effector", config.end_effector, context.end_effectors)
            frame, command = context.end_effectors[config.end_effector]
        elif context.end_effectors:
            frame, command = next(iter(context.end_effectors.values()))
        else:
            raise ConfigError(
                f"{owner}: end-effector control needs an end effector (declare one on an Arm part) or ee_link; got neither."
            )
        self.ee_frame: FrameRef = frame
        #: The frame commands are expressed in (the robot's root, or a body that may move).
        self.root_frame = command
        self._check_chain(context.model, binding, frame, owner)
        self.rotation = config.controls_rotation
        self.quaternion_input = (
            isinstance(config, PDEEPoseConfig)
            and config.rotation_format is RotationFormat.QUAT
            and not config.use_delta
        )
        self.euler_input = (
            isinstance(config, PDEEPoseConfig)
            and config.rotation_format is RotationFormat.EULER
            and not config.use_delta
        )
        super().__init__(config, binding, context)
        self.kinematics = context.kinematics
        self.solver = IKSolver(
            context.kinematics,
            frame,
            binding.qpos_adr,
            binding.dof_adr,
            binding.qpos_range,
            config.ik,
            config.rest_qpos,
        )
        self.control_timestep = context.control_timestep
        self._columns = binding.column_sel
        self._position_only = not self.rotation and not config.hold_orientation
        self._workspace = (
            (np.asarray(config.workspace.lower, dtype=np.float64), np.asarray(config.workspace.upper, dtype=np.float64))
            if config.workspace is not None
            else None
        )
        n, num_envs = binding.size, context.num_envs
        #: The IK solutions (joint targets), ``(num_envs, n)``. This array and
        #: :attr:`target_pose` are written in place, never replaced (the one-env
        #: observation copies from them directly: ``state_obs``).
        self.target_qpos: FloatArray = np.zeros((num_envs, n))
        #: Target tool pose in the root frame, ``(num_envs, 7)``.
        self.target_pose: FloatArray = np.tile(np.array([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0]), (num_envs, 1))
        self._result = IKResult(
            qpos=np.zeros((num_envs, n)),
            success=np.ones(num_envs, dtype=bool),
            position_error=np.zeros(num_envs),
            rotation_error=np.zeros(num_envs),
            iterations=np.zeros(num_envs, dtype=np.int64),
        )
        self._rotate_about_root = not (isinstance(config, PDEEPoseConfig) and config.rotation_frame is CommandFrame.EE)
        #: Delta rotations: the largest turn per axis (rad, ``(3,)``); a command whose
        #: rotation part, in units of it, is longer than 1 is scaled down to length 1 (as
        #: ManiSkill does), so a diagonal command turns no more than one along an axis.
        self._turn_limit: tuple[float, float, float] | None = None
        if isinstance(config, PDEEPoseConfig) and config.use_delta and self.rotation:
            name = type(config).__name__
            low, high = per_axis(name, "rot_lower", config.rot_lower), per_axis(name, "rot_upper", config.rot_upper)
            if np.all(high > 0) and np.array_equal(low, -high):
                self._turn_limit = (float(high[0]), float(high[1]), float(high[2]))
        # Hot-path state made once: the mode's flags, the tool and root frames bound to
        # the scratch kinematics, per-env scratch poses and views of their parts.
        self._use_delta = config.use_delta
        self._from_target = config.use_target or not config.use_delta
        self._translate_in_tool = config.translation_frame is CommandFrame.EE
        self._kinematics_load = context.kinematics.load
        self._tool_bound = self.solver.frame_bound  # (the tool's pose measured is the IK's at its seed)
        self._root_bound = BoundFrame(context.kinematics, command)
        self._measured, self._inverse = np.empty(7), np.empty(7)
        self._target, self._world_target, self._turn, self._axis = np.empty(7), np.empty(7), np.empty(4), np.empty(3)
        # Position and quaternion views (MuJoCo's functions take views made once faster than slices).
        self._measured_parts = (self._measured[:3], self._measured[3:])
        self._inverse_parts = (self._inverse[:3], self._inverse[3:])
        self._target_parts = (self._target[:3], self._target[3:])
        self._world_target_parts = (self._world_target[:3], self._world_target[3:])
        self._configuration = np.empty(context.model.nq)
        #: Per step: the IK seeds, and the feed-forward position and velocity targets.
        self._start, self._position, self._velocity = (np.empty((num_envs, n)) for _ in range(3))

    @staticmethod
    def _check_chain(model: mujoco.MjModel, binding: JointBinding, frame: FrameRef, owner: str) -> None:
        """Every controlled joint must move the end effector (be on its chain to the root)."""
        body = frame.id if frame.kind is FrameKind.BODY else int(model.site_bodyid[frame.id])
        ancestors = set()
        while body > 0:
            ancestors.add(body)
            body = int(model.body_parentid[body])
        for name, adr in zip(binding.joint_names, binding.dof_adr, strict=True):
            if int(model.dof_bodyid[adr]) not in ancestors:
                raise ConfigError(
                    f"{owner}: joint {name!r} does not move {frame.name!r}; end-effector control takes the joints "
                    "on the chain from the root to the end effector."
                )

    # -- action ---------------------------------------------------------------------------
    def action_bounds(self) -> tuple[FloatArray, FloatArray]:
        name = type(self.config).__name__
        low = [per_axis(name, "pos_lower", self.config.pos_lower)]
        high = [per_axis(name, "pos_upper", self.config.pos_upper)]
        if isinstance(self.config, PDEEPoseConfig):
            if self.quaternion_input:
                low.append(-np.ones(4))
                high.append(np.ones(4))
            else:
                low.append(per_axis(name, "rot_lower", self.config.rot_lower))
                high.append(per_axis(name, "rot_upper", self.config.rot_upper))
        return np.concatenate(low), np.concatenate(high)

    @property
    def checks_actions(self) -> bool:
        return self.quaternion_input

    @property
    def direction_entries(self) -> slice | None:
        """Quaternion input: entries 3-6, scaled down as one (normalized here anyway)."""
        return slice(3, 7) if self.quaternion_input else None

    def check_raw_action(self, raw: FloatArray) -> str | None:
        if not self.quaternion_input:
            return None
        norms = np.linalg.norm(raw[:, 3:7], axis=1)
        if np.all(norms > 1e-6):
            return None
        env = int(np.argmin(norms))
        return (
            f"expected a non-zero quaternion (w, x, y, z) in entries 3-6, got norm {norms[env]:.3g} in env {env} "
            f"({raw[env, 3:7].tolist()})."
        )

    def _measure(self, configuration: FloatArray) -> None:
        """Forward kinematics of one env: world poses of the root and the tool (their bound
        frames' ``pose``), and the tool in the root frame (``self._measured``)."""
        self._kinematics_load(configuration)
        tool, root = self._tool_bound, self._root_bound
        (inverse_position, inverse_quat), (measured_position, measured_quat) = self._inverse_parts, self._measured_parts
        tool.update()
        root.update()
        # relative_pose_into(measured, tool, root) inlined: the helper costs +1.6 us a call (its copies).
        mujoco.mju_negPose(inverse_position, inverse_quat, root.position, root.quat)
        mujoco.mju_mulPose(measured_position, measured_quat, inverse_position, inverse_quat, tool.position, tool.quat)

    def _set_target(self, raw: FloatArray, base_position: FloatArray, base_quat: FloatArray) -> None:
        """Target tool pose (``self._target``, ``(7,)``) in the root frame from one env's
        action and base pose (position ``(3,)``, quaternion ``(4,)``)."""
        out = self._target
        position, quat = self._target_parts
        if self._use_delta:
            if self._translate_in_tool:
                mujoco.mju_rotVecQuat(position, raw[:3], base_quat)
                position += base_position
            else:
                np.add(base_position, raw[:3], out=position)
            if self.rotation:
                turn, rotvec = self._turn, raw[3:6]
                if self._turn_limit is not None:
                    lx, ly, lz = self._turn_limit
                    # in Python floats: the same divisions, libm pow and sums as on NumPy's
                    # scalars (the clip keeps |r / l| <= 1: no overflow), without their unboxing
                    rx, ry, rz = rotvec.tolist()
                    length = math.sqrt((rx / lx) ** 2 + (ry / ly) ** 2 + (rz / lz) ** 2)
                    if length > 1.0:
                        rotvec = rotvec / length
                rotvec_to_quat_into(turn, rotvec, self._axis)
                if self._rotate_about_root:
                    mujoco.mju_mulQuat(quat, turn, base_quat)
                else:
                    mujoco.mju_mulQuat(quat, base_quat, turn)
        else:
            position[...] = raw[:3]
            if self.quaternion_input:
                quat[...] = raw[3:7]
            elif self.euler_input:
                mujoco.mju_euler2Quat(quat, raw[3:6], "xyz")  # intrinsic x-y-z: Rx Ry Rz
            elif self.rotation:
                rotvec_to_quat_into(quat, raw[3:6], self._axis)
        if self._workspace is not None:
            np.clip(position, self._workspace[0], self._workspace[1], out=position)
        mujoco.mju_normalize4(quat)
        if out[3] < 0.0:  # one sign per orientation
            quat *= -1.0

    def apply(self, raw: FloatArray, sim: SimView) -> None:
        qpos, qpos_sel = sim.qpos, self.binding.qpos_sel
        from_target, use_target, target_pose = self._from_target, self.config.use_target, self.target_pose
        posed = not from_target  # the tool's pose at the seed, measured (self._tool_bound is the IK's)
        start = self._start
        start[...] = self.target_qpos if from_target else qpos[:, qpos_sel]
        target, world_target, result, root = self._target, self._world_target, self._result, self._root_bound
        solve_one, position_only = self.solver.solve_one, self._position_only
        (target_position, target_quat), (world_position, world_quat) = self._target_parts, self._world_target_parts
        measured = self._measured_parts
        followers, move_followers = self.solver.followers, self.solver.move_followers
        for env in range(self.num_envs):
            if from_target:
                # Forward kinematics at the IK seed: gives the root pose, and IK starts there.
                configuration = self._configuration
                configuration[:] = qpos[env]
                configuration[qpos_sel] = start[env]
                if followers:  # joints coupled to the chain sit where IK puts them (Stretch's telescope)
                    move_followers(configuration, start[env])
                self._kinematics_load(configuration)
                root.update()
            else:
                configuration = qpos[env]
                self._measure(configuration)
            base_position, base_quat = (target_pose[env, :3], target_pose[env, 3:]) if use_target else measured
            if not self.rotation:
                target_quat[...] = target_pose[env, 3:]  # position modes hold the orientation
            self._set_target(raw[env], base_position, base_quat)
            # compose_into(world_target, root, target) inlined: +1.0 us a call (both: Panda ee step 46 -> 50 us).
            mujoco.mju_mulPose(world_position, world_quat, root.position, root.quat, target_position, target_quat)
            # The scratch data holds `configuration` (IK's start) with its kinematics done.
            solve_one(configuration, world_target, start[env], result, env, position_only, None, True, posed)
            target_pose[env] = target
        solution = result.qpos
        # With feed-forward: the mean position and the velocity of the straight joint
        # path start -> solution over one control step (the targets are held over the
        # substeps): (start + solution) / 2 and (solution - start) / dt. Envs whose IK
        # failed (at the edge of the workspace, a joint limit or a singularity) get a
        # plain position target, so the arm does not carry speed into the limit.
        targets = self.targets
        if self.config.feedforward:
            position, velocity = self._position, self._velocity
            np.add(start, solution, out=position)
            np.multiply(0.5, position, out=position)
            np.subtract(solution, start, out=velocity)
            np.divide(velocity, self.control_timestep, out=velocity)
            if np.count_nonzero(result.success) != len(result.success):
                failed = ~result.success
                position[failed] = solution[failed]
                velocity[failed] = 0.0
            targets.position[:, self._columns] = position
            targets.velocity[:, self._columns] = velocity
        else:
            targets.position[:, self._columns] = solution
        self.target_qpos[:] = solution

    def single_apply(self, raw: FloatArray, qpos: FloatArray) -> Callable[[], None] | None:
        """One env: :meth:`apply` of the action entries ``raw`` (a ``(1, action_dim)``
        view of a buffer the caller rewrites before each call) as a call of no arguments,
        reading the measured positions from ``qpos``, a ``(1, nq)`` view that follows the
        simulation (see :meth:`PDJointPosController.single_apply
        <robot_agents.controllers.joint.PDJointPosController.single_apply>`): the same
        operations on the same values in the same order (forward kinematics at the seed,
        target pose, the same IK solve, feed-forward targets), so the same targets, IK
        results and ``target_ee_pose``, bit for bit, without the per-env loop, its
        lookups and the batch's indexing. ``None`` for a subclass, a batch, or a
        quaternion action (whose direction entries the general path scales)."""
        if type(self) is not PDEEController or self.num_envs != 1 or self.quaternion_input:
            return None
        qpos_row, qpos_sel = qpos[0], self.binding.qpos_sel
        measured_q = qpos_row[qpos_sel] if isinstance(qpos_sel, slice) else None  # a live view
        take = None if measured_q is not None else np.asarray(qpos_sel, dtype=np.intp)
        from_target, rotation = self._from_target, self.rotation
        posed = not from_target  # the tool's pose at the seed, measured (self._tool_bound is the IK's)
        target_qpos, target_qpos_row = self.target_qpos, self.target_qpos[0]  # (rewritten in place, never replaced)
        # The IK's seed, ``(n,)``, and its row ``(1, n)``: read, never written, by the call
        # until its last line; views of the values themselves where they need no copy
        # (the previous targets, or the measured positions where the joints are
        # consecutive in ``qpos``), else the scratch row they are gathered into.
        if from_target:
            start_rows, start = target_qpos, target_qpos_row
        elif measured_q is not None:
            start_rows, start = qpos[:, qpos_sel], measured_q
        else:
            start_rows, start = self._start, self._start[0]
        target_row = self.target_pose[0]
        held_quat = target_row[3:]
        configuration, root_update = self._configuration, self._root_bound.update
        target, result = self._target, self._result
        (target_position, target_quat), (world_position, world_quat) = self._target_parts, self._world_target_parts
        world_target, root_position, root_quat = self._world_target, self._root_bound.position, self._root_bound.quat
        solve_one, position_only = self.solver.solve_one, self._position_only
        followers, move_followers = self.solver.followers, self.solver.move_followers
        # _measure's calls, bound once
        scratch_qpos, model, data = self.kinematics.data.qpos, self.kinematics.model, self.kinematics.data
        tool_update, tool_position, tool_quat = (
            self._tool_bound.update,
            self._tool_bound.position,
            self._tool_bound.quat,
        )
        # The root's inverse pose, made again only when the root's pose changes (bit for
        # bit: the same input gives the same inverse): a buffer of this call's own.
        inverse, root_pose, root_bits = np.empty(7), self._root_bound.pose, [b""]
        inverse_position, inverse_quat = inverse[:3], inverse[3:]
        measured_position, measured_quat = self._measured_parts
        set_target = self._single_target(raw[0], target_row if self.config.use_target else self._measured)
        solution, success = result.qpos, result.success
        feedforward, dt = self.config.feedforward, self.control_timestep
        columns = self._columns
        drive_position, drive_velocity = self.targets.position, self.targets.velocity
        direct = isinstance(columns, slice)
        if direct:
            # The feed-forward targets straight into views of the drives' buffers (never
            # replaced): the same operations as into the scratch rows, without their copies.
            position, velocity = drive_position[:, columns], drive_velocity[:, columns]
        else:
            position, velocity = self._position, self._velocity
        kinematics, com_pos, mul_pose, neg_pose = (
            mujoco.mj_kinematics,
            mujoco.mj_comPos,
            mujoco.mju_mulPose,
            mujoco.mju_negPose,
        )

        def apply_single() -> None:
            if from_target:
                # Forward kinematics at the IK seed: gives the root pose, and IK starts there.
                configuration[:] = qpos_row
                configuration[qpos_sel] = start
                if followers:
                    move_followers(configuration, start)
                scratch_qpos[:] = configuration  # Kinematics.load(configuration) inlined
                kinematics(model, data)
                com_pos(model, data)
                root_update()
                context = configuration
            else:
                if take is not None:
                    qpos_row.take(take, out=start)
                # _measure(qpos_row) inlined (Kinematics.load's calls too)
                scratch_qpos[:] = qpos_row
                kinematics(model, data)
                com_pos(model, data)
                tool_update()
                root_update()
                bits = root_pose.tobytes()
                if bits != root_bits[0]:  # (a fixed base: once)
                    neg_pose(inverse_position, inverse_quat, root_position, root_quat)
                    root_bits[0] = bits
                mul_pose(measured_position, measured_quat, inverse_position, inverse_quat, tool_position, tool_quat)
                context = qpos_row
            if not rotation:
                target_quat[...] = held_quat  # position modes hold the orientation
            set_target()
            mul_pose(world_position, world_quat, root_position, root_quat, target_position, target_quat)
            solve_one(context, world_target, start, result, 0, position_only, None, True, posed)
            target_row[...] = target
            if feedforward:
                np.add(start_rows, solution, out=position)
                np.multiply(0.5, position, out=position)
                np.subtract(solution, start_rows, out=velocity)
                np.divide(velocity, dt, out=velocity)
                if not success.item(0):
                    position[...] = solution
                    velocity[...] = 0.0
                if not direct:
                    drive_position[:, columns] = position
                    drive_velocity[:, columns] = velocity
            elif direct:
                position[...] = solution
            else:
                drive_position[:, columns] = solution
            target_qpos[...] = solution

        return apply_single

    def _single_target(self, row: FloatArray, base: FloatArray) -> Callable[[], None]:
        """:meth:`_set_target` of one env's action entries ``row`` ``(action_dim,)`` and
        the base pose ``base`` ``(7,)`` (buffers rewritten before each call) as a call of
        no arguments: the same operations in the same order, with the mode's branches
        taken once and the views of the action made once (absolute modes: the call
        itself)."""
        base_position, base_quat = base[:3], base[3:]
        if not self._use_delta:
            set_target = self._set_target
            return lambda: set_target(row, base_position, base_quat)
        target, (position, quat) = self._target, self._target_parts
        move, rotvec_entries, turn, axis = row[:3], row[3:6], self._turn, self._axis
        in_tool, rotation, limit, about_root = (
            self._translate_in_tool,
            self.rotation,
            self._turn_limit,
            self._rotate_about_root,
        )
        low, high = self._workspace if self._workspace is not None else (None, None)
        mul_quat, normalize = mujoco.mju_mulQuat, mujoco.mju_normalize4

        def set_delta_target() -> None:
            if in_tool:
                mujoco.mju_rotVecQuat(position, move, base_quat)
                np.add(position, base_position, out=position)  # (position += base_position)
            else:
                np.add(base_position, move, out=position)
            if rotation:
                rotvec = rotvec_entries
                if limit is not None:
                    lx, ly, lz = limit
                    rx, ry, rz = rotvec.tolist()
                    length = math.sqrt((rx / lx) ** 2 + (ry / ly) ** 2 + (rz / lz) ** 2)
                    if length > 1.0:
                        rotvec = rotvec / length
                # rotvec_to_quat_into(turn, rotvec, axis) inlined (the same dot, sqrt and division)
                angle = math.sqrt(rotvec.dot(rotvec))
                if angle < 1e-12:
                    turn[:] = (1.0, 0.0, 0.0, 0.0)
                else:
                    mujoco.mju_axisAngle2Quat(turn, np.divide(rotvec, angle, out=axis), angle)
                if about_root:
                    mul_quat(quat, turn, base_quat)
                else:
                    mul_quat(quat, base_quat, turn)
            if low is not None:
                np.clip(position, low, high, out=position)
            normalize(quat)
            if target[3] < 0.0:  # one sign per orientation
                np.multiply(quat, -1.0, out=quat)  # (quat *= -1.0)

        return set_delta_target

    def hold_raw(self, sim: SimView) -> FloatArray:
        """Absolute modes: the current target pose (the measured tool pose, in the command
        frame, since the reset): position (m) and, where the mode commands it, rotation
        (a rotation vector in rad, a ``w, x, y, z`` quaternion for quaternion input, or
        intrinsic x-y-z Euler angles in rad for Euler input),
        ``(num_envs, action_dim)``; delta modes: zero."""
        if self.config.use_delta:
            return super().hold_raw(sim)
        pose = self.target_pose
        if not self.rotation:
            position: FloatArray = pose[:, :3].copy()
            return position
        if self.quaternion_input:
            rotation = pose[:, 3:]
        elif self.euler_input:
            rotation = quat_to_euler(pose[:, 3:])
        else:  # one pose at a time, the same arithmetic as for a single pose
            rotation = np.stack([quat_to_rotvec(quat) for quat in pose[:, 3:]]).reshape(-1, 3)
        held: FloatArray = np.concatenate([pose[:, :3], rotation], axis=1)
        return held

    # -- lifecycle ------------------------------------------------------------------------
    def reset(self, env_ids: IntArray, sim: SimView) -> None:
        qpos = sim.qpos
        for env in env_ids:
            self._measure(qpos[env])
            self.target_pose[env] = self._measured
            if self.target_pose[env, 3] < 0.0:
                self.target_pose[env, 3:] *= -1.0
        measured_q = qpos[env_ids][:, self.binding.qpos_adr]
        self.target_qpos[env_ids] = measured_q
        result = self._result
        result.qpos[env_ids] = measured_q
        result.success[env_ids] = True
        result.position_error[env_ids] = 0.0
        result.rotation_error[env_ids] = 0.0

    @property
    def ik_success(self) -> BoolArray:
        """Whether the last IK solve met its tolerances, per env ``(num_envs,)`` (a view)."""
        return self._result.success

    @property
    def ik_position_error(self) -> FloatArray:
        """Position error (m) the last IK solve left, per env ``(num_envs,)`` (a view)."""
        return self._result.position_error

    @property
    def ik_rotation_error(self) -> FloatArray:
        """Rotation error (rad) the last IK solve left, per env ``(num_envs,)`` (a view)."""
        return self._result.rotation_error

    def observe(self) -> dict[str, FloatArray]:
        return {"target_qpos": self.target_qpos, "target_ee_pose": self.target_pose}

    def step_info(self) -> dict[str, npt.NDArray[np.generic]]:
        result = self._result  # (the properties' arrays, read once)
        return {
            "ik_success": result.success.copy(),
            "ik_position_error": result.position_error.copy(),
            "ik_rotation_error": result.rotation_error.copy(),
        }

    def get_state(self) -> dict[str, FloatArray]:
        return {
            "target_qpos": self.target_qpos.copy(),
            "target_ee_pose": self.target_pose.copy(),
            "ik_success": self.ik_success.astype(np.float64),
            "ik_position_error": self.ik_position_error.copy(),
            "ik_rotation_error": self.ik_rotation_error.copy(),
        }

    def set_state(self, state: dict[str, FloatArray]) -> None:
        self.target_qpos[:] = state["target_qpos"]
        self.target_pose[:] = state["target_ee_pose"]
        self._result.success[:] = np.asarray(state["ik_success"]) > 0.5
        self._result.position_error[:] = state["ik_position_error"]
        self._result.rotation_error[:] = state["ik_rotation_error"]

    def describe(self) -> str:
        cfg = self.config
        what = "pose" if self.rotation else "position"
        if cfg.use_delta:
            kind = ("delta-from-target " if cfg.use_target else "delta ") + what
        else:
            kind = what + (" (quaternion)" if self.quaternion_input else " (Euler x-y-z)" if self.euler_input else "")
        return f"end-effector {kind} via IK{' (normalized)' if cfg.normalize_action else ''}"
