"""Torque-limit cycles: the physics steps at which a force-limited PD drive can chatter.

MuJoCo's ``implicitfast`` integrator treats a drive's velocity feedback (``kv``)
implicitly, which keeps stiff gains stable at coarse steps, but only while the drive's
force is inside its range: a clamped force does not depend on velocity, so its
derivative is left out and the step is explicit. A joint near its target can then fall
into a cycle that flips its drive between the two limits every physics step. With
``L`` the effort limit, ``dt`` the step and ``m = I + b * dt`` the joint's apparent
inertia ``I`` (kg*m^2 or kg) plus its own damping ``b`` (``dof_damping``, always
implicit), each saturated step changes the velocity by ``L * dt / m``, so the cycle
alternates ``v = +-L * dt / (2 m)`` (its **amplitude**); it sustains itself when that
velocity saturates the drive again, ``kv * v >= L``, that is when

    kv * dt / m >= 2.

Below that ratio a saturated drive's velocity settles instead (``tests/test_cycles.py``
checks both sides on a one-joint model, and the Panda's wrist, whose cycle the sweep's
settle claim sees at 400 Hz and not at 500 Hz, against this bound: 485 Hz). The bound
is taken at the smallest apparent inertia ``1 / (M^-1)_jj`` found over joint
configurations sampled within the limits (``M``: the joint-space inertia with armature;
``1 / (M^-1)_jj`` is what the joint feels when the others move freely, a lower bound of
what it feels while their drives hold them).

Entering the cycle takes a joint speed above ``L / kv`` near the target. A drive with
a rated speed (``velocity_limit``) below that is not **reachable**: the robot's own
motion does not get there (an impact could).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from robot_agents.agent import Agent
from robot_agents.registry import agent_class
from robot_agents.sim.scene import Scene
from robot_agents.validation import check_whole

#: ``kv * dt / I`` at and above which a clamped drive can cycle between its limits.
CYCLE_RATIO = 2.0
#: Joint configurations sampled for the smallest apparent inertia.
DEFAULT_SAMPLES = 256


@dataclass(frozen=True)
class DriveCycleBound:
    """One force-limited drive with velocity feedback.

    Attributes:
        joint: the driven joint's name.
        stiffness: ``kp`` (N*m/rad or N/m) as built (the default mode's drive settings).
        damping: ``kv`` (N*m*s/rad or N*s/m).
        effort_limit: ``L`` (N*m or N), the drive's force range (the smaller bound).
        inertia: the smallest apparent inertia found, ``min 1 / (M^-1)_jj`` (kg*m^2 or kg).
        joint_damping: the joint's own damping ``b`` (N*m*s/rad or N*s/m).
        velocity_limit: the drive's rated speed (rad/s or m/s; ``inf``: none declared).
    """

    joint: str
    stiffness: float
    damping: float
    effort_limit: float
    inertia: float
    joint_damping: float
    velocity_limit: float

    @property
    def cycle_free_above(self) -> float:
        """The physics rate (Hz) above which the drive cannot cycle (0: it cannot at any
        rate, its joint's own damping is enough)."""
        excess = self.damping - CYCLE_RATIO * self.joint_damping
        return excess / (CYCLE_RATIO * self.inertia) if excess > 0 else 0.0

    @property
    def reachable(self) -> bool:
        """The robot's own motion can reach the cycle: rated speed above ``L / kv``."""
        return self.velocity_limit > self.effort_limit / self.damping

    def ratio(self, sim_freq: float) -> float:
        """``kv * dt / m`` at ``sim_freq`` (Hz); at or above :data:`CYCLE_RATIO` it can cycle."""
        dt = 1.0 / sim_freq
        return self.damping * dt / (self.inertia + self.joint_damping * dt)

    def amplitude(self, sim_freq: float) -> float:
        """Speed (rad/s or m/s) the joint alternates at in the cycle possible at
        ``sim_freq`` (Hz), ``L * dt / (2 m)``; 0 where no cycle is possible."""
        if self.ratio(sim_freq) < CYCLE_RATIO:
            return 0.0
        dt = 1.0 / sim_freq
        return self.effort_limit * dt / (2.0 * (self.inertia + self.joint_damping * dt))


def drive_cycle_bounds(
    robot: str | type[Agent], samples: int = DEFAULT_SAMPLES, seed: int = 0
) -> tuple[DriveCycleBound, ...]:
    """Every force-limited drive of ``robot`` with velocity feedback (as the default
    mode sets them), highest ``cycle_free_above`` first. Configurations: the default
    keyframe and ``samples`` uniform draws of the hinge and slide joints within their
    limits (unlimited ones: one turn, or +-pi m), from ``seed``."""
    cls = agent_class(robot, "drive_cycle_bounds")
    samples = check_whole(samples, "samples", "drive_cycle_bounds")
    scene = Scene(cls)
    try:
        scene.reset()
        agent = scene.agents[0]
        model = scene.model
        data = mujoco.MjData(model)
        data.qpos[:] = scene.world.physics_sources([0])[0].qpos
        drives = _limited_drives(model, set(agent.dof_adr.tolist()))
        speeds = {d.joint: d.velocity_limit for d in cls.check().drives}
        if not drives:
            return ()
        one_dof = [
            k
            for k, adr in enumerate(agent.qpos_adr)
            if int(model.jnt_type[_joint_at(model, int(adr))])
            in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
        ]
        sampled = agent.qpos_adr[one_dof]
        limits = np.clip(agent.qpos_limits[one_dof], -np.pi, np.pi)
        rng = np.random.default_rng(seed)
        largest = np.zeros(len(drives))  # max over configurations of (M^-1)_jj
        mass = np.zeros((model.nv, model.nv))
        dofs = [dof for _, dof in drives]
        for sample in range(samples + 1):
            if sample:
                data.qpos[sampled] = rng.uniform(limits[:, 0], limits[:, 1])
            mujoco.mj_kinematics(model, data)
            mujoco.mj_comPos(model, data)
            mujoco.mj_crb(model, data)
            mujoco.mj_fullM(model, data, mass)
            diagonal = np.diag(np.linalg.inv(mass))[dofs]
            np.maximum(largest, diagonal, out=largest)
        bounds = []
        for (actuator, dof), inverse in zip(drives, largest, strict=True):
            joint = int(model.dof_jntid[dof])
            name = model.joint(joint).name.split("/", 1)[-1]  # without the scene prefix
            bounds.append(
                DriveCycleBound(
                    joint=name,
                    stiffness=float(model.actuator_gainprm[actuator, 0]),
                    damping=-float(model.actuator_biasprm[actuator, 2]),
                    effort_limit=float(np.min(np.abs(model.actuator_forcerange[actuator]))),
                    inertia=1.0 / float(inverse),
                    joint_damping=float(model.dof_damping[dof]),
                    velocity_limit=float(speeds.get(name, np.inf)),
                )
            )
        return tuple(sorted(bounds, key=lambda b: -b.cycle_free_above))
    finally:
        scene.close()


def _joint_at(model: mujoco.MjModel, qpos_adr: int) -> int:
    """The joint whose coordinates include ``qpos[qpos_adr]``."""
    return int(np.searchsorted(model.jnt_qposadr, qpos_adr, side="right") - 1)


def _limited_drives(model: mujoco.MjModel, dofs: set[int]) -> list[tuple[int, int]]:
    """``(actuator, dof)`` of the force-limited joint drives on ``dofs`` with velocity
    feedback (affine bias with ``kv > 0``)."""
    out = []
    for actuator in range(model.nu):
        if int(model.actuator_trntype[actuator]) != int(mujoco.mjtTrn.mjTRN_JOINT):
            continue
        if not model.actuator_forcelimited[actuator] or int(model.actuator_biastype[actuator]) != int(
            mujoco.mjtBias.mjBIAS_AFFINE
        ):
            continue
        if not -model.actuator_biasprm[actuator, 2] > 0:
            continue
        dof = int(model.jnt_dofadr[model.actuator_trnid[actuator, 0]])
        if dof in dofs:
            out.append((actuator, dof))
    return out
