"""How deep random actions press each robot's links into the floor and into each other,
at the robot's default step, and what a stiffer floor contact would change.

The time-step sweep (:func:`robot_agents.tuning.claims.measure_step`) reports the
deepest contact of its random-action claim beside the claims ("random-action press"), not
judged. This script says where that depth comes from: for each robot and each of its
modes, the sweep's action sequences (``RANDOM_SEEDS``, ``RANDOM_SECONDS`` of uniform
random actions at 20 Hz control, from the default keyframe), and after every control
step the deepest contact of env 0, sorted into

- ``floor``: a robot geom against the scene's floor plane;
- ``self``: two geoms of the robot (links pressed into each other by their drives).

For each it prints the depth (m), the geom pair (:func:`contact_label`), the contact's
normal force (N) at that moment and the mode and seed.

``--floor-solref TIMECONST DAMPRATIO``, ``--floor-solimp DMIN DMAX WIDTH`` and
``--floor-solmix W`` give the floor other contact parameters (written into the compiled
model after the scene is built; robot geoms with a ``priority`` of their own keep theirs,
MuJoCo's rule). ``--claims`` also runs every claim of the sweep at the default step with
the same floor (``measure_step``) and prints those that fail, so a floor contact can be
judged against all of them; ``--claims-at HZ ...`` at these physics rates instead (the
sweep takes a robot's largest passing step to be one at which every finer step passes
too, so a claim failing at a finer step matters as much). The defaults are the library's floor
(:data:`robot_agents.model.scene.FLOOR_SOLREF` and its neighbours);
``--floor-solref 0.02 1 --floor-solimp 0.9 0.95 0.001 --floor-solmix 1`` is MuJoCo's
default contact, the library's floor before 2026-11-24.

Why a deep press: in MuJoCo a contact pushed at a constant unconstrained acceleration
``a0`` (m/s^2, the acceleration the contact prevents) settles at a penetration of about
``(1 - d) * d * timeconst**2 * dampratio**2 * a0``, ``d`` the impedance at that depth
(``solimp``'s ``dmax`` past ``width``): 1.9e-5 s^2 times ``a0`` for the default contact;
light links driven at their full torque (``a0`` of 10^3-10^4 m/s^2) press centimetres.

Usage: ``python benchmarks/random_press.py [UID ...] [--seeds 0 1 2] [--floor-solref T D]
[--floor-solimp D0 D1 W] [--floor-solmix W] [--claims | --claims-at HZ ...]``.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

import robot_agents as ra
from robot_agents.model.scene import FLOOR_SOLIMP, FLOOR_SOLMIX, FLOOR_SOLREF
from robot_agents.sim.scene import DEFAULT_CONTROL_FREQ, Scene, default_sim_freq
from robot_agents.tuning.claims import RANDOM_SECONDS, RANDOM_SEEDS, contact_label, measure_step, scene_setup


@dataclass(frozen=True)
class FloorContact:
    """Contact parameters for the scene's floor geom (MuJoCo's meaning and units)."""

    solref: tuple[float, float] = FLOOR_SOLREF
    solimp: tuple[float, float, float] = FLOOR_SOLIMP
    solmix: float = FLOOR_SOLMIX

    def apply(self, scene: Scene) -> None:
        model = scene.model
        floor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
        if floor < 0:
            return
        model.geom_solref[floor] = self.solref
        model.geom_solimp[floor, :3] = self.solimp
        model.geom_solmix[floor] = self.solmix


@dataclass
class Press:
    """The deepest contact of one kind seen so far."""

    depth: float = 0.0
    where: str = ""
    force: float = 0.0
    when: str = ""

    def row(self) -> str:
        if not self.where:
            return "none"
        return f"{self.depth:.4f} m  {self.where}  {self.force:.0f} N  ({self.when})"


def random_press(uid: str, seeds: Sequence[int], floor: FloorContact) -> tuple[Press, Press]:
    """The deepest floor and self contact of ``uid``'s random-action sequences."""
    cls = ra.get_agent(uid)
    control_freq = DEFAULT_CONTROL_FREQ
    on_floor, on_self = Press(), Press()
    force = np.zeros(6)
    for mode in cls.modes():
        for seed in seeds:
            scene = Scene(cls, control_freq=control_freq, control_modes=mode)
            floor.apply(scene)
            scene.reset()
            agent = scene.agents[0]
            model, data = scene.model, scene.world.physics_sources([0])[0]
            floor_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
            rng = np.random.default_rng(seed)
            space = agent.action_space
            for step in range(round(RANDOM_SECONDS * control_freq)):
                agent.set_action(rng.uniform(space.low, space.high))
                scene.step()
                for i in range(data.ncon):
                    contact = data.contact[i]
                    kind = on_floor if floor_id in (contact.geom1, contact.geom2) else on_self
                    if -contact.dist > kind.depth:
                        mujoco.mj_contactForce(model, data, i, force)
                        kind.depth = -float(contact.dist)
                        kind.where = f"{contact_label(model, contact.geom1)} / {contact_label(model, contact.geom2)}"
                        kind.force = float(force[0])
                        kind.when = f"{mode}, seed {seed}, step {step}"
            scene.close()
    return on_floor, on_self


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("robots", nargs="*", help="robot uids (default: every registered robot)")
    parser.add_argument("--seeds", type=int, nargs="+", default=list(RANDOM_SEEDS))
    parser.add_argument("--floor-solref", type=float, nargs=2, default=None, metavar=("TIMECONST", "DAMPRATIO"))
    parser.add_argument("--floor-solimp", type=float, nargs=3, default=None, metavar=("DMIN", "DMAX", "WIDTH"))
    parser.add_argument("--floor-solmix", type=float, default=None)
    parser.add_argument("--claims", action="store_true", help="also run every claim with this floor")
    parser.add_argument("--claims-at", type=int, nargs="+", default=None, metavar="HZ", help="... at these sim_freq")
    args = parser.parse_args(argv)
    default = FloorContact()
    floor = FloorContact(
        solref=tuple(args.floor_solref) if args.floor_solref else default.solref,
        solimp=tuple(args.floor_solimp) if args.floor_solimp else default.solimp,
        solmix=args.floor_solmix if args.floor_solmix is not None else default.solmix,
    )
    uids = args.robots or ra.list_agents()
    unknown = [uid for uid in uids if uid not in ra.list_agents()]
    if unknown:
        parser.error(f"unknown robot uids {unknown}; available: {ra.list_agents()}")
    print(f"floor: solref {floor.solref}, solimp {floor.solimp}, solmix {floor.solmix}; seeds {args.seeds}")
    claims_at = args.claims_at or ([None] if args.claims else [])
    for uid in uids:
        begin = time.perf_counter()
        on_floor, on_self = random_press(uid, args.seeds, floor)
        print(f"{uid}  (sim_freq {default_sim_freq([ra.get_agent(uid)])})")
        print(f"  floor: {on_floor.row()}")
        print(f"  self:  {on_self.row()}")
        cls = ra.get_agent(uid)
        for sim_freq in claims_at:
            rate = sim_freq or default_sim_freq([cls])
            with scene_setup(floor.apply):  # every claim's scene gets this floor
                result = measure_step(cls, rate, seeds=args.seeds)
            failed = [f"{c.name} {c.value:.4g} (bound {c.bound:g}; {c.detail})" for c in result.claims if not c.passed]
            print(f"  claims at {rate} Hz: {'all hold' if not failed else 'FAIL ' + '; '.join(failed)}")
        print(f"  ({time.perf_counter() - begin:.1f} s)", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
