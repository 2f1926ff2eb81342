"""Contact materials for robot links and props."""

from __future__ import annotations

from dataclasses import dataclass

from robot_agents.errors import ConfigError
from robot_agents.validation import is_real


@dataclass(frozen=True)
class FrictionMaterial:
    """MuJoCo contact friction of a geom.

    Attributes:
        sliding: tangential (Coulomb) friction coefficient, dimensionless.
        torsional: torsional friction (m), resists spinning about the contact normal.
        rolling: rolling friction (m), resists rolling.
    """

    sliding: float = 1.0
    torsional: float = 0.005
    rolling: float = 0.0001

    def __post_init__(self) -> None:
        for name in ("sliding", "torsional", "rolling"):
            value = getattr(self, name)
            if not (is_real(value) and value >= 0):
                raise ConfigError(f"FrictionMaterial.{name}: expected a number >= 0, got {value!r}.")

    def as_mujoco(self) -> list[float]:
        """The ``geom.friction`` triple."""
        return [float(self.sliding), float(self.torsional), float(self.rolling)]
