"""Scripted solvers for ``PickCube-v1``, ``PushCube-v1`` and ``ReachPose-v1``, written once
for every robot with the parts a task needs, through the agent interface and the task's
layout only.

PickCube, per env (all envs of a batch at once):

1. *Turn*: joint-position mode. Damped-least-squares IK on ``agent.frame_pose`` /
   ``agent.frame_jacobian`` finds the arm pose that holds the gripper's grasp point
   above the cube, fingers pointing down, closing across two faces of the cube (the
   gripper's geometry comes from ``env.layout.gripper``; joints that follow an arm joint
   through a linear equality, such as Stretch's telescope segments, move with it:
   ``arm_followers``; where it stays more than 1 cm off, it restarts from random
   configurations); the joints are driven there
   along a smooth 1.5 s ramp with the gripper open, and held there while the arm is
   still arriving (drives slower than the ramp: :data:`SETTLE_STEPS`). (A 5-joint
   arm's default keyframe need not point its jaw down, and its end-effector modes
   cannot turn the tool.)
2. End-effector delta mode, position only (``pd_ee_target_delta_pos``, else
   ``pd_ee_delta_pos``, else the pose modes with the turned orientation held):
   *approach* above the cube, *descend* until the grasp point is a fifth of an edge
   below the cube's centre (the fingers reach past its middle), *close* the gripper
   (at least 10 steps, until it stops closing: :data:`CLOSED_STILL`), *raise* the cube straight up (to the goal's height, at least one edge above the
   table), *carry* it to the goal and stop commanding once it is there; the tool moves
   at most 0.05 reach per step.
3. *Base assist* (robots with a base): where the arm alone cannot put the turned tool
   a tenth of the reach ahead and behind along the base's heading (Stretch: lift and
   telescope span a plane across it), the base drives the tool's moves that way, in
   the turn and in every end-effector stage, and the arm holds its place along the
   heading (:meth:`Arm.plan_base_assist`, :meth:`Arm.base_share`).

PushCube: the gripper closed (a bare flange as it is), the same kind of turn, fingers
down and leaning into the push (back from it where leaning in would put the arm into
itself: :meth:`Arm.self_contact`; straight down where the arm's IK cannot hold the lean
along the push: :func:`path_error`), to above the push start behind the cube (on the far
side from the goal, clear of it); then end-effector deltas: down until the fingertips touch the table, lift them
off it, push the cube along its line to the goal with the closed fingers (a one-jaw
gripper's beside its grasp point: :func:`push_point`; :func:`solve_push`), rising a
little each step once the cube has stalled for a few steps with the robot pressing it
down onto the table, or with the robot touching the table itself (:data:`PRESS`).

ReachPose: the same turn straight to the goal pose (position only on arms of fewer
than 6 joints), then end-effector deltas towards it (``pd_ee_target_delta_pose`` on arms
of 6 or more joints) for the rest of the episode.

Every action goes through ``Arm.action``: the arm's raw command and the gripper's
open / closed state become one action vector of the active mode, each part's slice
normalized the way its controller expects.

Run it to measure success over seeds for every registered robot that can do a task::

    python examples/scripted_pick.py                       # every task, 20 seeds each
    python examples/scripted_pick.py --task PickCube-v1 --robots so100 panda --seeds 10
    python examples/scripted_pick.py --task PickCube-v1 --robots panda --seed 3 --video pick.gif
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from typing import Any

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.agent.index import JointKind
from robot_agents.controllers.base_vel import PDBaseVelController
from robot_agents.envs.tasks.layout import tool_arm
from robot_agents.kinematics import linear_followers
from robot_agents.kinematics.rotations import pose_inverse, pose_multiply, quat_to_matrix, rotation_error
from robot_agents.media import write_video

TASKS = ("PickCube-v1", "PushCube-v1", "ReachPose-v1")


# -- the interface, in a few helpers -----------------------------------------------------------
def shorten(vectors: np.ndarray, bound: np.ndarray) -> np.ndarray:
    """``vectors`` ``(n, 3)`` scaled down, keeping their direction, into ``[-bound, bound]``."""
    scale = np.max(np.abs(vectors) / bound, axis=1, keepdims=True)
    out: np.ndarray = vectors / np.maximum(scale, 1.0)
    return out


def end_effector_mode(agent: ra.Agent, rotation: bool) -> str:
    """The end-effector delta mode to use: one that turns the tool when ``rotation`` is
    wanted, position-only otherwise when the robot has one; target-delta modes first
    (commands accumulate on the controller's target, so a zero command holds the
    target exactly; measured-delta modes re-solve from the measured joints every step,
    which can keep a light wrist joint dithering while the tool holds still)."""
    modes = agent.modes()
    ranked = (
        ("pd_ee_target_delta_pose", "pd_ee_delta_pose")
        if rotation
        else ("pd_ee_target_delta_pos", "pd_ee_delta_pos", "pd_ee_target_delta_pose", "pd_ee_delta_pose")
    )
    for mode in ranked:
        if mode in modes:
            return mode
    raise ra.ConfigError(f"scripted_pick: {type(agent).__name__} has no end-effector delta mode.")


def world_to_root(agent: ra.Agent, ee: str) -> np.ndarray:
    """Rotation matrices ``(num_envs, 3, 3)`` from world axes to the axes end-effector
    commands are expressed in (the robot's root frame)."""
    root = pose_multiply(agent.frame_pose(ee), pose_inverse(agent.frame_pose(ee, relative_to="root")))
    return np.swapaxes(quat_to_matrix(root[:, 3:]), 1, 2)


def arm_followers(agent: ra.Agent, arm_dof: np.ndarray) -> list[tuple[int, int, int, float, float]]:
    """The robot's joints that follow an arm joint (``arm_dof``: the arm's robot-local dof
    indices) through linear joint equalities, e.g. Stretch's telescope segments:
    ``(qpos index, dof index, arm column, c0, c1)``, robot-local indices (the library's
    ``linear_followers`` in the robot's own numbering). Frame poses and Jacobians at a
    given ``qpos`` move only the joints it sets, so the IK below moves these itself."""
    local_q = {int(adr): i for i, adr in enumerate(agent.qpos_adr)}
    local_v = {int(adr): i for i, adr in enumerate(agent.dof_adr)}
    return [
        (local_q[q], local_v[v], column, offset, slope)
        for q, v, column, offset, slope in linear_followers(agent.index.model, agent.dof_adr[arm_dof])
        if q in local_q
    ]


class Arm:
    """The robot's arm and gripper as the solvers use them."""

    def __init__(self, env: Any) -> None:
        self.env = env
        self.agent: ra.Agent = env.agent
        arm = tool_arm(self.agent, "scripted_pick")
        self.ee = arm.end_effectors[0].name
        # The frame end-effector commands are expressed in: the tool's command frame (a
        # body that may move with a mobile base), else the robot's root.
        self.command_frame = arm.end_effectors[0].command_frame or "root"
        joints = [self.agent.index.joint(j, "scripted_pick") for j in self.agent.part_joints[arm.name]]
        self.q_index = np.array([j.qpos_start for j in joints])
        self.v_index = np.array([j.dof_start for j in joints])
        self.limits = self.agent.qpos_limits[self.q_index]
        #: Arm joints a full turn may be added to or taken from within their limits
        #: (hinges whose range spans 2 pi or more: a UR's +-2 pi), ``(k,)`` bools.
        self.turns = np.array([j.kind is JointKind.HINGE for j in joints]) & (
            self.limits[:, 1] - self.limits[:, 0] >= 2.0 * np.pi
        )
        self.followers = arm_followers(self.agent, self.v_index)
        self.arm_joint = self.agent.part_joints[arm.name][0]
        gripper = self.agent.gripper().name if self.agent.grippers.parts else None
        # all of the gripper's joints: its controller may drive any one of them (a
        # leader the others follow through an equality), not necessarily the first
        self.gripper_joints = set(self.agent.part_joints[gripper]) if gripper else set()
        self.control_dt = 1.0 / env.control_freq
        #: Per env: whether the base carries the tool's moves along its heading (see
        #: :meth:`plan_base_assist`); off until a solver plans it.
        self.assist = np.zeros(env.num_envs, dtype=bool)
        self.has_base = self.agent.mobile.planar is not None  # a Base part on planar joints

    def set_mode(self, mode: str) -> None:
        """Switch the control mode and find which of its controllers drives the arm and
        which the gripper (a mode names its parts as it likes)."""
        self.env.set_control_mode(mode)
        self.controller = self.agent.controller
        self.from_target = "target" in mode
        self.arm_name = self.gripper = self.base = None
        for name, controller in self.controller.parts.items():
            joints = controller.config.joint_names
            if self.arm_joint in joints:
                self.arm_name = name
            if self.gripper_joints & set(joints):
                self.gripper = name
            if isinstance(controller, PDBaseVelController):
                self.base = name

    def action(
        self, arm_raw: np.ndarray, gripper_open: np.ndarray | None = None, base_speed: np.ndarray | None = None
    ) -> np.ndarray:
        """The whole action from the arm's raw command ``(num_envs, k)``, the gripper's
        state (``True``: open) and the base's forward speed ``(num_envs,)`` (m/s; needs
        a base part); other parts hold still."""
        n = self.env.num_envs
        action = np.zeros((n, self.controller.action_dim))
        for name, controller in self.controller.parts.items():
            slot = self.controller.slices[name]
            if name == self.arm_name:
                action[:, slot] = controller.from_raw(arm_raw)  # clipped, normalized if it is
            elif name == self.gripper and gripper_open is not None:
                # every gripper: +1 opens, -1 closes (unit_high / unit_low in raw units)
                raw = np.where(gripper_open[:, None], controller.unit_high, controller.unit_low)
                action[:, slot] = controller.from_raw(raw)
            elif name == self.base and base_speed is not None:
                raw = np.zeros((n, controller.action_dim))  # forward first, then (lateral and) turn
                raw[:, 0] = base_speed
                action[:, slot] = controller.from_raw(raw)
        return action

    # -- the base's share of the tool's moves ---------------------------------------------------
    def heading(self) -> np.ndarray:
        """World directions ``(num_envs, 3)`` the base drives forward along (horizontal)."""
        yaw = self.agent.base_rot
        return np.stack([np.cos(yaw), np.sin(yaw), np.zeros_like(yaw)], axis=1)

    def plan_base_assist(self, position: np.ndarray, quat: np.ndarray, probe: float) -> None:
        """Decide per env whether the base carries the tool's moves along its heading:
        where the arm alone cannot put the tool ``probe`` m ahead of ``position`` and
        behind it along the heading with the orientation ``quat`` (within 1 cm; Stretch:
        lift and telescope span a plane across its heading, and its wrist reaches
        2.4 cm either side of that plane)."""
        self.assist[:] = False
        if not self.has_base:
            return
        for sign in (1.0, -1.0):
            shifted = position + sign * probe * self.heading()
            q = self.solve(shifted, quat)
            self.assist |= np.linalg.norm(self.tool_at(q) - shifted, axis=1) > 0.01

    def robot_qpos(self, q: np.ndarray) -> np.ndarray:
        """The robot's joint positions ``(num_envs, nq)`` with the arm's joints at ``q``
        ``(num_envs, k)``, joints that follow an arm joint with it, the rest as they are."""
        full = self.agent.qpos.copy()
        full[:, self.q_index] = q
        for follower_q, _, column, offset, slope in self.followers:
            full[:, follower_q] = offset + slope * q[:, column]
        return full

    def tool_at(self, q: np.ndarray) -> np.ndarray:
        """Tool positions ``(num_envs, 3)`` with the arm's joints at ``q`` ``(num_envs, k)``
        (the rest of the robot as it is; joints that follow an arm joint with it)."""
        tool: np.ndarray = self.agent.frame_pose(self.ee, qpos=self.robot_qpos(q))[:, :3]
        return tool

    def base_share(self, wanted: np.ndarray, speed: float | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Split a move of the tool to ``wanted`` (``(num_envs, 3)``, world): in envs the
        base assists, the part along its heading goes to the base (at most ``speed`` m and
        its top speed this step). The moves start from where the arm's controller holds
        the tool (:meth:`commanded_tool`), not from the measured tool: a tool held back
        by what it pushes does not drive the base on. The tool position the arm is to
        go to and the base's forward speed ``(num_envs,)`` (m/s)."""
        if not self.assist.any():
            return wanted, np.zeros(len(wanted))
        heading = self.heading()
        along = np.where(self.assist, np.sum((wanted - self.commanded_tool()) * heading, axis=1), 0.0)
        top = float(self.controller.parts[self.base].raw_high[0]) * self.control_dt if self.base else 0.0
        limit = np.minimum(np.broadcast_to(np.asarray(speed, dtype=float).reshape(-1), along.shape), top)
        drive = np.clip(along, -limit, limit)
        return wanted - along[:, None] * heading, drive / self.control_dt

    def held_pose(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The measured tool pose (world), the command frame's world pose, and where the
        arm's controller holds the tool in that frame (its target in target-delta modes,
        the measured tool otherwise), each ``(num_envs, 7)``."""
        tool = self.agent.frame_pose(self.ee)
        tool_in_frame = self.agent.frame_pose(self.ee, relative_to=self.command_frame)
        frame = pose_multiply(tool, pose_inverse(tool_in_frame))
        held = self.controller.parts[self.arm_name].observe()["target_ee_pose"] if self.from_target else tool_in_frame
        return tool, frame, held

    def commanded_tool(self) -> np.ndarray:
        """Where the arm's controller holds the tool, ``(num_envs, 3)`` (world): its
        target in target-delta modes, the measured tool otherwise."""
        tool, frame, held = self.held_pose()
        position: np.ndarray = pose_multiply(frame, held)[:, :3] if self.from_target else tool[:, :3]
        return position

    def tool(self) -> np.ndarray:
        return self.agent.frame_pose(self.ee)

    def self_contact(self, q: np.ndarray) -> np.ndarray:
        """Per env: would the robot touch itself with the arm's joints at ``q``
        ``(num_envs, k)`` (the rest of the robot as it is; MuJoCo's collision detection
        on a scratch copy of the env's state, contacts closer than 1 mm)."""
        return self._touching(q, 2)

    def scene_contact(self, q: np.ndarray, ignore: str) -> np.ndarray:
        """Per env: would the robot press into the scene (the table, the floor) with the
        arm's joints at ``q`` ``(num_envs, k)``, body ``ignore`` (the cube) left out;
        as :meth:`self_contact`."""
        return self._touching(q, 1, self.env.model.body(ignore).id)

    def on_table(self) -> np.ndarray:
        """Per env: does the robot touch the table now (its contacts in the env's state)."""
        model = self.env.model
        table = model.body("table").id
        robot = set(self.agent.index.subtree_bodies(self.agent.index.root_body_id))
        bodies = model.geom_bodyid
        touching = np.zeros(self.env.num_envs, dtype=bool)
        for env, data in enumerate(self.env.scene.world.datas):
            for c in data.contact[: data.ncon]:
                pair = (int(bodies[c.geom1]), int(bodies[c.geom2]))
                if table in pair and (pair[0] in robot or pair[1] in robot):
                    touching[env] = True
                    break
        return touching

    def force_on(self, body: str) -> np.ndarray:
        """The robot's contact force on ``body`` now, per env ``(num_envs, 3)`` (N, world
        axes; the sum over the env's contacts between the robot's bodies and it)."""
        model = self.env.model
        target = model.body(body).id
        robot = set(self.agent.index.subtree_bodies(self.agent.index.root_body_id))
        bodies = model.geom_bodyid
        total = np.zeros((self.env.num_envs, 3))
        wrench = np.zeros(6)
        for env, data in enumerate(self.env.scene.world.datas):
            for i, c in enumerate(data.contact[: data.ncon]):
                first, second = int(bodies[c.geom1]), int(bodies[c.geom2])
                if target not in (first, second) or not (first in robot or second in robot):
                    continue
                # the force geom1 exerts on geom2, in the contact frame (its rows: normal, tangents)
                mujoco.mj_contactForce(model, data, i, wrench)
                force = c.frame.reshape(3, 3).T @ wrench[:3]
                total[env] += force if second == target else -force
        return total

    def _touching(self, q: np.ndarray, robot_bodies: int, skip: int = -1) -> np.ndarray:
        """Per env: any contact closer than 1 mm at ``q`` between ``robot_bodies`` (2:
        both, 1: one) of the robot's bodies and the rest, neither of them body ``skip``."""
        model = self.env.model
        scratch = mujoco.MjData(model)
        robot = set(self.agent.index.subtree_bodies(self.agent.index.root_body_id))
        bodies = model.geom_bodyid
        touching = np.zeros(len(q), dtype=bool)
        for env, (data, joints) in enumerate(zip(self.env.scene.world.datas, self.robot_qpos(q), strict=True)):
            scratch.qpos[:] = data.qpos
            scratch.qpos[self.agent.qpos_adr] = joints
            mujoco.mj_forward(model, scratch)
            for c in scratch.contact[: scratch.ncon]:
                pair = (int(bodies[c.geom1]), int(bodies[c.geom2]))
                if c.dist < -1e-3 and skip not in pair and sum(b in robot for b in pair) == robot_bodies:
                    touching[env] = True
                    break
        return touching

    def ee_command(
        self, position: np.ndarray, quat: np.ndarray | None, speed: float | np.ndarray = np.inf
    ) -> np.ndarray:
        """Raw end-effector delta towards tool ``position`` (and orientation ``quat``,
        world frame): the difference from the controller's target (``target_ee_pose``)
        in target-delta modes, from the measured tool otherwise, in the command frame,
        shortened (not clipped per axis, which would bend the path) to at most ``speed``
        (m per step; a number, or ``(num_envs, 1)`` per env) and what one action may command."""
        tool, root, base = self.held_pose()
        wanted = pose_multiply(pose_inverse(root), np.concatenate([position, tool[:, 3:] if quat is None else quat], 1))
        controller = self.controller.parts[self.arm_name]
        high = controller.raw_high
        step = shorten(wanted[:, :3] - base[:, :3], np.minimum(high[:3], speed))
        if controller.action_dim == 3:
            return step
        turn = np.zeros_like(step) if quat is None else rotation_error(wanted[:, 3:], base[:, 3:])
        return np.concatenate([step, shorten(turn, high[3:6])], axis=1)

    def solve(
        self,
        position: np.ndarray,
        quat: np.ndarray | None,
        iterations: int = 200,
        restarts: int = 8,
        refuse: Any = None,
    ) -> np.ndarray:
        """Arm joints ``(num_envs, k)`` that put the tool at ``position`` (and ``quat``):
        damped least squares on the agent's frame pose and Jacobian, from the measured
        joints; a joint at a limit that the step would push past it is left out of
        that step (so the others take over). Envs it leaves more than 1 cm (weighted
        error) from the target try again from the middle of the joint ranges, then from
        up to ``restarts - 1`` random configurations within the limits (fixed seed), and
        take the first that reaches it (within 1
        cm); where none does, the solution from the measured joints stays (a local
        minimum against joint limits is the usual cause: the WidowX 250 S's shoulder
        and wrist left the tool 13-16 cm off in 12 of 200 PickCube seeds). ``refuse``:
        a test of solutions (arm joints ``(num_envs, k)`` -> ``(num_envs,)`` bools);
        envs whose solution it refuses try the restarts too."""
        q, error = self.descend(self.agent.qpos, position, quat, iterations)
        low = np.where(np.isfinite(self.limits[:, 0]), self.limits[:, 0], -np.pi)
        high = np.where(np.isfinite(self.limits[:, 1]), self.limits[:, 1], np.pi)
        rng = np.random.default_rng(0)
        refused = np.zeros(len(q), dtype=bool) if refuse is None else refuse(q[:, self.q_index])
        for attempt in range(restarts):
            stuck = (error > 0.01) | refused
            if not stuck.any():
                break
            start = q.copy()
            # the first retry from the middle of every joint's range (an arm bent at each
            # joint, far from its stops); then random configurations
            seeds = 0.5 * (low + high) if attempt == 0 else rng.uniform(low, high, (len(q), len(low)))
            start[:, self.q_index] = np.where(stuck[:, None], seeds, q[:, self.q_index])
            retried, retried_error = self.descend(start, position, quat, iterations)
            better = stuck & (retried_error <= 0.01)  # a restart that reaches it
            if refuse is not None and better.any():
                accepted = ~refuse(retried[:, self.q_index])
                better &= accepted | ~refused  # a refused solution only gives way to an accepted one
                refused[better] = ~accepted[better]
            q[better], error[better] = retried[better], retried_error[better]
        solution: np.ndarray = q[:, self.q_index]
        return solution

    def arm_jacobian(self, q: np.ndarray, rows: int) -> np.ndarray:
        """The tool's Jacobian ``(num_envs, rows, k)`` over the arm's joints at the robot's
        joints ``q`` ``(num_envs, nq)``, joints that follow an arm joint moving with it."""
        full_jacobian = self.agent.frame_jacobian(self.ee, qpos=q)[:, :rows]
        jacobian = full_jacobian[:, :, self.v_index]
        for _, follower_v, column, _, slope in self.followers:  # coupled joints move with their leader
            jacobian[:, :, column] += slope * full_jacobian[:, :, follower_v]
        return jacobian

    def solve_with_base(self, position: np.ndarray, quat: np.ndarray, probe: float, refuse: Any = None) -> np.ndarray:
        """:meth:`solve`, after :meth:`plan_base_assist` (with ``probe``); envs the base
        assists solve for ``position`` moved along the heading by what the arm alone
        leaves short that way (the base drives there: :meth:`ramp`'s ``tool_goal``), so
        that the arm's joints need not bend towards a point off their reach."""
        self.plan_base_assist(position, quat, probe)
        q = self.solve(position, quat, refuse=refuse)
        if not self.assist.any():
            return q
        heading = self.heading()
        short = np.sum((position - self.tool_at(q)) * heading, axis=1)
        within = position - np.where(self.assist, short, 0.0)[:, None] * heading
        again = self.solve(within, quat, refuse=refuse)
        out: np.ndarray = np.where(self.assist[:, None], again, q)
        return out

    def descend(
        self, start: np.ndarray, position: np.ndarray, quat: np.ndarray | None, iterations: int
    ) -> tuple[np.ndarray, np.ndarray]:
        """``iterations`` damped-least-squares steps from the robot's joints ``start``
        ``(num_envs, nq)``: the joints reached and the remaining weighted error (m) per env."""
        q = start.copy()
        for follower_q, _, column, offset, slope in self.followers:
            q[:, follower_q] = offset + slope * q[:, self.q_index[column]]
        rows = 3 if quat is None else 6
        weight, damping = 0.3, 0.05
        low, high = self.limits[:, 0], self.limits[:, 1]
        for _ in range(iterations):
            pose = self.agent.frame_pose(self.ee, qpos=q)
            jacobian = self.arm_jacobian(q, rows)
            error = position - pose[:, :3]
            if quat is not None:
                error = np.concatenate([error, weight * rotation_error(quat, pose[:, 3:])], axis=1)
                jacobian[:, 3:] *= weight
            arm = q[:, self.q_index]
            free = np.ones_like(arm, dtype=bool)
            for _ in range(3):
                masked = jacobian * free[:, None, :]
                system = masked @ np.swapaxes(masked, 1, 2) + damping**2 * np.eye(rows)
                step = (np.swapaxes(masked, 1, 2) @ np.linalg.solve(system, error[:, :, None]))[:, :, 0]
                blocked = ((arm <= low + 1e-9) & (step < 0)) | ((arm >= high - 1e-9) & (step > 0))
                if not (blocked & free).any():
                    break
                free &= ~blocked
            q[:, self.q_index] = np.clip(arm + np.clip(step, -0.2, 0.2), low, high)
            for follower_q, _, column, offset, slope in self.followers:
                q[:, follower_q] = offset + slope * q[:, self.q_index[column]]
        pose = self.agent.frame_pose(self.ee, qpos=q)
        error = position - pose[:, :3]
        if quat is not None:
            error = np.concatenate([error, weight * rotation_error(quat, pose[:, 3:])], axis=1)
        return q, np.linalg.norm(error, axis=1)

    def nearest_turns(self, goal: np.ndarray, start: np.ndarray) -> np.ndarray:
        """``goal`` ``(num_envs, k)`` with whole turns added to or taken from the joints
        that allow it (:attr:`turns`) so that each lies nearest ``start`` within its
        limits: the same pose, less travel (a UR's IK solution 2 pi away is one the
        ramp's 1.5 s cannot drive, and the arm began the descent still turning)."""
        shifted = goal.copy()
        for k in np.flatnonzero(self.turns):
            low, high = self.limits[k]
            nearest = goal[:, k] + 2.0 * np.pi * np.round((start[:, k] - goal[:, k]) / (2.0 * np.pi))
            for candidate in (nearest, nearest - 2.0 * np.pi, nearest + 2.0 * np.pi):
                closer = (candidate >= low) & (candidate <= high)
                closer &= np.abs(candidate - start[:, k]) < np.abs(shifted[:, k] - start[:, k])
                shifted[closer, k] = candidate[closer]
        return shifted

    def ramp(
        self,
        step: Any,
        goal_q: np.ndarray,
        steps: int,
        gripper_open: np.ndarray | None,
        tool_goal: np.ndarray | None = None,
    ) -> None:
        """Drive the arm joints to ``goal_q`` along a smooth ramp (joint-position mode),
        the last 5 steps holding the goal, then holding it on until every env's arm has
        arrived, or will not arrive in time (:data:`ARRIVED`, at most
        :data:`SETTLE_STEPS` steps; none where the drives kept up). With ``tool_goal``
        (world, ``(num_envs, 3)``), envs the base assists (:meth:`plan_base_assist`) also drive the base along its
        heading by what the arm's solution leaves short of it that way, spread over the ramp."""
        self.set_mode("pd_joint_pos")
        start = self.agent.qpos[:, self.q_index]
        goal_q = self.nearest_turns(goal_q, start)
        base_goal = None
        if tool_goal is not None and self.assist.any():
            short = tool_goal - self.tool_at(goal_q)
            heading = self.heading()
            base_goal = (
                self.agent.base_pos + np.where(self.assist, np.sum(short * heading, axis=1), 0.0)[:, None] * heading
            )
        for k in range(steps):
            blend = 0.5 - 0.5 * math.cos(math.pi * min(1.0, (k + 1) / max(1, steps - 5)))
            speed = None
            if base_goal is not None:
                left = np.sum((base_goal - self.agent.base_pos) * self.heading(), axis=1)
                speed = left / (self.control_dt * max(1, steps - 5 - k))
            step(self.action(start + blend * (goal_q - start), gripper_open, speed))
        # Drives slower than the ramp (a file's position servos, their force limit
        # over their damping below the ramp's speed) are waited for: the end-effector
        # stages start from the pose the arm is in, and hold its orientation.
        for left in range(SETTLE_STEPS, 0, -1):
            lag = goal_q - self.agent.qpos[:, self.q_index]
            speed_now = self.agent.qvel[:, self.v_index]
            # a joint still short of the goal, moving towards it fast enough to arrive
            # in the steps left (not one held back by a contact or creeping)
            arriving = (np.abs(lag) >= ARRIVED) & (lag * speed_now > 0.0)
            arriving &= np.abs(speed_now) * left * self.control_dt >= np.abs(lag) - ARRIVED
            if not arriving.any():
                break
            step(self.action(goal_q, gripper_open, None if base_goal is None else np.zeros(len(goal_q))))


def grasp_orientation(
    tool_quat: np.ndarray, cube_quat: np.ndarray, approach: np.ndarray, closing: np.ndarray
) -> np.ndarray:
    """Tool orientations ``(n, 4)`` with the fingers pointing down and closing across the
    pair of cube faces nearest to the way they close now."""
    down = np.array([0.0, 0.0, -1.0])
    tool_basis = np.stack([approach, closing, np.cross(approach, closing)], axis=1)  # columns
    out = np.empty((len(tool_quat), 4))
    for env, (now, cube) in enumerate(zip(quat_to_matrix(tool_quat), quat_to_matrix(cube_quat), strict=True)):
        closing_now = now @ closing
        faces = [sign * cube[:, k] for k in (0, 1) for sign in (1.0, -1.0)]
        faces = [f - f[2] * np.array([0.0, 0.0, 1.0]) for f in faces]
        across = max(faces, key=lambda f: float(f @ closing_now))
        across /= np.linalg.norm(across)
        world_basis = np.stack([down, across, np.cross(down, across)], axis=1)
        rotation = world_basis @ tool_basis.T
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, rotation.reshape(-1))
        out[env] = quat
    return out


#: After the ramp, the arm holds its goal while in any env an arm joint is more than
#: ``ARRIVED`` (rad or m) short of it and moving towards it fast enough to get within
#: that in the steps left, at most ``SETTLE_STEPS`` control steps: the end-effector
#: stages hold the orientation the arm has when they start, and the push leans 0.3 rad.
#: (gymnasium-robotics' Franka kitchen, whose file's servos move its joints at most
#: 0.87 and 1.2 rad/s (force limit over joint damping), ended the ramp up to 0.37 rad
#: short in seed 1 of PushCube. Joints held back by a contact, or creeping, are not
#: waited for: the bare xArm6's pushes ended the ramp 0.15-0.81 rad short at under
#: 0.14 rad/s.)
ARRIVED, SETTLE_STEPS = 0.05, 20
#: How far along its heading the base must be able to spare the arm (in reaches): where
#: the arm alone cannot move the turned tool this far ahead and behind, the base carries
#: the tool's moves that way (:meth:`Arm.plan_base_assist`). A tenth of the reach: the
#: tasks spread cubes and goals about that far from the workspace centre.
BASE_PROBE = 0.1


# -- PickCube ---------------------------------------------------------------------------------
APPROACH, DESCEND, CLOSE, RAISE, CARRY = range(5)
#: The raise waits for the gripper to stop closing (its opening, 0 closed to 1 open,
#: changing less than this in a control step; at most 30 steps): a gripper slower than
#: the close's 10 steps caught the cube by its top edge on the way up.
CLOSED_STILL = 0.005
#: Largest tool speed of the end-effector stages, in reaches per step (0.95 m/s for the Panda).
SPEED = 0.05
#: How far below the cube's centre the grasp point goes, in cube edges.
DEPTH = 0.2
#: How far above the table the open fingers' tips stay while the tool descends (m).
TIP_CLEARANCE = 0.002
#: Damped-least-squares steps from a candidate pose above the cube to the grasp pose
#: below it, to see whether the arm would meet the table on the way down.
DESCENT_ITERATIONS = 50


def record(env: Any, frames: list[np.ndarray] | None) -> None:
    """Append ``env.render()``'s frame (every env's, stacked) to ``frames`` unless it is ``None``."""
    if frames is not None:
        frames.append(np.asarray(env.render()))


class Episode:
    """One episode of every env of ``env``, reset with ``seed``: steps it, keeps per env
    whether it has succeeded at any step, and appends each rendered frame to ``frames``
    (unless ``None``) after the reset and after every step."""

    def __init__(self, env: Any, seed: int, frames: list[np.ndarray] | None) -> None:
        self.env, self.frames = env, frames
        env.reset(seed=seed)
        record(env, frames)
        self.success = np.zeros(env.num_envs, dtype=bool)
        self.steps = 0
        self.limit = env.max_episode_steps or 100

    def step(self, action: np.ndarray) -> None:
        info = self.env.step(action)[4]
        self.success |= np.asarray(info["success"], dtype=bool).reshape(self.env.num_envs)
        self.steps += 1
        record(self.env, self.frames)

    @property
    def running(self) -> bool:
        return self.steps < self.limit


def in_tool(quat: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """``offset`` (a vector in the tool frame, ``(3,)``) in world axes for tool
    orientations ``quat`` ``(n, 4)``: ``(n, 3)``."""
    rotated: np.ndarray = np.einsum("nij,j->ni", quat_to_matrix(quat), offset)
    return rotated


def solve_pick(env: Any, seed: int, turn_steps: int = 30, frames: list[np.ndarray] | None = None) -> np.ndarray:
    """Run one episode in every env of ``env`` (a ``PickCube-v1`` env, reset with
    ``seed``); per env, whether it succeeded. ``frames``: a list to append
    ``env.render()``'s frame to, after the reset and after every step."""
    episode = Episode(env, seed, frames)
    arm = Arm(env)
    layout, geometry = env.layout, env.layout.gripper
    approach, closing = np.array(geometry.approach_axis), np.array(geometry.closing_axis)
    grasp_point = np.array(geometry.grasp_point)
    n, edge = env.num_envs, 2.0 * layout.cube_half_size
    above = np.array([0.0, 0.0, 0.1 * layout.reach + edge])

    def tool_target(grasp_at: np.ndarray, quat: np.ndarray) -> np.ndarray:
        return grasp_at - in_tool(quat, grasp_point)

    def lowest(cube: np.ndarray) -> np.ndarray:
        """Where the grasp point descends to: into the cube, the fingertips above the table."""
        deeper = cube - DEPTH * edge * np.array([0.0, 0.0, 1.0])
        deeper[:, 2] = np.maximum(deeper[:, 2], layout.table_height + geometry.tip_reach + TIP_CLEARANCE)
        return deeper

    # 1. Turn: joint positions along a ramp to the IK solution above the cube, one from
    # which the descent keeps the arm off the table (an elbow bent down, near the arm's
    # base, would meet it: the UR3 file with a gripper piece)
    cube = env.body_pose("cube")
    quat = grasp_orientation(arm.tool()[:, 3:], cube[:, 3:], approach, closing)
    turned = tool_target(cube[:, :3] + above, quat)
    low = tool_target(lowest(cube[:, :3]), quat)

    def descent_meets_table(q: np.ndarray) -> np.ndarray:
        reached, _ = arm.descend(arm.robot_qpos(q), low, quat, DESCENT_ITERATIONS)
        return arm.scene_contact(reached[:, arm.q_index], "cube")

    arm.ramp(
        episode.step,
        arm.solve_with_base(turned, quat, BASE_PROBE * layout.reach, refuse=descent_meets_table),
        turn_steps,
        np.ones(n, dtype=bool),
        turned,
    )
    # 2. End-effector deltas.
    arm.set_mode(end_effector_mode(arm.agent, rotation=False))
    stage = np.full(n, APPROACH)
    in_stage = np.zeros(n, dtype=int)
    grasp_at = np.zeros((n, 3))
    rest_z = layout.table_height + layout.cube_half_size
    while episode.running:
        cube = env.body_pose("cube")[:, :3]
        tool = arm.tool()
        point = tool[:, :3] + in_tool(tool[:, 3:], grasp_point)
        lifted = cube.copy()
        lifted[:, 2] = np.maximum(env.goal_pos[:, 2], rest_z + edge)
        # the fingertips stay above the table (they would press on it and stall the fingers)
        deeper = lowest(cube)
        cube_at = np.where((stage == RAISE)[:, None], lifted, env.goal_pos)  # where the cube goes next
        target = np.where((stage == APPROACH)[:, None], cube + above, deeper)
        target = np.where((stage == CLOSE)[:, None], grasp_at, target)
        target = np.where((stage >= RAISE)[:, None], point + cube_at - cube, target)  # carry the cube
        error = np.linalg.norm(target - point, axis=1)
        wanted, drive = arm.base_share(tool[:, :3] + target - point, SPEED * layout.reach)
        command = arm.ee_command(wanted, quat, speed=SPEED * layout.reach)
        # Near the goal, stop commanding: in a target-delta mode the arm then holds still.
        arrived = (stage == CARRY) & (np.linalg.norm(env.goal_pos - cube, axis=1) < 0.25 * env.goal_threshold)
        command[arrived], drive[arrived] = 0.0, 0.0
        last_opening = arm.agent.gripper_opening()
        episode.step(arm.action(command, stage < CLOSE, drive))
        opening = arm.agent.gripper_opening()
        in_stage += 1
        advance = (
            ((stage == APPROACH) & ((error < 0.25 * edge) | (in_stage > 15)))
            | ((stage == DESCEND) & ((error < 0.1 * edge) | (in_stage > 20)))
            | ((stage == CLOSE) & (in_stage > 10) & ((abs(opening - last_opening) < CLOSED_STILL) | (in_stage > 30)))
            | ((stage == RAISE) & ((error < 0.25 * edge) | (in_stage > 15)))
        )
        grasp_at = np.where(((stage == DESCEND) & advance)[:, None], target, grasp_at)
        stage = np.where(advance, np.minimum(stage + 1, CARRY), stage)
        in_stage[advance] = 0
    return episode.success


# -- ReachPose --------------------------------------------------------------------------------
def solve_reach(env: Any, seed: int, turn_steps: int = 30, frames: list[np.ndarray] | None = None) -> np.ndarray:
    """Run one episode in every env of ``env`` (a ``ReachPose-v1`` env, reset with
    ``seed``); per env, whether it succeeded. ``frames``: as :func:`solve_pick`."""
    episode = Episode(env, seed, frames)
    arm = Arm(env)
    n = env.num_envs

    position, quat = env.goal_pose[:, :3], env.goal_pose[:, 3:] if env.with_orientation else None
    opened = np.ones(n, dtype=bool) if arm.gripper_joints else None
    # 1. Joint positions along a ramp to the IK solution; 2. end-effector deltas.
    arm.ramp(episode.step, arm.solve(position, quat), turn_steps, opened)
    arm.set_mode(end_effector_mode(arm.agent, rotation=env.with_orientation))
    while episode.running:
        episode.step(arm.action(arm.ee_command(position, quat), opened))
    return episode.success


# -- PushCube ---------------------------------------------------------------------------------
ABOVE_BEHIND, DOWN_BEHIND, LIFT, PUSH = range(4)
#: Largest tool speed while pushing, in reaches per step (0.28 m/s for the Panda at
#: 20 Hz); twice that coming down to the table.
PUSH_SPEED = 0.015
#: How far behind the cube's centre the tool point comes down, beyond half an edge, in
#: reaches; nearer where the table ends: at least EDGE_MARGIN in from its edge, and at
#: least EDGE_MARGIN beyond the cube's face.
CLEARANCE, EDGE_MARGIN = 0.08, 0.02
#: How far the fingers lean from straight down into the push (rad; 17 deg): a wrist
#: that need not point straight down reaches lower near the arm's base (seeds 0-19:
#: 0.3 took google_robot 14 -> 18, koch-v1.1 15 -> 20, so100 6 -> 11, spot 18 -> 20 of 20);
#: back from it by as much where leaning in has the arm touch itself, straight down (else
#: back) where the arm's IK cannot hold it along the push (:func:`path_error`, :func:`solve_push`).
TILT = 0.3
#: The push's path as the lean is chosen (:func:`solve_push`): this many points from
#: the push start to the goal, each solved from the last by ``PATH_ITERATIONS``
#: damped-least-squares steps; a lean whose tool point the arm's IK leaves farther than
#: ``PATH_TOLERANCE`` m from any of them is not held.
PATH_POINTS, PATH_ITERATIONS, PATH_TOLERANCE = 8, 30, 0.01
#: How high the fingertips push, over the table, in cube edges (after touching it).
TIP_HEIGHT = 0.15
#: Where the tool point aims while pushing: behind the cube's centre on its line to the
#: goal, in cube edges (the tool, in the way, pushes the cube; off the line, it steers).
AIM_BEHIND = 0.25
#: Off the line by more than this many cube edges (the tool point from the line through
#: the cube's centre to the goal), the tool backs off to ``BACK_OFF`` edges behind the
#: cube's centre on the line, and pushes on once back within half of it.
OFF_LINE, BACK_OFF = 0.2, 1.5
#: While pushing, once the cube has stalled for ``STALL_STEPS`` steps in a row (moved
#: less than ``STALL`` times the push's top speed, ``PUSH_SPEED`` reaches, in each) with
#: the robot's contact force on it pointing down by more than ``PRESS`` times its
#: horizontal part, the tool point rises ``RISE`` cube edges each step. A push that
#: presses the cube onto the table adds that force to what the table's friction holds
#: (coefficient 1 here, MuJoCo's default for both geoms): once the downward part reaches
#: the horizontal one, no push slides the cube. Stretch's pushes stalled so (seed 0, its
#: last 45 steps: 10.5 N along the table, 10-11 N down, the table carrying 14-16 N
#: under the 4.0 N cube): its arm's IK, which solves for the position alone, put part of
#: the tool's 3.7 cm lead into the wrist pitch (0.022 rad, which would raise the leaning
#: fingers) and the lift 1.2 mm lower to make up for it; the cube's face held the rubber
#: tip by friction, the pitch stayed, and the stiff lift (10000 N/m) pressed down while
#: the telescope (5000 N/m on its lead segment, 312 N/m at the tip) pushed with 10 N.
#: A cube that moves, or that is pressed down only as the push starts, is left alone:
#: rising whenever the robot pressed down cost the SO-100 seed 4 of 20 and the bare
#: xArm6 seed 8; rising after one stalled step cost the Panda with the wrist camera seed
#: 130 of 200 (its first contact presses down before the cube slides; the raised tool
#: ended its push short at the end of its reach; with 4 steps it rises twice there,
#: 1.2 mm, and the cube still ends 0.6 mm outside the goal).
#: The push rises so too where the cube has stalled with the robot touching the table:
#: the table carries part of the arm's weight on the tool and its friction (coefficient
#: 1) holds the tool back. The WidowX 250 S at 100 Hz (16 of 200 seeds missed, 184/200;
#: 2026-11-29): its fingertips, driven onto the table, sank 2.8-3.8 mm into MuJoCo's soft
#: contact (1.4-1.9 mm at 160 Hz), so the push's height, measured there, stood 1.7 mm
#: lower; the tool, 3.5 mm under its target as its soft servo loop carries the arm
#: (kp 18.9 N*m/rad per XM430), dragged its fingertips on the table for the rest of the
#: episode in each miss (51-54 of the last 55 steps; 0.6 on average in the successes),
#: the table pressing up on it with 10-14 N and holding it back with 8-10 N, the drives
#: at a third of their torque limits at most, the target 18 mm ahead, the cube creeping
#: 0.3 mm a step. Rising then: 200/200 at 100 Hz and at 160 Hz (199/200 before: seed
#: 191 dragged so at both steps, 50 of the last 55 steps at 160 Hz); every other robot's
#: 20-seed count the same, on 200 seeds Stretch and both bare xArm6s one more each
#: (docs/tasks.md, "The WidowX 250 S's dragged pushes").
PRESS, RISE, STALL, STALL_STEPS = 0.5, 0.015, 0.25, 4


def push_orientation(
    tool_quat: np.ndarray, approach: np.ndarray, closing: np.ndarray, push: np.ndarray, lean: np.ndarray
) -> np.ndarray:
    """Tool orientations ``(n, 4)`` with the fingers (``approach``, tool frame) pointing
    down, leaning ``lean`` ``(n,)`` (rad) into the push direction ``push`` ``(n, 3)``
    (back from it where negative), and the closing axis horizontal, square to it (the
    way nearer to the tool's closing axis now, ``tool_quat``): the closed fingers push
    side by side."""
    down = np.array([0.0, 0.0, -1.0])
    tool_basis = np.stack([approach, closing, np.cross(approach, closing)], axis=1)
    out = np.empty((len(tool_quat), 4))
    for env, (along, now, tilt) in enumerate(zip(push, quat_to_matrix(tool_quat), lean, strict=True)):
        across = np.cross(down, along)
        if float(across @ (now @ closing)) < 0.0:  # of the two ways, the nearer to the tool's now
            across = -across
        pointing = math.cos(tilt) * down + math.sin(tilt) * along  # leaning into the push
        world_basis = np.stack([pointing, across, np.cross(pointing, across)], axis=1)
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, (world_basis @ tool_basis.T).reshape(-1))
        out[env] = quat
    return out


def push_point(geometry: Any, half: float) -> np.ndarray:
    """The point of the closed gripper that pushes, in the tool frame ``(3,)`` (m): the
    grasp point, or, where it lies farther than ``half`` (half the cube's edge, m) from
    every closed finger (``geometry.closed_clearance``), the grasp point moved across
    the approach axis to where the closed fingers are (``geometry.closed_point``): a
    one-jaw gripper's moving jaw closes on its fixed jaw, to the side (the SO-100 file's
    2.2 cm, the grasp point 2.6 cm from either jaw), and the closed jaws, aimed by the
    grasp point, passed beside the cube while the grasp point stood in it untouched."""
    grasp = np.array(geometry.grasp_point)
    if geometry.closed_point is None or not geometry.closed_clearance > half:
        return grasp
    approach = np.array(geometry.approach_axis)
    aside = np.array(geometry.closed_point) - grasp
    aside -= approach * float(aside @ approach)  # the descent finds the table's height itself
    return grasp + aside


def path_error(arm: Arm, path: np.ndarray, quat: np.ndarray, point_in_tool: np.ndarray) -> np.ndarray:
    """How far ``(num_envs,)`` (m, the worst point) the arm's IK leaves the tool point
    from the push's ``path`` ``(m, num_envs, 3)`` (world) with the tool held at ``quat``
    ``(num_envs, 4)``: the first point solved as the turn solves (:meth:`Arm.solve`, its
    restarts), each next one by :data:`PATH_ITERATIONS` steps from the last solution
    (a local solve, as the end-effector stages' IK follows the tool)."""
    offset = in_tool(quat, point_in_tool)
    q = arm.robot_qpos(arm.solve(path[0] - offset, quat))
    worst = np.zeros(len(quat))
    for point in path:
        q, _ = arm.descend(q, point - offset, quat, PATH_ITERATIONS)
        worst = np.maximum(worst, np.linalg.norm(arm.tool_at(q[:, arm.q_index]) - (point - offset), axis=1))
    return worst


def to_goal(cube: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """Horizontal unit vectors ``(n, 3)`` from the cube centres to the goals ``(n, 3)``."""
    along = goal - cube
    along[:, 2] = 0.0
    along /= np.maximum(np.linalg.norm(along, axis=1, keepdims=True), 1e-9)
    return along


def solve_push(env: Any, seed: int, turn_steps: int = 30, frames: list[np.ndarray] | None = None) -> np.ndarray:
    """Run one episode in every env of ``env`` (a ``PushCube-v1`` env, reset with
    ``seed``); per env, whether it succeeded. ``frames``: as :func:`solve_pick`.

    Per env: the gripper closed (if there is one), the *turn* puts the tool point above
    the push start (behind the cube, on the far side from the goal), fingers down; then
    end-effector deltas: *down* until the fingertips touch the table (the tool stops
    coming down; the model's finger shapes are not needed), *lift* them ``TIP_HEIGHT``
    edges off it, then *push* at that height: the tool point (the closed fingers'
    point where the grasp point lies clear of them: :func:`push_point`) aims at the cube's
    centre from behind along the line from the cube to the goal (redrawn every step,
    which steers the cube back onto it; off the line by more than ``OFF_LINE`` edges,
    the tool first backs off behind the cube on the line), at most ``PUSH_SPEED``
    reaches a step (twice that coming down), rising ``RISE`` edges each step once the
    cube has stalled for ``STALL_STEPS`` steps with the robot's force on it pointing
    down more than ``PRESS`` times its horizontal part or with the robot touching the
    table, and stops commanding once the
    cube's centre is within a quarter of the goal's radius."""
    episode = Episode(env, seed, frames)
    arm = Arm(env)
    layout = env.layout
    n, half, reach = env.num_envs, layout.cube_half_size, layout.reach
    geometry = layout.gripper
    if geometry is not None:
        approach, closing = np.array(geometry.approach_axis), np.array(geometry.closing_axis)
        point_in_tool = push_point(geometry, half)
        closed: np.ndarray | None = np.zeros(n, dtype=bool)
    else:  # a bare flange: its tool frame's z points out of it
        approach, closing = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
        point_in_tool, closed = np.zeros(3), None
    cube = env.body_pose("cube")[:, :3]
    push = to_goal(cube, env.goal_pos)
    # the push start: CLEARANCE behind the cube's near face, but on the table (a mobile
    # robot's cubes lie near the table's edge), at least EDGE_MARGIN in from its edge
    near_edge = layout.table_center[0] - layout.table_half_size[0] + EDGE_MARGIN * reach
    room = np.where(push[:, 0] > 1e-6, (cube[:, 0] - near_edge) / np.maximum(push[:, 0], 1e-6), np.inf)
    distance = np.maximum(np.minimum(half + CLEARANCE * reach, room), half + EDGE_MARGIN * reach)
    now = arm.tool()[:, 3:]
    lean_in = push_orientation(now, approach, closing, push, np.full(n, TILT))
    back = push_orientation(now, approach, closing, push, np.full(n, -TILT))
    for attempt in range(2):
        behind = cube - push * distance[:, None]
        behind[:, 2] = layout.table_height  # the tool point's lowest aim: the fingertips stop it first
        low = behind + np.array([0.0, 0.0, 2.0 * half])  # the tool point as it pushes, about
        # Leaning into the push; where the arm's IK finds no pose for that at the push
        # start without the robot touching itself (its wrist between the fingertips and
        # the arm's own links), leaning back where it finds one for that.
        blocked = arm.self_contact(arm.solve(low - in_tool(lean_in, point_in_tool), lean_in, refuse=arm.self_contact))
        clear = ~blocked
        if blocked.any():
            clear = ~arm.self_contact(arm.solve(low - in_tool(back, point_in_tool), back, refuse=arm.self_contact))
        cramped = blocked & ~clear
        if attempt == 1 or not cramped.any():
            break
        # Neither (a push start near the arm's base, the arm folded over it): the push
        # start halfway to the nearest the edge margin allows, where the arm has more room.
        distance = np.where(cramped, 0.5 * (half + EDGE_MARGIN * reach + distance), distance)
    quat = np.where((blocked & clear)[:, None], back, lean_in)
    above = behind + np.array([0.0, 0.0, 0.1 * reach + 2.0 * half + layout.cube_half_size])
    # Where the arm's IK cannot hold that lean along the push (the tool point off the path
    # by more than PATH_TOLERANCE: an arm whose shoulder stands high over the table), the
    # lean of the others (straight down, then the opposite lean) its IK holds best, if
    # any holds it better.
    end = env.goal_pos - push * AIM_BEHIND * 2.0 * half
    end[:, 2] = low[:, 2]
    path = low[None] + np.linspace(0.0, 1.0, PATH_POINTS)[:, None, None] * (end - low)[None]
    error = path_error(arm, path, quat, point_in_tool)
    leaned = np.sign(np.einsum("ij,ij->i", in_tool(quat, approach), push))  # +1: leaning in
    for tilt in (0.0, -1.0):
        short = error > PATH_TOLERANCE
        if not short.any():
            break
        other = push_orientation(now, approach, closing, push, tilt * TILT * leaned)
        other_error = path_error(arm, path, other, point_in_tool)
        better = short & (other_error < error - PATH_TOLERANCE)
        better &= ~arm.self_contact(arm.solve(low - in_tool(other, point_in_tool), other, refuse=arm.self_contact))
        quat = np.where(better[:, None], other, quat)
        error = np.where(better, other_error, error)
    turn_goal = arm.solve(above - in_tool(quat, point_in_tool), quat, refuse=arm.self_contact)
    arm.ramp(episode.step, turn_goal, turn_steps, closed)
    arm.set_mode(end_effector_mode(arm.agent, rotation=False))
    stage = np.full(n, ABOVE_BEHIND)
    in_stage = np.zeros(n, dtype=int)
    height = np.full(n, layout.table_height + half)  # of the tool point while pushing
    last_z = np.full(n, np.inf)
    realign = np.zeros(n, dtype=bool)
    last_cube = env.body_pose("cube")[:, :3]
    pressed = np.zeros(n, dtype=int)  # steps in a row the cube has stalled pressed down
    while episode.running:
        cube = env.body_pose("cube")[:, :3]
        tool = arm.tool()
        point = tool[:, :3] + in_tool(tool[:, 3:], point_in_tool)
        along = to_goal(cube, env.goal_pos)
        # Off the cube's line to the goal by more than OFF_LINE edges: back off behind the
        # cube on that line (clear of it) before pushing on.
        offset_xy = (point - cube) * np.array([1.0, 1.0, 0.0])
        lateral = np.linalg.norm(offset_xy - np.sum(offset_xy * along, axis=1, keepdims=True) * along, axis=1)
        realign = np.where(
            lateral > OFF_LINE * 2.0 * half, True, np.where(lateral < 0.5 * OFF_LINE * 2.0 * half, False, realign)
        )
        # Stalled, pressing the cube down rather than along it, or held back by the table
        # the tool drags on: the push rises (PRESS, RISE, STALL).
        force = arm.force_on("cube")
        stalled = np.linalg.norm((cube - last_cube)[:, :2], axis=1) < STALL * PUSH_SPEED * reach
        pressed_down = -force[:, 2] > PRESS * np.linalg.norm(force[:, :2], axis=1)
        pressing = (stage == PUSH) & stalled & (pressed_down | arm.on_table())
        pressed = np.where(pressing, pressed + 1, 0)
        last_cube = cube
        height = np.where(pressed >= STALL_STEPS, height + RISE * 2.0 * half, height)
        aim = cube - np.where(realign, BACK_OFF, AIM_BEHIND)[:, None] * 2.0 * half * along
        aim[:, 2] = height
        lifted = behind.copy()
        lifted[:, 2] = height
        target = np.where((stage == ABOVE_BEHIND)[:, None], above, behind)
        target = np.where((stage == LIFT)[:, None], lifted, target)
        target = np.where((stage == PUSH)[:, None], aim, target)
        speed = np.select([stage == ABOVE_BEHIND, stage == DOWN_BEHIND], [SPEED, 2.0 * PUSH_SPEED], PUSH_SPEED) * reach
        command = arm.ee_command(tool[:, :3] + target - point, None, speed=speed[:, None])
        arrived = (stage == PUSH) & (np.linalg.norm((env.goal_pos - cube)[:, :2], axis=1) < 0.25 * env.goal_radius)
        command[arrived] = 0.0
        episode.step(arm.action(command, closed))
        in_stage += 1
        z = point[:, 2]
        error = np.linalg.norm(target - point, axis=1)
        # down: touched once the tool stops coming down (well above where it aims) with
        # the robot on the table, or at its aim (a tool point at its tip), not while a
        # drive still settling after the turn stops it on the way
        touched = (stage == DOWN_BEHIND) & (
            ((in_stage > 2) & (last_z - z < 0.2 * PUSH_SPEED * reach) & ((error < 0.5 * half) | arm.on_table()))
            | (in_stage > 30)
        )
        height = np.where(touched, z + TIP_HEIGHT * 2.0 * half, height)
        advance = (
            ((stage == ABOVE_BEHIND) & ((error < 0.25 * half) | (in_stage > 15)))
            | touched
            | ((stage == LIFT) & ((error < 0.1 * half) | (in_stage > 5)))
        )
        stage = np.where(advance, np.minimum(stage + 1, PUSH), stage)
        in_stage[advance] = 0
        last_z = z
    return episode.success


SOLVERS = {"PickCube-v1": solve_pick, "PushCube-v1": solve_push, "ReachPose-v1": solve_reach}


def robots_for(task: str) -> list[str]:
    """Registered robots with the parts ``task`` needs (others say why when made)."""
    out = []
    for uid in ra.list_agents():
        try:
            ra.make_env(task, robot_uids=uid).close()
        except ra.ConfigError:
            continue
        out.append(uid)
    return out


def success_rate(task: str, uid: str, seeds: int, seed: int = 0) -> tuple[int, float]:
    """Successes over ``seeds`` envs seeded ``seed, seed + 1, ...`` (one batch), and the
    wall time in seconds."""
    start = time.perf_counter()
    env = ra.make_env(task, robot_uids=uid, num_envs=seeds).unwrapped
    try:
        successes = int(SOLVERS[task](env, seed).sum())
    finally:
        env.close()
    return successes, time.perf_counter() - start


def record_episode(task: str, uid: str, seed: int, path: str) -> bool:
    """One episode of ``task`` by ``uid`` from ``seed``, written to ``path`` (``.gif`` or
    ``.mp4``) as the env renders it (the goal drawn in); whether it succeeded."""
    env = ra.make_env(task, robot_uids=uid, render_mode="rgb_array").unwrapped
    frames: list[np.ndarray] = []
    try:
        succeeded = bool(SOLVERS[task](env, seed, frames=frames)[0])
    finally:
        env.close()
    write_video(path, frames, fps=env.control_freq)
    return succeeded


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--task", choices=TASKS, action="append", help="default: every task")
    parser.add_argument("--robots", nargs="*", help="uids (default: every registered robot the task takes)")
    parser.add_argument("--seeds", type=int, default=20, help="envs (seeds 0 .. N-1) per robot")
    parser.add_argument("--video", help="record one episode (one task, one robot, --seed) to this .gif / .mp4")
    parser.add_argument("--seed", type=int, default=0, help="with --video: the episode's seed")
    args = parser.parse_args(argv)
    if args.seeds < 1 or args.seed < 0:
        parser.error(f"expected --seeds >= 1 and --seed >= 0, got --seeds {args.seeds} and --seed {args.seed}")
    if args.video:
        if len(args.task or ()) != 1 or len(args.robots or ()) != 1:
            parser.error("--video records one episode: give one --task and one robot in --robots")
        succeeded = record_episode(args.task[0], args.robots[0], args.seed, args.video)
        print(
            f"{args.task[0]} {args.robots[0]} seed {args.seed}: {'success' if succeeded else 'no success'}; {args.video}"
        )
        return 0
    print("| task | robot | successes | time |\n|---|---|---|---|")
    for task in args.task or TASKS:
        for uid in args.robots or robots_for(task):
            reason = ra.get_agent(uid).task_limits.get(task)
            if reason and not args.robots:  # declared out of reach: listed, not run
                print(f"| {task} | {uid} | not run: the robot declares it cannot do the task | - |", flush=True)
                continue
            try:
                successes, seconds = success_rate(task, uid, args.seeds)
            except ra.ActionError as error:  # a robot whose action layout the solver cannot fill
                what = str(error).splitlines()[0].rsplit(": ", 1)[-1]
                print(f"| {task} | {uid} | not run: the solver cannot command it ({what}) | - |", flush=True)
                continue
            print(f"| {task} | {uid} | {successes}/{args.seeds} | {seconds:.1f} s |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
