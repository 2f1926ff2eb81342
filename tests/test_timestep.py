"""The time-step sweep (robot_agents.tuning.timestep), per-robot default steps
(``AgentDefinition.sim_freq``) and the Panda wrist's torque-limit oscillation."""

from __future__ import annotations

import dataclasses
import io
from collections.abc import Callable
from pathlib import Path
from typing import ClassVar

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import check_keyframes, hold_action, run_random_actions
from robot_agents.cli import cmd_check
from robot_agents.errors import ConfigError
from robot_agents.model.compose import Attachment
from robot_agents.robots.panda.panda import HAND_ON_FLANGE, PANDA_HAND_DRIVES, Panda, PandaHand
from robot_agents.robots.servo_arms.so100 import SO100
from robot_agents.sim.scene import DEFAULT_SIM_FREQ, Scene
from robot_agents.tuning.claims import (
    CLAIMS,
    LEGGED_SETTLE_SECONDS,
    OVERSHOOT_BOUND,
    SETTLE_SECONDS,
    SETTLE_SPEED,
    SETTLE_WINDOW,
    ClaimResult,
    Penetration,
    StepResult,
    _random,
    contact_label,
    measure_step,
    scene_setup,
    settle_hold,
)
from robot_agents.tuning.grasp_claim import SLIP_BOUND, grasp_claim
from robot_agents.tuning.timestep import SweepResult, sweep_timestep
from tests.random_actions import after_random_actions


def settled_speed(cls: type[ra.Agent], mode: str, sim_freq: int, seed: int = 0) -> tuple[float, str]:
    """Fastest joint speed after 10 s of random actions and the sweep's settle hold
    (``settle_hold``), and that joint."""
    scene = after_random_actions(cls, mode, sim_freq, seed)
    speed, joint = settle_hold(scene, scene.agents[0])
    scene.close()
    return speed, joint


def test_panda_wrist_settles_after_random_actions() -> None:
    """Without the wrist's rotor inertia (armature 0), joint 7 (12 N*m limit, kv = 100,
    about 0.05 kg*m^2) is left in a bang-bang cycle between its torque limits, 0.26 rad/s
    after 10 s of random pd_joint_delta_pos actions and 1 s of holding still: MuJoCo
    integrates the drive's damping implicitly only while the force is inside its range."""
    speed, joint = settled_speed(Panda, "pd_joint_delta_pos", 500)
    assert speed < SETTLE_SPEED, f"{joint} still moves at {speed:.3f} rad/s"


def test_settle_claim_asks_the_robot_to_stay_where_the_random_actions_left_it() -> None:
    """After random target-delta actions (seed 0) the Bridge WidowX's accumulated targets
    lie far from its joints: holding them, its tuned, overdamped forearm roll is still
    travelling after 3 s (the 2026-11-23 claim failed this robot at every step); the
    claim's hold first sets the targets to the measured pose, and the arm is still."""
    scene = after_random_actions(ra.get_agent("widowx250s_bridgedataset_flat_table"), "pd_joint_target_delta_pos", 1000)
    state = scene.get_state()
    agent = scene.agents[0]
    hold = hold_action(agent)  # the accumulated targets, kept
    for _ in range(round(SETTLE_SECONDS * scene.control_freq)):
        agent.set_action(hold)
        scene.step()
    travelling = float(np.abs(agent.qvel[0]).max())
    scene.set_state(state)
    speed, _ = settle_hold(scene, agent)
    scene.close()
    assert travelling > 0.1
    assert speed < SETTLE_SPEED


def test_settle_claim_fails_a_drive_cycling_between_its_torque_limits() -> None:
    """The Panda's wrist cycles at 400 Hz (seed 2, the sweep's failure one step coarser
    than its default): the cycle goes on from targets at the measured pose too."""
    speed, joint = settled_speed(Panda, "pd_joint_delta_pos", 400, seed=2)
    assert speed > 0.1 and joint.endswith("panda_joint7"), (speed, joint)


def test_legged_settle_claim_fails_a_drive_cycling_between_its_torque_limits() -> None:
    """The Go2 with ManiSkill's kp 1000 / kv 100 (cycles below 2.5-3.6 kHz in MuJoCo) at
    400 Hz: after random actions a calf drive flips between its limits, about 3 rad/s
    while barely moving, and the legged claim (cycling joints only) sees it; at Unitree's
    own gains no joint cycles."""
    go2 = ra.get_agent("unitree_go2")
    maniskill_gains = type(
        "ManiSkillGainsGo2",
        (go2,),
        {"uid": "", "actuators": tuple(dataclasses.replace(a, stiffness=1000.0, damping=100.0) for a in go2.actuators)},
    )
    for cls, cycles in ((maniskill_gains, True), (go2, False)):
        scene = after_random_actions(cls, "pd_joint_pos", 400)
        speed, joint = settle_hold(scene, scene.agents[0], LEGGED_SETTLE_SECONDS, cycles_only=True)
        scene.close()
        if cycles:
            assert speed > 1.0 and joint.endswith("calf_joint"), (speed, joint)
        else:
            assert (speed, joint) == (0.0, "")


def test_legged_settle_claim_lets_a_fallen_robot_rock() -> None:
    """Random target-delta actions (seed 1) throw the ANYmal onto its back at 640 Hz; 5 s
    into the hold it still rocks, a leg joint swinging faster than the settle bound with
    the body: moving with it, no joint cycles, and the claim holds."""
    scene = after_random_actions(ra.get_agent("anymal_c"), "pd_joint_target_delta_pos", 640, seed=1)
    state = scene.get_state()
    fastest, _ = settle_hold(scene, scene.agents[0], LEGGED_SETTLE_SECONDS)
    scene.set_state(state)
    cycling, _ = settle_hold(scene, scene.agents[0], LEGGED_SETTLE_SECONDS, cycles_only=True)
    scene.close()
    assert fastest > SETTLE_SPEED
    assert cycling == 0.0


def settle_with_fake_speeds(speed_at: Callable[[int], float]) -> float:
    """``settle_hold`` of the SO-100 holding still when, after each control step ``k``
    (from 1), its first joint's measured speed is replaced by ``speed_at(k)``."""
    scene = Scene(SO100, control_modes="pd_joint_pos", sim_freq=200)
    scene.reset()
    agent = scene.agents[0]
    step = 0

    def replace_speed() -> None:
        nonlocal step
        step += 1
        scene.world.datas[0].qvel[agent.index.dof_adr[0]] = speed_at(step)
        scene.world.invalidate()

    speed, _ = settle_hold(scene, agent, on_step=replace_speed)
    scene.close()
    return speed


def test_settle_claim_needs_every_joint_below_the_bound_over_its_last_window() -> None:
    """One slow sample does not pass the claim: speeds below the bound at the last step
    only fail it with the window's 0.2; a fast step before the window does not count."""
    steps, window = round(SETTLE_SECONDS * 20), round(SETTLE_WINDOW * 20)
    assert settle_with_fake_speeds(lambda k: 0.01 if k == steps else 0.2) == 0.2
    assert settle_with_fake_speeds(lambda k: 0.2 if k == steps - window else 0.01) == 0.01
    assert settle_with_fake_speeds(lambda k: 0.2 if k == steps - window + 1 else 0.01) == 0.2


def test_panda_wrist_oscillates_without_armature() -> None:
    """The same motion without the armature shows the cycle (the test above can fail)."""

    class BarePanda(Panda):
        uid = ""
        actuators = (Panda.actuators[0].__class__(**{**vars(Panda.actuators[0]), "armature": None}),)
        keyframes: ClassVar = Panda.keyframes

    speed, joint = settled_speed(BarePanda, "pd_joint_delta_pos", 500)
    assert speed > 0.1 and joint.endswith("panda_joint7")


@pytest.mark.parametrize(
    ("uid", "mode"),
    [
        ("ur_10e", "pd_joint_vel"),
        ("widowxai", "pd_joint_pos_vel"),
        ("widowx250s_bridgedataset_flat_table", "pd_joint_pos"),
        ("google_robot", "pd_joint_target_delta_pos"),
        ("floating_panda_gripper", "pd_joint_pos"),
    ],
)
def test_drives_that_cycled_between_their_torque_limits_settle_at_their_default_step(uid: str, mode: str) -> None:
    """The UR10e (Menagerie's gains), the WidowX AI (at 1 kHz), the Bridge WidowX
    (unclamped tuned drives), the Google Robot's head (damping 90, not 900) and the
    floating Panda gripper's mount (no effort limit) settle after 10 s of random actions
    and the sweep's hold."""
    cls = ra.get_agent(uid)
    speed, joint = settled_speed(cls, mode, cls.sim_freq or DEFAULT_SIM_FREQ)
    assert speed < SETTLE_SPEED, f"{joint} still moves at {speed:.3f} rad/s"


def test_ur10e_wrists_cycle_with_the_former_gains() -> None:
    """kp 5000, kv 500 on the wrists (54 N*m (56 when the gains were), 0.1 kg*m^2 armature: kv * dt / I = 10 at
    2 ms) leaves a wrist in a torque-limit cycle: the test above can fail."""
    ur = ra.get_agent("ur_10e")

    class FormerUR10e(ur):  # type: ignore[valid-type,misc]
        uid = ""
        actuators = (dataclasses.replace(ur.actuators[0], stiffness=5000.0, damping=500.0),)

    speed, joint = settled_speed(FormerUR10e, "pd_joint_vel", 500)
    assert speed > 0.1 and "wrist" in joint


def test_floating_gripper_mount_cycles_with_maniskills_effort_limit() -> None:
    """With ManiSkill's 100 N*m limit on the mount, a hinge carrying only the hand cycles
    between its limits at 200 Hz (without the limit it settles there and at its 160 Hz):
    the test above can fail."""
    floating = ra.get_agent("floating_panda_gripper")

    class LimitedMount(floating):  # type: ignore[valid-type,misc]
        uid = ""
        actuators = (dataclasses.replace(floating.actuators[0], effort_limit=100.0),)

    speed, joint = settled_speed(LimitedMount, "pd_joint_pos", 200)
    assert speed > 0.1 and "rot" in joint, (speed, joint)
    assert settled_speed(floating, "pd_joint_pos", 200)[0] < SETTLE_SPEED


def largest_overshoot(cls: type[ra.Agent], mode: str, sim_freq: int, soft_limits: bool = False) -> float:
    """How far (rad or m) any joint passes its limit over 10 s of random actions
    (``soft_limits``: with MuJoCo's default limit stiffness, time constant 20 ms)."""
    scene = Scene(cls, control_modes=mode, sim_freq=sim_freq)
    if soft_limits:
        scene.model.jnt_solref[:] = (0.02, 1.0)
    scene.reset()
    agent = scene.agents[0]
    limits = agent.qpos_limits
    worst = [0.0]

    def measure() -> None:
        q = agent.qpos[0]
        worst[0] = max(worst[0], float(np.max(np.maximum(q - limits[:, 1], limits[:, 0] - q), initial=0.0)))

    run_random_actions(scene, 10.0, 0, measure)
    scene.close()
    return worst[0]


@pytest.mark.parametrize(
    ("uid", "mode", "soft"),
    [("ur_10e", "pd_ee_pose", 0.3), ("widowx250s_bridgedataset_sink", "pd_joint_delta_pos_vel", 0.3)],
)
def test_stiff_joint_limits_keep_random_actions_within_the_overshoot_bound(uid: str, mode: str, soft: float) -> None:
    """The UR10e's and the WidowX 250 S's joint limits are stiff (their controllers keep
    the joints inside): at the default step random actions pass a limit by less than
    the sweep's bound; with MuJoCo's soft default (20 ms) the same actions pass it by
    more than ``soft`` rad."""
    cls = ra.get_agent(uid)
    step = cls.sim_freq or DEFAULT_SIM_FREQ
    assert largest_overshoot(cls, mode, step) < OVERSHOOT_BOUND
    assert largest_overshoot(cls, mode, step, soft_limits=True) > soft


def test_measure_step_reports_every_claim() -> None:
    result = measure_step(Panda, 500, seeds=(0,))
    assert [c.name for c in result.claims] == [c for c in CLAIMS if c != "standing"]  # an arm: no legs
    assert result.passed, result.claims
    tracking = result.claim("ee_tracking")
    assert tracking is not None and tracking.value < 0.05
    grasp = result.claim("grasp")
    assert grasp is not None and grasp.value < SLIP_BOUND and "40.3 mm cube" in grasp.detail
    # the random press is reported with its place: on seed 0 the hand meets the floor
    assert result.random_press_depth > 0.01
    assert result.random_press_where == "floor / panda-0/panda_hand geom 0"


def test_scene_setup_hands_every_claim_scene_to_the_setup() -> None:
    """Within ``scene_setup`` each claim's scene goes through the setup before its reset
    (here a stiffer floor, timeconst 4 ms and impedance 0.99 against MuJoCo's 20 ms and
    0.95: with seed 0 the Panda's hand presses 2.0 cm into it under random actions,
    against 4.2 cm into the default floor); outside the block, none does."""
    made: list[Scene] = []

    def stiff_floor(scene: Scene) -> None:
        made.append(scene)
        floor = mujoco.mj_name2id(scene.model, mujoco.mjtObj.mjOBJ_GEOM, "floor")
        if floor >= 0:
            scene.model.geom_solref[floor] = (0.004, 1.0)
            scene.model.geom_solimp[floor, :3] = (0.99, 0.99, 0.001)

    plain = measure_step(Panda, 500, seeds=(0,))
    assert not made
    with scene_setup(stiff_floor):
        stiff = measure_step(Panda, 500, seeds=(0,))
    # the hold, one random run per mode (one seed), the tracking and the grasp claims
    assert len(made) == len(Panda.modes()) + 3 and len({id(s) for s in made}) == len(made)
    assert stiff.passed, stiff.claims
    assert plain.random_press_where == stiff.random_press_where == "floor / panda-0/panda_hand geom 0"
    assert stiff.random_press_depth < 0.6 * plain.random_press_depth
    measure_step(Panda, 500, seeds=(0,))
    assert len(made) == len(Panda.modes()) + 3  # the setup is gone with the block


def test_contact_label_names_unnamed_geoms_by_their_body() -> None:
    spec = mujoco.MjSpec()
    spec.worldbody.add_geom(name="floor", type=mujoco.mjtGeom.mjGEOM_PLANE, size=[1, 1, 0.1])
    body = spec.worldbody.add_body(name="link")
    body.add_geom(size=[0.1, 0, 0])
    body.add_geom(name="pad", size=[0.1, 0, 0])
    body.add_geom(size=[0.1, 0, 0])
    model = spec.compile()
    assert [contact_label(model, g) for g in range(model.ngeom)] == ["floor", "link geom 0", "pad", "link geom 2"]


def test_the_keyframe_check_names_an_unnamed_geom_in_the_floor(tmp_path: Path) -> None:
    """``check_keyframes`` names the geoms of its deepest contact as the time-step
    sweep does (:func:`contact_label`): an unnamed geom by its body (it printed
    ``"floor / "`` for the mani-skill Fetch's wheel, 4.98 mm into the floor): a link
    hanging 1 cm into the floor at its keyframe."""
    path = tmp_path / "sunk.xml"
    path.write_text(
        '<mujoco><worldbody><body name="post"><geom type="box" size="0.05 0.05 0.2" pos="0 0 0.3"/>'
        '<body name="link" pos="0.1 0 0.3"><joint name="hinge" axis="0 1 0" range="-1 1"/>'
        '<geom type="capsule" size="0.02" fromto="0 0 0 0 0 -0.29"/></body></body></worldbody></mujoco>'
    )
    declared = {"uid": "sunk", "mjcf_path": path, "mount_pose": (0, 0, 0, 1, 0, 0, 0)}  # not lifted clear
    result = check_keyframes(type("Sunk", (ra.Agent,), declared))
    assert not result.passed
    assert "deepest penetration 10.00 mm (default: floor / sunk-0/link geom 0)" in result.detail, result.detail


def test_robots_without_a_gripper_make_no_grasp_claim() -> None:
    assert grasp_claim(ra.get_agent("ur_10e"), 500, 20, Penetration()) is None
    assert grasp_claim(ra.get_agent("panda_stick"), 500, 20, Penetration()) is None


def test_grasp_claim_fails_when_the_fingers_cannot_hold_the_cube() -> None:
    """The Panda's hand at 0.1 N instead of 70 N: the 64 g cube slides out once it has
    its weight (the claim can fail); at 70 N it moves less than 1 mm in the 2 s hold."""

    class WeakHand(PandaHand):
        actuators = (dataclasses.replace(PANDA_HAND_DRIVES, effort_limit=0.1),)

    class WeakPanda(Panda):
        uid = ""
        attachments: ClassVar = (Attachment(WeakHand, at="panda_link8", quat=HAND_ON_FLANGE),)

    weak = grasp_claim(WeakPanda, 500, 20, Penetration())
    assert weak is not None and not weak.passed and "cube lost" in weak.detail  # moved more than its edge
    strong = grasp_claim(Panda, 500, 20, Penetration())
    assert strong is not None and strong.passed and strong.value < 0.001


def test_grasp_claim_closes_grippers_whose_joints_close_upwards() -> None:
    """The Robotiq 2F-85's drivers close towards their upper limit (0 -> 0.8 rad): the
    claim closes it with the action's -1, as every gripper, and the cube is held."""
    robot = ra.get_agent("floating_robotiq_2f_85_gripper")
    result = grasp_claim(robot, robot.sim_freq or 500, 20, Penetration())  # at its default step
    assert result is not None and result.passed and result.value < SLIP_BOUND, result


def test_grasp_claim_tries_the_cube_deeper_between_the_fingers(tmp_path: Path) -> None:
    """With its former, softer pads the Koch's jaw loses the cube a fifth of an edge in
    from its grasp point (near the tips) and holds it 0.4 edge deeper: the claim reports
    where it held (with the near-rigid pads it holds at the first depth)."""
    result = grasp_claim(former_contact_variant("koch-v1.1", tmp_path), 400, 20, Penetration())
    assert result is not None and result.passed and "0.4 edge in" in result.detail, result
    held = grasp_claim(ra.get_agent("koch-v1.1"), 400, 20, Penetration())
    assert held is not None and held.passed and "0.2 edge in" in held.detail, held


#: The robots whose fingertip contacts were made near-rigid (issue 14): the slip (m) each
#: must stay under at its default step, and the (fixed, former) texts that restore the
#: former contact in its model files (with MuJoCo's soft friction the held cube then
#: creeps out).
NEAR_RIGID = 'solref="0.01 1" solimp="0.9999 0.9999 0.01"'
#: The Stretch's pads: the same, overdamped (damping ratio 2) so that a pressed pad rests
#: (tests/test_pad_press.py; robots/stretch/stretch.py).
STRETCH_PADS = 'solref="0.01 2" solimp="0.9999 0.9999 0.01"'
FIXED_GRASPS: dict[str, tuple[float, tuple[tuple[str, str], ...]]] = {
    "google_robot": (0.0015, ((f'<geom priority="1" {NEAR_RIGID} rgba', "<geom rgba"),)),
    "stretch": (
        0.001,
        (
            (
                f'<geom rgba="0.95 0.95 0.95 1" condim="4" priority="1" {STRETCH_PADS}/>',
                '<geom rgba="0.95 0.95 0.95 1"/>',
            ),
            (STRETCH_PADS, 'solref="0.002 1" solimp="0.95 0.99 0.001"'),
        ),
    ),
    # both through their shared pad class (servo_arm_defaults.xml)
    "so100": (0.001, ((f'condim="4" {NEAR_RIGID}', 'solref="0.002 1" solimp="0.95 0.99 0.001"'),)),
    "koch-v1.1": (0.001, ((f'condim="4" {NEAR_RIGID}', 'solref="0.002 1" solimp="0.95 0.99 0.001"'),)),
}
#: Those whose former contact failed the claim at the default step (the Koch's softer
#: pads held its cube 0.4-0.6 edge deep instead, and let it creep 2.5 mm at 200 Hz
#: before the claim tried that deep: test_grasp_claim_tries_the_cube_deeper_...).
CREPT_AT_DEFAULT = ("google_robot", "so100", "stretch")


def former_contact_variant(uid: str, tmp_path: Path) -> type[ra.Agent]:
    """``uid`` rebuilt with its former (softer) fingertip contact, from a copy of its
    model files with the fixed texts of :data:`FIXED_GRASPS` put back."""
    cls = ra.get_agent(uid)
    path = Path(str(cls.mjcf_path))
    # the model file and the default files it includes
    texts = {sibling.name: sibling.read_text() for sibling in path.parent.glob("*.xml")}
    for fixed, former in FIXED_GRASPS[uid][1]:
        assert any(fixed in text for text in texts.values()), fixed
        texts = {name: text.replace(fixed, former) for name, text in texts.items()}
    for name, text in texts.items():
        assert NEAR_RIGID not in text and STRETCH_PADS not in text, name
        (tmp_path / name).write_text(text)
    return type(f"Former{cls.__name__}", (cls,), {"uid": "", "mjcf_path": tmp_path / path.name})


@pytest.mark.parametrize("uid", sorted(FIXED_GRASPS))
def test_fingertips_hold_the_cube_at_the_default_step(uid: str) -> None:
    """The sweep's grasp at the robot's declared step: the cube moves less than its
    bound (measured: google_robot 0.21 mm at 500 Hz (its 77.9 mm cube at its grasp frame,
    2026-11-29, SimplerEnv's current arm gains), stretch 0.43 mm at 200 Hz (its pads overdamped, 2026-11-29), so100 0.25 mm at 200 Hz, koch-v1.1 0.01 mm at
    320 Hz; 4.8, 10.4 and 2.4 mm for the first three with the former contacts)."""
    cls = ra.get_agent(uid)
    assert cls.sim_freq is not None
    result = grasp_claim(cls, cls.sim_freq, 20, Penetration())
    assert result is not None and result.passed and result.value < FIXED_GRASPS[uid][0], result


@pytest.mark.parametrize("uid", CREPT_AT_DEFAULT)
def test_former_fingertip_contact_lets_the_cube_creep_out(uid: str, tmp_path: Path) -> None:
    """The same model with the former (softer) fingertip contact fails the claim at the
    same step: the cube creeps along the tips though far inside its friction cone."""
    cls = ra.get_agent(uid)
    assert cls.sim_freq is not None
    result = grasp_claim(former_contact_variant(uid, tmp_path), cls.sim_freq, 20, Penetration())
    assert result is not None and not result.passed, result


def step_result(sim_freq: int, failing: tuple[str, ...]) -> StepResult:
    claims = tuple(ClaimResult(name, name not in failing, 0.0, 1.0) for name in CLAIMS)
    return StepResult(sim_freq, claims)


def test_a_claim_failing_at_every_step_does_not_limit_the_step() -> None:
    """A claim that fails even at the finest step is the robot's to fix: it is reported
    as failing everywhere and the largest step is then judged by the other claims."""
    result = SweepResult(
        "x",
        20,
        (
            step_result(40, ("grasp", "settle")),
            step_result(100, ("grasp", "settle")),
            step_result(200, ("grasp",)),
            step_result(1000, ("grasp",)),
        ),
    )
    assert result.largest_passing is None
    assert result.failing_everywhere == ("grasp",)
    assert result.largest_passing_other_claims == 200
    # a failure that grows with the step does depend on it
    worse = SweepResult(
        "x",
        20,
        (
            StepResult(200, tuple(ClaimResult(n, n != "settle", 3.0 if n == "settle" else 0.0, 1.0) for n in CLAIMS)),
            StepResult(500, tuple(ClaimResult(n, n != "settle", 1.8 if n == "settle" else 0.0, 1.0) for n in CLAIMS)),
            StepResult(1000, tuple(ClaimResult(n, n != "settle", 1.0 if n == "settle" else 0.0, 0.5) for n in CLAIMS)),
        ),
    )
    assert worse.failing_everywhere == ("settle",) and worse.largest_passing_other_claims == 500
    clean = SweepResult("x", 20, (step_result(100, ("settle",)), step_result(200, ()), step_result(1000, ())))
    assert clean.failing_everywhere == () and clean.largest_passing == clean.largest_passing_other_claims == 200


def test_sweep_measures_the_finest_step_first_and_stops_after_two_passes() -> None:
    seen: list[int] = []
    result = sweep_timestep("panda", substeps=(2, 20, 25, 50), seeds=(0,), progress=lambda s: seen.append(s.sim_freq))
    assert seen == [1000, 40, 400, 500]
    assert [s.sim_freq for s in result.steps] == [40, 400, 500, 1000]
    assert result.largest_passing == 400


def test_sweep_finds_a_failing_coarse_step_and_a_passing_fine_one() -> None:
    """At 40 Hz (two substeps per 20 Hz action) the WidowX 250 S's claims fail; at 160 Hz they hold."""
    result = sweep_timestep("widowx250s", substeps=(2, 8), seeds=(0,), stop_after=None)
    by_freq = {s.sim_freq: s for s in result.steps}
    assert not by_freq[40].passed
    assert by_freq[160].passed
    assert result.largest_passing == 160
    assert "| 40 | 25 |" in result.table()


def test_sweep_rejects_bad_input() -> None:
    with pytest.raises(ConfigError):
        sweep_timestep("so100", substeps=(0,))
    with pytest.raises(ConfigError):
        sweep_timestep(int)  # type: ignore[arg-type]
    for seeds in ((), (-1,), (0.5,), "0", 3):
        with pytest.raises(ConfigError, match="seeds"):
            sweep_timestep("so100", seeds=seeds)  # type: ignore[arg-type]
        with pytest.raises(ConfigError, match="seeds"):
            measure_step(SO100, 200, seeds=seeds)  # type: ignore[arg-type]


def test_random_claim_reports_the_worst_of_its_seeds() -> None:
    """Each seed is its own action sequence; the claim's value is the worst over them,
    reported with the mode and seed where it happened."""
    single = {seed: _random(SO100, 200, 20, (seed,), Penetration())[0] for seed in (0, 1)}
    both = _random(SO100, 200, 20, (0, 1), Penetration())[0]
    assert single[0].value != single[1].value  # two different sequences
    assert both.value == max(single[0].value, single[1].value)
    worst = max((0, 1), key=lambda seed: single[seed].value)
    assert f"(seed {worst})" in both.detail and "(seed" not in single[0].detail


def test_check_sweep_prints_the_table(monkeypatch: pytest.MonkeyPatch) -> None:
    import robot_agents.tuning.timestep as timestep

    monkeypatch.setattr(timestep, "DEFAULT_SUBSTEPS", (25,))
    real = timestep.sweep_timestep
    monkeypatch.setattr(  # one seed, for speed; the substeps are the (patched) default's
        timestep, "sweep_timestep", lambda cls, substeps, stop_after=None: real(cls, substeps=substeps, seeds=(0,))
    )
    out = io.StringIO()
    code = cmd_check("widowx250s", out, sweep=True)
    text = out.getvalue()
    assert code == 0 and "| 500 | 2 |" in text and "sim_freq 500 Hz" in text
    # where random actions pressed deepest: the WidowX's own links or the floor
    assert "deepest contact under random actions at 500 Hz (reported, not judged):" in text
    assert "widowx250s-0/" in text.split("deepest contact under random actions", 1)[1].splitlines()[0]
    # the torque-limit cycle analysis follows: every WidowX 250 S drive's damping is its
    # joints' own (the servos' back-EMF, outside the force limit: widowx250s.py), which
    # cannot cycle (the fingers were listed at 26 Hz before 2026-11-29 09:32 UTC, the arm's
    # joints at 25 Hz and below, not reachable, before 2026-11-29 10:10 UTC)
    assert "no force-limited drive can cycle between its limits" in text
    assert "torque-limit cycles possible below" not in text


def test_declared_sim_freq_is_the_default_and_an_explicit_one_wins() -> None:
    class Fast(SO100):
        uid = ""
        sim_freq = 200

    assert Scene(Fast).sim_freq == 200
    assert Scene(Fast, sim_freq=1000).sim_freq == 1000
    assert Scene(SO100).sim_freq == (SO100.sim_freq or DEFAULT_SIM_FREQ)
    assert Scene([Fast, Panda]).sim_freq == max(200, Panda.sim_freq or DEFAULT_SIM_FREQ)


def test_bad_declared_sim_freq_is_a_clean_error() -> None:
    class Bad(SO100):
        uid = ""
        sim_freq = 0

    with pytest.raises(ConfigError, match="sim_freq"):
        Bad.validate_definition()
