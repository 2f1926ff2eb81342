from __future__ import annotations

from pathlib import Path

import pytest

import robot_agents as ra
from tests.conftest import make_pendulum_class


def test_builtin_robots_registered() -> None:
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
        assert ra.unregister_agent("reg_pendulum") is not None
    assert "reg_pendulum" not in ra.list_agents()
    with pytest.raises(ra.UnknownNameError):
        ra.unregister_agent("reg_pendulum")


def test_register_rejects_non_agents_and_bad_definitions(pendulum_file: Path) -> None:
    with pytest.raises(ra.RegistryError, match=r"subclass of robot_agents\.Agent"):
        ra.register_agent()(int)  # type: ignore[type-var]
    no_uid = make_pendulum_class(pendulum_file, uid="")
    with pytest.raises(ra.RegistryError, match="non-empty string uid"):
        ra.register_agent()(no_uid)
    no_modes = make_pendulum_class(pendulum_file, uid="no_modes", control_modes={})
    with pytest.raises(ra.ConfigError, match="control_modes"):
        ra.register_agent()(no_modes)
    bad_default = make_pendulum_class(pendulum_file, uid="bad_default", default_control_mode="pd_joint_poss")
    with pytest.raises(ra.UnknownNameError, match="pd_joint_pos"):
        ra.register_agent()(bad_default)
    assert "bad_default" not in ra.list_agents()
