from __future__ import annotations

from pathlib import Path

import pytest

import robot_agents as ra
from tests.conftest import make_pendulum_class


def test_builtin_robots_registered_lazily() -> None:
    import subprocess
    import sys

    # Importing the library loads no robot model; asking for a uid imports its module.
    code = (
        "import sys, robot_agents as ra; "
        "assert 'robot_agents.robots.panda.panda' not in sys.modules; "
        "assert 'panda' in ra.list_agents(); "
        "assert 'robot_agents.robots.panda.panda' not in sys.modules; "
        "ra.get_agent('panda'); assert 'robot_agents.robots.panda.panda' in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True)
    uids = ra.list_agents()
    for uid in ("panda", "panda_stick", "floating_panda_gripper"):
        assert uid in uids
    assert ra.get_agent("panda").uid == "panda"


def test_unknown_uid_lists_close_matches() -> None:
    with pytest.raises(ra.UnknownNameError) as err:
        ra.get_agent("pandaa")
    message = str(err.value)
    assert "'pandaa'" in message and "Did you mean" in message and "'panda'" in message
    assert "panda_stick" in message  # the full list of what is available
    assert err.value.suggestions[0] == "panda"
    assert isinstance(err.value, KeyError)  # also catchable as a KeyError


def test_register_get_unregister(pendulum_file: Path) -> None:
    cls = make_pendulum_class(pendulum_file, uid="reg_pendulum")
    ra.register_agent()(cls)
    try:
        assert ra.get_agent("reg_pendulum") is cls
        assert "reg_pendulum" in ra.list_agents()
        other = make_pendulum_class(pendulum_file, uid="reg_pendulum")
        with pytest.raises(ra.RegistryError, match="already registered"):
            ra.register_agent()(other)
        ra.register_agent(override=True)(other)
        assert ra.get_agent("reg_pendulum") is other
    finally:
        removed = ra.unregister_agent("reg_pendulum")
    assert removed is other
    assert "reg_pendulum" not in ra.list_agents()
    with pytest.raises(ra.UnknownNameError):
        ra.unregister_agent("reg_pendulum")


def test_register_rejects_non_agents_and_bad_definitions(pendulum_file: Path) -> None:
    with pytest.raises(ra.RegistryError, match=r"subclass of robot_agents\.Agent"):
        ra.register_agent()(int)  # type: ignore[type-var]
    no_uid = make_pendulum_class(pendulum_file, uid="")
    with pytest.raises(ra.RegistryError, match="non-empty string uid"):
        ra.register_agent()(no_uid)
    no_drives = make_pendulum_class(pendulum_file, uid="no_drives", actuators=(), control_modes={}, parts=())
    no_drives.mjcf_path = pendulum_file.with_name("nothing_moves.xml")
    no_drives.mjcf_path.write_text("<mujoco><worldbody><body><geom size='0.1'/></body></worldbody></mujoco>")
    with pytest.raises(ra.ModelError, match=r"no joint in the compiled model: nothing a robot could move.*ra\.Prop"):
        ra.register_agent()(no_drives)
    bad_keyframe = make_pendulum_class(
        pendulum_file, uid="bad_keyframe", keyframes={"far": ra.Keyframe(qpos={"shoulder": 3.0})}
    )
    with pytest.raises(
        ra.ConfigError, match=r"keyframes\['far'\]: joint 'shoulder' at 3 is outside its limits \[-2.5, 2.5\]"
    ):
        ra.register_agent()(bad_keyframe)
    assert "bad_keyframe" not in ra.list_agents()
    bad_default = make_pendulum_class(pendulum_file, uid="bad_default", default_control_mode="pd_joint_poss")
    with pytest.raises(ra.UnknownNameError, match="pd_joint_pos"):
        ra.register_agent()(bad_default)
    assert "bad_default" not in ra.list_agents()


def test_register_without_parentheses_or_with_the_class(pendulum_file: Path) -> None:
    """``@register_agent`` bare and ``register_agent(cls)`` register the class under its
    own uid (the latter was once a decorator factory taking the class as a uid, which
    silently registered nothing)."""
    bare = make_pendulum_class(pendulum_file, uid="bare_pendulum")
    direct = make_pendulum_class(pendulum_file, uid="direct_pendulum")
    try:
        assert ra.register_agent(bare) is bare
        assert ra.get_agent("bare_pendulum") is bare
        assert ra.register_agent(direct, override=True) is direct
        assert ra.get_agent("direct_pendulum") is direct
    finally:
        ra.unregister_agent("bare_pendulum")
        ra.unregister_agent("direct_pendulum")
    with pytest.raises(ra.RegistryError, match=r"expected a uid string or an Agent subclass, got 3"):
        ra.register_agent(3)  # type: ignore[arg-type]


def test_maniskill_uid_alias_gives_the_builtin_robot(pendulum_file: Path) -> None:
    from robot_agents.registry import is_known_uid
    from robot_agents.robot_source import resolve_robot

    google = ra.get_agent("google_robot")
    assert ra.get_agent("googlerobot") is google  # ManiSkill 3.0.1's uid for it
    assert resolve_robot("googlerobot") is google
    assert is_known_uid("googlerobot") and not is_known_uid("googlerobott")
    assert "googlerobot" not in ra.list_agents()  # uids only
    env = ra.make_env("Empty-v1", robot_uids="googlerobot")
    try:
        assert type(env.unwrapped.agent) is google
    finally:
        env.close()
    # A robot registered under the alias itself comes first.
    mine = make_pendulum_class(pendulum_file, uid="googlerobot")
    ra.register_agent()(mine)
    try:
        assert ra.get_agent("googlerobot") is mine
    finally:
        ra.unregister_agent("googlerobot")
    assert ra.get_agent("googlerobot") is google
    # An alias of an unregistered robot resolves to nothing.
    ra.unregister_agent("google_robot")
    try:
        with pytest.raises(ra.UnknownNameError):
            ra.get_agent("googlerobot")
        assert not is_known_uid("googlerobot")
    finally:
        ra.register_agent()(google)
