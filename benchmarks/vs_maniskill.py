"""Side by side with the peer library: env steps/s of every robot both libraries have,
ours and ManiSkill 3's CPU simulation, in one run.

For each robot both libraries register (:data:`SHARED`, our uid -> the peer's) and each
mode both have (``pd_joint_delta_pos`` and the end-effector mode ``pd_ee_delta_pose``,
``pd_ee_delta_pos`` where we have no pose mode; the Bridge setups have only ManiSkill's
``arm_pd_ee_target_delta_pose_align2_gripper_pd_joint_pos``), same task (``Empty-v1``),
state observations, 20 Hz control, small actions of alternating sign
(``step_throughput.small_actions``; the peer's worker draws its own the same way),
each library at its own default physics step (ours: the robot's ``sim_freq``; the
peer's: 100 Hz), four loops timed in one set of alternating blocks:

- ``ours x1``: ``env.step`` at ``num_envs=1``;
- ``peer x1``: the peer's ``env.step`` in a worker process (the worker times its own
  loop, so pipe traffic is not counted);
- ``ours xN`` (``--num-envs``, default 64): one batched world on all cores (its stepping
  threads), env steps/s of all envs together;
- ``peer xC``: C = the machine's cores peer workers stepping at the same time (ManiSkill's
  CPU simulation runs one env per process), env steps/s of all of them (wall time of the
  slowest, pipe traffic included).

``--output PATH`` writes the tables as a Markdown page (docs/vs-maniskill.md).

``--our-mode MODE`` steps our env in ``MODE`` against the peer's ``pd_joint_delta_pos``
(the joint row only): a legged robot standing in ``pd_joint_target_delta_pos``, where in
``pd_joint_delta_pos`` our loaded legs give (the targets follow the measured pose) and
the robot folds into a heap of contacts, while the peer's legs carry no weight (it
switches gravity off on them). The row names both modes.

    python benchmarks/vs_maniskill.py                          # every shared robot
    python benchmarks/vs_maniskill.py panda so100 --rounds 5
    python benchmarks/vs_maniskill.py anymal_c unitree_go2 --our-mode pd_joint_target_delta_pos
    MS_ASSET_DIR=/tmp/ms_assets python benchmarks/vs_maniskill.py --output docs/vs-maniskill.md

The peer downloads some robots' assets at first use (``xarm6_*``, ``widowxai*``,
``widowx250s*``, ``ur_10e``, ``googlerobot``, ``floating_robotiq_2f_85_gripper``,
``anymal_c``, ``unitree_h1``, ``unitree_go2`` and their simplified variants, ``xlerobot``); a machine without network needs them
under ``$MS_ASSET_DIR/data/robots/`` in ManiSkill's layout (the repositories and tags
named in ``mani_skill/utils/assets/data.py``, each tag's files in its target folder). A robot the peer
cannot load is reported with its error. Needs the peer's interpreter
(``--maniskill-python``; default ``~/.venvs/maniskill/bin/python``, made by
``/work/shared/peers/setup_maniskill.sh``); without one the script says so and exits 0.
Not run in CI; nothing here imports ManiSkill.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

import mujoco
import numpy as np

import robot_agents as ra
from peer import Peer, PeerPool, default_peer_python
from step_throughput import interleaved, small_actions

#: Every robot both libraries register: our uid -> ManiSkill 3.0.1's.
SHARED = {
    "panda": "panda",
    "panda_wristcam": "panda_wristcam",
    "panda_stick": "panda_stick",
    "floating_panda_gripper": "floating_panda_gripper",
    "floating_robotiq_2f_85_gripper": "floating_robotiq_2f_85_gripper",
    "xarm6_nogripper": "xarm6_nogripper",
    "xarm6_nogripper_wristcam": "xarm6_nogripper_wristcam",
    "xarm6_robotiq": "xarm6_robotiq",
    "xarm6_robotiq_wristcam": "xarm6_robotiq_wristcam",
    "ur_10e": "ur_10e",
    "widowx250s": "widowx250s",
    "widowx250s_bridgedataset_flat_table": "widowx250s_bridgedataset_flat_table",
    "widowx250s_bridgedataset_sink": "widowx250s_bridgedataset_sink",
    "widowxai": "widowxai",
    "widowxai_wristcam": "widowxai_wristcam",
    "so100": "so100",
    "koch-v1.1": "koch-v1.1",
    "fetch": "fetch",
    "google_robot": "googlerobot",
    "unitree_h1": "unitree_h1",
    "allegro_hand_right": "allegro_hand_right",
    "dclaw": "dclaw",
    "allegro_hand_left": "allegro_hand_left",
    "allegro_hand_right_touch": "allegro_hand_right_touch",
    "anymal_c": "anymal_c",
    "unitree_go2": "unitree_go2",
    "trifingerpro": "trifingerpro",
    "floating_ability_hand_right": "floating_ability_hand_right",
    "xarm7_ability": "xarm7_ability",
    "xlerobot": "xlerobot",
    "unitree_go2_simplified_locomotion": "unitree_go2_simplified_locomotion",
    "unitree_h1_simplified": "unitree_h1_simplified",
    "humanoid": "humanoid",
    "fixed_inspire_hand_right": "fixed_inspire_hand_right",
    "fixed_inspire_hand_left": "fixed_inspire_hand_left",
    "floating_inspire_hand_right": "floating_inspire_hand_right",
    "floating_inspire_hand_left": "floating_inspire_hand_left",
    "unitree_g1_simplified_upper_body": "unitree_g1_simplified_upper_body",
    "unitree_g1_simplified_upper_body_with_head_camera": "unitree_g1_simplified_upper_body_with_head_camera",
    "unitree_g1_simplified_upper_body_right_arm": "unitree_g1_simplified_upper_body_right_arm",
    "unitree_g1": "unitree_g1",
    "unitree_g1_simplified_legs": "unitree_g1_simplified_legs",
}
#: The only mode ManiSkill gives the Bridge setups.
BRIDGE_MODE = "arm_pd_ee_target_delta_pose_align2_gripper_pd_joint_pos"
#: Robots whose ManiSkill agent has only these modes (its floating Ability Hand: only
#: ``pd_joint_pos``, the mount's absolute targets and the hand's).
PEER_ONLY_MODES = {"floating_ability_hand_right": ["pd_joint_pos"]}


def modes_of(uid: str) -> list[str]:
    """The modes compared for ``uid``: a joint mode and an end-effector mode."""
    ours = ra.get_agent(uid).modes()
    if BRIDGE_MODE in ours and uid.startswith("widowx250s_bridgedataset"):
        return [BRIDGE_MODE]
    if uid in PEER_ONLY_MODES:
        return list(PEER_ONLY_MODES[uid])
    ee = next((m for m in ("pd_ee_delta_pose", "pd_ee_delta_pos") if m in ours), None)
    return ["pd_joint_delta_pos"] + ([ee] if ee else [])  # legs or a hand alone: no end effector


def our_loop(uid: str, mode: str, num_envs: int, rng: np.random.Generator) -> tuple[Callable[[int], None], ra.RobotEnv]:
    """A loop stepping our env ``count`` times with pairs of opposite small actions."""
    env: ra.RobotEnv = ra.make_env(
        "Empty-v1", robot_uids=uid, control_mode=mode, num_envs=num_envs, max_episode_steps=None
    ).unwrapped  # type: ignore[assignment]
    env.reset(seed=0)
    pairs = [action for action in small_actions(env, 32, rng) for action in (action, -action)]
    if num_envs == 1:
        pairs = [action[0] for action in pairs]
    counter = [0]

    def loop(count: int) -> None:
        for _ in range(count):
            env.step(pairs[counter[0] % len(pairs)])
            counter[0] += 1

    return loop, env


def compare(
    uid: str,
    mode: str,
    python: str,
    rounds: int,
    block: int,
    num_envs: int,
    cores: int,
    rng: np.random.Generator,
    our_mode: str | None = None,
) -> str:
    """One table row: the four loops in alternating blocks (ours in ``our_mode`` where
    given, the peer in ``mode``)."""
    peer_uid = SHARED[uid]
    ours = our_mode or mode
    one, env_one = our_loop(uid, ours, 1, rng)
    many, env_many = our_loop(uid, ours, num_envs, rng)
    # a batch step is num_envs env steps: fewer calls per block keep the blocks alike in time
    many_block = max(1, block // 8)
    peer = Peer(python, peer_uid, mode)
    freq = env_one.scene.sim_freq
    label = f"`{mode}`" if ours == mode else f"ours `{ours}`, the peer's `{mode}`"
    row = f"| `{uid}` | {label} | {freq}"
    if not peer.ready:
        env_one.close()
        env_many.close()
        why = (
            "the peer has no such mode for this robot" if "not in supported modes" in peer.status else peer.status[:100]
        )
        return f"{row} | - | - | {why} | - | - | - | - |"
    pool = PeerPool(python, peer_uid, mode, cores)
    loops: list[Callable[[int], None]] = [one, peer.loop]
    if pool.ready:
        loops.append(pool.loop)
    rates = interleaved(loops, rounds, block)
    many_rate = interleaved([many], max(2, rounds // 2), many_block)[0] * num_envs
    peer_rate = rounds * block / sum(peer.blocks[1:])  # the worker's own timing, after the warm-up block
    peer_hz = peer.status.split()[3]
    peer.close()
    ours_rate = rates[0]
    if pool.ready:
        pool_rate = cores * rounds * block / sum(pool.blocks[1:])
        pool.close()
        pool_cells = f"{pool_rate:.0f} | {many_rate / pool_rate:.2f}x"
    else:
        pool_cells = f"did not run: {pool.status[:60]} | -"
    env_one.close()
    env_many.close()
    return (
        f"{row} | {peer_hz} | {ours_rate:.0f} | {peer_rate:.0f} | **{ours_rate / peer_rate:.2f}x** | "
        f"{many_rate:.0f} | {pool_cells} |"
    )


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("uids", nargs="*", default=list(SHARED))
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--block", type=int, default=40, help="control steps per timed block (one env)")
    parser.add_argument("--num-envs", type=int, default=64, help="envs of our batched loop")
    parser.add_argument("--maniskill-python", default=None)
    parser.add_argument("--output", type=Path, default=None, help="write the tables to this Markdown file")
    parser.add_argument(
        "--our-mode",
        default=None,
        help="step our env in this mode against the peer's pd_joint_delta_pos (the joint row only)",
    )
    args = parser.parse_args(argv)
    python = args.maniskill_python or default_peer_python()
    if python is None:
        print("mani-skill is not installed (see /work/shared/peers/setup_maniskill.sh): nothing to compare.")
        return 0
    unknown = [uid for uid in args.uids if uid not in SHARED]
    if unknown:
        parser.error(f"not robots both libraries have: {unknown}; shared: {sorted(SHARED)}")
    cores = os.cpu_count() or 1
    rng = np.random.default_rng(0)
    started = datetime.datetime.now(datetime.UTC)
    load_before = os.getloadavg()[0]
    lines = [
        "| robot | mode | our sim_freq (Hz) | peer sim_freq (Hz) | ours x1 | peer x1 | ours / peer x1 | "
        f"ours x{args.num_envs} | peer x{cores} processes | ours x{args.num_envs} / peer x{cores} |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    print("\n".join(lines), flush=True)
    for uid in args.uids:
        for mode in modes_of(uid) if args.our_mode is None else ["pd_joint_delta_pos"]:
            line = compare(uid, mode, python, args.rounds, args.block, args.num_envs, cores, rng, args.our_mode)
            lines.append(line)
            print(line, flush=True)
    load_after = os.getloadavg()[0]
    machine = (
        f"{started:%Y-%m-%d %H:%M} UTC, robot_agents {ra.__version__}, MuJoCo {mujoco.__version__}, "
        f"Python {platform.python_version()}, {cores} cores ({platform.processor() or platform.machine()}), "
        f"load average {load_before:.1f} before and {load_after:.1f} after the run"
    )
    print(f"\n{machine}")
    if args.output is not None:
        assets = os.environ.get("MS_ASSET_DIR")  # where the peer's downloaded robot assets were
        command = ("" if assets is None else f"MS_ASSET_DIR={assets} ") + "python benchmarks/vs_maniskill.py "
        command += " ".join(argv if argv is not None else sys.argv[1:])
        args.output.write_text(page(machine, command.strip(), args.rounds, args.block, "\n".join(lines)))
    return 0


def page(machine: str, command: str, rounds: int, block: int, table: str) -> str:
    """The Markdown page ``--output`` writes."""
    return f"""# Side by side with ManiSkill (generated by `benchmarks/vs_maniskill.py`)

Env steps/s (higher is better) of every robot both libraries register, `Empty-v1`,
state observations, 20 Hz control, small actions of alternating sign, each library at
its own default physics step. ManiSkill 3.0.1's CPU simulation (`sim_backend="cpu"`,
`render_backend="none"`) runs in worker processes of its own interpreter; all loops of a
row are timed in one set of alternating blocks ({rounds} rounds of {block} steps; the
batched loop in blocks of an eighth of that), so machine noise hits both libraries
alike and the ratios are the figures to keep. `x1`: one env. `ours xN`: one batched
world of N envs stepped on all cores (threads). `peer xC`: C peer processes of one env
each stepping at the same time (ManiSkill's CPU simulation runs one env per process).
See [benchmarks.md](benchmarks.md#side-by-side-with-maniskill-benchmarksvs_maniskillpy)
for what the figures say.

Run: {machine}.

    {command}

{table}
"""


if __name__ == "__main__":
    raise SystemExit(main())
