from __future__ import annotations

import math

import numpy as np
import pytest

import robot_agents as ra


def test_keyframe_normalizes_and_copies() -> None:
    frame = ra.Keyframe(qpos=[0.1, 0.2], base_quat=(2.0, 0.0, 0.0, 0.0))
    assert frame.qpos == (0.1, 0.2)
    assert frame.base_quat == (1.0, 0.0, 0.0, 0.0)
    np.testing.assert_array_equal(frame.qvel_array(), [0.0, 0.0])
    array = frame.qpos_array()
    array[0] = 5.0
    assert frame.qpos[0] == 0.1


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"qpos": [0.0, math.nan]}, "finite"),
        ({"qpos": [0.0], "qvel": [0.0, 1.0]}, "expected 1 values"),
        ({"qpos": [0.0], "base_pos": [0.0, 0.0]}, "expected 3 values"),
        ({"qpos": [0.0], "base_quat": [0.0, 0.0, 0.0, 0.0]}, "unit quaternion"),
    ],
)
def test_keyframe_rejects_bad_values(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(ra.ConfigError, match=match):
        ra.Keyframe(**kwargs)  # type: ignore[arg-type]
