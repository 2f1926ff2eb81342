"""The peer library (ManiSkill 3) in worker processes, for side-by-side benchmarks.

Nothing here imports ManiSkill: each worker is the peer's own Python (a separate
virtual environment, made by ``/work/shared/peers/setup_maniskill.sh``) running
:data:`PEER_WORKER`. Used by ``vs_maniskill.py`` and ``step_throughput.py``.
"""

from __future__ import annotations

import subprocess
import textwrap
import time
from pathlib import Path

#: Where ``setup_maniskill.sh`` puts the peer's interpreter by default.
DEFAULT_PEER_PYTHON = Path.home() / ".venvs" / "maniskill" / "bin" / "python"


def default_peer_python() -> str | None:
    """The peer's interpreter when it exists (``None`` otherwise)."""
    return str(DEFAULT_PEER_PYTHON) if DEFAULT_PEER_PYTHON.exists() else None


#: Peer-side code that lets SAPIEN load robots without a GPU: it builds render materials
#: and visual meshes even with render_backend="none"; they are replaced by inert
#: stand-ins (visuals only: the physics is untouched). Top-level code; indent it to
#: run it inside a block.
INERT_VISUALS = """
import sapien.render, sapien.wrapper.urdf_loader as urdf_loader, sapien.wrapper.actor_builder as builder
class Inert:
    def __init__(self, *a, **k): pass
    def __getattr__(self, name): return Inert()
    def __call__(self, *a, **k): return Inert()
    def __getitem__(self, k): return [1.0, 1.0, 1.0, 1.0][k]
    def __iter__(self): return iter([1.0, 1.0, 1.0, 1.0])
    def __len__(self): return 4
for module in (sapien.render, urdf_loader):
    for name in ("RenderMaterial", "RenderTexture2D"):
        if hasattr(module, name):
            setattr(module, name, Inert)
for name in dir(builder.ActorBuilder):
    if name.startswith("add_") and "visual" in name:
        setattr(builder.ActorBuilder, name, lambda self, *a, **k: self)
"""

#: The peer's worker, run by the peer's own Python: makes ``Empty-v1`` with the robot
#: and mode given on the command line, then for every line ``N`` it reads, steps N
#: small actions of alternating sign and answers with the seconds the steps took
#: (visuals replaced by :data:`INERT_VISUALS`).
PEER_WORKER = (
    """
import sys, time
import numpy as np
try:"""
    + textwrap.indent(INERT_VISUALS, "    ")
    + """    import builtins
    builtins.input = lambda *a: "n"  # asset downloads ask; never download here
    import gymnasium as gym, mani_skill, mani_skill.envs
    env = gym.make("Empty-v1", robot_uids=sys.argv[1], obs_mode="state", control_mode=sys.argv[2],
                   sim_backend="cpu", render_backend="none")
    env.reset(seed=0)
except BaseException as error:
    print("unavailable", type(error).__name__, str(error).replace(chr(10), " ")[:160], flush=True)
    sys.exit(0)
space = env.action_space
mid, half = (space.low + space.high) / 2, (space.high - space.low) / 2
rng = np.random.default_rng(0)
actions = [(mid + (-1) ** i * 0.1 * half * rng.uniform(0, 1, space.shape)).astype(np.float32) for i in range(64)]
u = env.unwrapped
print("ready", mani_skill.__version__, u.control_freq, u.sim_freq, flush=True)
count = 0
for line in sys.stdin:
    n = int(line)
    start = time.perf_counter()
    for _ in range(n):
        env.step(actions[count % 64])
        count += 1
    print(time.perf_counter() - start, flush=True)
"""
)


class Peer:
    """The peer library's env in a worker process (see ``PEER_WORKER``)."""

    def __init__(self, python: str, uid: str, mode: str) -> None:
        self.process = subprocess.Popen(
            [python, "-c", PEER_WORKER, uid, mode],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )
        if self.process.stdout is None:
            raise RuntimeError("the peer worker has no stdout pipe")
        words = self.process.stdout.readline().split()
        self.ready = bool(words) and words[0] == "ready"
        self.status = " ".join(words) if words else "no answer"
        self.blocks: list[float] = []
        if not self.ready:
            self.close()

    def loop(self, count: int) -> None:
        """Step ``count`` times in the worker; records the worker's own timing of them."""
        if self.process.stdin is None or self.process.stdout is None:
            raise RuntimeError("the peer worker has no pipes")
        self.process.stdin.write(f"{count}\n")
        self.process.stdin.flush()
        self.blocks.append(float(self.process.stdout.readline()))

    def close(self) -> None:
        if self.process.stdin is not None:
            self.process.stdin.close()
        self.process.wait(timeout=60)


class PeerPool:
    """``n`` peer workers stepping at the same time (ManiSkill's CPU simulation runs
    one env per process; this is how it uses all cores). :meth:`loop` sends every
    worker the same count, waits for all, and records the wall time of the whole."""

    def __init__(self, python: str, uid: str, mode: str, n: int) -> None:
        self.workers = [Peer(python, uid, mode) for _ in range(n)]
        self.ready = all(w.ready for w in self.workers)
        self.status = next((w.status for w in self.workers if not w.ready), self.workers[0].status)
        self.blocks: list[float] = []
        if not self.ready:
            self.close()

    def loop(self, count: int) -> None:
        start = time.perf_counter()
        for worker in self.workers:
            if worker.process.stdin is None:
                raise RuntimeError("the peer worker has no stdin pipe")
            worker.process.stdin.write(f"{count}\n")
            worker.process.stdin.flush()
        for worker in self.workers:
            if worker.process.stdout is None:
                raise RuntimeError("the peer worker has no stdout pipe")
            worker.process.stdout.readline()
        self.blocks.append(time.perf_counter() - start)

    def close(self) -> None:
        for worker in self.workers:
            if worker.process.poll() is None:
                worker.close()
