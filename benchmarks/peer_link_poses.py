"""Our robot's link poses against the peer's (ManiSkill 3 loading its own asset) at the
same random joint configurations: a check of a model's kinematics against the file the
peer simulates, for robots whose joints and links carry the peer's names.

The peer's worker (its own Python, :func:`peer.default_peer_python`) makes ``Empty-v1``
with the peer's uid, draws ``--samples`` configurations uniformly within the peer's joint
limits (slides and unlimited joints within +-1 m / +-pi; fixed seed), sets them and reports
the world pose of every link; here our robot is put at the same joint values, by joint
name, and every link both models have (by name; ``--links`` to choose) is compared: the
largest position (m) and rotation (rad) differences. The peer computes in float32.

    MS_ASSET_DIR=/tmp/ms_assets python benchmarks/peer_link_poses.py xlerobot
    python benchmarks/peer_link_poses.py google_robot --peer-uid googlerobot --samples 10

Exit status 1 when a difference exceeds ``--tolerance`` (default 1e-5 m / rad); 0 with a
message when the peer's interpreter or robot is not available. Not run in CI.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import textwrap

import numpy as np

import robot_agents as ra
from peer import INERT_VISUALS, default_peer_python
from robot_agents.kinematics.rotations import rotation_error

#: The peer-side script: argv = peer uid, samples, seed; prints one JSON line.
WORKER = (
    """
import json, sys
import numpy as np
try:"""
    + textwrap.indent(INERT_VISUALS, "    ")
    + """    import builtins
    builtins.input = lambda *a: "n"  # asset downloads ask; never download here
    import gymnasium as gym, torch, mani_skill.envs
    env = gym.make("Empty-v1", robot_uids=sys.argv[1], obs_mode="state", sim_backend="cpu", render_backend="none")
    env.reset(seed=0)
except BaseException as error:
    print(json.dumps({"unavailable": type(error).__name__ + " " + str(error).replace(chr(10), " ")[:200]}))
    sys.exit(0)
robot = env.unwrapped.agent.robot
joints = robot.get_active_joints()
limits = robot.get_qlimits()[0].cpu().numpy().astype(float)
slide = np.array([j.type == "prismatic" for j in joints])
wide = np.where(slide, 1.0, np.pi)  # slides within +-1 m, unlimited hinges within +-pi
low = np.where(np.isfinite(limits[:, 0]) & ~slide, limits[:, 0], np.maximum(limits[:, 0], -wide))
high = np.where(np.isfinite(limits[:, 1]) & ~slide, limits[:, 1], np.minimum(limits[:, 1], wide))
rng = np.random.default_rng(int(sys.argv[3]))
samples = []
for _ in range(int(sys.argv[2])):
    q = rng.uniform(low, high)
    robot.set_qpos(torch.tensor(q[None], dtype=torch.float32))
    poses = {}
    for name, link in robot.links_map.items():
        pose = link.pose
        poses[name] = np.concatenate([pose.p[0].cpu().numpy(), pose.q[0].cpu().numpy()]).astype(float).tolist()
    samples.append({"q": q.tolist(), "poses": poses})
print(json.dumps({"joints": [j.name for j in joints], "samples": samples}))
"""
)


def peer_poses(python: str, uid: str, samples: int, seed: int) -> dict:
    """The worker's answer: joint names, and per sample the joint values and link poses
    (``x, y, z, qw, qx, qy, qz``, world), or ``{"unavailable": why}``."""
    result = subprocess.run(
        [python, "-c", WORKER, uid, str(samples), str(seed)], capture_output=True, text=True, timeout=600
    )
    lines = [line for line in result.stdout.splitlines() if line.startswith("{")]
    if not lines:
        return {"unavailable": f"no answer (exit {result.returncode}): {result.stderr.strip()[-300:]}"}
    answer: dict = json.loads(lines[-1])
    return answer


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uid", help="our robot's uid")
    parser.add_argument("--peer-uid", help="the peer's uid (default: ours)")
    parser.add_argument("--samples", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--links", nargs="*", help="links to compare (default: every link both models have)")
    parser.add_argument("--tolerance", type=float, default=1e-5, help="largest difference accepted (m, rad)")
    parser.add_argument("--maniskill-python", default=default_peer_python())
    args = parser.parse_args()
    if not args.maniskill_python:
        print("the peer's interpreter is not installed (/work/shared/peers/setup_maniskill.sh); nothing to compare")
        return 0
    answer = peer_poses(args.maniskill_python, args.peer_uid or args.uid, args.samples, args.seed)
    if "unavailable" in answer:
        print(f"the peer cannot load {args.peer_uid or args.uid}: {answer['unavailable']}")
        return 0
    scene = ra.Scene(args.uid)
    scene.reset()
    agent = scene.agents[0]
    model = scene.model
    ours = {model.body(b).name[len(agent.prefix) :] for b in range(model.nbody)}
    missing = [j for j in answer["joints"] if j not in agent.joint_names]
    if missing:
        print(f"the peer's joints {missing} are not {args.uid}'s: {list(agent.joint_names)}")
        return 1
    links = args.links or sorted(ours & set(answer["samples"][0]["poses"]))
    worst: dict[str, tuple[float, float]] = {}
    for sample in answer["samples"]:
        q = agent.qpos[0].copy()
        for name, value in zip(answer["joints"], sample["q"], strict=True):
            q[agent.joint_names.index(name)] = value
        for link in links:
            mine = agent.frame_pose(link, q)[0]
            theirs = np.asarray(sample["poses"][link])
            position = float(np.linalg.norm(mine[:3] - theirs[:3]))
            rotation = float(np.linalg.norm(rotation_error(mine[None, 3:], theirs[None, 3:])))
            previous = worst.get(link, (0.0, 0.0))
            worst[link] = (max(previous[0], position), max(previous[1], rotation))
    scene.close()
    print("| link | position (m) | rotation (rad) |\n|---|---|---|")
    for link, (position, rotation) in worst.items():
        print(f"| `{link}` | {position:.2g} | {rotation:.2g} |")
    largest = max(max(v) for v in worst.values())
    print(
        f"\n{len(links)} links of {args.uid} at {args.samples} random configurations (seed {args.seed}): "
        f"largest differences {max(v[0] for v in worst.values()):.2g} m, {max(v[1] for v in worst.values()):.2g} rad"
    )
    return 1 if largest > args.tolerance else 0


if __name__ == "__main__":
    sys.exit(main())
