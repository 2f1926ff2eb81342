"""Public robot model files with the two-line definition: does each load, hold its
default pose and stay stable under random actions, with nothing but its path?

Model files come from public packages, fetched with ``pip download --no-deps`` (the
``mani-skill`` wheel carries URDFs of arms, hands, a mobile manipulator and humanoids;
gymnasium, a dependency, carries its MuJoCo XMLs). Each robot is defined as a user
would, in two or three lines::

    class Robot(ra.Agent):
        uid = "robot"
        urdf_path = "path/to/robot.urdf"
        fix_root_link = False  # only for floating robots

and checked with the same functions as ``robot-agents check``: load time, the default
mode's hold of the default keyframe for 2 s (drift), and 2 s of uniformly random
actions in the default mode (stable: no MuJoCo reset, finite state).

Usage: ``python benchmarks/public_models.py [--wheel mani_skill-3.0.1-py3-none-any.whl]``
(without ``--wheel`` it downloads the wheel; needs network access to PyPI).

``--robosuite robosuite-1.5.2-py3-none-any.whl`` and ``--dm-control
dm_control-1.0.50-py3-none-any.whl`` (wheels fetched with ``pip download --no-deps``)
add the MJCF files of those packages: robosuite's arms, grippers, hands and mobile
bases (written for robosuite to compose: most arms are driven by torque motors, its
bases by velocity servos) and dm_control's Kinova arm and hand, soccer walkers and two
suite models; ``--gymnasium-robotics``, ``--metaworld`` and ``--gym-aloha`` (wheels
gymnasium_robotics 1.4.2, metaworld 3.1.1, gym_aloha 0.1.5) their robots: a Fetch and a
Sawyer moved by mocap welds, the Shadow and Adroit hands, a Franka in a kitchen, one
ALOHA arm of two. Only the rows of the wheels given are printed when any is given.
"""

from __future__ import annotations

import argparse
import re
import subprocess
import sys
import tempfile
import time
import warnings
import zipfile
from pathlib import Path

import gymnasium

from robot_agents.checks import check_holds, check_random_actions
from robot_agents.robot_source import robot_from_file

GYM = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets"
ROBOTS = "mani_skill/assets/robots/"
#: (category, file, floating): floating robots get ``fix_root_link = False`` (a third line).
MODELS = [
    ("arm", ROBOTS + "panda/panda_v2.urdf", False),
    ("arm", ROBOTS + "xarm7/xarm7.urdf", False),
    ("arm", ROBOTS + "so100/so100.urdf", False),
    ("arm", ROBOTS + "koch/follower_arm_v1.1.urdf", False),
    ("arm + tool", ROBOTS + "panda/panda_stick.urdf", False),
    ("gripper", ROBOTS + "panda/panda_v2_gripper.urdf", False),
    ("hand", ROBOTS + "allegro/allegro_hand_right.urdf", False),
    ("hand (.glb meshes)", ROBOTS + "allegro/allegro_hand_right_glb.urdf", False),
    ("hand", ROBOTS + "ability_hand/ability_hand_right.urdf", False),
    ("hand", ROBOTS + "inspire_hand/RH56DFX-2LR/urdf/inspire_hand_left.urdf", False),
    ("hand (.glb meshes)", ROBOTS + "dclaw/dclaw_gripper_glb.urdf", False),
    ("hand", ROBOTS + "trifinger/robot_properties_fingers/urdf/pro/trifingerpro.urdf", False),
    ("arm + hand", ROBOTS + "xarm7/xarm7_ability_right_hand.urdf", False),
    ("mobile manipulator", ROBOTS + "fetch/fetch.urdf", False),
    ("mobile manipulator", ROBOTS + "panda/mobile_panda_single_arm.urdf", False),
    ("humanoid", ROBOTS + "g1_humanoid/g1.urdf", True),
    ("humanoid", ROBOTS + "humanoid/humanoid.xml", True),
    ("humanoid", "gym:humanoid.xml", True),
    ("humanoid", "gym:humanoidstandup.xml", True),
    ("quadruped", "gym:ant.xml", True),
    ("planar", "gym:half_cheetah.xml", False),
    ("planar", "gym:hopper.xml", False),
    ("planar", "gym:walker2d.xml", False),
    ("planar", "gym:swimmer.xml", False),
    ("arm", "gym:reacher.xml", False),
    ("arm", "gym:pusher.xml", False),
    ("pendulum", "gym:inverted_double_pendulum.xml", False),
]
RS = "robosuite/models/assets/"
DMC = "dm_control/"
#: MJCF files of the robosuite and dm_control wheels (``--robosuite``, ``--dm-control``).
MJCF_MODELS = [
    *(("arm", f"rs:robots/{name}/robot.xml", False) for name in ("panda", "ur5e", "iiwa", "sawyer", "kinova3")),
    *(("arm", f"rs:robots/{name}/robot.xml", False) for name in ("jaco", "xarm7")),
    ("humanoid upper body", "rs:robots/gr1/robot.xml", False),
    ("two arms", "rs:robots/baxter/robot.xml", False),
    ("mobile manipulator", "rs:robots/tiago/robot.xml", False),
    ("arm", "rs:robots/spot_arm/robot.xml", False),
    *(
        ("gripper", f"rs:grippers/{name}.xml", False)
        for name in ("panda_gripper", "rethink_gripper", "robotiq_gripper_140", "robotiq_gripper_85", "xarm7_gripper")
    ),
    *(
        ("hand", f"rs:grippers/{name}.xml", False)
        for name in ("robotiq_gripper_s", "jaco_three_finger_gripper", "inspire_right_hand", "fourier_right_hand")
    ),
    *(("mobile base", f"rs:bases/{name}.xml", False) for name in ("omron_mobile_base", "floating_legged_base")),
    ("arm", "dmc:third_party/kinova/jaco_arm.xml", False),
    ("hand", "dmc:third_party/kinova/jaco_hand.xml", False),
    # dm_control gives these walkers their free joint when it composes them
    ("walker", "dmc:locomotion/soccer/assets/boxhead/boxhead.xml", False),
    ("walker", "dmc:locomotion/walkers/assets/jumping_ball/jumping_ball_with_head.xml", False),
    ("arm", "dmc:suite/manipulator.xml", False),
    ("finger", "dmc:suite/finger.xml", False),
    ("arm (mocap-moved)", "gr:fetch/pick_and_place.xml", False),
    ("hand", "gr:hand/reach.xml", False),
    ("hand", "gr:adroit_hand/adroit_relocate.xml", False),
    ("arm (in a kitchen)", "gr:kitchen_franka/kitchen_assets/kitchen_env_model.xml", False),
    ("arm (mocap-moved)", "mw:sawyer_xyz/sawyer_reach_v3.xml", False),
    ("arm (one of two)", "al:bimanual_viperx_transfer_cube.xml", False),
]
GR, MW, AL = "gymnasium_robotics/envs/assets/", "metaworld/assets/", "gym_aloha/assets/"
#: The top-level body that is the robot, where a file holds several robots.
ROOT_BODIES = {"al:bimanual_viperx_transfer_cube.xml": "vx300s_left"}


def wheel_dir(wheel: str | None, work: Path) -> Path:
    if wheel is None:
        subprocess.run(
            [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(work), "mani-skill==3.0.1"],
            check=True,
        )
        wheel = str(next(work.glob("mani_skill-*.whl")))
    return extract(wheel, ROBOTS, work / "wheel")


def extract(wheel: str, prefix: str, out: Path) -> Path:
    """The files under ``prefix`` of a downloaded wheel, unpacked under ``out``."""
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(out, [n for n in archive.namelist() if n.startswith(prefix)])
    return out / prefix


def evaluate(path: Path, floating: bool, root_body: str | None = None) -> list[str]:
    start = time.perf_counter()
    cls = robot_from_file(path, floating, root_body=root_body)
    try:
        with warnings.catch_warnings(record=True) as notes:
            warnings.simplefilter("always")
            checked = cls.check()
        load = time.perf_counter() - start
        hold = check_holds(cls, seconds=2.0)
        stable = check_random_actions(type(cls.__name__, (cls,), {"control_modes": {}}), seconds=2.0)
    except Exception as err:  # report, do not stop: the point is the table
        first = str(err).splitlines()[0]
        return ["no", "-", "-", "3" if floating else "2", f"{time.perf_counter() - start:.2f}", first[:110]]
    fixes = sorted(
        {"fixed: " + m.group(1) for n in notes if (m := re.search(r"compiled with ([^:]+):", str(n.message)))}
    )
    pairs = [n for n in notes if "touch at the default keyframe" in str(n.message)]
    if pairs:
        fixes.append(str(pairs[0].message).split(": ")[1].split(" touch")[0] + " excluded at the default pose")
    parts = " + ".join(f"{type(p).__name__} {len(checked.part_joints[p.name])}" for p in checked.parts)
    note = (
        f"{len(checked.drives)} drives ({checked.drives[0].source.split(' (')[0]}), parts {parts}, "
        f"mode {checked.default_mode}"
    )
    return [
        "yes",
        hold.detail.split(" (")[0].replace("largest drift ", "")
        if "not applicable" not in hold.detail
        else "n/a (efforts)",
        "yes" if stable.passed else "no",
        "3" if floating else "2",
        f"{load:.2f}",
        note + ("; " + "; ".join(fixes) if fixes else ""),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--wheel", default=None, help="a downloaded mani_skill wheel (default: pip download it)")
    parser.add_argument("--robosuite", default=None, help="a downloaded robosuite wheel: its MJCF robots")
    parser.add_argument("--dm-control", default=None, help="a downloaded dm_control wheel: its MJCF robots")
    parser.add_argument("--gymnasium-robotics", default=None, help="a downloaded gymnasium-robotics wheel")
    parser.add_argument("--metaworld", default=None, help="a downloaded metaworld wheel")
    parser.add_argument("--gym-aloha", default=None, help="a downloaded gym-aloha wheel")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        roots: dict[str, Path] = {}
        if args.robosuite is not None:
            roots["rs:"] = extract(args.robosuite, RS, Path(tmp) / "robosuite")
        if args.dm_control is not None:
            roots["dmc:"] = extract(args.dm_control, DMC, Path(tmp) / "dm_control")
        for scheme, wheel, prefix in (
            ("gr:", args.gymnasium_robotics, GR),
            ("mw:", args.metaworld, MW),
            ("al:", args.gym_aloha, AL),
        ):
            if wheel is not None:
                roots[scheme] = extract(wheel, prefix, Path(tmp) / scheme[:-1])
        if roots:
            models = [m for m in MJCF_MODELS if m[1].split(":")[0] + ":" in roots]
        else:
            roots = {"gym:": GYM, "": wheel_dir(args.wheel, Path(tmp))}
            models = MODELS
        print("| category | model | loads | hold drift (2 s) | stable (2 s random) | user lines | load s | notes |")
        print("|---|---|---|---|---|---|---|---|")
        for category, name, floating in models:
            scheme = name.split(":")[0] + ":" if ":" in name else ""
            label = name[len(scheme or ROBOTS) :]
            row = evaluate(roots[scheme] / label, floating, ROOT_BODIES.get(name))
            print(f"| {category} | {label} | " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
