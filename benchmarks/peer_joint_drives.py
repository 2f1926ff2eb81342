"""Fetch's joint damping and drives against the peer's (ManiSkill 3 loading its own
``fetch.urdf``), and its fingers closing from open on both sides: what the peer simulates
of the URDF's ``<dynamics damping>`` (docs/notes/fetch-facts.md, "Joint damping").

The peer's worker (its own Python, :func:`peer.default_peer_python`) makes ``Empty-v1``
with ``fetch`` in ``pd_joint_pos`` and reports every active joint's PhysX properties
twice: as the URDF loader left them (caught before the agent's first
``set_control_mode``) and as the control mode's controllers set them (drive stiffness,
damping, force limit; joint friction, armature). PhysX joints have one damping, the
drive's. Here, ours: each joint's own damping (``dof_damping``) and its drive's gains.

Then the fingers, open (0.05 m) in free air, get the closing command (gripper -1: target
-0.01 m), the rest of the robot held: the left finger's position after 0.05 s and its
peak speed over 0.5 s, sampled every physics step on both sides (ours: control at the
physics rate; the peer: its 100 Hz physics, stepped between its 20 Hz control steps).

    python benchmarks/peer_joint_drives.py

Prints "the peer's interpreter is not installed" and exits 0 without it. Not run in CI.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import textwrap

import robot_agents as ra
from peer import INERT_VISUALS, default_peer_python
from robot_agents.checks import hold_action
from robot_agents.registry import agent_class

FINGERS = ("l_gripper_finger_joint", "r_gripper_finger_joint")
OPEN = 0.05
SECONDS = 0.5

#: The peer-side script (argv: seconds); prints one JSON line.
WORKER = (
    """
import json, sys
import numpy as np
try:"""
    + textwrap.indent(INERT_VISUALS, "    ")
    + """    import builtins
    builtins.input = lambda *a: "n"  # asset downloads ask; never download here
    import gymnasium as gym, torch, mani_skill, mani_skill.envs
    import mani_skill.agents.base_agent as base_agent
    loaded = {}
    set_mode = base_agent.BaseAgent.set_control_mode
    def spy(self, control_mode=None):  # the URDF loader's joint properties, before any controller
        if not loaded:
            for joint in self.robot.active_joints:
                j = joint._objs[0]
                loaded[joint.name] = [float(j.stiffness), float(j.damping), float(j.force_limit), float(j.friction)]
        return set_mode(self, control_mode)
    base_agent.BaseAgent.set_control_mode = spy
    env = gym.make("Empty-v1", robot_uids="fetch", obs_mode="state", control_mode="pd_joint_pos",
                   sim_backend="cpu", render_backend="none")
    env.reset(seed=0)
except BaseException as error:
    print(json.dumps({"unavailable": type(error).__name__ + " " + str(error).replace(chr(10), " ")[:200]}))
    sys.exit(0)
u = env.unwrapped
agent = u.agent
joints = agent.robot.active_joints
controlled = {}
for joint in joints:
    j = joint._objs[0]
    controlled[joint.name] = [float(j.stiffness), float(j.damping), float(j.force_limit), float(j.friction),
                              float(np.asarray(j.armature).reshape(-1)[0])]
names = [j.name for j in joints]
fingers = [names.index("l_gripper_finger_joint"), names.index("r_gripper_finger_joint")]
q = agent.robot.get_qpos().clone()
q[0, fingers] = 0.05
agent.robot.set_qpos(q)
agent.robot.set_qvel(q * 0)
agent.controller.reset()
action = np.zeros(env.action_space.shape, dtype=np.float32)
qpos = q[0].numpy()
for part, span in agent.controller.action_mapping.items():  # pd_joint_pos: arm and body absolute
    if part in ("arm", "body"):
        action[span[0]:span[1]] = qpos[[names.index(n) for n in agent.controller.controllers[part].config.joint_names]]
start, _ = agent.controller.action_mapping["gripper"]
action[start] = -1.0
trace = []
for _ in range(round(float(sys.argv[1]) * u.control_freq)):
    agent.set_action(torch.tensor(action[None]))
    for _ in range(u._sim_steps_per_control):
        agent.before_simulation_step()
        u.scene.step()
        trace.append([float(agent.robot.get_qpos()[0, fingers[0]]), float(agent.robot.get_qvel()[0, fingers[0]])])
print(json.dumps({"version": mani_skill.__version__, "sim_freq": u.sim_freq, "control_freq": u.control_freq,
                  "loaded": loaded, "controlled": controlled, "trace": trace}))
"""
)


def peer_answer(python: str, seconds: float) -> dict:
    """The worker's answer, or ``{"unavailable": why}``."""
    result = subprocess.run([python, "-c", WORKER, str(seconds)], capture_output=True, text=True, timeout=600)
    lines = [line for line in result.stdout.splitlines() if line.startswith("{")]
    if not lines:
        return {"unavailable": f"no answer (exit {result.returncode}): {result.stderr.strip()[-300:]}"}
    answer: dict = json.loads(lines[-1])
    return answer


def our_close(seconds: float) -> tuple[int, list[tuple[float, float]]]:
    """Our fingers from open under the closing command, control at the physics rate:
    the physics rate and the left finger's (position, speed) after every step."""
    sim_freq = int(agent_class("fetch", "our_close").sim_freq)
    scene = ra.Scene("fetch", control_modes="pd_joint_pos", control_freq=sim_freq)
    scene.reset(keyframes="rest")
    agent = scene.agents[0]
    fingers = [agent.joint_names.index(j) for j in FINGERS]
    qpos = agent.qpos[0].copy()
    qpos[fingers] = OPEN
    agent.reset(qpos=qpos)
    action = hold_action(agent)
    action[agent.controller.slices["gripper"].start] = -1.0
    trace = []
    for _ in range(round(seconds * sim_freq)):
        agent.set_action(action)
        scene.step()
        trace.append((float(agent.qpos[0, fingers[0]]), float(agent.qvel[0, fingers[0]])))
    scene.close()
    return sim_freq, trace


def close_row(who: str, sim_freq: int, trace: list) -> str:
    at = trace[round(0.05 * sim_freq) - 1][0]
    first = trace[0]
    peak = max(abs(v) for _, v in trace)
    return (
        f"| {who} | {sim_freq} | {OPEN - first[0]:.4f} m at {abs(first[1]):.3f} m/s | {at:.4f} | {peak:.3f} | "
        f"{trace[-1][0]:.4f} |"
    )


def main() -> int:
    parser = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    parser.add_argument("--maniskill-python", default=default_peer_python())
    args = parser.parse_args()
    if not args.maniskill_python:
        print("the peer's interpreter is not installed (/work/shared/peers/setup_maniskill.sh); nothing to compare")
        return 0
    answer = peer_answer(args.maniskill_python, SECONDS)
    if "unavailable" in answer:
        print(f"the peer cannot load fetch: {answer['unavailable']}")
        return 0
    scene = ra.Scene("fetch", control_modes="pd_joint_pos")
    model, agent = scene.model, scene.agents[0]
    drives = {d.joint: d for d in type(agent).check().drives}
    print(f"ManiSkill {answer['version']} (sim {answer['sim_freq']} Hz) against ours, Fetch in pd_joint_pos\n")
    print(
        "| joint | peer as loaded: kp / kd / force limit / friction | peer under its controller: kp / kd / "
        "force limit / friction / armature | ours: joint damping; drive kp / kd / effort limit |\n|---|---|---|---|"
    )
    for name, loaded in answer["loaded"].items():
        controlled = answer["controlled"][name]
        ours = "-"
        if name in drives:
            dof = model.jnt_dofadr[model.joint(agent.prefix + name).id]
            d = drives[name]
            ours = f"{model.dof_damping[dof]:g}; {d.stiffness:g} / {d.damping:g} / {d.effort_limit:g}"
        print(
            f"| `{name}` | {' / '.join(f'{v:.3g}' for v in loaded)} | {' / '.join(f'{v:.3g}' for v in controlled)} "
            f"| {ours} |"
        )
    scene.close()
    sim_freq, trace = our_close(SECONDS)
    print(
        f"\nFingers open ({OPEN} m) -> closing command, the left finger every physics step over {SECONDS} s:\n\n"
        "| who | physics (Hz) | first step | position at 0.05 s (m) | peak speed (m/s) | at the end (m) |\n"
        "|---|---|---|---|---|---|"
    )
    print(close_row("ours", sim_freq, trace))
    print(close_row("peer", int(answer["sim_freq"]), answer["trace"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
