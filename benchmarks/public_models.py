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


def wheel_dir(wheel: str | None, work: Path) -> Path:
    if wheel is None:
        subprocess.run(
            [sys.executable, "-m", "pip", "download", "--no-deps", "-q", "-d", str(work), "mani-skill==3.0.1"],
            check=True,
        )
        wheel = str(next(work.glob("mani_skill-*.whl")))
    out = work / "wheel"
    with zipfile.ZipFile(wheel) as archive:
        archive.extractall(out, [n for n in archive.namelist() if n.startswith(ROBOTS)])
    return out


def evaluate(path: Path, floating: bool) -> list[str]:
    start = time.perf_counter()
    cls = robot_from_file(path, floating)
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
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        root = wheel_dir(args.wheel, Path(tmp))
        print("| category | model | loads | hold drift (2 s) | stable (2 s random) | user lines | load s | notes |")
        print("|---|---|---|---|---|---|---|---|")
        for category, name, floating in MODELS:
            path = GYM / name[4:] if name.startswith("gym:") else root / name
            row = evaluate(path, floating)
            label = name[4:] if name.startswith("gym:") else name[len(ROBOTS) :]
            print(f"| {category} | {label} | " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
