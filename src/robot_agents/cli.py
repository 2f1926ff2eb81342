"""``robot-agents`` command line: ``list``, ``info ROBOT``, ``demo ROBOT``, ``check ROBOT``,
``tune ROBOT``, ``--version``. ROBOT is a registered uid, a model file path (the two-line robot) or
``module:Class``."""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import warnings
from collections.abc import Sequence
from dataclasses import fields
from pathlib import Path
from typing import NoReturn, TextIO

import numpy as np

import robot_agents
from robot_agents.agent import Agent
from robot_agents.agent.declaration import composition
from robot_agents.agent.derived import DERIVED_SOURCE
from robot_agents.errors import RobotAgentsError, did_you_mean
from robot_agents.media.video import SUPPORTED_SUFFIXES, check_output_path
from robot_agents.registry import get_agent, list_agents
from robot_agents.robot_source import OUT_AXES, UP_AXES, FileOptions, resolve_robot
from robot_agents.robots.catalog import BUILTIN_PIECES
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ
from robot_agents.tuning import step_response, timestep

MAX_SECONDS = 60.0
"""Upper bound of ``demo --seconds`` (simulated seconds per pose) and ``check --seconds``."""
CHECK_MIN_SECONDS = 1.0 / DEFAULT_CONTROL_FREQ
"""Lower bound of ``check --seconds``: one control step of the checks' scenes (0.05 s at
their 20 Hz control); fewer seconds ran no random action at all and passed."""
MAX_SUBSTEPS = 1000
"""Upper bound of each ``check --sweep --substeps`` count: 20 kHz at the sweep's 20 Hz
control, a 0.05 ms physics step (the default sweep stops at 50, 1 kHz)."""


class UsageError(Exception):
    """A command-line argument with a bad value (reported in one line, exit status 2)."""


#: argparse's refusal of a value outside an argument's choices (a command, ``--up``,
#: ``--gripper``, ``--at-axis``): the value given and the choices, quoted.
_INVALID_CHOICE = re.compile(r"invalid choice: '([^']*)' \(choose from (.*)\)")


class Parser(argparse.ArgumentParser):
    """argparse's parser whose refusal of a value outside the choices ends with the close
    ones (``invalid choice: 'lst' (choose from ...). Did you mean 'list'?``), as the
    library's errors do."""

    def error(self, message: str) -> NoReturn:
        refused = _INVALID_CHOICE.search(message)
        hint = did_you_mean(refused.group(1), re.findall(r"'([^']*)'", refused.group(2))) if refused else ""
        if hint:
            message += "." + hint
        super().error(message)


def parse_substeps(text: str | None) -> tuple[int, ...] | None:
    """``--substeps``: comma-separated physics substeps per control step to sweep, each a
    whole number from 1 to :data:`MAX_SUBSTEPS` (``None``: the sweep's default, 2-50 at
    20 Hz control: 40 Hz-1 kHz)."""
    if text is None:
        return None
    try:
        values = tuple(int(part) for part in text.split(","))
    except ValueError:
        values = ()
    if not values or min(values) < 1 or max(values) > MAX_SUBSTEPS:
        raise UsageError(
            f"argument --substeps: expected whole numbers from 1 to {MAX_SUBSTEPS} separated by commas "
            f"(e.g. 10,20,50,100; {MAX_SUBSTEPS} is {DEFAULT_CONTROL_FREQ * MAX_SUBSTEPS / 1000:g} kHz at "
            f"{DEFAULT_CONTROL_FREQ} Hz control), got {text!r}"
        )
    return values


def parse_seconds(text: str, what: str = "simulated seconds per pose", minimum: float | None = None) -> float:
    """``--seconds``: a finite number of ``what`` (demo: simulated seconds per pose; check:
    seconds of random actions per mode), > 0 (or >= ``minimum``, and then said why: check
    takes at least one control step, :data:`CHECK_MIN_SECONDS`) and <= :data:`MAX_SECONDS`."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    low_ok = value > 0.0 if minimum is None else value >= minimum
    if not (math.isfinite(value) and low_ok and value <= MAX_SECONDS):
        low = (
            "> 0"
            if minimum is None
            else f">= {minimum:g} (one control step at {DEFAULT_CONTROL_FREQ} Hz, the checks' control rate)"
        )
        raise UsageError(f"argument --seconds: expected a number of {what}, {low} and <= {MAX_SECONDS:g}, got {text!r}")
    return value


def default_demo_output(spec: str) -> str:
    """``demo``'s video when no ``--output`` is given: ``<uid>_demo.gif`` for a registered
    uid (dots kept: ``koch-v1.1_demo.gif``), the file's stem for a model file, the class
    name for ``module:Class``."""
    if spec in list_agents():
        name = spec
    elif ":" in spec:
        name = spec.rpartition(":")[2]
    else:
        name = Path(spec).stem
    return f"{name}_demo.gif"


def _table(rows: list[list[str]], out: TextIO) -> None:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for n, row in enumerate(rows):
        out.write("  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip() + "\n")
        if n == 0:
            out.write("  ".join("-" * w for w in widths) + "\n")


def cmd_list(out: TextIO) -> int:
    from robot_agents.sim.scene import Scene

    rows = [["uid", "dof", "control modes"]]
    for uid in list_agents():
        cls = get_agent(uid)
        scene = Scene(cls)
        rows.append([uid, str(scene.agents[0].dof), ", ".join(cls.modes())])
        scene.close()
    _table(rows, out)
    return 0


def cmd_info(uid: str, out: TextIO, floating: bool = False, cls: type[Agent] | None = None, up: str = "z") -> int:
    """Describe the robot ``uid`` names (``cls``: already resolved, so that its load
    notes are not given twice)."""
    from robot_agents.sim.scene import Scene

    cls = cls if cls is not None else resolve_robot(uid, floating, up)
    scene = Scene(cls)
    agent = scene.agents[0]
    summary = (cls.__doc__ or "").strip().splitlines()
    out.write(f"{uid}: {summary[0] if summary else cls.__name__}\n")
    editor = next((k for k in cls.__mro__ if "edit_model" in vars(k)), None)
    edited = (
        f" (changed as read by {editor.__name__}.edit_model)"
        if editor is not None and editor.__name__ != "AgentDefinition"
        else ""
    )
    out.write(f"model: {cls.model_path()}{edited}\n")
    for prefix, piece in composition(cls).pieces:
        out.write(f"  + {piece.__name__} ({piece.model_path().name}){f' as {prefix!r}' if prefix else ''}\n")
    links = {ee.name: ee.link for part in cls.check().parts for ee in getattr(part, "end_effectors", ())}
    tools = ", ".join(f"{n} ({links[n]})" if links.get(n, n) != n else n for n in agent.frames.end_effectors) or "-"
    out.write(f"root: {'fixed' if cls.fix_root_link else 'free'}; end effectors: {tools}\n")
    parts = "; ".join(f"{p} ({', '.join(joints)})" for p, joints in agent.part_joints.items()) or "-"
    out.write(f"parts: {parts}\n")
    drives: dict[str, list[str]] = {}
    for joint, source in agent.drives.describe():
        drives.setdefault(source, []).append(joint)
    for source, joints in drives.items():
        out.write(f"drive: {source}: {', '.join(joints)}\n")
    unlimited = [
        d.joint for d in cls.check().drives if d.source.startswith(DERIVED_SOURCE) and not math.isfinite(d.effort_limit)
    ]
    if unlimited:
        out.write(
            f"  no effort limit for {', '.join(unlimited)}: the model file gives none; state the motors' with "
            "actuators = (ra.DerivedActuators(effort_limit=..., armature=...),) "
            "(docs/using-a-model-file.md, 'Facts a file leaves out')\n"
        )
    out.write("\n")
    # each drive's limits: effort (N*m or N) and rated speed (rad/s or m/s); "-": none
    limits = {d.joint: (d.effort_limit, d.velocity_limit) for d in cls.check().drives}
    rows = [["joint", "lower", "upper", "effort", "speed"]]
    for name in agent.joint_names:
        info = agent.index.joint(name, "robot-agents info")
        effort, speed = (f"{v:g}" if math.isfinite(v) else "-" for v in limits.get(name, (math.inf, math.inf)))
        if info.nq != 1:  # a ball joint's quaternion: its limit is the largest rotation angle
            limit = f"{info.range[1]:.4f} rad turn" if info.limited else "-"
            rows.append([f"{name} ({info.kind.value})", "-", limit, effort, speed])
            continue
        lo, hi = agent.qpos_limits[info.qpos_start]
        rows.append([name, f"{lo:.4f}", f"{hi:.4f}", effort, speed])
    _table(rows, out)
    out.write("\nkeyframes:\n")
    aliases = cls.keyframe_aliases()
    for name in cls.keyframe_names():
        also = [alias for alias, target in aliases.items() if target == name]
        label = name + (f" (also {', '.join(map(repr, also))})" if also else "")
        frame = agent.keyframe(name, "robot-agents info")
        out.write(f"  {label}: qpos = [{', '.join(f'{q:.4f}' for q in frame.qpos)}]\n")
        if np.any(frame.qvel) or np.any(frame.base_vel):
            speeds = ", ".join(f"{v:.4f}" for v in frame.qvel)
            base = f", base_vel = [{', '.join(f'{v:.4f}' for v in frame.base_vel)}]" if np.any(frame.base_vel) else ""
            out.write(f"  {' ' * len(label)}  qvel = [{speeds}]{base}\n")
    out.write("\n")
    rows = [["control mode", "action", "parts"]]
    for mode in cls.modes():
        agent.set_control_mode(mode)
        parts = ", ".join(
            f"{p}[{s.stop - s.start}]: {agent.controller.parts[p].describe()}"
            for p, s in agent.controller.slices.items()
        )
        rows.append(
            [mode + (" (default)" if mode == cls.default_mode() else ""), str(agent.controller.action_dim), parts]
        )
    _table(rows, out)
    out.write("\n" + "\n".join(_sensor_lines(cls)) + "\n")
    scene.close()
    return 0


def _sensor_lines(cls: type[Agent]) -> list[str]:
    """One line per declared camera and touch sensor (``sensors: none`` without any)."""
    lines = []
    for camera in composition(cls).cameras:
        projection = f"fovy {camera.vertical_fov():.1f} deg" + (", intrinsic K" if camera.intrinsic else "")
        lines.append(
            f"  camera {camera.uid} on {camera.mount}: {camera.width}x{camera.height}, {projection}, "
            f"near {camera.near:g} m, far {camera.far:g} m"
        )
    for touch in composition(cls).touch_sensors:
        where = f"site {touch.site}" if touch.site else f"{touch.shape} site on {touch.link}"
        lines.append(f"  touch {touch.uid} on {where} (normal force, N)")
    return ["sensors:", *lines] if lines else ["sensors: none"]


def cmd_demo(
    uid: str,
    output: str,
    seconds: str,
    out: TextIO,
    floating: bool = False,
    up: str = "z",
    cls: type[Agent] | None = None,
) -> int:
    """Check the arguments (before anything is simulated), run the demo and print its
    summary (``cls``: the robot already resolved)."""
    seconds_per_pose = parse_seconds(seconds)
    output_path = check_output_path(output)
    # an unknown robot fails here, before the demo's imports
    cls = cls if cls is not None else resolve_robot(uid, floating, up)
    cls.check()

    from robot_agents.demo import run_demo

    summary = run_demo(cls, output=output_path, seconds_per_pose=seconds_per_pose)
    out.write("\n".join(summary.lines()) + "\n")
    return 0 if summary.finite else 1


def cmd_check(
    spec: str,
    out: TextIO,
    floating: bool = False,
    seconds: float = 5.0,
    sweep: bool = False,
    substeps: Sequence[int] | None = None,
    up: str = "z",
    cls: type[Agent] | None = None,
) -> int:
    """Describe the robot (as ``info``), then run the physics checks; non-zero exit on a
    failure. ``sweep``: instead, the time-step sweep's table (exit 1 when no step passes),
    over ``substeps`` per control step (default: the sweep's); ``cls``: the robot
    already resolved."""
    from robot_agents.checks import run_checks

    cls = cls if cls is not None else resolve_robot(spec, floating, up)
    cmd_info(spec, out, floating, cls)
    if sweep:
        swept = timestep.sweep_timestep(cls, substeps=substeps or timestep.DEFAULT_SUBSTEPS, stop_after=None)
        best = swept.largest_passing
        out.write(f"\ntime-step sweep (control at {swept.control_freq} Hz):\n{swept.table()}\n\n")
        out.write(
            f"largest step at which every claim holds: {1000 / best:.3g} ms (sim_freq {best} Hz)\n"
            if best is not None
            else "no step tried passes every claim\n"
        )
        if swept.failing_everywhere:
            others = swept.largest_passing_other_claims
            out.write(
                f"failing at every step tried (the robot's to fix, not the step's): "
                f"{', '.join(swept.failing_everywhere)}; the other claims hold at "
                + (f"{1000 / others:.3g} ms (sim_freq {others} Hz)\n" if others is not None else "no step\n")
            )
        finest = max(swept.steps, key=lambda step: step.sim_freq)
        if finest.random_press_where:
            out.write(
                f"deepest contact under random actions at {finest.sim_freq} Hz (reported, not judged): "
                f"{finest.random_press_depth * 100:.2g} cm, {finest.random_press_where}\n"
            )
        _write_cycle_bounds(cls, out)
        return 0 if best is not None else 1
    model = cls.check().index.model
    out.write(f"total mass: {float(model.body_mass.sum()):.3f} kg\n")
    _write_simulated_geoms(cls, out)
    out.write("\nchecks:\n")
    results = run_checks(cls, random_seconds=seconds)
    for result in results:
        out.write(result.line() + "\n")
    failed = [r for r in results if not r.passed]
    out.write(f"\n{len(results) - len(failed)} passed, {len(failed)} failed\n")
    return 1 if failed else 0


def cmd_tune(
    cls: type[Agent],
    out: TextIO,
    joints: Sequence[str] | None = None,
    step: float | None = None,
    keyframe: str | None = None,
    seconds: float = 1.0,
    stiffness: float | None = None,
    damping: float | None = None,
    effort_limit: float | None = None,
    csv_path: str | None = None,
) -> int:
    """Each joint's answer to a step of its target (robot_agents.tuning.step_response),
    with the declared gains or with those given (``csv_path``: the records as a CSV
    table too); exit 1 when the physics diverged."""
    from robot_agents.tuning.step_response import step_responses, write_csv

    responses = step_responses(
        cls,
        tuple(joints) if joints else None,
        step=step,
        keyframe=keyframe,
        seconds=seconds,
        stiffness=stiffness,
        damping=damping,
        effort_limit=effort_limit,
    )
    tried = ", ".join(
        f"{name} {value:g}"
        for name, value in (("stiffness", stiffness), ("damping", damping), ("effort limit", effort_limit))
        if value is not None
    )
    rate = round(1.0 / responses[0].physics_step)
    out.write(
        f"step responses of {cls.__name__} at {rate} Hz, {seconds:g} s each, from keyframe "
        f"{keyframe or cls.keyframe_names()[0]!r}" + (f", trying {tried}" if tried else ", declared gains") + ":\n"
    )
    for response in responses:
        out.write(response.line() + "\n")
    if csv_path is not None:
        out.write(f"records: {write_csv(responses, csv_path)}\n")
    return 1 if any(r.unstable for r in responses) else 0


def _write_simulated_geoms(cls: type[Agent], out: TextIO) -> None:
    """How many of the scene's geoms the physics steps (robot_agents.model.physics_twin)."""
    from robot_agents.sim.scene import Scene

    scene = Scene(cls)
    simulated, drawn = scene.model.ngeom, scene.render_model.ngeom
    scene.close()
    out.write(
        f"geoms simulated: {simulated} of {drawn} in its scene, floor included"
        + (f" (the other {drawn - simulated} only drawn: no contacts, no mass)\n" if drawn > simulated else "\n")
    )


def _write_cycle_bounds(cls: type[Agent], out: TextIO) -> None:
    """The drives that can cycle between their torque limits, and below which rate
    (robot_agents.tuning.cycles)."""
    from robot_agents.tuning.cycles import drive_cycle_bounds

    bounds = [b for b in drive_cycle_bounds(cls) if b.cycle_free_above > 0]
    if not bounds:
        out.write("no force-limited drive can cycle between its limits\n")
        return
    out.write("torque-limit cycles possible below (analysis, no simulation):\n")
    for bound in bounds:
        note = "" if bound.reachable else " (not reachable: rated speed below the cycle's entry speed)"
        out.write(
            f"  {bound.joint}: {bound.cycle_free_above:.0f} Hz (kv {bound.damping:g}, limit {bound.effort_limit:g}, "
            f"lightest inertia {bound.inertia:.3g}){note}\n"
        )


def _robot_arguments(parser: argparse.ArgumentParser, default: str | None = None) -> None:
    """The robot argument and the options that shape a model file's robot (one flag per
    field of :class:`~robot_agents.robot_source.FileOptions`, its ``dest`` the field's
    name: ``_run`` passes them on by name)."""
    robot_help = "a registered uid, a model file (.urdf, .xml) or module:Class"
    if default is None:
        parser.add_argument("uid", metavar="ROBOT", help=robot_help)
    else:
        parser.add_argument(
            "uid", metavar="ROBOT", nargs="?", default=default, help=f"{robot_help} (default: {default})"
        )
    parser.add_argument("--floating", action="store_true", help="a model file's root gets a free joint")
    parser.add_argument(
        "--up",
        default="z",
        choices=sorted(UP_AXES),
        help="a model file's up axis (default z): a file drawn y-up stands with --up y",
    )
    parser.add_argument(
        "--gripper",
        choices=sorted(BUILTIN_PIECES),
        help="mount this built-in gripper or tool on a model file (with --at; it points along --at-axis)",
    )
    parser.add_argument("--at", help="with --gripper: the model file's body or site it is mounted on (a flange)")
    parser.add_argument(
        "--at-axis",
        default="z",
        choices=list(OUT_AXES),
        help="with --gripper: the axis of the --at frame the gripper points along (default z; x for a frame "
        "with the tool along x, such as a ROS-Industrial 'flange')",
    )
    parser.add_argument(
        "--root-body", help="the model file's top-level body that is the robot, where there are several"
    )


def build_parser() -> argparse.ArgumentParser:
    substeps = timestep.DEFAULT_SUBSTEPS  # the sweep's steps, for --substeps' help
    parser = Parser(prog="robot-agents", description="Robot agents on MuJoCo.")
    parser.add_argument("--version", action="version", version=f"robot-agents {robot_agents.__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("list", help="registered robots with their DoF and control modes")
    info = sub.add_parser("info", help="joints, keyframes, control modes and sensors of a robot")
    _robot_arguments(info)
    check = sub.add_parser("check", help="describe a robot and run its physics checks (exit 1 on a failure)")
    _robot_arguments(check)
    check.add_argument(
        "--seconds",
        default="5.0",
        help=f"seconds of random actions per mode, >= {CHECK_MIN_SECONDS:g} (one control step at "
        f"{DEFAULT_CONTROL_FREQ} Hz) and <= {MAX_SECONDS:g} (default: 5)",
    )
    check.add_argument(
        "--sweep", action="store_true", help="the time-step sweep: every physics claim per step, largest step first"
    )
    check.add_argument(
        "--substeps",
        default=None,
        help=f"with --sweep: physics substeps per control step to try, 1 to {MAX_SUBSTEPS}, comma-separated "
        f"(default {','.join(map(str, substeps))}: {DEFAULT_CONTROL_FREQ * min(substeps):g} Hz-"
        f"{DEFAULT_CONTROL_FREQ * max(substeps) / 1000:g} kHz at {DEFAULT_CONTROL_FREQ:g} Hz control; "
        "e.g. 50,100,200 for up to 4 kHz)",
    )
    tune = sub.add_parser(
        "tune",
        help="each joint's answer to a step of its target, with the declared gains or with gains to try",
    )
    _robot_arguments(tune)
    tune.add_argument("--joints", nargs="+", default=None, help="joint name patterns (default: every driven joint)")
    tune.add_argument("--step", type=float, default=None, help="step of the target, rad or m (default 0.1 / 0.01)")
    tune.add_argument("--keyframe", default=None, help="the pose stepped from (default: the robot's first keyframe)")
    tune.add_argument(
        "--seconds",
        type=float,
        default=1.0,
        help=f"seconds recorded after each step, {step_response.MIN_SECONDS:g} to {step_response.MAX_SECONDS:g} "
        "(default: 1)",
    )
    tune.add_argument("--stiffness", type=float, default=None, help="stiffness to try, N*m/rad or N/m")
    tune.add_argument("--damping", type=float, default=None, help="damping to try, N*m*s/rad or N*s/m")
    tune.add_argument("--effort-limit", type=float, default=None, help="effort limit to try, N*m or N")
    tune.add_argument(
        "--csv", default=None, help="also write every physics step of each record to this CSV file (for plotting)"
    )
    demo = sub.add_parser(
        "demo", help="move a robot through its keyframes and write a GIF or MP4 (its cameras beside the scene)"
    )
    _robot_arguments(demo, default="panda")
    demo.add_argument(
        "--output",
        "-o",
        default=None,
        help=f"video path ending in {' or '.join(SUPPORTED_SUFFIXES)}; .mp4 needs robot-agents[video] "
        "(default: <uid>_demo.gif)",
    )
    demo.add_argument(
        "--seconds", default="2.0", help=f"simulated seconds per pose, > 0 and <= {MAX_SECONDS:g} (default: 2)"
    )
    return parser


def show_note(
    message: Warning | str,
    category: type[Warning],
    filename: str,
    lineno: int,
    file: TextIO | None = None,
    line: str | None = None,
) -> None:
    """A warning raised while a command runs, as one line on stderr: the library's notes
    (``RuntimeWarning``: what a model file left out and what was derived or changed) as
    ``robot-agents: note: ...``, any other as ``robot-agents: <category>: ...``; without
    Python's source location and code line, which name the library's internals, not the
    user's input. (:func:`warnings.showwarning`'s signature.)"""
    kind = "note" if issubclass(category, RuntimeWarning) else category.__name__
    (file if file is not None else sys.stderr).write(f"robot-agents: {kind}: {message}\n")


def main(argv: Sequence[str] | None = None, out: TextIO | None = None) -> int:
    """Entry point; returns the exit status. Warnings while the command runs are printed
    by :func:`show_note` (Python's filters still decide which are shown: each once)."""
    stream = out if out is not None else sys.stdout
    args = build_parser().parse_args(argv)
    try:
        with warnings.catch_warnings():
            warnings.showwarning = show_note
            status = _run(args, stream)
        stream.flush()  # here, not at exit: a closed pipe is reported below
        return status
    except KeyboardInterrupt:  # Ctrl-C during a long check or demo: no traceback
        sys.stderr.write("robot-agents: interrupted\n")
        return 130
    except BrokenPipeError:
        # the reader stopped reading (robot-agents list | head -3): stop quietly, as
        # command-line tools do, and keep Python's exit-time flush from failing again
        if stream is sys.stdout:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 1


def _run(args: argparse.Namespace, stream: TextIO) -> int:
    """The command ``args`` names, its output to ``stream``; a bad argument or robot is
    reported in one line on stderr (exit status 2)."""
    try:
        if args.command == "list":
            return cmd_list(stream)
        # the command's own arguments first: a typo is reported before a model file loads
        if args.command == "check":
            seconds = parse_seconds(args.seconds, "seconds of random actions per mode", CHECK_MIN_SECONDS)
            substeps = parse_substeps(args.substeps)
            if substeps is not None and not args.sweep:
                raise UsageError("argument --substeps: chooses the steps of the time-step sweep; add --sweep")
        elif args.command == "tune" and args.csv is not None:
            if not Path(args.csv).parent.is_dir():
                raise UsageError(f"argument --csv: the folder of {args.csv!r} does not exist")
            if Path(args.csv).is_dir():
                raise UsageError(f"argument --csv: expected a file name, got the existing directory {args.csv!r}")
        elif args.command == "demo":
            output = args.output if args.output is not None else default_demo_output(args.uid)
            parse_seconds(args.seconds)
            check_output_path(output)
        cls = resolve_robot(args.uid, **{option.name: getattr(args, option.name) for option in fields(FileOptions)})
        if args.command == "info":
            return cmd_info(args.uid, stream, args.floating, cls, args.up)
        if args.command == "check":
            return cmd_check(args.uid, stream, args.floating, seconds, args.sweep, substeps, args.up, cls)
        if args.command == "tune":
            return cmd_tune(
                cls,
                stream,
                args.joints,
                args.step,
                args.keyframe,
                args.seconds,
                args.stiffness,
                args.damping,
                args.effort_limit,
                args.csv,
            )
        return cmd_demo(args.uid, output, args.seconds, stream, args.floating, args.up, cls)
    except (RobotAgentsError, UsageError) as err:
        # one line, also for a message that quotes MuJoCo's (its element on a second line)
        message = "; ".join(line.strip() for line in str(err).splitlines() if line.strip())
        sys.stderr.write(f"robot-agents: error: {message}\n")
        return 2


if __name__ == "__main__":
    sys.exit(main())
