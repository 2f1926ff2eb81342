"""The main job: show a robot move, offline, from its built-in model.

The robot goes through each of its keyframes under joint position control (targets
moved smoothly between poses), then waves its joints about the first keyframe; the
scene camera records a video (GIF or MP4, by the output's suffix) and the run is
summarised. A robot with cameras shows what each of them sees beside the scene view,
at the same height, each panel labelled with its camera's name.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import time
from dataclasses import dataclass, field
from pathlib import Path

import mujoco
import numpy as np
import numpy.typing as npt

from robot_agents.agent import Agent
from robot_agents.agent.index import JointKind
from robot_agents.checks import hold_action
from robot_agents.controllers.joint import PDJointPosConfig
from robot_agents.errors import ConfigError
from robot_agents.media import check_output_path, draw_label, write_video
from robot_agents.parts.declaration import Gripper
from robot_agents.registry import get_agent
from robot_agents.sensors.camera import MAX_SIZE, is_pixel_count
from robot_agents.sensors.framing import framing_camera, robot_bounds
from robot_agents.sensors.renderer import make_renderer
from robot_agents.sensors.rig import CameraRig
from robot_agents.sim.scene import Scene
from robot_agents.validation import is_real

DEMO_MODE = "pd_joint_pos"
SCENE_LABEL = "scene"
"""Label of the scene view when robot camera views are shown beside it."""


@dataclass
class KeyframeResult:
    """How closely the robot reached one keyframe (max abs joint error, rad or m)."""

    name: str
    max_error: float


@dataclass
class DemoSummary:
    uid: str
    dof: int
    control_mode: str
    simulated_seconds: float
    frames: int
    video: Path
    wall_seconds: float
    keyframes: list[KeyframeResult] = field(default_factory=list)
    max_abs_qvel: float = 0.0
    finite: bool = True

    def lines(self) -> list[str]:
        rows = [
            f"robot            {self.uid} ({self.dof} DoF)",
            f"control mode     {self.control_mode}",
            f"simulated        {self.simulated_seconds:.1f} s in {self.wall_seconds:.1f} s wall time",
            f"video            {self.video} ({self.frames} frames)",
        ]
        rows += [
            f"keyframe {k.name:<8s} reached within {k.max_error:.1e} (max joint error, rad/m)" for k in self.keyframes
        ]
        rows.append(
            f"state finite     {self.finite} (no NaN, no MuJoCo instability); peak joint speed {self.max_abs_qvel:.2f}"
        )
        return rows


def run_demo(
    uid: str | type[Agent],
    output: str | Path = "robot_agents_demo.gif",
    seconds_per_pose: float = 2.0,
    fps: int = 10,
    size: tuple[int, int] = (320, 240),
) -> DemoSummary:
    """Run the demo for robot ``uid`` and write the video to ``output``.

    Args:
        uid: Registered robot uid, or a robot class.
        output: Video file; ``.gif`` or ``.mp4`` (needs ``robot-agents[video]``). Its
            directory must exist. Checked before anything is simulated.
        seconds_per_pose: Simulated seconds spent reaching each keyframe.
        fps: Video frame rate (frames per second) to aim for; the actual rate
            divides the control frequency.
        size: Scene view ``(width, height)`` in pixels; robot cameras are shown
            beside it at the same height.

    Raises:
        MediaError: ``output`` has an unsupported suffix, its directory is missing
            or read-only, or ``.mp4`` is asked for without imageio-ffmpeg.
        ConfigError: ``size`` is not two whole numbers of pixels in ``[1, 8192]``, or
            ``fps`` is not a positive number.
    """
    if not (isinstance(size, (tuple, list)) and len(size) == 2 and all(is_pixel_count(v) for v in size)):
        raise ConfigError(
            f"run_demo: expected size to be (width, height), whole numbers of pixels in [1, {MAX_SIZE}], got {size!r}."
        )
    if not (is_real(fps) and fps > 0 and math.isfinite(fps)):
        raise ConfigError(f"run_demo: expected fps to be a positive number of frames per second, got {fps!r}.")
    output = check_output_path(output)
    start = time.perf_counter()
    cls: type[Agent] = get_agent(uid) if isinstance(uid, str) else uid
    mode = DEMO_MODE if DEMO_MODE in cls.modes() else cls.default_mode()
    scene = Scene(cls, control_modes=mode)
    with contextlib.ExitStack() as resources:  # closed also when a step or the video fails
        resources.callback(scene.close)
        agent = scene.agents[0]
        scene.reset()
        renderer = make_renderer(scene.render_model, size[0], size[1])
        resources.callback(renderer.close)
        camera = _framing_camera(scene, agent, size[0] / size[1])
        robot_views = _robot_views(scene, size[1])
        if robot_views is not None:
            resources.callback(robot_views.close)
        record_every = max(1, round(scene.control_freq / fps))
        frames: list[npt.NDArray[np.uint8]] = []
        peak_speed = 0.0
        step_count = 0

        def advance(action: npt.NDArray[np.float64]) -> None:
            nonlocal peak_speed, step_count
            agent.set_action(action)
            scene.step()
            peak_speed = max(peak_speed, float(np.max(np.abs(agent.qvel))))
            if step_count % record_every == 0:
                renderer.update_scene(scene.world.render_sources([0])[0], camera=camera)
                scene_view = renderer.render().copy()
                if robot_views is None:
                    frames.append(scene_view)
                else:
                    views = robot_views.capture(scene.world, ("rgb",), env_ids=[0])
                    panels = [draw_label(scene_view, SCENE_LABEL)]
                    panels += [draw_label(images["rgb"][0], name) for name, images in views.items()]
                    frames.append(np.concatenate(panels, axis=1))
            step_count += 1

        steps_per_pose = max(1, round(seconds_per_pose * scene.control_freq))
        position_mode = mode == DEMO_MODE
        results: list[KeyframeResult] = []
        poses = [(name, None) for name in agent.keyframe_names()]
        for name, _ in [*poses[1:], *poses[:1]]:
            goal = agent.keyframe_qpos(name)
            begin = agent.qpos[0]
            hold = None if position_mode else hold_action(agent)  # taken once: the pose reached
            for i in range(steps_per_pose):
                if hold is None:
                    blend = min(1.0, (i + 1) / (0.6 * steps_per_pose))
                    smooth = blend * blend * (3 - 2 * blend)
                    advance(_action_for(agent, begin + smooth * (goal - begin)))
                else:
                    advance(hold)
            if not position_mode:
                scene.reset(keyframes=name)
            results.append(KeyframeResult(name, float(np.max(np.abs(agent.qpos[0] - goal)))))
        if position_mode and poses:
            base = agent.keyframe_qpos(poses[0][0])
            gripping = {
                j for p in agent.parts_by_name.values() if isinstance(p, Gripper) for j in agent.part_joints[p.name]
            }
            # legs carrying the robot keep its stand: out-of-phase waves would topple it
            held = gripping | set(agent.legs.joints)
            movable = [i for i, n in enumerate(agent.joint_names) if n not in held]
            span = agent.qpos_limits[movable, 1] - agent.qpos_limits[movable, 0]
            # Up to 0.35 rad for a hinge, 5 cm for a slide (a floating mount stays in view).
            slides = np.array([j.kind is JointKind.SLIDE for j in agent.index.joints])[movable]
            amplitude = np.minimum(np.where(slides, 0.05, 0.35), 0.15 * np.where(np.isfinite(span), span, 2.0))
            # grippers and hands close and open once meanwhile (their declared poses)
            hands = [p for p in agent.parts_by_name.values() if isinstance(p, Gripper)]
            finger_index = [[agent.joint_names.index(j) for j in agent.part_joints[p.name]] for p in hands]
            for i in range(steps_per_pose * 2):
                phase = 2 * np.pi * i / (steps_per_pose * 2)
                target = base.copy()
                target[movable] += amplitude * np.sin(phase + np.arange(len(movable)))
                closing = 0.5 * (1 - np.cos(phase))  # 0 open, 1 closed, 0 open again
                for part, index in zip(hands, finger_index, strict=True):
                    opened, closed = part.positions(len(index))
                    target[index] = opened + closing * (closed - opened)
                target = np.clip(target, agent.qpos_limits[:, 0], agent.qpos_limits[:, 1])
                advance(_action_for(agent, target))
        finite = bool(np.all(np.isfinite(scene.world.get_state()))) and not np.any(scene.world.instability_counts())
        path = write_video(output, frames, fps=scene.control_freq / record_every)
        summary = DemoSummary(
            uid=cls.uid or cls.__name__,
            dof=agent.dof,
            control_mode=mode,
            simulated_seconds=step_count * scene.control_timestep,
            frames=len(frames),
            video=path,
            wall_seconds=time.perf_counter() - start,
            keyframes=results,
            max_abs_qvel=peak_speed,
            finite=finite,
        )
        return summary


def _robot_views(scene: Scene, height: int) -> CameraRig | None:
    """The robot's own cameras, resized to ``height`` pixels (aspect kept), or ``None``."""
    cameras = [
        dataclasses.replace(
            c, config=c.config.resized(max(1, round(c.config.width * height / c.config.height)), height)
        )
        for c in scene.cameras.cameras.values()
        if c.robot is not None
    ]
    return CameraRig(scene.render_model, cameras) if cameras else None


def _framing_camera(scene: Scene, agent: Agent, aspect: float) -> mujoco.MjvCamera:
    """A free camera that frames the robot at every keyframe (the demo visits each),
    seen from the front left, with room for the motion around them, in an image
    ``aspect`` (width / height) times as wide as tall. Leaves the scene reset to its
    first keyframe."""
    names = agent.keyframe_names()
    lower, upper = robot_bounds(scene.world, [agent.prefix])
    for name in names[1:]:
        scene.reset(keyframes=name)
        low, high = robot_bounds(scene.world, [agent.prefix])
        lower, upper = np.minimum(lower, low), np.maximum(upper, high)
    if len(names) > 1:
        scene.reset(keyframes=names[0])
    return framing_camera(lower, upper, margin=1.1, aspect=aspect)


def _action_for(agent: Agent, qpos_target: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """The ``pd_joint_pos`` action (per part) that commands ``qpos_target`` (shape ``(dof,)``):
    absolute targets; a part with delta targets (legs) steps towards it; a velocity part (a
    mobile base) holds still."""
    parts = []
    for controller in agent.controller.parts.values():
        config = controller.config
        index = [agent.joint_names.index(j) for j in config.joint_names]
        if not isinstance(config, PDJointPosConfig):
            raw = np.zeros(controller.action_dim)
        elif config.use_delta:
            raw = (qpos_target[index] - agent.qpos[0, index])[: controller.action_dim]
        else:
            raw = qpos_target[index][: controller.action_dim]
        parts.append(controller.from_raw(raw))
    return np.concatenate(parts)
