"""Habitat-lab's ``MobileManipulator`` names on a bound robot: a base class of
:class:`~robot_agents.agent.agent.Agent`.

Habitat users read and command the robot itself: ``agent.base_pos``,
``agent.arm_joint_pos = q``, ``agent.ee_transform(0)``, ``agent.open_gripper()`` ...
(docs/mobile-manipulators.md). These names are one concept, a vocabulary: none holds
state or logic of its own; each forwards to the object that does the work,
:class:`~.manipulator.ManipulatorView` (arm, gripper and end effector; built on first
use), :class:`~.mobile.MobileBase` (the base's pose) or :class:`~.grippers.GripperParts`
(open / closed). Why a base class of ``Agent`` and not something else:

- composition alone (``agent.manipulator.arm_joint_pos``) would take the names off the
  agent, where the docs and tests call them;
- forwarding through ``__getattr__`` or generated properties would hide them from type
  checkers, ``dir()`` and the API docs, and lose the ``arm_joint_pos`` setter and the
  docstrings;
- an explicit base class keeps every name, signature, docstring and result as it was,
  and leaves ``agent.py`` the bound robot's lifecycle. It comes before
  :class:`~.definition.AgentDefinition` in ``Agent``'s bases, so attribute lookup on a
  robot class is as when these lived in ``Agent``.

The class declares the attributes of ``Agent`` it reads; it is not meant to be used on
its own.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, cast

import numpy as np
import numpy.typing as npt

from robot_agents.agent.manipulator import ManipulatorView, MobileManipulatorParams
from robot_agents.validation import check_open

if TYPE_CHECKING:
    from robot_agents.agent.agent import Agent
    from robot_agents.agent.control import ControlModes
    from robot_agents.agent.grippers import GripperParts
    from robot_agents.agent.joint_state import JointState
    from robot_agents.agent.mobile import MobileBase
    from robot_agents.sim.backend import SimBackend

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]


class MobileManipulatorAPI:
    """Habitat's mobile-manipulator attributes of an :class:`~robot_agents.agent.agent.Agent`
    (see the module doc); every array has a leading ``num_envs`` axis."""

    # Set by Agent.__init__.
    world: SimBackend
    state: JointState
    control: ControlModes
    mobile: MobileBase
    grippers: GripperParts
    _manipulator: ManipulatorView | None

    def _check_open(self, where: str) -> None:
        """Raise :class:`StateError` once the simulation this robot is bound to was closed
        (its env's or scene's ``close()``)."""
        check_open(self.world.closed, f"the env (scene) of this {type(self).__name__}", where)

    # ------------------------------------------------------------------ mobile base (Habitat's names)
    @property
    def base_pos(self) -> FloatArray:
        """Ground point under the base, ``(num_envs, 3)`` (m, world; z is the mount's).

        Settable, as Habitat's: ``agent.base_pos = p`` teleports every env's base to
        ``p``, ``(3,)`` / ``(num_envs, 3)`` (x, y, z; z must be the base's z, which the
        base cannot leave: ``agent.base_pos = agent.base_pos`` holds) or ``(2,)`` /
        ``(num_envs, 2)`` (x, y), keeps its yaw and holds it there (as :meth:`set_base_pose`)."""
        return self.mobile.position

    @base_pos.setter
    def base_pos(self, value: npt.ArrayLike) -> None:
        where = f"{type(self).__name__}.base_pos"
        self._check_open(where)
        self._set_base_pose(self.mobile.ground_xy(value, where), None, None, where)

    @property
    def base_rot(self) -> FloatArray:
        """Base yaw about world +z, ``(num_envs,)`` (rad, in ``(-pi, pi]``; positive turns
        from +x towards +y, to the left).

        Settable, as Habitat's: ``agent.base_rot = yaw`` (rad, a number or one per env)
        turns every env's base in place and holds it there (as :meth:`set_base_pose`)."""
        return self.mobile.yaw

    @base_rot.setter
    def base_rot(self, value: npt.ArrayLike) -> None:
        where = f"{type(self).__name__}.base_rot"
        self._check_open(where)
        self._set_base_pose(None, value, None, where)

    def set_base_pose(
        self, xy: npt.ArrayLike | None = None, yaw: npt.ArrayLike | None = None, env_ids: npt.ArrayLike | None = None
    ) -> None:
        """Teleport the base to ``xy`` ``(2,)`` / ``(n, 2)`` (m) and ``yaw`` (rad), then hold."""
        where = f"{type(self).__name__}.set_base_pose"
        self._check_open(where)
        self._set_base_pose(xy, yaw, env_ids, where)

    def _set_base_pose(
        self, xy: npt.ArrayLike | None, yaw: npt.ArrayLike | None, env_ids: npt.ArrayLike | None, where: str
    ) -> None:
        self.mobile.set(xy, yaw, env_ids, where)
        self.control.active.reset(self.state.env_ids(env_ids, where), self.world)

    # ------------------------------------------------------------------ Habitat's manipulator API
    @property
    def manipulator(self) -> ManipulatorView:
        """The Habitat-named arm / gripper / end-effector API (built on first use)."""
        if self._manipulator is None:
            self._manipulator = ManipulatorView(cast("Agent", self))  # only Agent has this base
        return self._manipulator

    @property
    def params(self) -> MobileManipulatorParams:
        """Habitat's ``MobileManipulatorParams``, derived from the parts (names, SI units)."""
        return self.manipulator.params

    @property
    def arm_joint_pos(self) -> FloatArray:
        """Arm joint positions ``(num_envs, n)`` (rad / m)."""
        return self.manipulator.arm_joint_pos

    @arm_joint_pos.setter
    def arm_joint_pos(self, values: npt.ArrayLike) -> None:
        """Teleport the arm joints to ``values`` ``(n,)`` or ``(num_envs, n)`` (rad / m;
        within their limits, else :class:`StateError`) at rest, and hold them there (the
        other joints' drive targets stay)."""
        self.manipulator.set_arm_joint_pos(values)

    @property
    def arm_motor_pos(self) -> FloatArray:
        """Arm drive position targets ``(num_envs, n)`` (rad / m).

        Settable, as Habitat's: ``agent.arm_motor_pos = q`` (``(n,)`` or ``(num_envs, n)``,
        within the joints' limits) sets the targets until the next action overwrites them;
        the joints are not moved."""
        return self.manipulator.arm_motor_pos

    @arm_motor_pos.setter
    def arm_motor_pos(self, values: npt.ArrayLike) -> None:
        self.manipulator.set_arm_motor_pos(values)

    @property
    def arm_velocity(self) -> FloatArray:
        """Arm joint velocities ``(num_envs, n)`` (rad/s, m/s)."""
        return self.manipulator.arm_velocity

    @property
    def gripper_joint_pos(self) -> FloatArray:
        """Gripper joint positions ``(num_envs, n)`` (rad / m).

        Settable, as Habitat's: ``agent.gripper_joint_pos = g`` (``(n,)`` or
        ``(num_envs, n)``, within the joints' limits) teleports the gripper joints at rest
        and holds them there."""
        return self.manipulator.gripper_joint_pos

    @gripper_joint_pos.setter
    def gripper_joint_pos(self, values: npt.ArrayLike) -> None:
        self.manipulator.set_gripper_joint_pos(values)

    @property
    def leg_joint_pos(self) -> FloatArray:
        """Leg joint positions ``(num_envs, n)`` (rad / m) of ``Legs`` parts (Habitat's leg
        base: Spot's).

        Settable, as Habitat's: ``agent.leg_joint_pos = q`` (``(n,)`` or ``(num_envs, n)``,
        within the joints' limits) teleports the legs at rest and holds them there (held
        legs are then pinned there while a kinematic base moves)."""
        return self.manipulator.leg_joint_pos

    @leg_joint_pos.setter
    def leg_joint_pos(self, values: npt.ArrayLike) -> None:
        self.manipulator.set_leg_joint_pos(values)

    @property
    def leg_motor_pos(self) -> FloatArray:
        """Leg drive position targets ``(num_envs, n)`` (rad / m)."""
        return self.manipulator.leg_motor_pos

    def open_gripper(self, env_ids: npt.ArrayLike | None = None) -> None:
        """Put the gripper joints of ``env_ids`` (default: every env) at the open state
        (``params.gripper_open_state``, rad / m; teleport, at rest) and hold them there
        (the other joints' drive targets stay)."""
        self.manipulator.open_gripper(env_ids)

    def close_gripper(self, env_ids: npt.ArrayLike | None = None) -> None:
        """Put the gripper joints of ``env_ids`` (default: every env) at the closed state
        (``params.gripper_closed_state``, rad / m; teleport, at rest) and hold them there
        (the other joints' drive targets stay)."""
        self.manipulator.close_gripper(env_ids)

    def set_gripper_target_state(self, state: npt.ArrayLike) -> None:
        """Gripper drive targets at ``state`` (0 open ... 1 closed) until the next action."""
        self.manipulator.set_gripper_target_state(state)

    def ee_transform(self, i: int = 0) -> FloatArray:
        """World transform ``(num_envs, 4, 4)`` of end effector ``i``."""
        return self.manipulator.ee_transform(i)

    def ee_local_offset(self, i: int = 0) -> FloatArray:
        """End effector ``i``'s position in its link frame ``(3,)`` (m)."""
        return self.manipulator.ee_local_offset(i)

    def clip_ee_to_workspace(self, pos: npt.ArrayLike, i: int = 0) -> FloatArray:
        """Base-frame positions ``(num_envs, 3)`` (``params.base_link``'s frame) clipped
        into the sampled workspace box."""
        return self.manipulator.clip_ee_to_workspace(pos, i)

    def calculate_ee_forward_kinematics(self, q: npt.ArrayLike, i: int = 0) -> FloatArray:
        """World transform ``(num_envs, 4, 4)`` of end effector ``i`` at arm joints ``q``; no side effects."""
        return self.manipulator.calculate_ee_forward_kinematics(q, i)

    def calculate_ee_inverse_kinematics(
        self, pose: npt.ArrayLike, i: int = 0, position_only: bool = False, restarts: int = 20
    ) -> tuple[FloatArray, BoolArray]:
        """Arm joints ``(num_envs, n)`` reaching world ``pose`` and per-env success; no side effects."""
        return self.manipulator.calculate_ee_inverse_kinematics(pose, i, position_only, restarts)

    def is_gripper_open(self, gripper: str | None = None) -> BoolArray:
        """Per env: every driven gripper joint within its tolerance of ``open``."""
        return self.grippers.within(gripper, 1.0)

    def is_gripper_closed(self, gripper: str | None = None) -> BoolArray:
        """Per env: every driven gripper joint within its tolerance of ``closed``."""
        return self.grippers.within(gripper, 0.0)

    def gripper_opening(self, gripper: str | None = None) -> FloatArray:
        """Per env, how open the gripper is: 0 at ``closed``, 1 at ``open`` (its first joint)."""
        return self.grippers.opening(gripper)
