"""A floating robot whose file has no actuators stands on its derived drives: the static
torque each joint carries standing at the default keyframe (its joints locked, settled on
a floor) stiffens its gains, its joints that carry the weight are ``Legs`` and it defaults
to ``pd_joint_target_delta_pos``. Written here as a small MJCF quadruped whose stance is
worked out by hand; a fixed-base arm and a floating arm keep the inertia gains."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents import checks
from robot_agents.actuators.gains import (
    STANCE_DAMPING_SHARE,
    STANCE_SAG,
    STANCE_STABLE_SHARE,
    gains_from_inertia,
    gains_over_configurations,
    inertia_matrix,
)
from robot_agents.agent.declaration import _build
from robot_agents.agent.derived_drives import drive_configurations
from robot_agents.agent.stance import GRAVITY, Stance, find_stance
from robot_agents.parts.declaration import Arm, Legs
from robot_agents.robot_source import robot_from_file
from robot_agents.sim.scene import DEFAULT_SIM_FREQ

BODY_MASS = 8.0
THIGH_MASS, SHIN_MASS, FOOT_MASS = 0.3, 0.2, 0.05
THIGH = 0.2  # m, vertical
REACH = 0.1  # m: the foot's horizontal offset from the knee (front legs forward, rear legs back)
SHIN_DROP = 0.2  # m
FOOT_RADIUS = 0.02
TOTAL_MASS = BODY_MASS + 4 * (THIGH_MASS + SHIN_MASS + FOOT_MASS)


def quadruped(effort: float = 50.0, y_up: bool = False) -> str:
    """A box body (8 kg) on four two-hinge legs (hip and knee about y), feet mirrored
    front / rear so that the stance is symmetric; no actuators. ``y_up``: the same robot
    written in a frame whose up is +y (as some URDFs are, e.g. pybullet's
    ``laikago_toes.urdf``): every point and axis ``(x, y, z)`` becomes ``(x, z, -y)`` (a
    turn of -90 deg about x), the root body unturned."""

    def v(x: float, y: float, z: float) -> str:
        return " ".join(f"{c:g}" for c in ((x, z, -y) if y_up else (x, y, z)))

    def half_sizes(x: float, y: float, z: float) -> str:
        return " ".join(f"{c:g}" for c in ((x, z, y) if y_up else (x, y, z)))

    legs = ""
    for name, x, y in (("fr", 0.2, -0.12), ("fl", 0.2, 0.12), ("rr", -0.2, -0.12), ("rl", -0.2, 0.12)):
        dx = REACH if x > 0 else -REACH
        legs += f"""
      <body name="{name}_thigh" pos="{v(x, y, 0)}">
        <joint name="{name}_hip" axis="{v(0, 1, 0)}" range="-1.5 1.5" actuatorfrcrange="-{effort} {effort}"/>
        <geom type="capsule" size="0.015" fromto="0 0 0 {v(0, 0, -THIGH)}" mass="{THIGH_MASS}"/>
        <body name="{name}_shin" pos="{v(0, 0, -THIGH)}">
          <joint name="{name}_knee" axis="{v(0, 1, 0)}" range="-1.5 1.5" actuatorfrcrange="-{effort} {effort}"/>
          <geom type="capsule" size="0.012" fromto="0 0 0 {v(dx, 0, -SHIN_DROP)}" mass="{SHIN_MASS}"/>
          <geom name="{name}_foot" type="sphere" size="{FOOT_RADIUS}" pos="{v(dx, 0, -SHIN_DROP)}" mass="{FOOT_MASS}"
                friction="1.0"/>
        </body>
      </body>"""
    return f"""<mujoco model="stance_quadruped{"_y_up" if y_up else ""}">
  <compiler angle="radian"/>
  <worldbody>
    <body name="trunk">
      <geom type="box" size="{half_sizes(0.25, 0.15, 0.05)}" mass="{BODY_MASS}"/>{legs}
    </body>
  </worldbody>
</mujoco>
"""


def arm() -> str:
    """A three-hinge arm on a base plate; no actuators."""
    return """<mujoco model="stance_arm">
  <compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <geom type="box" size="0.1 0.1 0.03" mass="2"/>
      <body name="upper" pos="0 0 0.03">
        <joint name="yaw" axis="0 0 1" range="-3 3" actuatorfrcrange="-30 30"/>
        <geom type="capsule" size="0.03" fromto="0 0 0 0 0 0.3" mass="1.5"/>
        <body name="fore" pos="0 0 0.3">
          <joint name="shoulder" axis="0 1 0" range="-2 2" actuatorfrcrange="-30 30"/>
          <geom type="capsule" size="0.025" fromto="0 0 0 0.3 0 0" mass="1"/>
          <body name="hand" pos="0.3 0 0">
            <joint name="elbow" axis="0 1 0" range="-2 2" actuatorfrcrange="-30 30"/>
            <geom type="capsule" size="0.02" fromto="0 0 0 0.2 0 0" mass="0.5"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / f"{name}.xml"
    path.write_text(text)
    return path


def stance_of(cls: type[ra.Agent]) -> Stance | str:
    checked = cls.check()
    spec = _build(cls, None, None, checked.compiler, checked.derived_exclusions, quiet=True)[0]
    joints = [d.joint for d in checked.drives]
    return find_stance(spec, checked.index, joints, checked.keyframes["default"].qpos, 0.002)


def test_static_torques_match_the_hand_calculation(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_torques", quadruped()), floating=True)
    found = stance_of(cls)
    assert isinstance(found, Stance), found
    weight = TOTAL_MASS * GRAVITY
    assert found.weight == pytest.approx(weight, rel=1e-6)
    # symmetric stance: each foot carries a quarter of the weight
    np.testing.assert_allclose(found.load, weight / 4, rtol=0.02)
    # knee: the foot's load at REACH, less the shin's and the foot's own weight at their levers;
    # the lock holds the shin against the floor's push (positive about +y for a foot at +x)
    share = weight / 4
    knee = share * REACH - SHIN_MASS * GRAVITY * REACH / 2 - FOOT_MASS * GRAVITY * REACH
    torque = dict(zip(found.joints, found.torque, strict=True))
    for leg, sign in (("fr", 1.0), ("fl", 1.0), ("rr", -1.0), ("rl", -1.0)):
        assert torque[f"{leg}_knee"] == pytest.approx(sign * knee, rel=0.03)
        assert torque[f"{leg}_hip"] == pytest.approx(sign * knee, rel=0.03)  # vertical thigh: the same lever
    assert sorted(found.legs) == sorted(found.joints)
    assert set(found.feet) == {"fr_shin", "fl_shin", "rr_shin", "rl_shin"}


def test_derived_quadruped_stands_and_holds(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_stands", quadruped()), floating=True)
    checked = cls.check()
    assert [type(p) for p in checked.parts] == [Legs]
    assert checked.default_mode == "pd_joint_target_delta_pos"
    found = stance_of(cls)
    assert isinstance(found, Stance)
    # each drive gives at most STANCE_SAG under its static torque
    inertia = gains_from_inertia(checked.index.model, found.joints, _full(checked)).stiffness
    for joint, tau, lever, kp_inertia in zip(found.joints, found.torque, found.lever, inertia, strict=True):
        kp = checked.derived_gains[joint][0]
        assert kp == pytest.approx(max(kp_inertia, abs(tau) / STANCE_SAG + lever), rel=1e-9)
        assert abs(tau) / kp <= STANCE_SAG
    standing = checks.check_standing(cls)
    assert standing is not None and standing.passed, standing
    holds = checks.check_holds(cls)
    assert holds.passed, holds.line()
    stable = checks.check_pd_stability(cls)
    assert stable.passed, stable.line()


def _full(checked: object) -> np.ndarray:
    model = checked.index.model  # type: ignore[attr-defined]
    full = model.qpos0.copy()
    full[checked.index.qpos_adr] = checked.keyframes["default"].qpos  # type: ignore[attr-defined]
    return np.asarray(full)


def test_the_stance_settles_without_bouncing(tmp_path: Path) -> None:
    """Dropped 1 mm onto its feet at the keyframe, holding it: every foot stays on the
    floor from touchdown on, and after the landing (0.1 s) the base comes to its sag
    from one side (no oscillation about it), within a millimetre."""
    cls = robot_from_file(write(tmp_path, "quad_settles", quadruped()), floating=True)
    scene = ra.Scene(cls, sim_freq=500, control_freq=500)  # one physics step per control step
    agent = scene.agents[0]
    model = scene.model
    scene.reset()
    hold = checks.hold_action(agent)
    heights, touching = [], []
    for _ in range(1000):  # 2 s
        agent.set_action(hold)
        scene.step()
        heights.append(float(agent.base_pose[0, 2]))
        data = scene.world.physics_sources([0])[0]
        bodies = {
            model.body(int(model.geom_bodyid[g])).name for c in data.contact[: data.ncon] for g in (c.geom1, c.geom2)
        }
        touching.append({b for b in bodies if b.endswith("_shin")})
    scene.close()
    landed = next(k for k, feet in enumerate(touching) if len(feet) == 4)
    assert landed < 25
    assert all(len(feet) == 4 for feet in touching[landed:]), "a foot left the floor"
    offset = np.array(heights[50:]) - heights[-1]
    assert np.all(np.abs(offset) < 1e-3)
    assert np.all(offset >= -1e-6) or np.all(offset <= 1e-6), "the base oscillates about its rest height"


def test_a_fixed_arm_keeps_its_inertia_gains(tmp_path: Path) -> None:
    """No stance for a fixed arm: its gains are the inertia gains over its joints' ranges."""
    cls = robot_from_file(write(tmp_path, "stance_fixed_arm", arm()))
    checked = cls.check()
    joints = [d.joint for d in checked.drives]
    model = checked.index.model
    configurations = drive_configurations(model, checked.index, joints, _full(checked))
    gains = gains_over_configurations(model, joints, configurations, 1.0 / DEFAULT_SIM_FREQ)
    for joint, kp, kv in zip(gains.joints, gains.stiffness, gains.damping, strict=True):
        assert checked.derived_gains[joint][:2] == (float(kp), float(kv))
    assert isinstance(checked.parts[0], Arm)
    assert checked.default_mode == "pd_joint_delta_pos"


def test_a_floating_arm_resting_on_its_base_keeps_its_inertia_gains(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "stance_floating_arm", arm()), floating=True)
    found = stance_of(cls)
    assert isinstance(found, str) and "do not move" in found
    checked = cls.check()
    joints = [d.joint for d in checked.drives]
    gains = gains_from_inertia(checked.index.model, joints, _full(checked))
    assert [checked.derived_gains[j][0] for j in joints] == [float(k) for k in gains.stiffness]
    assert not any(isinstance(p, Legs) for p in checked.parts)
    assert checked.default_mode == "pd_joint_delta_pos"


def test_a_load_beyond_the_effort_limits_is_a_note(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_weak", quadruped(effort=1.0)), floating=True)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        checked = cls.check()
    notes = [str(w.message) for w in caught if "cannot stand" in str(w.message)]
    assert len(notes) == 1 and "fr_knee" in notes[0]
    assert all(checked.derived_gains[j][2] == 1.0 for j in checked.derived_gains)  # the file's limits stay


def test_stance_constants() -> None:
    assert STANCE_SAG == checks.HOLD_TOLERANCE / 2
    assert STANCE_STABLE_SHARE == checks.STABLE_SHARE / 2


def test_a_stance_needs_a_free_root(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_fixed", quadruped()))
    checked = cls.check()
    spec = _build(cls, None, None, checked.compiler, checked.derived_exclusions, quiet=True)[0]
    assert find_stance(spec, checked.index, [d.joint for d in checked.drives], np.zeros(8), 0.002) == (
        "its root is fixed"
    )
    assert mujoco.mj_name2id(checked.index.model, mujoco.mjtObj.mjOBJ_JOINT, "fr_knee") >= 0


# dm_control's quadruped couples each leg's joints by tendon equalities (solref 0.005 / 0.5:
# stiff at a 2 ms step, half-critical); with the stance drives' damping far beyond the
# explicit bound it hopped. Here each leg's hip and knee are coupled the same way.
COUPLING_SOLREF = "0.005 0.5"


def coupled_quadruped() -> str:
    """:func:`quadruped` with ``(hip + knee) / 2`` of each leg held at 0 (its keyframe
    value) by a soft tendon equality, as dm_control's quadruped couples its legs."""
    legs = ("fr", "fl", "rr", "rl")
    tendons = "".join(
        f'<fixed name="{leg}_couple"><joint joint="{leg}_hip" coef="0.5"/><joint joint="{leg}_knee" coef="0.5"/></fixed>'
        for leg in legs
    )
    equalities = "".join(
        f'<tendon name="{leg}_couple" tendon1="{leg}_couple" solref="{COUPLING_SOLREF}" solimp="0.95 0.99 0.01"/>'
        for leg in legs
    )
    return quadruped().replace(
        "</worldbody>", f"</worldbody>\n  <tendon>{tendons}</tendon>\n  <equality>{equalities}</equality>"
    )


def _free_inertia(checked: object) -> dict[str, float]:
    """``1 / (M^-1)_ii`` of each driven joint at the default keyframe (kg*m^2)."""
    model = checked.index.model  # type: ignore[attr-defined]
    data = mujoco.MjData(model)
    data.qpos[:] = _full(checked)
    mobility = np.diag(np.linalg.inv(inertia_matrix(model, data)))
    return {j: 1.0 / float(mobility[model.joint(j).dofadr[0]]) for j in checked.derived_gains}  # type: ignore[attr-defined]


def test_free_inertia_is_what_a_force_at_the_joint_meets(tmp_path: Path) -> None:
    cls = robot_from_file(write(tmp_path, "quad_free_inertia", quadruped()), floating=True)
    checked = cls.check()
    joints = [d.joint for d in checked.drives]
    gains = gains_from_inertia(checked.index.model, joints, _full(checked))
    assert gains.free_inertia is not None and gains.passive_damping is not None
    expected = _free_inertia(checked)
    np.testing.assert_allclose(gains.free_inertia, [expected[j] for j in joints], rtol=1e-9)
    # the body and the other joints free, a leg swings more easily than with them held
    assert np.all(gains.free_inertia < gains.inertia)
    np.testing.assert_array_equal(gains.passive_damping, 0.0)


def test_stance_damping_stays_within_the_constraint_solvers_bound(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``dt (kv + b) <= 2 I_free``: a joint's damping takes at most twice its velocity in one
    step, so contact and equality forces, sized for ``M``, are off by at most 3. (The
    inertia gains, critical at 10 Hz on the held inertia, stay a floor.)"""
    cls = robot_from_file(write(tmp_path, "quad_damping_bound", coupled_quadruped()), floating=True)
    checked = cls.check()
    free = _free_inertia(checked)
    model = checked.index.model
    floor = gains_from_inertia(model, list(checked.derived_gains), _full(checked)).as_dict()
    from robot_agents.actuators import gains as gains_module

    monkeypatch.setattr(gains_module, "STANCE_DAMPING_SHARE", math.inf)
    unbounded = robot_from_file(write(tmp_path, "quad_damping_unbounded", coupled_quadruped()), floating=True)
    critical = unbounded.check().derived_gains
    for joint, (kp, kv, _limit) in checked.derived_gains.items():
        assert kp == critical[joint][0]  # the stiffness is not touched
        b = float(model.dof_damping[model.joint(joint).dofadr[0]])
        bound = STANCE_DAMPING_SHARE * 2.0 * free[joint] / 0.002 - b
        assert kv == pytest.approx(max(floor[joint][1], min(critical[joint][1], bound)), rel=1e-9)
        assert critical[joint][1] > 2 * bound  # critical against the carried body: far beyond


def test_legs_coupled_by_equalities_stand_with_bounded_damping(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Tendon equalities coupling each leg's joints: with the damping critical against the
    carried body (``dt kv / I_free`` up to 3.8 here) the robot hops (the hold drifts 0.015
    rad, the base moves 50 mm); within the bound it stands still."""
    from robot_agents.actuators import gains as gains_module

    monkeypatch.setattr(gains_module, "STANCE_DAMPING_SHARE", math.inf)
    unbounded = robot_from_file(write(tmp_path, "quad_coupled_unbounded", coupled_quadruped()), floating=True)
    hops = checks.check_standing(unbounded)
    assert hops is not None and not hops.passed, hops  # the base moved 50 mm
    assert not checks.check_holds(unbounded).passed  # 0.015 rad
    monkeypatch.undo()
    cls = robot_from_file(write(tmp_path, "quad_coupled", coupled_quadruped()), floating=True)
    standing = checks.check_standing(cls)
    assert standing is not None and standing.passed, standing
    assert float(standing.detail.split()[2]) < 5.0, standing  # mm after settling (50 unbounded)
    holds = checks.check_holds(cls)
    assert holds.passed, holds.line()
    assert checks.check_pd_stability(cls).passed


def head_quadruped() -> str:
    """:func:`quadruped` with a neck hinge carrying a 1.5 kg head ahead of the body: a
    joint that carries weight but stands on no foot (dm_control's dog: neck, tail, jaw)."""
    neck = """
      <body name="neck" pos="0.25 0 0.05">
        <joint name="neck_pitch" axis="0 1 0" range="-1 1"/>
        <geom type="capsule" size="0.02" fromto="0 0 0 0.15 0 0.1" mass="0.5"/>
        <body name="head" pos="0.15 0 0.1">
          <geom type="sphere" size="0.05" mass="1.5"/>
        </body>
      </body>"""
    body = f'<geom type="box" size="0.25 0.15 0.05" mass="{BODY_MASS}"/>'
    return quadruped().replace(body, body + neck)


def test_a_head_on_standing_legs_holds_its_target(tmp_path: Path) -> None:
    """The neck is a ``Body`` part beside the ``Legs``; with deltas from the measured pose
    its head's weight walked it down step by step (0.22 rad over the 2 s hold); with deltas
    from its targets, as the legs', it holds."""
    cls = robot_from_file(write(tmp_path, "quad_head", head_quadruped()), floating=True)
    checked = cls.check()
    assert [type(p).__name__ for p in checked.parts] == ["Legs", "Body"]
    assert checked.part_joints["body"] == ("neck_pitch",)
    for mode, config in checked.modes.items():
        body = config["body"]  # type: ignore[index]
        assert body.use_target, mode  # type: ignore[union-attr]
    holds = checks.check_holds(cls)
    assert holds.passed, holds.line()
    standing = checks.check_standing(cls)
    assert standing is not None and standing.passed, standing


def test_derived_drives_ignore_the_files_actuator_defaults(tmp_path: Path) -> None:
    """A file's default ``<general>`` (dm_control's ``dyntype="filter"``) is for its own
    actuators: the derived PD drives have gear 1 and no activation dynamics."""
    text = quadruped().replace(
        '<compiler angle="radian"/>',
        '<compiler angle="radian"/>\n  <default><general dyntype="filter" dynprm="0.1" gear="10"/></default>',
    )
    cls = robot_from_file(write(tmp_path, "quad_actuator_defaults", text), floating=True)
    scene = ra.Scene(cls)
    model = scene.model
    assert model.nu == 8
    np.testing.assert_array_equal(model.actuator_dyntype, int(mujoco.mjtDyn.mjDYN_NONE))
    np.testing.assert_array_equal(model.actuator_gear[:, 0], 1.0)
    assert model.na == 0
    scene.close()


#: A mount turned +90 deg about x: the y-up file's +y becomes the world's +z.
Y_UP_MOUNT = (0.0, 0.0, 0.0, math.sqrt(0.5), math.sqrt(0.5), 0.0, 0.0)


def test_a_mount_turns_a_file_drawn_y_up_onto_its_feet(tmp_path: Path) -> None:
    """Two lines leave a y-up file lying on its side (its legs carry nothing, no Legs);
    a third, ``mount_pose`` turned about x, stands it: the derived keyframe rests 1 mm
    above the floor in the turned frame, the stance is the z-up file's (same static
    torques, same derived gains) and the robot holds and stands."""
    path = write(tmp_path, "quad_y_up", quadruped(y_up=True))
    lying = robot_from_file(path, floating=True).check()
    assert not any(isinstance(p, Legs) for p in lying.parts)
    upright = type("QuadYUp", (robot_from_file(path, floating=True),), {"mount_pose": Y_UP_MOUNT})
    checked = upright.check()
    assert [type(p) for p in checked.parts] == [Legs]
    assert checked.default_mode == "pd_joint_target_delta_pos"
    reference = robot_from_file(write(tmp_path, "quad_z_up", quadruped()), floating=True).check()
    for joint, gains in reference.derived_gains.items():  # type: ignore[union-attr]
        assert checked.derived_gains[joint] == pytest.approx(gains, rel=1e-3), joint  # type: ignore[index]
    # the default keyframe's base, composed with the mount, rests 1 mm above the floor like the z-up robot's
    base = checked.keyframes["default"].base
    world = np.empty(3)
    mujoco.mju_rotVecQuat(world, base[:3], np.array(Y_UP_MOUNT[3:]))
    assert world == pytest.approx(reference.keyframes["default"].base[:3], abs=1e-9)
    standing = checks.check_standing(upright)
    assert standing is not None and standing.passed, standing
    holds = checks.check_holds(upright)
    assert holds.passed, holds.line()


def test_the_command_line_stands_a_y_up_file_with_up_y(tmp_path: Path) -> None:
    """``robot-agents check FILE --floating --up y`` runs every check on the turned robot
    (standing included) and passes; ``--up`` is refused for a registered uid, and
    ``robot_from_file`` names the up axes it knows."""
    import io

    from robot_agents import cli
    from robot_agents.robot_source import UP_AXES

    path = write(tmp_path, "quad_cli_y_up", quadruped(y_up=True))
    out = io.StringIO()
    status = cli.main(["check", str(path), "--floating", "--up", "y", "--seconds", "1"], out)
    text = out.getvalue()
    assert status == 0, text
    assert "[PASS] stands 5 s on its legs" in text
    assert UP_AXES["y"] == pytest.approx(Y_UP_MOUNT[3:])
    assert cli.main(["info", "panda", "--up", "y"], io.StringIO()) == 2
    with pytest.raises(ra.UnknownNameError, match=r"up axis 'w'\. Available: 'x', 'y', 'z'"):
        robot_from_file(path, floating=True, up="w")


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_each_up_axis_turns_that_axis_up(axis: str) -> None:
    from robot_agents.robot_source import UP_AXES

    turned = np.empty(3)
    mujoco.mju_rotVecQuat(turned, np.eye(3)["xyz".index(axis)], np.array(UP_AXES[axis]))
    np.testing.assert_allclose(turned, [0.0, 0.0, 1.0], atol=1e-15)
