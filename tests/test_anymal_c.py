"""ANYbotics ANYmal C: it stands on its own legs on a free base, its masses, joint ranges,
inertias and foot positions match MuJoCo Menagerie's model (chained here from that
model's own rotated joint frames), and random actions in every mode stay stable."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

import robot_agents as ra
from robot_agents.checks import hold_action
from robot_agents.kinematics.rotations import quat_to_matrix
from robot_agents.robots.anybotics.anymal_c import (
    ANYMAL_DRIVES,
    LEG_JOINTS,
    STANDING_HEIGHT,
    STANDING_QPOS,
    AnymalC,
)
from tests.chain_check import axis_rotation, transform

# Menagerie's anybotics_anymal_c/anymal_c.xml, read as data: per leg, the hip's pose in
# the base, the HAA axis, the thigh's pose in the hip, the HFE axis, the shank's offset
# in the thigh, the KFE axis, the URDF's foot frame in the shank; the links' inertials
# (mass, centre of mass, principal axes, principal moments) in those frames.
LF_HIP_INERTIA = (
    (0.0566606, -0.015294, -0.00829784),
    (-0.127978, 0.709783, -0.135278, 0.679359),
    (0.00585729, 0.00491868, 0.00329081),
)
RF_HIP_INERTIA = (
    (0.0567633, 0.015294, -0.00829784),
    (0.13524, 0.679072, 0.127985, 0.710065),
    (0.00585928, 0.0049205, 0.00329064),
)
LF_THIGH_INERTIA = (
    (0.0308147, 4.64995e-05, -0.245696),
    (0.993166, -0.00515309, -0.0806592, 0.0841972),
    (0.03025, 0.0298943, 0.00418465),
)
RF_THIGH_INERTIA = (
    (0.0308147, 4.64995e-05, -0.245696),
    (0.992775, -0.00512735, -0.0806685, 0.0886811),
    (0.0302511, 0.0298933, 0.0041845),
)
LF_SHANK_INERTIA = (
    (0.005462, -0.0612528, -0.0806598),
    (0.992934, -0.115904, -0.00105487, -0.0254421),
    (0.0101637, 0.00923838, 0.00111927),
)
RF_SHANK_INERTIA = (
    (0.005462, 0.0612528, -0.0806598),
    (0.992934, 0.115904, -0.00105487, 0.0254421),
    (0.0101637, 0.00923838, 0.00111927),
)
MENAGERIE = {
    "LF": dict(hip=((0.2999, 0.104, 0.0), (0.258819, 0.965926, 0, 0)), haa=(1, 0, 0),
               thigh=((0.0599, -0.0725816, -0.041905), (0.183013, -0.683013, 0.683013, 0.183013)), hfe=(1, 0, 0),
               kfe=(1, 0, 0), foot=(0.01305, -0.08795, -0.33797),
               inertia=(LF_HIP_INERTIA, LF_THIGH_INERTIA, LF_SHANK_INERTIA)),
    "RF": dict(hip=((0.2999, -0.104, 0.0), (0.258819, -0.965926, 0, 0)), haa=(1, 0, 0),
               thigh=((0.0599, 0.0725816, -0.041905), (0.183013, 0.683013, 0.683013, -0.183013)), hfe=(-1, 0, 0),
               kfe=(-1, 0, 0), foot=(0.01305, 0.08795, -0.33797),
               inertia=(RF_HIP_INERTIA, RF_THIGH_INERTIA, RF_SHANK_INERTIA)),
    "LH": dict(hip=((-0.2999, 0.104, 0.0), (0, 0, 0.965926, -0.258819)), haa=(-1, 0, 0),
               thigh=((0.0599, 0.0725816, -0.041905), (0.183013, 0.683013, 0.683013, -0.183013)), hfe=(1, 0, 0),
               kfe=(1, 0, 0), foot=(0.01305, 0.08795, -0.33797),
               inertia=(RF_HIP_INERTIA, RF_THIGH_INERTIA, RF_SHANK_INERTIA)),
    "RH": dict(hip=((-0.2999, -0.104, 0.0), (0, 0, -0.965926, -0.258819)), haa=(-1, 0, 0),
               thigh=((0.0599, -0.0725816, -0.041905), (-0.183013, 0.683013, -0.683013, -0.183013)), hfe=(-1, 0, 0),
               kfe=(-1, 0, 0), foot=(0.01305, -0.08795, -0.33797),
               inertia=(LF_HIP_INERTIA, LF_THIGH_INERTIA, LF_SHANK_INERTIA)),
}  # fmt: skip
SHANK_IN_THIGH = (0.1003, 0.0, -0.285)
MASSES = {"base": 19.2035, "HIP": 2.781, "THIGH": 3.071, "SHANK": 0.58842}
HAA_RANGES = {"L": (-0.72, 0.49), "R": (-0.49, 0.72)}


def frame(pos: tuple[float, ...], quat: tuple[float, ...] = (1.0, 0.0, 0.0, 0.0)) -> np.ndarray:
    q = np.asarray(quat, dtype=float)
    return transform(quat_to_matrix(q / np.linalg.norm(q)), np.asarray(pos, dtype=float))


def menagerie_leg(leg: str, q: tuple[float, float, float], base: np.ndarray) -> list[np.ndarray]:
    """World poses of the hip, thigh and shank frames and of the foot frame (Menagerie's
    rotated frames, chained here)."""
    d = MENAGERIE[leg]
    hip = base @ frame(*d["hip"]) @ transform(axis_rotation(d["haa"], q[0]), np.zeros(3))
    thigh = hip @ frame(*d["thigh"]) @ transform(axis_rotation(d["hfe"], q[1]), np.zeros(3))
    shank = thigh @ frame(SHANK_IN_THIGH) @ transform(axis_rotation(d["kfe"], q[2]), np.zeros(3))
    return [hip, thigh, shank, shank @ frame(d["foot"])]


def leg_angles(qpos: np.ndarray, names: tuple[str, ...], leg: str) -> tuple[float, float, float]:
    return tuple(float(qpos[names.index(f"{leg}_{j}")]) for j in ("HAA", "HFE", "KFE"))  # type: ignore[return-value]


@pytest.fixture(scope="module")
def scene() -> ra.Scene:
    scene = ra.Scene("anymal_c")
    yield scene
    scene.close()


def body_pose(scene: ra.Scene, name: str) -> np.ndarray:
    body = scene.world.datas[0].body(scene.agents[0].prefix + name)
    return transform(body.xmat.reshape(3, 3).copy(), body.xpos.copy())


def stand(cls: type[ra.Agent] | str, seconds: float = 5.0) -> dict[str, object]:
    """Reset to ``standing`` and repeat the default mode's hold action for ``seconds``."""
    scene = ra.Scene(cls)
    agent = scene.agents[0]
    scene.reset(keyframes="standing")
    keyframe, hold = agent.qpos[0].copy(), hold_action(agent)
    poses, feet_paths, worst_tilt, touching, max_sag = [], [], 0.0, set(), 0.0
    feet = {f"{leg}_SHANK" for leg in ("LF", "RF", "LH", "RH")}
    model = scene.model
    for _ in range(round(seconds * scene.control_freq)):
        agent.set_action(hold)
        scene.step()
        pose = agent.base_pose[0]
        poses.append(pose[:3].copy())
        max_sag = max(max_sag, float(np.max(np.abs(agent.qpos[0] - keyframe))))
        feet_paths.append([scene.world.datas[0].site(f"{agent.prefix}{leg}_FOOT").xpos.copy() for leg in MENAGERIE])
        worst_tilt = max(worst_tilt, math.degrees(math.acos(min(1.0, quat_to_matrix(pose[3:])[2, 2]))))
        data = scene.world.datas[0]
        for c in data.contact[: data.ncon]:
            names = {model.body(model.geom_bodyid[g]).name for g in (c.geom1, c.geom2)}
            touching |= {n.split("/")[-1] for n in names if n != "world"}
    result = {
        "poses": np.array(poses),
        "tilt": worst_tilt,
        "touching": touching - feet,
        "feet_touching": touching & feet,
        "sag": agent.qpos[0] - keyframe,
        "max_sag": max_sag,
        "feet": np.array(feet_paths),  # (steps, 4, 3)
        "unstable": int(scene.world.instability_counts()[0]),
    }
    scene.close()
    return result


def test_stands_on_its_legs_at_the_standing_keyframe() -> None:
    """5 s of the default mode's hold action: the base settles 7 mm below the keyframe's
    0.545 m (the feet's 2.3 mm drop and the legs' sag: KFE 0.026, HFE 0.024, HAA 0.003 rad
    at kp 400; 0.042 rad at most while landing) and then stays within 0.22 mm, upright
    (0.007 deg), on its four feet alone."""
    result = stand("anymal_c")
    poses = result["poses"]
    assert isinstance(poses, np.ndarray)
    settled = poses[20:]  # after the first second
    assert np.ptp(settled[:, 2]) < 0.01 and np.max(np.linalg.norm(settled - settled[0], axis=1)) < 0.001
    assert 0.53 < poses[-1, 2] < STANDING_HEIGHT
    assert result["tilt"] < 2.0
    assert result["touching"] == set() and len(result["feet_touching"]) == 4  # type: ignore[arg-type]
    sag = np.abs(np.asarray(result["sag"]))
    assert 0.01 < sag.max() < 0.05, sag  # stiff enough, and the legs do carry the weight
    assert np.all(np.abs(np.asarray(result["max_sag"])) < 0.05)  # also while landing
    assert result["unstable"] == 0


def test_maniskill_gains_let_it_sink() -> None:
    """ManiSkill's kp 80, kv 2 (which carry a base without its legs' weight there: ManiSkill
    switches gravity off on the legs) let the knees give 0.17 rad under the whole robot."""
    soft = type(
        "AnymalCManiSkillGains",
        (AnymalC,),
        {
            "uid": "",
            "actuators": (ra.PDActuator(joints=ANYMAL_DRIVES.joints, stiffness=80.0, damping=2.0, effort_limit=100.0),),
        },
    )
    result = stand(soft, seconds=3.0)
    assert np.abs(np.asarray(result["sag"])).max() > 0.1


def test_mujocos_default_friction_cone_lets_the_feet_creep() -> None:
    """Without Menagerie's elliptic cone and impratio 100 the feet keep sliding outwards
    under the standing robot after it has settled (MuJoCo's soft pyramidal friction creeps
    under a steady sideways load); with them they stay put."""
    pyramidal = type("AnymalCPyramidal", (AnymalC,), {"uid": "", "friction_cone": None, "impratio": None})
    slid = {}
    for cls in (AnymalC, pyramidal):
        feet = np.asarray(stand(cls, seconds=5.0)["feet"])
        slid[cls.__name__] = float(np.max(np.linalg.norm((feet[-1] - feet[19])[:, :2], axis=1)))  # 1 s to 5 s
    assert slid["AnymalC"] < 1e-3 and slid["AnymalCPyramidal"] > 3e-3, slid  # 0.5 mm, 6 mm


def test_scenes_with_the_anymal_take_its_sparse_jacobian() -> None:
    """The ANYmal declares MuJoCo's sparse constraint Jacobian (faster for it: its module);
    a scene with it uses that, one without any robot asking keeps MuJoCo's choice, and a
    robot asking for the dense one gets it unless another asks for the sparse one."""
    sparse, dense, auto = (
        int(j) for j in (mujoco.mjtJacobian.mjJAC_SPARSE, mujoco.mjtJacobian.mjJAC_DENSE, mujoco.mjtJacobian.mjJAC_AUTO)
    )
    assert ra.Scene("anymal_c").model.opt.jacobian == sparse
    assert ra.Scene(["panda", "anymal_c"]).model.opt.jacobian == sparse
    assert ra.Scene("panda").model.opt.jacobian == auto
    panda_dense = type("PandaDense", (ra.get_agent("panda"),), {"uid": "", "jacobian": "dense"})
    assert ra.Scene(panda_dense).model.opt.jacobian == dense
    assert ra.Scene([panda_dense, "anymal_c"]).model.opt.jacobian == sparse


def test_scene_takes_the_contact_options() -> None:
    assert AnymalC.friction_cone == "elliptic" and AnymalC.impratio == 100.0
    alone = ra.Scene("anymal_c")
    assert alone.model.opt.cone == 1 and alone.model.opt.impratio == 100.0  # mjCONE_ELLIPTIC
    mixed = ra.Scene(["panda", "anymal_c"])
    assert mixed.model.opt.cone == 1 and mixed.model.opt.impratio == 100.0
    assert ra.Scene("panda").model.opt.cone == 0
    for bad in ({"friction_cone": "round"}, {"impratio": 0.5}, {"jacobian": "auto"}):
        with pytest.raises(ra.ConfigError, match=next(iter(bad))):
            type("BadAnymal", (AnymalC,), {"uid": "", **bad}).validate_definition()


def test_masses_and_joint_ranges_match_menagerie(scene: ra.Scene) -> None:
    model, prefix = scene.model, scene.agents[0].prefix
    robot = [b for b in range(model.nbody) if model.body(b).name.startswith(prefix)]
    assert sum(model.body_mass[b] for b in robot) == pytest.approx(44.96518, abs=1e-6)
    assert model.body(prefix + "base").mass[0] == pytest.approx(MASSES["base"])
    for leg in MENAGERIE:
        for link in ("HIP", "THIGH", "SHANK"):
            assert model.body(f"{prefix}{leg}_{link}").mass[0] == pytest.approx(MASSES[link])
        np.testing.assert_allclose(model.joint(f"{prefix}{leg}_HAA").range, HAA_RANGES[leg[0]])
        for joint in ("HFE", "KFE"):
            np.testing.assert_allclose(model.joint(f"{prefix}{leg}_{joint}").range, (-9.42478, 9.42478))


def test_feet_and_inertias_match_menageries_chain(scene: ra.Scene) -> None:
    """At the standing keyframe and at a random pose: every foot frame within 1 mm (in fact
    1e-6 m) of Menagerie's chain; every link's centre of mass and world inertia tensor
    equal to Menagerie's inertials carried through the same chain."""
    agent = scene.agents[0]
    names = agent.joint_names
    rng = np.random.default_rng(3)
    poses = [np.array([dict(zip(LEG_JOINTS, STANDING_QPOS, strict=True))[n] for n in names])]
    poses.append(rng.uniform(-0.49, 0.49, len(names)))
    for qpos in poses:
        agent.reset(qpos=qpos)
        base = frame(agent.base_pose[0, :3], agent.base_pose[0, 3:])
        data = scene.world.datas[0]
        for leg in MENAGERIE:
            hip, thigh, shank, foot = menagerie_leg(leg, leg_angles(qpos, names, leg), base)
            np.testing.assert_allclose(data.site(f"{agent.prefix}{leg}_FOOT").xpos, foot[:3, 3], atol=1e-6)
            for link, pose, (com, axes, moments) in zip(
                ("HIP", "THIGH", "SHANK"), (hip, thigh, shank), MENAGERIE[leg]["inertia"], strict=True
            ):
                body = data.body(f"{agent.prefix}{leg}_{link}")
                principal = pose @ frame(com, axes)
                expected = principal[:3, :3] @ np.diag(moments) @ principal[:3, :3].T
                rot = body.ximat.reshape(3, 3)
                actual = rot @ np.diag(scene.model.body(body.id).inertia) @ rot.T
                np.testing.assert_allclose(body.xipos, principal[:3, 3], atol=1e-6)
                np.testing.assert_allclose(actual, expected, atol=2e-6)


def test_standing_keyframe_and_actions_follow_maniskill(scene: ra.Scene) -> None:
    agent = scene.agents[0]
    assert list(AnymalC.keyframes) == ["standing", "rest"]
    scene.reset(keyframes="standing")
    np.testing.assert_allclose(agent.base_pose[0], (0, 0, STANDING_HEIGHT, 1, 0, 0, 0))
    by_name = dict(zip(agent.joint_names, agent.qpos[0], strict=True))
    assert tuple(by_name[j] for j in LEG_JOINTS) == STANDING_QPOS
    np.testing.assert_array_equal(agent.keyframe_qpos("rest"), agent.keyframe_qpos("standing"))
    modes = AnymalC.modes()
    for mode in modes:
        (config,) = AnymalC.mode_parts(mode).values()  # one part: the legs
        assert tuple(config.joint_names) == LEG_JOINTS  # ManiSkill's action order
    (delta,) = AnymalC.mode_parts("pd_joint_delta_pos").values()
    assert delta.lower == -0.225 and delta.upper == 0.225
    assert AnymalC.default_mode() == "pd_joint_target_delta_pos"
    # the feet (sphere bottoms) start 2.3 mm above the floor
    feet = [scene.world.datas[0].geom(f"{agent.prefix}{leg}_foot") for leg in MENAGERIE]
    assert [round(float(f.xpos[2]) - 0.03, 4) for f in feet] == [0.0023] * 4


@pytest.mark.parametrize("mode", AnymalC.modes())
def test_random_actions_for_ten_seconds_stay_stable(mode: str) -> None:
    scene = ra.Scene("anymal_c", control_modes=mode)
    agent = scene.agents[0]
    scene.reset()
    rng = np.random.default_rng(0)
    space = agent.action_space
    fastest = 0.0
    for _ in range(10 * scene.control_freq):
        agent.set_action(rng.uniform(space.low, space.high))
        scene.step()
        fastest = max(fastest, float(np.max(np.abs(agent.qvel))))
    assert scene.world.instability_counts()[0] == 0
    assert np.all(np.isfinite(scene.world.get_state()))
    # no armature in the public model: the light shanks whip at up to ~235 rad/s under
    # random absolute targets (+-2 pi); a blow-up would be orders of magnitude more
    assert fastest < 500.0
    assert -0.1 < agent.base_pose[0, 2] < 2.0  # on the floor, not thrown
    scene.close()


def test_is_standing_and_is_fallen() -> None:
    """Standing in the default mode; ManiSkill's default mode (deltas on the measured pose)
    folds the loaded legs at a zero action until the belly is on the floor."""
    for mode, standing in (("pd_joint_target_delta_pos", True), ("pd_joint_delta_pos", False)):
        scene = ra.Scene("anymal_c", control_modes=mode)
        agent = scene.agents[0]
        scene.reset(keyframes="standing")
        hold = hold_action(agent)
        for _ in range(5 * scene.control_freq):
            agent.set_action(hold)
            scene.step()
        assert bool(agent.is_standing()[0]) is standing and bool(agent.is_fallen()[0]) is not standing, mode
        assert bool(agent.base_pose[0, 2] > 0.5) is standing
        scene.close()
