"""Contact materials for robot links and props."""

from __future__ import annotations

from dataclasses import dataclass

import mujoco

from robot_agents.errors import ConfigError
from robot_agents.keywords import checked_keywords
from robot_agents.validation import check_vector, is_real

#: MuJoCo's ``priority`` a geom gets when its material sets ``solref`` or ``solimp``, so
#: that its values win the mix against a geom of lower priority (a prop, a file's default).
STIFF_PRIORITY = 1
#: The contact of the built-in Panda's fingertips (``robots/panda/assets/panda_defaults.xml``),
#: which a gripper a model file implies gets on its fingers (``solref``: MuJoCo raises the
#: 0.002 s to two physics steps; ``solimp``: impedance 0.95 at contact, 0.99 past 1 mm).
PAD_SOLREF = (0.002, 1.0)
PAD_SOLIMP = (0.95, 0.99, 0.001)


@checked_keywords
@dataclass(frozen=True)
class FrictionMaterial:
    """MuJoCo contact material of a geom: its friction and, optionally, how soft its
    contacts are.

    MuJoCo's contacts are soft: pressed with force F, a contact at rest sinks
    ``(1 - d) * (F / m) * timeconst^2 * dampratio^2`` deep, with ``d`` the impedance at
    that depth (``solimp``: ``d_max`` past ``width``), ``timeconst`` and ``dampratio``
    from ``solref`` and ``m`` the effective mass at the contact (for a light object
    pinched by a heavy gripper: about the object's own mass; MuJoCo's reference
    acceleration is ``-b v - k d r`` with ``k = 1 / (d_max^2 timeconst^2 dampratio^2)``).
    With MuJoCo's defaults an 8 g cube sinks 2.5 mm per newton, so a gripper squeezing a
    light object needs stiffer pads (the Panda's fingertips, ``timeconst`` 0.004 s and
    ``d`` 0.99: 0.02 mm per newton); the built-in robots declare theirs in their MJCF, a
    file without them (URDF has no such fields) gets them here.

    Attributes:
        sliding: tangential (Coulomb) friction coefficient, dimensionless.
        torsional: torsional friction (m), resists spinning about the contact normal.
        rolling: rolling friction (m), resists rolling.
        solref: ``(timeconst s, dampratio)`` of the geom's contacts (MuJoCo's ``solref``;
            both negative: ``(-stiffness, -damping)``); MuJoCo raises a timeconst under
            two physics steps to two steps. ``None`` keeps the model's (MuJoCo's
            default ``(0.02, 1)``).
        solimp: ``(d_min, d_max, width m)`` or ``(d_min, d_max, width m, midpoint, power)``
            (MuJoCo's ``solimp``: the impedance rises from ``d_min`` at zero
            penetration to ``d_max`` at ``width``); ``None`` keeps the model's
            (MuJoCo's default ``(0.9, 0.95, 0.001, 0.5, 2)``).

    Setting ``solref`` or ``solimp`` also gives the geom ``priority``
    :data:`STIFF_PRIORITY`: MuJoCo then takes the contact's ``solref``, ``solimp`` and
    friction from this geom alone against a geom of lower priority, instead of mixing
    them (friction: the larger of the two).
    """

    sliding: float = 1.0
    torsional: float = 0.005
    rolling: float = 0.0001
    solref: tuple[float, float] | None = None
    solimp: tuple[float, ...] | None = None

    def __post_init__(self) -> None:
        for name in ("sliding", "torsional", "rolling"):
            value = getattr(self, name)
            if not (is_real(value) and value >= 0):
                raise ConfigError(f"FrictionMaterial.{name}: expected a number >= 0, got {value!r}.")
        if self.solref is not None:
            solref = check_vector(self.solref, 2, "(timeconst s, dampratio)", "FrictionMaterial.solref")
            if not (all(v > 0 for v in solref) or all(v < 0 for v in solref)):
                raise ConfigError(
                    "FrictionMaterial.solref: expected (timeconst s, dampratio) both > 0, or (-stiffness, -damping) "
                    f"both < 0, got {self.solref!r}."
                )
            object.__setattr__(self, "solref", solref)
        if self.solimp is not None:
            size = 5 if getattr(self.solimp, "__len__", None) and len(self.solimp) == 5 else 3
            what = "(d_min, d_max, width m)" if size == 3 else "(d_min, d_max, width m, midpoint, power)"
            solimp = check_vector(self.solimp, size, f"{what} (3 or 5)", "FrictionMaterial.solimp")
            d_min, d_max, width = solimp[:3]
            midpoint, power = solimp[3:] if size == 5 else (0.5, 2.0)
            if not (0 < d_min < 1 and 0 < d_max < 1 and width > 0 and 0 < midpoint < 1 and power >= 1):
                raise ConfigError(
                    f"FrictionMaterial.solimp: expected 0 < d_min, d_max < 1, width > 0 m, 0 < midpoint < 1 and "
                    f"power >= 1, got {self.solimp!r}."
                )
            object.__setattr__(self, "solimp", solimp)

    def as_mujoco(self) -> list[float]:
        """The ``geom.friction`` triple."""
        return [float(self.sliding), float(self.torsional), float(self.rolling)]

    def apply(self, geom: mujoco.MjsGeom) -> None:
        """Write this material into ``geom`` of an ``MjSpec`` (friction; ``solref``,
        ``solimp`` and ``priority`` when set)."""
        geom.friction = self.as_mujoco()
        if self.solref is not None or self.solimp is not None:
            set_contact_softness(geom, self.solref, self.solimp)


def set_contact_softness(
    geom: mujoco.MjsGeom, solref: tuple[float, ...] | None, solimp: tuple[float, ...] | None
) -> None:
    """Give ``geom`` (of an ``MjSpec``) ``priority`` :data:`STIFF_PRIORITY` and the given
    ``solref`` / ``solimp`` (``None``: the geom's own; a 3-number ``solimp`` takes MuJoCo's
    default midpoint 0.5 and power 2): a :class:`FrictionMaterial`'s softness, and a
    derived gripper's pads (:func:`robot_agents.model.robot_spec.set_pad_contact`)."""
    geom.priority = STIFF_PRIORITY
    if solref is not None:
        geom.solref = list(solref)
    if solimp is not None:
        geom.solimp = list(solimp) + ([0.5, 2.0] if len(solimp) == 3 else [])
