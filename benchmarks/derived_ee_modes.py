"""End-effector modes of two-line arms from model files: the task space derived on
each arm, and how well one delta action lands (docs/using-a-model-file.md, "End-effector
modes of a file's arm").

For each model file: the two-line robot (``uid`` and the path, nothing else), its
derived task space (reach, largest translation per step, modes), then ``--trials``
one-step trials (seeded): a random configuration within 80 % of the arm joints' ranges
(the other joints at the default keyframe), and the tool pose of a configuration at
most 0.15 rad (m) away per joint, kept when neither touches anything (the robot's own
bodies: no floor in this scene) and one normalized delta action reaches it (the
translation within its per-axis bound, the rotation vector within the bounds'
ellipsoid); the robot is reset to the first, steps that action in
``pd_ee_target_delta_pose`` (``pd_ee_target_delta_pos`` for an arm with fewer than 6
joints) and holds the target 1 s. Printed: how many land within 1 mm (and 1 deg for a
pose mode), and the 95th percentiles of the position and rotation errors.

``--keyframe-gains`` declares the drives the library derived before 2026-11-28 (PD gains
critically damped at 10 Hz from each joint's inertia at the default keyframe alone,
``gains_from_inertia`` at that pose, with the file's effort limits): the comparison for
the gains derived over the joints' ranges (``gains_over_configurations``).

Usage: ``python benchmarks/derived_ee_modes.py FILE [FILE ...] [--trials 50]
[--keyframe-gains]`` (the ``mani-skill`` wheel's arms: ``pip download --no-deps
mani-skill==3.0.1`` and unzip ``mani_skill/assets/robots``).
"""

from __future__ import annotations

import argparse
import math
import warnings
from pathlib import Path

import numpy as np

import robot_agents as ra
from robot_agents.actuators.gains import gains_from_inertia
from robot_agents.controllers.task_space import delta_action
from robot_agents.kinematics.rotations import quat_angle

REACH_SHARE = 0.8  # starting configurations: within this share of each joint's range
STEP = 0.15  # the target configuration: at most this far per joint (rad or m)


def two_line(path: Path, keyframe_gains: bool) -> type[ra.Agent]:
    cls: type[ra.Agent] = type("TwoLine", (ra.Agent,), {"uid": f"two_line_{path.stem}", "urdf_path": path})
    if not keyframe_gains:
        return cls
    checked = cls.check()
    model = checked.index.model
    joints = [d.joint for d in checked.drives]
    full = model.qpos0.copy()
    full[checked.index.qpos_adr] = next(iter(checked.keyframes.values())).qpos
    gains = gains_from_inertia(model, joints, full)
    limits = tuple(float(v) if math.isfinite(v) else 1e6 for v in gains.effort_limit)
    drive = ra.PDActuator(
        joints=tuple(joints),
        stiffness=tuple(float(v) for v in gains.stiffness),
        damping=tuple(float(v) for v in gains.damping),
        effort_limit=limits,
    )
    return type("KeyframeGains", (cls,), {"uid": f"{cls.uid}_keyframe_gains", "actuators": (drive,)})


def trial_row(path: Path, trials: int, keyframe_gains: bool) -> str:
    cls = two_line(path, keyframe_gains)
    checked = cls.check()
    arm = next((p for p in checked.parts if isinstance(p, ra.Arm)), None)
    if arm is None or arm.task_space is None:
        return f"| {path.name} | - | - | none | - | - | - |"
    space = arm.task_space
    joints = checked.part_joints[arm.name]
    rotation = "pd_ee_target_delta_pose" in checked.modes
    mode = "pd_ee_target_delta_pose" if rotation else "pd_ee_target_delta_pos"
    scene = ra.Scene(cls, control_modes=mode, floor=False)
    agent = scene.agents[0]
    columns = np.array([agent.joint_names.index(j) for j in joints])
    low, high = agent.qpos_limits[columns, 0], agent.qpos_limits[columns, 1]
    middle, half = (low + high) / 2, REACH_SHARE / 2 * (high - low)
    rest = agent.keyframe_qpos(agent.keyframe_names()[0])
    rng = np.random.default_rng(0)
    errors = []
    while len(errors) < trials:
        start, goal = rest.copy(), rest.copy()
        start[columns] = rng.uniform(middle - half, middle + half)
        goal[columns] = np.clip(start[columns] + rng.uniform(-STEP, STEP, len(columns)), low, high)
        before = agent.frame_pose("ee", qpos=start, relative_to="root")[0]
        after = agent.frame_pose("ee", qpos=goal, relative_to="root")[0]
        action = delta_action(space, before, after, rotation)
        if action is None:
            continue
        agent.reset(qpos=goal)
        if scene.world.datas[0].ncon:  # the target pose touches itself: not reachable
            continue
        agent.reset(qpos=start)
        if scene.world.datas[0].ncon:
            continue
        hold = np.zeros((1, agent.action_space.shape[-1]))  # the gripper (if any) at its middle
        first = hold.copy()
        first[0, : len(action)] = action
        agent.set_action(first)
        scene.step()
        for _ in range(scene.control_freq):
            agent.set_action(hold)
            scene.step()
        pose = agent.frame_pose("ee", relative_to="root")[0]
        angle = math.degrees(float(quat_angle(pose[3:], after[3:]))) if rotation else 0.0
        errors.append((1000 * float(np.linalg.norm(pose[:3] - after[:3])), angle))
    scene.close()
    array = np.array(errors)
    landed = int(np.sum((array[:, 0] <= 1.0) & (array[:, 1] <= 1.0)))
    reach = space.max_translation / 0.1
    modes = "pose" if rotation else "position"
    return (
        f"| {path.name} | {len(joints)} | {reach:.2f} | {modes} ({space.max_translation * 1000:.0f} mm, "
        f"{space.max_rotation} rad a step) | {landed}/{trials} | {np.percentile(array[:, 0], 95):.2f} "
        f"| {np.percentile(array[:, 1], 95):.2f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("paths", type=Path, nargs="+", help="model files of arms")
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--keyframe-gains", action="store_true", help="the drives derived at the keyframe alone")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    print(f"drives: {'at the default keyframe alone' if args.keyframe_gains else 'derived over the joints ranges'}")
    print(
        "| file | arm joints | reach (m) | end-effector modes | landed within 1 mm / 1 deg "
        "| 95th pct position error (mm) | 95th pct rotation error (deg) |"
    )
    print("|---|---|---|---|---|---|---|")
    for path in args.paths:
        print(trial_row(path.resolve(), args.trials, args.keyframe_gains), flush=True)


if __name__ == "__main__":
    main()
