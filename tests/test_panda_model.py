"""Geometry of the built-in Panda model: the elbow housing (panda_link4) and the
forearm (panda_link5) meet, and the forearm is one piece, as on the real arm."""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from robot_agents.model.compiling import compile_spec
from robot_agents.robots.panda.panda import Panda

VISUAL_GROUP = 2
POSES = ["q0", *Panda.keyframes]


def compiled(pose: str) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = compile_spec(Panda.build_spec(), "test")  # the arm with the hand attached
    data = mujoco.MjData(model)
    if pose != "q0":
        data.qpos[:] = Panda.check().keyframes[pose].qpos
    mujoco.mj_forward(model, data)
    return model, data


def visual_geoms(model: mujoco.MjModel, body: str) -> list[int]:
    body_id = model.body(body).id
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] == body_id and model.geom_group[g] == VISUAL_GROUP]


def distance(model: mujoco.MjModel, data: mujoco.MjData, geom1: int, geom2: int) -> float:
    """Signed distance (m) between two geoms; negative when they overlap."""
    return mujoco.mj_geomDistance(model, data, geom1, geom2, 1.0, np.zeros(6))


@pytest.mark.parametrize("pose", POSES)
def test_elbow_and_forearm_meet(pose: str) -> None:
    """No visible gap between the elbow housing and the forearm (it was 2 mm)."""
    model, data = compiled(pose)
    gap = min(
        distance(model, data, a, b)
        for a in visual_geoms(model, "panda_link4")
        for b in visual_geoms(model, "panda_link5")
    )
    assert gap <= 1e-3, f"{pose}: link4-link5 visual gap {gap * 1000:.2f} mm"


def test_forearm_is_one_piece() -> None:
    """Every visual geom of the forearm touches another one: the strut is joined to the
    drum at the elbow (it used to float 22 mm away from it)."""
    model, data = compiled("q0")
    geoms = visual_geoms(model, "panda_link5")
    reached, todo = {geoms[0]}, [geoms[0]]
    while todo:
        current = todo.pop()
        for g in geoms:
            if g not in reached and distance(model, data, current, g) <= 1e-3:
                reached.add(g)
                todo.append(g)
    assert reached == set(geoms), f"detached forearm geoms: {sorted(set(geoms) - reached)}"


def test_elbow_and_forearm_keep_their_identified_masses() -> None:
    model, _ = compiled("q0")
    assert model.body("panda_link4").mass[0] == pytest.approx(3.587895, abs=1e-6)
    assert model.body("panda_link5").mass[0] == pytest.approx(1.225946, abs=1e-6)
