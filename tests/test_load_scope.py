"""Model files are parsed once per check and Scene build (robot_agents.model.load_scope),
and read again by the next: a file edited between two loads is seen."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

import robot_agents as ra
from robot_agents.model import load_scope
from robot_agents.robot_source import robot_from_file
from tests.conftest import PENDULUM_MJCF

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> list[Path]:
    """The model files parsed (load_model_spec calls), in order."""
    seen: list[Path] = []
    parse = load_scope.load_model_spec

    def counted(path: Path, compiler: ra.CompilerSettings) -> object:
        seen.append(Path(path).name)  # type: ignore[arg-type]
        return parse(path, compiler)

    monkeypatch.setattr(load_scope, "load_model_spec", counted)
    return seen


def test_a_scene_of_a_new_robot_with_a_piece_parses_each_file_once(reads: list[Path]) -> None:
    # a scene of it parsed each file three times (its check: the build, the piece's names
    # told from the arm's, the arm alone beside the piece; the scene's build), and each
    # once more for a second robot of it
    cls = robot_from_file(EXAMPLES / "my_arm.urdf", gripper="robotiq_2f85", at="flange")
    ra.registry.get_piece("robotiq_2f85").check()  # the piece's own check, beforehand
    reads.clear()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        scene = ra.Scene([cls, cls])
    assert sorted(reads) == ["my_arm.urdf", "robotiq_2f85.xml"]
    scene.close()
    ra.Scene(cls).close()  # a later scene reads them again
    assert sorted(reads) == ["my_arm.urdf", "my_arm.urdf", "robotiq_2f85.xml", "robotiq_2f85.xml"]


def test_a_file_edited_between_two_loads_is_read_again(tmp_path: Path) -> None:
    path = tmp_path / "edited.xml"
    path.write_text(
        PENDULUM_MJCF.replace("</mujoco>", '<keyframe><key name="home" qpos="0.1 0.2"/></keyframe></mujoco>')
    )
    first = robot_from_file(path)
    assert first.keyframe_aliases() == {"home": "default"}
    path.write_text(
        PENDULUM_MJCF.replace("</mujoco>", '<keyframe><key name="rest" qpos="0.3 0.4"/></keyframe></mujoco>')
    )
    second = robot_from_file(path)
    assert second.keyframe_aliases() == {"rest": "default"}
    assert list(second.check().keyframes["default"].qpos) == [0.3, 0.4]


def test_each_load_in_a_scope_is_a_copy_of_its_own(pendulum_file: Path) -> None:
    with load_scope.one_read_per_file():
        one = load_scope.load_spec(pendulum_file, ra.CompilerSettings())
        one.worldbody.first_body().name = "changed"
        two = load_scope.load_spec(pendulum_file, ra.CompilerSettings())
        assert two is not one and two.worldbody.first_body().name == "base"
        with load_scope.one_read_per_file():  # a nested scope shares the outer one
            assert load_scope._LOADED.get() is not None
    assert load_scope._LOADED.get() is None
