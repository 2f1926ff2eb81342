"""The standing claim of the time-step sweep and the hold of a robot on its legs, on a
quadruped written here: a 8 kg box on four two-joint legs with ball feet."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

import robot_agents as ra
from robot_agents.agent.legs import foot_bodies
from robot_agents.checks import LOAD_SETTLE_SECONDS, check_holds, standing_leg_joints
from robot_agents.tuning.claims import Penetration, measure_step
from robot_agents.tuning.standing_claim import STAND_DRIFT, STAND_TILT, standing_claim

LEG = """<body name="{n}_thigh" pos="{x} {y} 0"><joint name="{n}_hip" axis="0 1 0" range="-1.5 1.5"/>
  <geom type="capsule" fromto="0 0 0 0 0 -0.15" size="0.02" mass="0.5"/>
  <body name="{n}_shin" pos="0 0 -0.15"><joint name="{n}_knee" axis="0 1 0" range="-2.5 0"/>
    <geom type="capsule" fromto="0 0 0 0 0 -0.15" size="0.015" mass="0.3"/>
    <body name="{n}_foot" pos="0 0 -0.15"><geom name="{n}_foot" type="sphere" size="0.02" mass="0.05"/></body>
  </body></body>"""
CORNERS = (("fl", 0.2, 0.12), ("fr", 0.2, -0.12), ("hl", -0.2, 0.12), ("hr", -0.2, -0.12))
QUADRUPED_MJCF = (
    '<mujoco model="quadruped"><compiler angle="radian"/>'
    '<default><joint damping="0.1" armature="0.01"/></default><worldbody>'
    '<body name="torso" pos="0 0 0.3"><geom name="torso" type="box" size="0.2 0.1 0.05" mass="8"/>'
    + "".join(LEG.format(n=n, x=x, y=y) for n, x, y in CORNERS)
    + "{arm}</body></worldbody></mujoco>"
)
#: A one-joint arm on the torso's front (so that the legs are not the main part).
ARM = """<body name="arm" pos="0.2 0 0.05"><joint name="arm_joint" axis="0 1 0" range="-1 1"/>
  <geom type="capsule" fromto="0 0 0 0.1 0 0" size="0.01" mass="0.1"/></body>"""
#: Hips at 0.5 rad, knees at -1.0: each foot 0.263 m below its hip, under it; the ball
#: feet (2 cm) touch the floor with the torso's centre 0.283 m up.
STANDING = ra.Keyframe(qpos={".*_hip": 0.5, ".*_knee": -1.0}, base_pos=(0.0, 0.0, 0.285))


def quadruped(
    path: Path, front_stiffness: float = 200.0, hind_stiffness: float = 200.0, arm: bool = False, **extra: Any
) -> type[ra.Agent]:
    path.write_text(QUADRUPED_MJCF.format(arm=ARM if arm else ""))
    attributes: dict[str, Any] = {
        "uid": "",
        "mjcf_path": path,
        "fix_root_link": False,
        "actuators": (
            ra.PDActuator(joints="f._(hip|knee)", stiffness=front_stiffness, damping=5.0, effort_limit=40.0),
            ra.PDActuator(joints="h._(hip|knee)", stiffness=hind_stiffness, damping=5.0, effort_limit=40.0),
        ),
        "parts": (ra.Legs(name="legs", joints=".*_(hip|knee)"),),
        "keyframes": {"standing": STANDING},
        "default_control_mode": "pd_joint_pos",
    }
    attributes.update(extra)
    return type("Quadruped", (ra.Agent,), attributes)


@pytest.fixture
def model_file(tmp_path: Path) -> Path:
    return tmp_path / "quadruped.xml"


def test_the_feet_are_the_distal_leg_links(model_file: Path) -> None:
    cls = quadruped(model_file)
    assert standing_leg_joints(cls) == tuple(f"{n}_{j}" for n, _, _ in CORNERS for j in ("hip", "knee"))
    scene = ra.Scene(cls)
    model, index = scene.model, scene.agents[0].index
    feet = foot_bodies(model, [index.joint(f"{n}_{j}", "test").id for n, _, _ in CORNERS for j in ("hip", "knee")])
    names = sorted(model.body(b).name.split("/")[-1] for b in feet)
    assert names == sorted(f"{n}_{part}" for n, _, _ in CORNERS for part in ("foot", "shin"))
    scene.close()


def test_a_stiff_quadruped_stands_and_holds_after_settling(model_file: Path) -> None:
    cls = quadruped(model_file)
    claim = standing_claim(cls, 500, 20, Penetration())
    assert claim is not None and claim.passed, claim
    assert claim.value < 1e-4 and "feet alone on the floor" in claim.detail
    hold = check_holds(cls)
    # the legs give under the body's weight while it settles (about 0.012 rad at these
    # gains), then stay put
    assert hold.passed and f"after {LOAD_SETTLE_SECONDS:g} s on its legs" in hold.detail, hold
    sag = float(hold.detail.rsplit("sag meanwhile: ", 1)[1].rstrip(")"))
    assert 0.005 < sag < 0.03
    step = measure_step(cls, 500, seeds=(0,))
    assert [c.name for c in step.claims] == ["hold", "random", "settle", "standing", "penetration"]
    assert step.passed, step.claims


def test_weak_legs_fail_the_claim_by_the_body_on_the_floor(model_file: Path) -> None:
    claim = standing_claim(quadruped(model_file, 3.0, 3.0), 500, 20, Penetration())
    assert claim is not None and not claim.passed
    assert "touching the floor besides the feet" in claim.detail and "thigh" in claim.detail


def test_weak_front_legs_fail_the_claim_by_tilting(model_file: Path) -> None:
    """The front legs give (9 deg of pitch) with the feet still alone on the floor."""
    claim = standing_claim(quadruped(model_file, front_stiffness=3.0), 500, 20, Penetration())
    assert claim is not None and not claim.passed and "feet alone on the floor" in claim.detail
    tilt = math.radians(float(claim.detail.split("tilt ", 1)[1].split(" deg", 1)[0]))
    assert tilt > STAND_TILT


def test_a_step_too_coarse_fails_the_claim(model_file: Path) -> None:
    claim = standing_claim(quadruped(model_file), 40, 20, Penetration())
    assert claim is not None and not claim.passed and claim.value > STAND_DRIFT


def test_robots_without_legs_carrying_them_make_no_claim(model_file: Path) -> None:
    assert standing_claim(ra.get_agent("ur_10e"), 500, 20, Penetration()) is None
    assert standing_claim(ra.get_agent("spot"), 200, 20, Penetration()) is None  # held legs, kinematic base
    fixed = quadruped(model_file, fix_root_link=True)
    with pytest.warns(RuntimeWarning, match=r"keyframes\['standing'\]: base_pos .* they are ignored"):
        assert standing_leg_joints(fixed) == () and standing_claim(fixed, 500, 20, Penetration()) is None


def test_the_check_command_runs_the_standing_check(model_file: Path) -> None:
    from robot_agents.checks import check_standing, run_checks

    names = [r.name for r in run_checks(quadruped(model_file), random_seconds=1.0)]
    assert names[2] == "stands 5 s on its legs from each keyframe"
    weak = check_standing(quadruped(model_file, 3.0, 3.0))
    assert weak is not None and not weak.passed and "thigh" in weak.detail
    assert check_standing(ra.get_agent("panda")) is None
    assert "stands" not in " ".join(r.name for r in run_checks(ra.get_agent("ur_10e"), random_seconds=0.5))


def test_is_standing_and_is_fallen(model_file: Path) -> None:
    """Standing: upright, only the feet on the floor; fallen: any other body on it."""
    import numpy as np

    from robot_agents.errors import ConfigError

    side = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)  # rolled 90 deg
    keyframes = {
        "standing": STANDING,
        "on_side": ra.Keyframe(qpos=STANDING.qpos, base_pos=(0, 0, 0.13), base_quat=side),
    }
    scene = ra.Scene(quadruped(model_file, keyframes=keyframes), num_envs=2)
    agent = scene.agents[0]
    assert len(agent.legs.feet) == 8  # four shins and their ball feet
    scene.reset(keyframes="standing")
    scene.reset(env_ids=[1], keyframes="on_side")
    hold = np.tile(agent.keyframe_qpos("standing"), (2, 1))
    for _ in range(20):  # 1 s
        agent.set_action(hold)
        scene.step()
    assert agent.is_standing().tolist() == [True, False]
    assert agent.is_fallen().tolist() == [False, True]
    tilt = math.acos(1 - 2 * float(np.sum(agent.base_pose[1, 4:6] ** 2)))
    assert agent.is_standing(max_tilt=tilt + 0.01).tolist() == [True, False]  # upright enough, but fallen
    with pytest.raises(ConfigError, match="max_tilt"):
        agent.is_standing(max_tilt=-1.0)
    scene.close()
    weak = ra.Scene(quadruped(model_file, 3.0, 3.0))
    weak.reset()
    for _ in range(60):  # 3 s: the legs give and the thighs come down on the floor
        weak.agents[0].set_action(weak.agents[0].keyframe_qpos("standing"))
        weak.step()
    assert weak.agents[0].is_fallen().tolist() == [True] and weak.agents[0].is_standing().tolist() == [False]
    weak.close()
    arm = ra.Scene("ur_10e")
    for method in (arm.agents[0].is_standing, arm.agents[0].is_fallen):
        with pytest.raises(ConfigError, match="no legs carrying a free base"):
            method()
    arm.close()


def test_legs_beside_an_arm_take_deltas_from_their_targets_and_stand(model_file: Path) -> None:
    """Generated modes append the legs to the arm's modes with deltas from their targets:
    zero actions keep the robot standing in every joint-position mode."""
    import numpy as np

    parts = (ra.Arm(name="arm", joints="arm_joint"), ra.Legs(name="legs", joints=".*_(hip|knee)"))
    actuators = (ra.PDActuator(joints=".*", stiffness=200.0, damping=5.0, effort_limit=40.0),)
    cls = quadruped(model_file, arm=True, parts=parts, actuators=actuators, default_control_mode=None)
    for mode in ("pd_joint_delta_pos", "pd_joint_target_delta_pos"):
        legs = cls.modes()[mode]["legs"]
        assert legs.use_delta and legs.use_target, mode
        scene = ra.Scene(cls, control_modes=mode)
        scene.reset()
        agent = scene.agents[0]
        for _ in range(60):  # 3 s of zero actions
            agent.set_action(np.zeros(agent.controller.action_dim))
            scene.step()
        assert agent.is_standing().tolist() == [True], mode
        assert float(agent.base_pose[0, 2]) > 0.27, mode  # stood at 0.283 m: given only the drives' sag
        scene.close()
