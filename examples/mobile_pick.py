"""Drive a mobile manipulator to a table and pick up a cube (``MobilePickCube-v1``).

Works for every registered robot with a ``Base``, an ``Arm`` with an end effector and a
``Gripper`` (``stretch``, ``google_robot``, ``spot``, ``fetch``). The task starts the robot
1.0-1.5 m from the table, at an angle; the script uses only the robot's public
interface and one control mode, ``pd_ee_target_delta_pos``, whose action holds a slice
for every part (arm: tool displacement; gripper: -1 closes, +1 opens; base: velocity):

1. **Drive.** Where to stand: the task's stance at the table (``env.stance_xy``,
   ``env.stance_yaw``), shifted so that the resting tool comes to lie above the cube
   (never closer to the table than the stance). A go-to-pose controller on
   ``agent.base_pos`` / ``agent.base_rot`` commands the base velocity: a holonomic
   base drives and turns at once; a differential drive turns towards the goal, drives
   (backwards when the goal is behind it), then turns to the goal heading. The arm
   holds its pose: a zero end-effector displacement in the frame that moves with the base.
2. **Pick.** Along the way the fingers point at rest (``env.layout.gripper``: from
   above for Spot, the Google Robot and Fetch, from the side for Stretch): the grasp point to
   a stand-off short of the cube, onto the cube, close the gripper, lift 10 cm.
3. **Report**: success as the task scores it (the cube grasped, 5 cm up).

Run it::

    python examples/mobile_pick.py --robot stretch --seed 0
    python examples/mobile_pick.py --robot spot --seed 3 --video spot.mp4
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

import robot_agents as ra
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.media import write_video

MODE = "pd_ee_target_delta_pos"
#: Go-to-pose gains (1/s) and when the base has arrived (m, rad).
DRIVE_GAIN, TURN_GAIN = 2.0, 3.0
POSITION_TOLERANCE, HEADING_TOLERANCE = 0.005, 0.005
#: The tool moves at most this far per step (m): 0.3 m/s at 20 Hz, 0.1 m/s near the cube.
TOOL_STEP, SLOW_STEP = 0.015, 0.005
#: The grasp point stops this far short of the cube (in cube edges + m), then goes onto
#: its centre, lower by up to this much (cube edges, for fingers coming from above), and
#: lifts it by LIFT (m).
STANDOFF_EDGES, STANDOFF = 1.0, 0.06
DEPTH_EDGES = 0.2
LIFT = 0.1
#: How far above the table the fingertips stay, coming from above (m; as
#: ``scripted_pick.py``'s PickCube solver): the grasp point goes no lower than the table
#: plus the fingers' reach past it (``layout.gripper.tip_reach``) plus this.
TIP_CLEARANCE = 0.002


@dataclass(frozen=True)
class PickResult:
    """What one episode did (lengths in m)."""

    robot: str
    seed: int
    success: bool
    lifted: float  # how far above its resting height the cube ends
    start_distance: float  # from the base's start to where it stood to pick
    driven: float  # length of the path the base drove
    base_error: float  # from where the base stopped to the picking pose
    drive_steps: int
    steps: int
    seconds: float


def wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


def rotate_z(vector: np.ndarray, angle: float) -> np.ndarray:
    """``vector`` (x, y, ...) turned by ``angle`` about +z (x and y only)."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * vector[0] - s * vector[1], s * vector[0] + c * vector[1]])


class MobileManipulator:
    """The robot's base, arm and gripper, and one action vector for all its parts."""

    def __init__(self, env: Any) -> None:
        self.env = env
        self.agent: ra.Agent = env.agent
        parts = self.agent.parts_by_name.values()
        self.base = next(p for p in parts if isinstance(p, ra.Base))
        self.arm = next(p for p in parts if isinstance(p, ra.Arm) and p.end_effectors)
        self.gripper = next(p for p in parts if isinstance(p, ra.Gripper))
        # end-effector commands are expressed in this frame, which moves with the base
        self.command_frame = self.arm.end_effectors[0].command_frame or "root"

    def action(
        self, tool_step: np.ndarray | None = None, gripper_open: bool = True, base: np.ndarray | None = None
    ) -> np.ndarray:
        """The mode's action: the tool's displacement (world, m), the gripper, the base's
        velocity (``(vx, vy, wz)`` or ``(v, wz)``, robot frame); other parts hold."""
        controller = self.agent.controller
        action = np.zeros(controller.action_dim)
        if tool_step is not None:
            frame = quat_to_matrix(self.agent.frame_pose(self.command_frame)[0, 3:])
            arm = controller.parts[self.arm.name]
            action[controller.slices[self.arm.name]] = arm.from_raw((frame.T @ tool_step)[None])[0]
        # the gripper's action is normalized in every generated mode: +1 opens, -1 closes
        action[controller.slices[self.gripper.name]] = 1.0 if gripper_open else -1.0
        if base is not None:
            velocity = controller.parts[self.base.name].from_raw(base[None])[0]
            action[controller.slices[self.base.name]] = velocity
        return action

    def base_velocity(self, goal_xy: np.ndarray, goal_yaw: float, turning: bool) -> np.ndarray:
        """Go-to-pose: the base velocity towards ``goal_xy``, or (``turning``) towards
        ``goal_yaw`` in place."""
        offset = rotate_z(goal_xy - self.agent.base_pos[0, :2], -float(self.agent.base_rot[0]))  # robot frame
        heading_error = wrap(goal_yaw - float(self.agent.base_rot[0]))
        forward = lateral = turn = 0.0
        if turning:
            turn = TURN_GAIN * heading_error
        elif self.base.holonomic:
            forward, lateral = DRIVE_GAIN * offset
            turn = TURN_GAIN * heading_error
        else:
            bearing = math.atan2(offset[1], offset[0])
            reverse = abs(bearing) > math.pi / 2  # the goal is behind: back up to it
            bearing = wrap(bearing - math.pi) if reverse else bearing
            turn = TURN_GAIN * bearing
            if abs(bearing) < 0.1:
                forward = DRIVE_GAIN * float(offset[0])
        speed = math.hypot(forward, lateral)
        if speed > self.base.max_speed:
            forward, lateral = forward * self.base.max_speed / speed, lateral * self.base.max_speed / speed
        turn = float(np.clip(turn, -self.base.max_turn, self.base.max_turn))
        return np.array([forward, lateral, turn] if self.base.holonomic else [forward, turn])


def standing_pose(robot: MobileManipulator, env: Any, cube: np.ndarray) -> tuple[np.ndarray, float]:
    """Where the base stands to pick (x, y) and its heading: the task's stance, shifted
    so that the resting grasp point lies above the stand-off point short of the cube,
    but never closer to the table (which lies along +x)."""
    agent, gripper = robot.agent, env.layout.gripper
    yaw_now, base_now = float(agent.base_rot[0]), agent.base_pos[0, :2]
    tool = agent.tcp_pose[0]
    rotation = quat_to_matrix(tool[3:])
    # the resting grasp point and the way the fingers point, in the base's frame ...
    grasp_in_base = rotate_z((tool[:3] + rotation @ np.array(gripper.grasp_point))[:2] - base_now, -yaw_now)
    approach_in_base = rotate_z(rotation @ np.array(gripper.approach_axis), -yaw_now)
    # ... and in the world once the base stands at the stance's heading
    standoff = STANDOFF_EDGES * 2.0 * env.layout.cube_half_size + STANDOFF
    goal = cube[:2] - rotate_z(approach_in_base, env.stance_yaw) * standoff - rotate_z(grasp_in_base, env.stance_yaw)
    goal[0] = min(goal[0], env.stance_xy[0])
    return goal, float(env.stance_yaw)


def pick(robot_uid: str, seed: int, video: str | None = None) -> PickResult:
    """Run one ``MobilePickCube-v1`` episode with ``robot_uid`` reset with ``seed``."""
    start_time = time.perf_counter()
    env = ra.make_env(
        "MobilePickCube-v1", robot_uids=robot_uid, control_mode=MODE, render_mode="rgb_array" if video else None
    ).unwrapped
    frames: list[np.ndarray] = []
    steps, info = 0, {}

    def step(action: np.ndarray) -> None:
        nonlocal steps, info
        info = env.step(action)[4]
        steps += 1
        if video:
            frames.append(np.asarray(env.render()))

    try:
        env.reset(seed=seed)
        robot = MobileManipulator(env)
        agent, layout = robot.agent, env.layout
        cube = env.body_pose("cube")[0, :3]
        goal_xy, goal_yaw = standing_pose(robot, env, cube)
        start_xy = agent.base_pos[0, :2].copy()

        # 1. Drive: to the goal position, then to the goal heading, then let it settle.
        driven, last = 0.0, start_xy
        for turning in (False, True):
            for _ in range(300):
                done = (
                    abs(wrap(goal_yaw - float(agent.base_rot[0]))) < HEADING_TOLERANCE
                    if turning
                    else np.linalg.norm(goal_xy - agent.base_pos[0, :2]) < POSITION_TOLERANCE
                )
                if done:
                    break
                step(robot.action(np.zeros(3), base=robot.base_velocity(goal_xy, goal_yaw, turning)))
                driven += float(np.linalg.norm(agent.base_pos[0, :2] - last))
                last = agent.base_pos[0, :2].copy()
        for _ in range(5):
            step(robot.action(np.zeros(3)))
        drive_steps = steps
        base_error = float(np.linalg.norm(goal_xy - agent.base_pos[0, :2]))

        # 2. Pick: the grasp point's way points, each held until reached (or for a while).
        tool = agent.tcp_pose[0]
        grasp_offset = quat_to_matrix(tool[3:]) @ np.array(layout.gripper.grasp_point)
        edge = 2.0 * layout.cube_half_size
        approach = quat_to_matrix(tool[3:]) @ np.array(layout.gripper.approach_axis)
        standoff = STANDOFF_EDGES * edge + STANDOFF
        # from above the fingers reach past the middle; from the side they close on the
        # centre, so that the cube does not turn about the line between the fingers
        down = max(0.0, -float(approach[2]))
        grasp_at = cube + approach * DEPTH_EDGES * edge * down
        if down > 0.0:  # the fingertips above the table (the Google Robot's reach 26 mm past its grasp point)
            grasp_at[2] = max(grasp_at[2], layout.table_height + layout.gripper.tip_reach * down + TIP_CLEARANCE)
        lifted_to = grasp_at + np.array([0.0, 0.0, LIFT])
        stages = (  # (grasp point goal, gripper open, tolerance (m), at most steps, tool speed)
            (cube - approach * standoff, True, 0.01, 80, TOOL_STEP),
            (grasp_at, True, 0.005, 40, SLOW_STEP),
            (grasp_at, False, 0.0, 15, TOOL_STEP),
            (lifted_to, False, 0.01, 40, SLOW_STEP),
            (lifted_to, False, 0.0, 10, SLOW_STEP),
        )
        target = tool[:3].copy()  # the controller's tool target: the sum of the commands
        for goal, gripper_open, tolerance, budget, speed in stages:
            for _ in range(budget):
                if tolerance and np.linalg.norm(agent.tcp_pose[0, :3] + grasp_offset - goal) < tolerance:
                    break
                move = goal - grasp_offset - target
                move *= min(1.0, speed / max(float(np.linalg.norm(move)), 1e-9))
                target += move
                step(robot.action(move, gripper_open))
        lifted = float(env.body_pose("cube")[0, 2] - env.cube_rest_z)
        return PickResult(
            robot=robot_uid,
            seed=seed,
            success=bool(info["success"][0]),
            lifted=lifted,
            start_distance=float(np.linalg.norm(goal_xy - start_xy)),
            driven=driven,
            base_error=base_error,
            drive_steps=drive_steps,
            steps=steps,
            seconds=time.perf_counter() - start_time,
        )
    finally:
        if video and frames:
            write_video(video, frames, fps=20)
        env.close()


def mobile_manipulators() -> list[str]:
    """Registered robots with a Base, an Arm with an end effector and a Gripper."""
    out = []
    for uid in ra.list_agents():
        parts = ra.get_agent(uid).check().parts
        if (
            any(isinstance(p, ra.Base) for p in parts)
            and any(isinstance(p, ra.Arm) and p.end_effectors for p in parts)
            and any(isinstance(p, ra.Gripper) for p in parts)
        ):
            out.append(uid)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--robot", default="stretch", choices=mobile_manipulators())
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--video", help="save the episode as a video (.mp4 or .gif)")
    args = parser.parse_args(argv)
    if args.seed < 0:
        parser.error(f"expected --seed >= 0, got {args.seed}")
    result = pick(args.robot, args.seed, args.video)
    print(
        f"{result.robot} seed {result.seed}: {'success' if result.success else 'FAILED'}; "
        f"drove {result.driven:.2f} m ({result.start_distance:.2f} m start to pick) in {result.drive_steps} steps, "
        f"cube lifted {100 * result.lifted:.1f} cm; {result.steps} steps, {result.seconds:.1f} s"
    )
    return 0 if result.success else 1


if __name__ == "__main__":
    sys.exit(main())
