"""The Allegro Hand's touch sensors (``allegro_hand_right_touch``) checked against
numbers: ManiSkill's 16 FSR names in its order; each site covering the palm-side half of
its link's collision shape (read from the compiled model) 1 mm proud; a fingertip pressed
on a grasped cube reading the normal force MuJoCo reports for its contacts while an
untouched one reads 0; a cube resting in the upturned palm read by the palm's sensors as
its weight. Its physics claims run in tests/test_allegro.py with the right hand's."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.robots.wonik.allegro import PALM_UP_MOUNT
from robot_agents.robots.wonik.allegro_touch import MARGIN, TOUCH_NAMES
from tests.test_allegro import CUBE_HALF, CUBE_IN_BASE, CUBE_MASS, in_world

UID = "allegro_hand_right_touch"

#: ManiSkill 3.0.1's AllegroHandRightTouch: palm_fsr_link_names + finger_fsr_link_names.
MANISKILL_FSR = (
    "link_base_fsr",
    "link_0.0_fsr",
    "link_4.0_fsr",
    "link_8.0_fsr",
    "link_14.0_fsr",
    "link_15.0_fsr",
    "link_15.0_tip_fsr",
    "link_1.0_fsr",
    "link_2.0_fsr",
    "link_3.0_tip_fsr",
    "link_5.0_fsr",
    "link_6.0_fsr",
    "link_7.0_tip_fsr",
    "link_9.0_fsr",
    "link_10.0_fsr",
    "link_11.0_tip_fsr",
)
PALM_SENSORS = MANISKILL_FSR[:4]


def test_sensors_are_maniskill_s_fsrs_in_its_order() -> None:
    assert TOUCH_NAMES == MANISKILL_FSR
    scene = ra.Scene(UID)
    scene.reset()
    agent = scene.agents[0]
    assert agent.touch.shape == (1, 16)
    assert agent.get_proprioception()["touch"].shape == (1, 16)
    scene.close()


def collision_geom(model: mujoco.MjModel, body: int) -> int:
    """The body's one colliding geom."""
    geoms = [g for g in range(model.ngeom) if model.geom_bodyid[g] == body and model.geom_contype[g]]
    assert len(geoms) == 1
    return geoms[0]


def site_box(model: mujoco.MjModel, site: int) -> tuple[np.ndarray, np.ndarray]:
    """A site's low and high corners (m) in its body's frame (the sites are unturned)."""
    np.testing.assert_array_equal(model.site_quat[site], (1.0, 0.0, 0.0, 0.0))
    return model.site_pos[site] - model.site_size[site], model.site_pos[site] + model.site_size[site]


def test_each_site_covers_the_palm_side_half_of_its_link_s_collision_shape() -> None:
    """A finger sensor's box reaches from the link's axis (x = 0) to 1 mm past its
    collision shape's palm-side face, and 1 mm past it across and along; the palm's four
    together cover its face the same way, the upper half in three strips."""
    scene = ra.Scene(UID)
    model = scene.model
    prefix = scene.agents[0].prefix
    palm: list[tuple[np.ndarray, np.ndarray]] = []
    for name in TOUCH_NAMES:
        site = model.site(prefix + name).id
        body = int(model.site_bodyid[site])
        geom = collision_geom(model, body)
        low, high = site_box(model, site)
        centre, size = model.geom_pos[geom], model.geom_size[geom]
        if name in PALM_SENSORS:
            palm.append((low, high))
            continue
        if model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_CAPSULE:
            radius, half_length = size[0], size[1]
            half = np.array([radius, radius, half_length + radius])
        else:
            assert model.geom_type[geom] == mujoco.mjtGeom.mjGEOM_BOX
            half = size.copy()
        np.testing.assert_allclose(low, [0.0, centre[1] - half[1] - MARGIN, centre[2] - half[2] - MARGIN], atol=1e-12)
        np.testing.assert_allclose(high, centre + half + MARGIN, atol=1e-12)
    geom = collision_geom(model, model.body(prefix + "base_link").id)
    centre, size = model.geom_pos[geom], model.geom_size[geom]
    low = np.min([p[0] for p in palm], axis=0)
    high = np.max([p[1] for p in palm], axis=0)
    np.testing.assert_allclose(low, [centre[0], -size[1] - MARGIN, centre[2] - size[2] - MARGIN], atol=1e-12)
    np.testing.assert_allclose(high, [centre[0] + size[0] + MARGIN, size[1] + MARGIN, MARGIN], atol=1e-12)
    volume = sum(float(np.prod(h - lo)) for lo, h in palm)
    assert volume == pytest.approx(float(np.prod(high - low)), rel=1e-9)  # no overlap, no gap
    scene.close()


def contact_normal_forces(scene: ra.Scene, body: str) -> float:
    """Sum of the normal forces (N) MuJoCo reports for the contacts on ``body``."""
    model, data = scene.model, scene.world.datas[0]
    body_id = model.body(body).id
    total, wrench = 0.0, np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        if body_id in (model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]):
            mujoco.mj_contactForce(model, data, i, wrench)
            total += wrench[0]
    return total


def contacts_inside(scene: ra.Scene, site: str) -> float:
    """Sum of the normal forces (N) MuJoCo reports for the contacts on ``site``'s body
    whose point lies inside the site's box."""
    model, data = scene.model, scene.world.datas[0]
    site_id = model.site(site).id
    body_id = int(model.site_bodyid[site_id])
    total, wrench = 0.0, np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        if body_id in (model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2]):
            local = data.site_xmat[site_id].reshape(3, 3).T @ (contact.pos - data.site_xpos[site_id])
            if np.all(np.abs(local) <= model.site_size[site_id]):
                mujoco.mj_contactForce(model, data, i, wrench)
                total += wrench[0]
    return total


def test_fingertips_pressed_in_a_grasp_read_the_contact_forces_and_untouched_ones_read_zero() -> None:
    """The declared power grasp (palm up, the 5.5 cm, 100 g cube closed on, 2 s): the
    thumb's tip presses on the cube and its sensor reads the normal force MuJoCo reports
    for the tip's contacts (all on its pad side: several newtons); the ring finger's tip
    touches nothing and reads 0; every sensor reads the contacts inside its site, the
    index tip's on its back (the thumb) not counted, as ManiSkill's palm-side pads would
    not feel them."""
    cube = ra.Prop("cube", "box", (CUBE_HALF,) * 3, pos=(0.3, 0.0, CUBE_HALF), mass=CUBE_MASS)
    scene = ra.Scene(UID, props=[cube], robot_poses=[PALM_UP_MOUNT], control_modes="pd_joint_pos")
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    np.testing.assert_array_equal(agent.touch, 0.0)
    hand = agent.gripper()
    opened, closed = np.asarray(hand.open, dtype=np.float64), np.asarray(hand.closed, dtype=np.float64)

    def act(action: np.ndarray, steps: int) -> None:
        for _ in range(steps):
            agent.set_action(action)
            scene.step()

    act(opened, 20)
    model = scene.model
    joint = int(model.body("cube").jntadr[0])
    qpos_adr = np.arange(7) + int(model.jnt_qposadr[joint])
    dof_adr = np.arange(6) + int(model.jnt_dofadr[joint])
    pose = np.array([[*in_world(CUBE_IN_BASE), 1.0, 0.0, 0.0, 0.0]])
    scene.world.write_joint_state([0], qpos_adr, pose, dof_adr, np.zeros((1, 6)))
    act(opened, 10)
    act(closed, 40)
    assert agent.is_grasping("cube")[0]
    reading = dict(zip(TOUCH_NAMES, agent.touch[0], strict=True))
    prefix = agent.prefix
    thumb = reading["link_15.0_tip_fsr"]
    assert thumb > 3.0
    assert thumb == pytest.approx(contact_normal_forces(scene, prefix + "link_15.0_tip"), rel=1e-9)
    assert contact_normal_forces(scene, prefix + "link_11.0_tip") == 0.0
    assert reading["link_11.0_tip_fsr"] == 0.0
    for name, value in reading.items():
        assert value == pytest.approx(contacts_inside(scene, prefix + name), rel=1e-9, abs=1e-12), name
    assert contact_normal_forces(scene, prefix + "link_3.0_tip") > 1.0 and reading["link_3.0_tip_fsr"] == 0.0
    palm = sum(reading[name] for name in PALM_SENSORS)
    assert palm == pytest.approx(contact_normal_forces(scene, prefix + "base_link"), rel=1e-9)
    scene.close()


def test_the_palm_s_sensors_read_a_resting_cube_s_weight() -> None:
    """Palm up, a 200 g cube laid on the palm: the palm's sensors together read its
    weight (the contacts' normal forces carry it), the fingers' 0."""
    mass, half = 0.2, 0.02
    palm_face = 0.0111
    centre = (PALM_UP_MOUNT[0] + 0.045, 0.0, PALM_UP_MOUNT[2] + palm_face + half + 0.001)
    cube = ra.Prop("cube", "box", (half,) * 3, pos=centre, mass=mass)
    scene = ra.Scene(UID, props=[cube], robot_poses=[PALM_UP_MOUNT])
    scene.reset(keyframes="palm_up")
    agent = scene.agents[0]
    hold = np.zeros(agent.action_space.shape[-1])
    for _ in range(scene.control_freq):  # 1 s
        agent.set_action(hold)
        scene.step()
    reading = dict(zip(TOUCH_NAMES, agent.touch[0], strict=True))
    palm = sum(reading.pop(name) for name in PALM_SENSORS)
    assert palm == pytest.approx(mass * 9.81, rel=0.01)
    assert palm == pytest.approx(contact_normal_forces(scene, "cube"), rel=1e-9)
    assert all(value == 0.0 for value in reading.values()), reading
    scene.close()
