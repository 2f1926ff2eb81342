"""A fingertip pressed into a fixed block comes to rest: the Allegro hands' middle finger,
its proximal joint driven 0.3 rad past the angle at which its tip meets a block welded to
the world (``palm_side``, ``pd_joint_pos``, 3 s). Over the last second every joint is
slower than the sweep's settle bound and the contact force steady; with the fingertip
pads' former near-rigid contact (solref 0.01 s, impedance 0.9999) the tip chattered on
the block (allegro.py's docstring has the measurements)."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.robots.wonik.allegro import AllegroHandRight
from robot_agents.robots.wonik.allegro_left import AllegroHandLeft
from robot_agents.robots.wonik.allegro_touch import AllegroHandRightTouch
from robot_agents.tuning.claims import SETTLE_SPEED

#: The middle finger's proximal joint (ManiSkill's order) and fingertip body.
PROXIMAL = 5
TIP = "link_7.0_tip"
#: Proximal angle (rad) at which the tip meets the block, and how far past it the target is.
CONTACT_ANGLE = 0.3
PAST_CONTACT = 0.3
#: Block half extents (m): 4 x 3 x 8 cm, narrower than the 8.7 cm between the index and
#: ring fingers' centre lines, so that only the middle finger reaches it.
BLOCK_HALF = (0.02, 0.015, 0.04)
SECONDS = 3
#: The former pads' contact, as it was in the tip class of allegro_hand_right.xml.
NEAR_RIGID = 'condim="4" priority="1" solref="0.01 1" solimp="0.9999 0.9999 0.01"'
PADS = 'condim="4" priority="1"/>'


def block_at_contact(cls: type[ra.Agent]) -> ra.Prop:
    """A static block whose face (normal -x, towards the palm side) the middle fingertip's
    capsule touches when the proximal joint is at :data:`CONTACT_ANGLE`, the others at
    ``palm_side``."""
    scene = ra.Scene(cls, control_modes="pd_joint_pos")
    scene.reset(keyframes="palm_side")
    model, data = scene.model, scene.world.datas[0]
    prefix = scene.agents[0].prefix
    data.qpos[model.jnt_qposadr[model.joint(f"{prefix}joint_{PROXIMAL}.0").id]] = CONTACT_ANGLE
    mujoco.mj_kinematics(model, data)
    tip = model.body(f"{prefix}{TIP}").id
    geom = next(g for g in range(model.ngeom) if model.geom_bodyid[g] == tip and model.geom_contype[g])
    axis = data.geom_xmat[geom].reshape(3, 3)[:, 2]
    radius, half = model.geom_size[geom][:2]
    ends = data.geom_xpos[geom] + np.outer((half, -half), axis)
    face = float(ends[:, 0].max()) + radius
    scene.close()
    return ra.Prop("block", "box", BLOCK_HALF, pos=(face + BLOCK_HALF[0], 0.0, float(ends[:, 2].mean())), mass=None)


def press(cls: type[ra.Agent], sim_freq: int) -> tuple[np.ndarray, np.ndarray]:
    """The block's total contact normal force (N) and the fastest joint (rad/s) at each
    control step (20 Hz) of the last second of :data:`SECONDS` pressing."""
    scene = ra.Scene(cls, props=[block_at_contact(cls)], control_modes="pd_joint_pos", sim_freq=sim_freq)
    scene.reset(keyframes="palm_side")
    agent = scene.agents[0]
    model, data = scene.model, scene.world.datas[0]
    block = model.body("block").id
    target = np.array(agent.qpos, dtype=np.float64)
    target[0, PROXIMAL] = CONTACT_ANGLE + PAST_CONTACT
    wrench = np.zeros(6)
    forces, speeds = [], []
    for step in range(SECONDS * scene.control_freq):
        agent.set_action(target)
        scene.step()
        if step < (SECONDS - 1) * scene.control_freq:
            continue
        force = 0.0
        for i in range(data.ncon):
            contact = data.contact[i]
            if block in (model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]):
                mujoco.mj_contactForce(model, data, i, wrench)
                force += wrench[0]
        forces.append(force)
        speeds.append(float(np.abs(agent.qvel[0]).max()))
    scene.close()
    return np.array(forces), np.array(speeds)


@pytest.mark.parametrize("cls", [AllegroHandRight, AllegroHandLeft, AllegroHandRightTouch])
def test_a_fingertip_pressed_into_a_fixed_block_comes_to_rest(cls: type[ra.Agent]) -> None:
    """At the declared step and two finer ones: joints below the settle bound, the force
    steady within 1 % (measured: 18.4 N, steady to 2e-5 N, joints below 1.4e-5 rad/s, from 160 Hz to 2 kHz)."""
    for sim_freq in (cls.sim_freq or 200, 500, 1000):
        forces, speeds = press(cls, sim_freq)
        assert speeds.max() < SETTLE_SPEED, f"{cls.uid} at {sim_freq} Hz: {speeds.max():.3f} rad/s"
        assert forces.min() > 10.0, f"{cls.uid} at {sim_freq} Hz: the tip left the block ({forces.min():.1f} N)"
        swing = (forces.max() - forces.min()) / forces.mean()
        assert swing < 0.01, f"{cls.uid} at {sim_freq} Hz: {forces.min():.1f}-{forces.max():.1f} N"


def test_the_former_near_rigid_pads_chatter_on_the_block(tmp_path: Path) -> None:
    """The check can fail: with the pads' former contact the tip loses and regains the
    block (measured at 200 Hz: 0-42 N, 1.46 rad/s over the last second)."""
    path = Path(str(AllegroHandRight.mjcf_path))
    source = path.read_text()
    assert source.count(PADS) == 1
    (tmp_path / path.name).write_text(source.replace(PADS, NEAR_RIGID + "/>"))
    near_rigid = type("NearRigidPads", (AllegroHandRight,), {"uid": "", "mjcf_path": tmp_path / path.name})
    forces, speeds = press(near_rigid, 200)
    assert speeds.max() > 10 * SETTLE_SPEED
    assert forces.min() < 0.5 * forces.max()
