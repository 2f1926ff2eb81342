"""Habitat's mobile-manipulator vocabulary on a bound robot, in names, not ids.

:class:`MobileManipulatorParams` is a frozen record of what Habitat-lab's
``MobileManipulatorParams`` holds (arm, gripper, wheel and leg joints, their start
positions, the gripper's open / closed states, end-effector links and offsets, and the
end effector's workspace box), derived from the robot's parts and first keyframe,
with joint and link names checked once when the robot is bound.

:class:`ManipulatorView` implements the agent methods with Habitat's names
(``arm_joint_pos``, ``ee_transform``, ``calculate_ee_forward_kinematics`` ...), batch
first: every array has a leading ``num_envs`` axis.

Frames: MuJoCo is z-up (the base yaws about +z, forward is the base's +x); Habitat is
y-up (forward is -z). Every pose here is in our z-up world; see
docs/mobile-manipulators.md for the mapping of a Habitat user's numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from robot_agents.errors import ConfigError, StateError
from robot_agents.kinematics.forward import FrameKind, FrameRef
from robot_agents.kinematics.ik import IKSolver, LinearFollowers
from robot_agents.kinematics.ik_config import IKConfig
from robot_agents.validation import POSE_AXES, check_bool, check_quat_rows, check_whole, is_whole

if TYPE_CHECKING:
    from robot_agents.agent.agent import Agent

FloatArray = npt.NDArray[np.float64]

#: Global IK (a target anywhere in the workspace, not a controller's small step):
#: more iterations than a controller's solver, tolerances well inside 1 mm / 1 deg.
GLOBAL_IK = IKConfig(max_iterations=200, position_tolerance=1e-4, rotation_tolerance=math.radians(0.1))

#: Arm configurations sampled (fixed seed) to bound the end effector's workspace.
WORKSPACE_SAMPLES = 512


@dataclass(frozen=True)
class MobileManipulatorParams:
    """Habitat's ``MobileManipulatorParams`` in our words (all names, SI units).

    Attributes:
        arm_joints: the arm's joints, in model order.
        gripper_joints: the gripper's joints (first = the leader).
        wheel_joints: passive wheel hinges of the base (left then right).
        leg_joints: joints of ``Legs`` parts.
        leg_init_params: leg joint positions of the first keyframe (rad / m).
        arm_init_params: arm joint positions of the first keyframe (rad / m).
        gripper_init_params: gripper joint positions of the first keyframe.
        gripper_open_state, gripper_closed_state: gripper joint positions when open /
            closed (rad / m, one per gripper joint).
        gripper_state_eps: how close to open / closed counts (rad / m).
        ee_links: the body or site each end effector is fixed to.
        ee_offsets: each end effector's position in its link's frame (m).
        ee_constraint: per end effector, the box ``(3, 2)`` (min, max per axis, m) of
            its positions in the base frame (``base_link``'s; the root frame for a robot
            without planar base joints) over the arm's joint ranges (512 samples,
            fixed seed, and the keyframe with each arm joint at each of its limits;
            joints that follow an arm joint through a linear joint equality, such as
            Stretch's telescope segments, with it; the other joints at the first
            keyframe).
        base_link: the body the base joints move (``""`` for a fixed robot), by the
            robot's own name (as ``frame_pose`` takes it, without the scene's prefix).
        base_dynamics: ``"dynamic"`` or ``"kinematic"``, as the base runs now
            (:meth:`Agent.set_base_dynamics` included).
    """

    arm_joints: tuple[str, ...]
    gripper_joints: tuple[str, ...]
    wheel_joints: tuple[str, ...]
    leg_joints: tuple[str, ...]
    arm_init_params: tuple[float, ...]
    leg_init_params: tuple[float, ...]
    gripper_init_params: tuple[float, ...]
    gripper_open_state: tuple[float, ...]
    gripper_closed_state: tuple[float, ...]
    gripper_state_eps: float
    ee_links: tuple[str, ...]
    ee_offsets: tuple[tuple[float, float, float], ...]
    ee_constraint: tuple[tuple[tuple[float, float], ...], ...]
    base_link: str
    base_dynamics: str


def _per_joint(value: float | tuple[float, ...], n: int) -> tuple[float, ...]:
    values = np.broadcast_to(np.asarray(value, dtype=np.float64).reshape(-1), (n,)) if n else np.zeros(0)
    return tuple(float(v) for v in values)


def _matrix(pose: FloatArray) -> FloatArray:
    """Poses ``(n, 7)`` to homogeneous transforms ``(n, 4, 4)``."""
    w, x, y, z = pose[:, 3], pose[:, 4], pose[:, 5], pose[:, 6]
    out = np.zeros((len(pose), 4, 4))
    out[:, 0, 0] = 1 - 2 * (y * y + z * z)
    out[:, 0, 1] = 2 * (x * y - w * z)
    out[:, 0, 2] = 2 * (x * z + w * y)
    out[:, 1, 0] = 2 * (x * y + w * z)
    out[:, 1, 1] = 1 - 2 * (x * x + z * z)
    out[:, 1, 2] = 2 * (y * z - w * x)
    out[:, 2, 0] = 2 * (x * z - w * y)
    out[:, 2, 1] = 2 * (y * z + w * x)
    out[:, 2, 2] = 1 - 2 * (x * x + y * y)
    out[:, :3, 3] = pose[:, :3]
    out[:, 3, 3] = 1.0
    return out


class ManipulatorView:
    """The Habitat-named API of one bound robot (see the module docstring)."""

    def __init__(self, agent: Agent) -> None:
        from robot_agents.parts.declaration import Arm, Base, Gripper, Legs

        self.agent = agent
        owner = type(agent).__name__
        self.owner = owner
        parts = list(agent.parts_by_name.values())
        joints = agent.part_joints
        arm = next((p for p in parts if isinstance(p, Arm)), None)
        gripper = next((p for p in parts if isinstance(p, Gripper)), None)
        base = next((p for p in parts if isinstance(p, Base)), None)
        self.arm = arm
        self.gripper = gripper
        self.arm_joints = joints[arm.name] if arm else ()
        self.gripper_joints = joints[gripper.name] if gripper else ()
        index = agent.index
        arm_info = [index.joint(j, owner) for j in self.arm_joints]
        grip_info = [index.joint(j, owner) for j in self.gripper_joints]
        self.leg_joints = tuple(j for p in parts if isinstance(p, Legs) for j in joints[p.name])
        leg_info = [index.joint(j, owner) for j in self.leg_joints]
        self._leg_qpos = np.array([j.qpos_adr for j in leg_info], dtype=np.int64)
        self._leg_dof = np.array([j.dof_adr for j in leg_info], dtype=np.int64)
        self._leg_followers = LinearFollowers.of(agent.world.model, self._leg_dof)
        self._arm_qpos = np.array([j.qpos_adr for j in arm_info], dtype=np.int64)
        self._arm_dof = np.array([j.dof_adr for j in arm_info], dtype=np.int64)
        self._grip_qpos = np.array([j.qpos_adr for j in grip_info], dtype=np.int64)
        self._grip_dof = np.array([j.dof_adr for j in grip_info], dtype=np.int64)
        # Joints outside the part that follow one of its joints through a linear joint
        # equality (Stretch's telescope segments follow joint_arm_l0): moved with it.
        self._arm_followers = LinearFollowers.of(agent.world.model, self._arm_dof)
        self._grip_followers = LinearFollowers.of(agent.world.model, self._grip_dof)
        self._arm_limits = np.array(
            [j.range if j.limited else (-np.pi, np.pi) for j in arm_info], dtype=np.float64
        ).reshape(-1, 2)
        self._ee_frames = [
            agent.frames.end_effector(ee.name, f"{owner} MobileManipulatorParams")
            for ee in (arm.end_effectors if arm else ())
        ]
        self._solvers: dict[int, IKSolver] = {}
        first = agent.default_keyframe()
        keyframe = agent.keyframe_qpos(first) if first is not None else None
        robot_adr = {int(a): k for k, a in enumerate(index.qpos_adr)}
        # The workspace is sampled about the first keyframe (torso, head, ... as there),
        # never about the state the robot happens to be in when the params are first read.
        self._reference_qpos = np.array(agent.world.model.qpos0, dtype=np.float64)[None]
        if keyframe is not None:
            self._reference_qpos[0, index.qpos_adr] = keyframe

        def start(adrs: npt.NDArray[np.int64]) -> tuple[float, ...]:
            if keyframe is None:
                return tuple(0.0 for _ in adrs)
            return tuple(float(keyframe[robot_adr[int(a)]]) for a in adrs)

        n_grip = len(self.gripper_joints)
        self._params = MobileManipulatorParams(
            arm_joints=self.arm_joints,
            gripper_joints=self.gripper_joints,
            wheel_joints=base.wheels if base else (),
            leg_joints=self.leg_joints,
            arm_init_params=start(self._arm_qpos),
            leg_init_params=start(self._leg_qpos),
            gripper_init_params=start(self._grip_qpos),
            gripper_open_state=_per_joint(gripper.open, n_grip) if gripper else (),
            gripper_closed_state=_per_joint(gripper.closed, n_grip) if gripper else (),
            gripper_state_eps=float(gripper.tolerance) if gripper else 0.0,
            ee_links=tuple(ee.link for ee in (arm.end_effectors if arm else ())),
            ee_offsets=tuple(ee.pos for ee in (arm.end_effectors if arm else ())),
            ee_constraint=self._workspace(),
            # the robot's own name (as ee_links and frame_pose take it), without the scene prefix
            base_link=(
                index.model.body(agent.mobile._base_body()).name.removeprefix(index.prefix)
                if agent.mobile.kind != "fixed"
                else ""
            ),
            base_dynamics=agent.mobile.dynamics,
        )

    @property
    def params(self) -> MobileManipulatorParams:
        """The robot's :class:`MobileManipulatorParams` (``base_dynamics`` as the base
        runs now)."""
        dynamics = self.agent.mobile.dynamics
        if self._params.base_dynamics != dynamics:
            self._params = replace(self._params, base_dynamics=dynamics)
        return self._params

    # -- helpers ---------------------------------------------------------------------
    def _with_arm(self, configurations: FloatArray, q: FloatArray) -> None:
        """Put the arm of ``configurations`` ``(n, nq)`` at ``q`` ``(n, arm joints)``,
        with the joints that follow it."""
        configurations[:, self._arm_qpos] = q
        configurations[:, self._arm_followers.qpos_adr] = self._arm_followers.positions(q)

    def _require_arm(self, where: str) -> None:
        if not len(self._arm_qpos):
            raise ConfigError(f"{self.owner}.{where}: the robot has no Arm part.")

    def _ee(self, i: int, where: str) -> int:
        if not is_whole(i) or not 0 <= i < len(self._ee_frames):
            raise ConfigError(
                f"{self.owner}.{where}: expected an end-effector index in [0, {len(self._ee_frames)}), got {i!r}."
            )
        return int(i)

    def _base_frame_poses(self, configurations: FloatArray, i: int) -> FloatArray:
        """End-effector positions ``(n, 3)`` in the base frame: the frame of the body the
        planar base joints move (``params.base_link``), wherever ``configurations`` put
        the base (a keyframe may start the base turned or away from the mount); the root
        frame for a robot without planar base joints."""
        agent = self.agent
        mobile = agent.mobile
        reference: FrameRef | None
        if mobile.kind == "planar":
            body = mobile._base_body()
            reference = FrameRef(FrameKind.BODY, body, agent.index.model.body(body).name)
        else:
            reference = agent.frames.reference("root", "workspace")
        poses = agent.frames.pose(self._ee_frames[i], reference, configurations)
        return poses[:, :3]

    def _workspace(self) -> tuple[tuple[tuple[float, float], ...], ...]:
        if not len(self._arm_qpos) or not self._ee_frames:
            return ()
        n = len(self._arm_qpos)
        sampled = np.random.default_rng(0).uniform(
            self._arm_limits[:, 0], self._arm_limits[:, 1], (WORKSPACE_SAMPLES, n)
        )
        # Reach is often largest with one joint at a limit and the others at the keyframe
        # (Stretch's telescope out, wrist straight), which random samples rarely hit.
        at_limits = np.repeat(self._reference_qpos[:, self._arm_qpos], 2 * n, axis=0)
        at_limits[np.arange(2 * n), np.repeat(np.arange(n), 2)] = self._arm_limits.reshape(-1)
        arm = np.concatenate([sampled, at_limits])
        configurations = np.repeat(self._reference_qpos, len(arm), axis=0)
        self._with_arm(configurations, arm)
        boxes = []
        for i in range(len(self._ee_frames)):
            points = self._base_frame_poses(configurations, i)
            boxes.append(tuple((float(lo), float(hi)) for lo, hi in zip(points.min(0), points.max(0), strict=True)))
        return tuple(boxes)

    # -- joint state -----------------------------------------------------------------
    @property
    def arm_joint_pos(self) -> FloatArray:
        self._require_arm("arm_joint_pos")
        value: FloatArray = self.agent.world.qpos[:, self._arm_qpos].copy()
        return value

    def set_arm_joint_pos(self, values: npt.ArrayLike, env_ids: npt.ArrayLike | None = None) -> None:
        """Teleport the arm joints of ``env_ids`` (default: every env) to ``values``
        ``(n,)`` or ``(len(env_ids), n)`` (rad / m, within their limits; velocities zero),
        the joints that follow them through linear joint equalities with them, and hold
        them there."""
        where = f"{self.owner}.arm_joint_pos"
        self._require_arm("arm_joint_pos")
        self._write(self._arm_qpos, self._arm_dof, self._arm_followers, values, env_ids, where, "arm joint positions")

    @property
    def arm_velocity(self) -> FloatArray:
        self._require_arm("arm_velocity")
        value: FloatArray = self.agent.world.qvel[:, self._arm_dof].copy()
        return value

    @property
    def arm_motor_pos(self) -> FloatArray:
        """The arm drives' position targets ``(num_envs, n)`` (rad / m)."""
        self._require_arm("arm_motor_pos")
        columns = self.agent.drives.columns(self.arm_joints, f"{self.owner}.arm_motor_pos")
        value: FloatArray = self.agent.drives.targets.position[:, columns].copy()
        return value

    def set_arm_motor_pos(self, values: npt.ArrayLike) -> None:
        """Arm drive position targets at ``values`` ``(n,)`` or ``(num_envs, n)`` (rad / m,
        within the joints' limits), until the next action overwrites them; the joints are
        not moved (Habitat's ``arm_motor_pos`` setter)."""
        where = f"{self.owner}.arm_motor_pos"
        self._require_arm("arm_motor_pos")
        agent = self.agent
        agent._check_open(where)
        state = agent.state
        rows = state.batch(values, state.num_envs, len(self._arm_qpos), "arm drive position targets", where)
        by_adr = {int(a): k for k, a in enumerate(agent.index.qpos_adr)}
        state.check_within_limits(rows, np.array([by_adr[int(a)] for a in self._arm_qpos], dtype=np.int64), where)
        columns = agent.drives.columns(self.arm_joints, where)
        agent.drives.targets.position[:, columns] = rows
        agent.drives.write(agent.world.ctrl)

    @property
    def gripper_joint_pos(self) -> FloatArray:
        value: FloatArray = self.agent.world.qpos[:, self._grip_qpos].copy()
        return value

    # -- legs (Habitat's leg base) -------------------------------------------------------
    def _require_legs(self, where: str) -> None:
        if not len(self._leg_qpos):
            raise ConfigError(f"{self.owner}.{where}: the robot has no Legs part.")

    @property
    def leg_joint_pos(self) -> FloatArray:
        self._require_legs("leg_joint_pos")
        value: FloatArray = self.agent.world.qpos[:, self._leg_qpos].copy()
        return value

    def set_leg_joint_pos(self, values: npt.ArrayLike, env_ids: npt.ArrayLike | None = None) -> None:
        """Teleport the leg joints of ``env_ids`` (default: every env) to ``values``
        ``(n,)`` or ``(len(env_ids), n)`` (rad / m, within their limits; velocities zero)
        and hold them there (held legs are pinned there while a kinematic base moves)."""
        where = f"{self.owner}.leg_joint_pos"
        self._require_legs("leg_joint_pos")
        self._write(self._leg_qpos, self._leg_dof, self._leg_followers, values, env_ids, where, "leg joint positions")

    @property
    def leg_motor_pos(self) -> FloatArray:
        """The leg drives' position targets ``(num_envs, n)`` (rad / m)."""
        self._require_legs("leg_motor_pos")
        columns = self.agent.drives.columns(self.leg_joints, f"{self.owner}.leg_motor_pos")
        value: FloatArray = self.agent.drives.targets.position[:, columns].copy()
        return value

    def set_gripper_joint_pos(self, values: npt.ArrayLike, env_ids: npt.ArrayLike | None = None) -> None:
        """Teleport the gripper joints of ``env_ids`` (default: every env) to ``values``
        ``(n,)`` or ``(len(env_ids), n)`` (rad / m, within their limits; velocities zero),
        the joints that follow them through linear joint equalities with them, and hold
        them there."""
        where = f"{self.owner}.gripper_joint_pos"
        self._require_gripper("gripper_joint_pos")
        self._write(
            self._grip_qpos, self._grip_dof, self._grip_followers, values, env_ids, where, "gripper joint positions"
        )

    def _write(
        self,
        qpos_adr: npt.NDArray[np.int64],
        dof_adr: npt.NDArray[np.int64],
        followers: LinearFollowers,
        values: npt.ArrayLike,
        env_ids: npt.ArrayLike | None,
        where: str,
        what: str,
    ) -> None:
        agent = self.agent
        agent._check_open(where)
        state = agent.state
        ids = state.env_ids(env_ids, where)
        rows = state.batch(values, len(ids), len(qpos_adr), what, where)
        # the followers too (the equality would pull them there), all checked first
        rows = np.concatenate([rows, followers.positions(rows)], axis=1)
        qpos_adr = np.concatenate([qpos_adr, followers.qpos_adr])
        dof_adr = np.concatenate([dof_adr, followers.dof_adr])
        by_adr = {int(a): k for k, a in enumerate(agent.index.qpos_adr)}
        state.check_within_limits(rows, np.array([by_adr[int(a)] for a in qpos_adr], dtype=np.int64), where)
        self.agent.world.write_joint_state(ids, qpos_adr, rows, dof_adr, np.zeros((len(ids), len(dof_adr))))
        self._hold(ids, qpos_adr)

    def _hold(self, ids: npt.NDArray[np.int64], qpos_adr: npt.NDArray[np.int64]) -> None:
        """After a teleport of the joints at ``qpos_adr`` in envs ``ids``: the controllers
        that command one of them restart from the measured state and their joints' drives
        hold it; every other drive target stays (an arm target set through
        ``arm_motor_pos`` survives ``open_gripper()``, as in Habitat)."""
        agent = self.agent
        world, drives = agent.world, agent.drives
        written = {int(a) for a in qpos_adr}
        touched = [c for c in agent.controller.parts.values() if written & {int(a) for a in c.binding.qpos_adr}]
        held = written | {int(a) for c in touched for a in c.binding.qpos_adr}
        columns = np.array([k for k, a in enumerate(drives.qpos_adr) if int(a) in held], dtype=np.int64)
        if len(columns):
            rows = np.ix_(ids, columns)
            drives.targets.position[rows] = np.asarray(world.qpos)[np.ix_(ids, drives.qpos_adr[columns])]
            drives.targets.velocity[rows] = 0.0
            drives.targets.effort[rows] = 0.0
        for controller in touched:
            controller.reset(ids, world)
        drives.write(world.ctrl, world.qpos, world.qvel)

    # -- gripper -----------------------------------------------------------------------
    def _require_gripper(self, where: str) -> None:
        if self.gripper is None:
            raise ConfigError(f"{self.owner}.{where}: the robot has no Gripper part.")

    def open_gripper(self, env_ids: npt.ArrayLike | None = None) -> None:
        self._require_gripper("open_gripper")
        self._write(
            self._grip_qpos,
            self._grip_dof,
            self._grip_followers,
            self.params.gripper_open_state,
            env_ids,
            f"{self.owner}.open_gripper",
            "g",
        )

    def close_gripper(self, env_ids: npt.ArrayLike | None = None) -> None:
        self._require_gripper("close_gripper")
        self._write(
            self._grip_qpos,
            self._grip_dof,
            self._grip_followers,
            self.params.gripper_closed_state,
            env_ids,
            f"{self.owner}.close_gripper",
            "g",
        )

    def set_gripper_target_state(self, state: npt.ArrayLike) -> None:
        """Gripper drive targets at ``state`` (0 open, 1 closed; a number or one per env),
        until the next action overwrites them."""
        where = f"{self.owner}.set_gripper_target_state"
        self._require_gripper("set_gripper_target_state")
        self.agent._check_open(where)
        n = self.agent.state.num_envs
        try:
            if np.asarray(state).dtype.kind == "b":  # True is not a gripper state
                raise TypeError
            fraction = np.asarray(state, dtype=np.float64).reshape(-1)
        except Exception:  # strings, bools, ragged lists, whatever the input's own __array__ raises
            raise StateError(f"{where}: expected a state in [0, 1] or {n} of them, got {state!r}.") from None
        if fraction.size == 1:
            fraction = np.full(n, fraction[0])
        if fraction.size != n or not np.all((fraction >= 0) & (fraction <= 1)):
            raise StateError(f"{where}: expected a state in [0, 1] or {n} of them, got {state!r}.")
        opened, closed = np.array(self.params.gripper_open_state), np.array(self.params.gripper_closed_state)
        targets = opened[None] + fraction[:, None] * (closed - opened)[None]
        driven = [j for j in self.gripper_joints if j in self.agent.drives.joint_names]
        columns = self.agent.drives.columns(driven, where)
        keep = [k for k, j in enumerate(self.gripper_joints) if j in driven]
        self.agent.drives.targets.position[:, columns] = targets[:, keep]
        self.agent.drives.write(self.agent.world.ctrl)

    # -- end effector ------------------------------------------------------------------
    def ee_transform(self, i: int = 0) -> FloatArray:
        """World transform ``(num_envs, 4, 4)`` of end effector ``i`` (offset included)."""
        frame = self._ee_frames[self._ee(i, "ee_transform")]
        return _matrix(self.agent.frames.measured_pose(frame, self.agent.world))

    def ee_local_offset(self, i: int = 0) -> FloatArray:
        """Position ``(3,)`` of end effector ``i`` in its link's frame (m)."""
        return np.array(self.params.ee_offsets[self._ee(i, "ee_local_offset")], dtype=np.float64)

    def clip_ee_to_workspace(self, pos: npt.ArrayLike, i: int = 0) -> FloatArray:
        """Base-frame positions ``(num_envs, 3)`` (``params.base_link``'s frame) clipped
        into ``ee_constraint[i]``."""
        box = np.array(self.params.ee_constraint[self._ee(i, "clip_ee_to_workspace")])
        n = self.agent.state.num_envs
        points = self.agent.state.batch(pos, n, 3, "end-effector position (m)", f"{self.owner}.clip_ee_to_workspace")
        clipped: FloatArray = np.clip(points, box[:, 0], box[:, 1])
        return clipped

    def calculate_ee_forward_kinematics(self, q: npt.ArrayLike, i: int = 0) -> FloatArray:
        """World transform ``(num_envs, 4, 4)`` of end effector ``i`` with the arm at
        ``q`` (``(n,)`` or ``(num_envs, n)``, rad / m), the joints that follow it through
        linear joint equalities with it, and everything else as measured; computed on
        scratch data, the simulation is untouched."""
        where = f"{self.owner}.calculate_ee_forward_kinematics"
        self._require_arm("calculate_ee_forward_kinematics")
        frame = self._ee_frames[self._ee(i, "calculate_ee_forward_kinematics")]
        state = self.agent.state
        configurations = np.array(self.agent.world.qpos, dtype=np.float64)
        self._with_arm(configurations, state.batch(q, state.num_envs, len(self._arm_qpos), "arm q", where))
        return _matrix(self.agent.frames.pose(frame, None, configurations))

    def calculate_ee_inverse_kinematics(
        self, pose: npt.ArrayLike, i: int = 0, position_only: bool = False, restarts: int = 20
    ) -> tuple[FloatArray, npt.NDArray[np.bool_]]:
        """Arm joint positions ``(num_envs, n)`` that put end effector ``i`` at world
        ``pose`` (``(num_envs, 7)`` position + quaternion w-x-y-z, or ``(num_envs, 3)``
        positions: position only), seeded from the measured arm; and per env whether
        the solver met its tolerances. The simulation is untouched."""
        where = f"{self.owner}.calculate_ee_inverse_kinematics"
        self._require_arm("calculate_ee_inverse_kinematics")
        k = self._ee(i, "calculate_ee_inverse_kinematics")
        position_only = check_bool(position_only, "position_only", where)
        restarts = check_whole(restarts, "restarts", where, minimum=0)
        n = self.agent.state.num_envs
        try:
            targets = np.asarray(pose, dtype=np.float64)
        except Exception:  # strings, ragged lists, whatever the input's own __array__ raises
            raise StateError(
                f"{where}: expected finite poses of shape ({n}, 7) or positions ({n}, 3), got {pose!r:.80}."
            ) from None
        if targets.ndim == 1:
            targets = targets[None]
        if targets.shape not in ((n, 7), (n, 3)) or not np.all(np.isfinite(targets)):
            raise StateError(
                f"{where}: expected finite poses of shape ({n}, 7) or positions ({n}, 3), got {np.shape(pose)}."
            )
        width = int(targets.shape[-1])
        if width == 7:
            check_quat_rows(targets[:, 3:], f"poses {POSE_AXES}", where)
        else:
            position_only = True
            targets = np.concatenate([targets, np.tile([1.0, 0.0, 0.0, 0.0], (n, 1))], axis=1)
        if k not in self._solvers:
            self._solvers[k] = IKSolver(
                self.agent.frames.kinematics,
                self._ee_frames[k],
                self._arm_qpos,
                self._arm_dof,
                self._arm_limits,
                GLOBAL_IK,
            )
        context = np.array(self.agent.world.qpos, dtype=np.float64)
        result = self._solvers[k].solve(
            context, targets, context[:, self._arm_qpos], position_only=position_only, restarts=restarts
        )
        return result.qpos.copy(), result.success.copy()
