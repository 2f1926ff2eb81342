"""One control mode: a flat action split by slices over per-part controllers (arm,
gripper, base, ...), their drive overrides, and the drive stage they feed."""

from __future__ import annotations

import operator
from collections.abc import Callable, Mapping
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from robot_agents.actuators.drives import DriveOverride, Drives
from robot_agents.controllers.base import (
    Controller,
    FloatArray,
    IntArray,
    clip_ufunc,
    one_pass_clip_exact,
    scale_directions,
)
from robot_agents.controllers.joint import PDJointPosController, SingleTerms
from robot_agents.errors import StateError

_FLOAT64 = np.dtype(np.float64)


class ControlledSim(Protocol):
    """What a control mode reads (``qpos``, ``qvel``) and writes (``ctrl``, through the drives)."""

    ctrl: FloatArray

    @property
    def qpos(self) -> FloatArray: ...

    @property
    def qvel(self) -> FloatArray: ...


class CombinedController:
    """The controllers of one control mode, in action order.

    ``parts`` maps a part name (``"arm"``, ``"gripper"``, ...) to its controller; the
    flat action is their actions concatenated in that order. Activating the mode
    applies the robot's declared drive settings with the mode's ``override`` on top.
    """

    def __init__(self, mode: str, parts: Mapping[str, Controller], drives: Drives, override: DriveOverride) -> None:
        self.mode = mode
        self.parts = dict(parts)
        self.drives = drives
        self.override = override
        kinds = {kind for c in self.parts.values() for kind in c.config.target_kinds()}
        self._uses_velocity = "velocity" in kinds
        self._uses_effort = "effort" in kinds
        self.slices: dict[str, slice] = {}
        start = 0
        for name, controller in self.parts.items():
            self.slices[name] = slice(start, start + controller.action_dim)
            start += controller.action_dim
        self.action_dim = start
        controllers = list(self.parts.values())
        self.action_low = np.concatenate([c.action_low for c in controllers]) if controllers else np.zeros(0)
        self.action_high = np.concatenate([c.action_high for c in controllers]) if controllers else np.zeros(0)
        self._substep_parts = [c for c in controllers if c.needs_substep]
        # (fixed: the parts' configs and the drives' kinds are)
        self._needs_substep = bool(self._substep_parts) or drives.needs_substep
        # One clip and one multiply-add for the whole action: normalized entries are
        # clipped to [-1, 1] and mapped onto [low, high], raw entries clipped to it.
        normalized = (
            np.concatenate([np.full(c.action_dim, c.config.normalize_action) for c in controllers])
            if controllers
            else np.zeros(0, dtype=bool)
        )
        raw_low = np.concatenate([c.raw_low for c in controllers]) if controllers else np.zeros(0)
        raw_high = np.concatenate([c.raw_high for c in controllers]) if controllers else np.zeros(0)
        # the raw values -1 and +1 map onto (swapped for reverse-normalized parts)
        unit_low = np.concatenate([c.unit_low for c in controllers]) if controllers else np.zeros(0)
        unit_high = np.concatenate([c.unit_high for c in controllers]) if controllers else np.zeros(0)
        self._clip_low = np.where(normalized, -1.0, raw_low)
        self._clip_high = np.where(normalized, 1.0, raw_high)
        self._one_pass_clip = one_pass_clip_exact(self._clip_low, self._clip_high)
        with np.errstate(invalid="ignore"):  # unbounded raw entries: inf - inf is never selected
            self._scale = np.where(normalized, (unit_high - unit_low) / 2, 1.0)
            self._offset = np.where(normalized, (unit_high + unit_low) / 2, 0.0)
        # ``(1, action_dim)`` rows of the per-entry constants: against a ``(1, A)`` action
        # NumPy takes its loop without broadcasting (several times faster on small
        # arrays; the same elementwise operations, so the same bits). The two-pass clip
        # keeps the 1-d bounds: with a zero bound, which zero max / min return may depend
        # on the loop taken.
        self._clip_low_row, self._clip_high_row = self._clip_low[None], self._clip_high[None]
        self._scale_row, self._offset_row = self._scale[None], self._offset[None]
        self._apply = [(c.apply, self.slices[name]) for name, c in self.parts.items()]
        self._checked = [(name, c) for name, c in self.parts.items() if c.checks_actions]
        # Directions (quaternions) in the action, scaled down as one vector before the clip.
        self._directions = [
            slice(self.slices[name].start + entries.start, self.slices[name].start + entries.stop)
            for name, c in self.parts.items()
            if (entries := c.direction_entries) is not None
        ]
        self._reporting = [c for c in controllers if type(c).step_info is not Controller.step_info]
        # One env: the parts' calls of their own (:meth:`_plan_single`), for the simulation
        # they were made for, reading the action clipped and scaled into one buffer.
        self._single_sim: object = None
        self._single_plan: list[Callable[[], None]] | None = None
        self._raw_single: FloatArray = np.empty((1, self.action_dim))
        #: One env, joint-position parts only: the whole action's call on Python floats
        #: (:meth:`_fuse_single`), made with :attr:`_single_plan`; ``None`` where it has none.
        self.single_values: Callable[[list[float]], None] | None = None
        #: With :attr:`single_values`: the drives' targets of every part, ``(1, n)``, in
        #: part order (a view of the drives' buffer), which the call leaves equal to the
        #: parts' :attr:`target_qpos` concatenated, bit for bit.
        self.single_targets: FloatArray | None = None

    @property
    def needs_substep(self) -> bool:
        """True when targets or controls change between physics substeps."""
        return self._needs_substep

    def activate(self, sim: ControlledSim) -> None:
        """Apply this mode's drive settings and start holding the measured pose in every env."""
        self.drives.activate(self.override, self._uses_velocity, self._uses_effort)
        self.reset(np.arange(sim.ctrl.shape[0]), sim)

    def reset(self, env_ids: IntArray, sim: ControlledSim) -> None:
        """Hold the measured pose in ``env_ids`` (targets and controls)."""
        self.drives.hold(env_ids, sim.qpos[env_ids])
        for controller in self.parts.values():
            controller.reset(env_ids, sim)
        self.drives.write(sim.ctrl, sim.qpos, sim.qvel)

    def _to_raw(self, action: FloatArray) -> FloatArray:
        # clip, then scale and shift, in place on one new array (the result is handed to
        # the controllers, which may keep views of it)
        if self._directions:
            action = scale_directions(action, self._directions)
        if self._one_pass_clip:
            raw: FloatArray = clip_ufunc(action, self._clip_low_row, self._clip_high_row)
        else:
            raw = np.maximum(action, self._clip_low)
            np.minimum(raw, self._clip_high, out=raw)
        np.multiply(raw, self._scale_row, out=raw)
        np.add(raw, self._offset_row, out=raw)
        return raw

    def check_action(self, action: FloatArray) -> str | None:
        """Why the parts cannot apply ``action`` ``(num_envs, action_dim)`` (``None`` if they can)."""
        if not self._checked:
            return None
        raw = self._to_raw(action)
        for name, controller in self._checked:
            problem = controller.check_raw_action(raw[:, self.slices[name]])
            if problem is not None:
                return f"part {name!r}: {problem}"
        return None

    def _plan_single(self, sim: ControlledSim) -> None:
        """For one env of a simulation with live views (:meth:`BatchedWorld.live_view
        <robot_agents.sim.world.BatchedWorld.live_view>`): each part's call of no arguments
        (:meth:`PDJointPosController.single_apply
        <robot_agents.controllers.joint.PDJointPosController.single_apply>`) reading its
        entries of :attr:`_raw_single` and the live ``qpos``, when every part has one and
        no entry is a direction; otherwise none (:meth:`set_action` takes the general
        path)."""
        self._single_sim, self._single_plan, self.single_values, self.single_targets = sim, None, None, None
        live_view = getattr(sim, "live_view", None)
        qpos = None if live_view is None or self._directions else live_view("qpos")
        if qpos is None:
            return
        plan = []
        for name, controller in self.parts.items():
            single_apply = getattr(controller, "single_apply", None)
            raw = self._raw_single[:, self.slices[name]]
            if single_apply is None:
                call = None
            elif type(controller) is PDJointPosController:
                call = controller.single_apply(raw, qpos, raw_never_negative_zero=self._never_negative_zero(name))
            else:
                call = single_apply(raw, qpos)
            if call is None:
                return
            plan.append(call)
        self._single_plan = plan
        self.single_values = self._fuse_single(sim, qpos)
        if self.single_values is not None:
            columns = [c for part in self.parts.values() for c in part.binding.columns.tolist()]
            self.single_targets = self.drives.targets.position[:, columns[0] : columns[0] + len(columns)]

    def _never_negative_zero(self, name: str) -> bool:
        """Whether part ``name``'s raw entries are never ``-0.0``: :meth:`_to_raw_single`
        adds the offsets last, and an entry whose offset is not ``-0.0`` is never ``-0.0``
        (round to nearest: ``x + c`` is ``-0.0`` only when both are)."""
        offsets = self._offset_row[0, self.slices[name]]
        return not np.any((offsets == 0.0) & np.signbit(offsets))

    def entry_constants(self) -> list[EntryConstants]:
        """Per action entry, ``(clip low, clip high, scale, offset)`` as Python floats: what
        :meth:`_to_raw_single` applies to the entry (clipped, times the scale, plus the
        offset), for the fused call's arithmetic on floats."""
        return list(
            zip(
                self._clip_low.tolist(),
                self._clip_high.tolist(),
                self._scale.tolist(),
                self._offset.tolist(),
                strict=True,
            )
        )

    def _fuse_single(self, sim: ControlledSim, qpos: FloatArray) -> Callable[[list[float]], None] | None:
        """One env, every part a joint-position part with a one-env call that clips in
        one pass or not at all (:meth:`PDJointPosController.single_terms
        <robot_agents.controllers.joint.PDJointPosController.single_terms>`), their drive
        columns consecutive and in action order, the action clipped in one pass: a call
        taking the action's entries as Python floats (``action_dim`` of them) that
        computes every part's targets on Python floats, writes them into the drives'
        buffer in one assignment, gives each part a new :attr:`target_qpos` (a copy of
        its columns) and writes the controls (:meth:`Drives.write
        <robot_agents.actuators.drives.Drives.write>`). ``None`` otherwise.

        The same values, bit for bit, as :meth:`_to_raw_single` and the parts' calls:
        Python's ``*`` and ``+`` on floats are the same IEEE double operations as NumPy's
        float64 ufuncs (each rounded once, in the same order: ``(v * scale) + offset``,
        ``measured + change``, ``target + m * entry``, ``m * entry + o``); a float32 or
        float16 entry becomes the same double either way (exactly). The clips are
        comparisons (``low if t < low else high if t > high else t``), which return what
        ``clip_ufunc`` returns wherever no value and bound are zeros of opposite signs
        (equal values otherwise have the same bits; a NaN is returned as it is by both):
        the action's one-pass clip has no zero bound (:func:`one_pass_clip_exact`), and a
        part's one-pass clip either has none or clips targets that are never ``-0.0``
        against bounds that are not ``-0.0`` (:meth:`PDJointPosController.single_apply
        <robot_agents.controllers.joint.PDJointPosController.single_apply>`)."""
        if self._checked or not self._one_pass_clip:
            return None
        constants = self.entry_constants()
        terms: list[SingleTerms] = []
        makers = []
        for name, controller in self.parts.items():
            if type(controller) is not PDJointPosController:
                return None
            part_terms = controller.single_terms(self._never_negative_zero(name))
            if part_terms is None:
                return None
            terms.append(part_terms)
            entries = self.slices[name]
            make = _part_targets(entries, constants[entries], part_terms, controller)
            if make is None:
                return None
            makers.append(make)
        columns = [column for t in terms for column in t.columns]
        if not columns or columns != list(range(columns[0], columns[0] + len(columns))):
            return None
        position = self.drives.targets.position  # never replaced
        row = position[0, columns[0] : columns[0] + len(columns)]  # (1-d: a list is written faster)
        views, start = [], columns[0]
        for t in terms:
            views.append(position[:, start : start + len(t.columns)])
            start += len(t.columns)
        pairs = list(zip(self.parts.values(), views, strict=True))
        measured_row = qpos[0]  # a read-only view that follows the simulation
        reads_measured = any(t.base == PDJointPosController._FROM_MEASURED for t in terms)
        write = self.drives.write

        def single_values(values: list[float]) -> None:
            measured = measured_row.tolist() if reads_measured else values
            targets: list[float] = []
            for make in makers:
                targets += make(values, measured)
            row[...] = targets
            for part, view in pairs:
                part._previous_target = part.target_qpos  # type: ignore[attr-defined]
                part.target_qpos = view.copy()  # type: ignore[attr-defined]
            write(sim.ctrl)

        return single_values

    def _to_raw_single(self, action: npt.NDArray[Any]) -> None:
        """:meth:`_to_raw` of one env's action ``(1, action_dim)`` into :attr:`_raw_single`
        (the same operations; an action of another dtype first converted into it,
        exactly, as the clip would convert it: cheaper than the clip's own conversion)."""
        raw = self._raw_single
        if action.dtype is not _FLOAT64:
            raw[...] = action
            action = raw
        if self._one_pass_clip:
            clip_ufunc(action, self._clip_low_row, self._clip_high_row, out=raw)
        else:
            np.maximum(action, self._clip_low, out=raw)
            np.minimum(raw, self._clip_high, out=raw)
        np.multiply(raw, self._scale_row, out=raw)
        np.add(raw, self._offset_row, out=raw)

    def set_action(self, action: FloatArray, sim: ControlledSim) -> None:
        """``action``: validated, shape ``(num_envs, action_dim)``; targets, then controls."""
        if sim is not self._single_sim:
            self._plan_single(sim)
        plan = self._single_plan
        if plan is not None:  # one env: the fused call (floats) or the parts' own calls
            values = self.single_values
            if values is not None and action.dtype.kind == "f":
                values(action.ravel().tolist())
                return
            self._to_raw_single(action)
            for call in plan:
                call()
            self.drives.write(sim.ctrl)
            return
        raw = self._to_raw(action)
        for apply, part_slice in self._apply:
            apply(raw[:, part_slice], sim)
        self.drives.write(sim.ctrl)

    def before_substep(self, substep: int, substeps: int, sim: ControlledSim) -> None:
        for controller in self._substep_parts:
            controller.before_substep(substep, substeps, sim)
        self.drives.write(sim.ctrl, sim.qpos, sim.qvel)

    def observe(self) -> dict[str, dict[str, FloatArray]]:
        """What a policy sees of each part's controller (e.g. its current targets; the
        arrays may be internal buffers: copy before keeping them)."""
        return {name: c.observe() for name, c in self.parts.items()}

    def step_info(self) -> dict[str, npt.NDArray[np.generic]]:
        """What the parts report about the last action (e.g. ``ik_success``), merged;
        keys two parts share are prefixed with the part name."""
        if not self._reporting:
            return {}
        if len(self._reporting) == 1:
            return self._reporting[0].step_info()
        merged: dict[str, npt.NDArray[np.generic]] = {}
        for name, controller in self.parts.items():
            for key, value in controller.step_info().items():
                merged[f"{name}/{key}" if key in merged else key] = value
        return merged

    def get_state(self) -> dict[str, Any]:
        """Each part's state (copies). The joint targets need no saving: the next action
        (or substep) rewrites every target the mode uses from this state."""
        return {name: c.get_state() for name, c in self.parts.items()}

    def check_state(self, state: Any, where: str) -> None:
        """Raise :class:`StateError` unless ``state`` matches :meth:`get_state`'s parts,
        keys and array shapes (nothing is changed)."""
        expected = self.get_state()
        if not isinstance(state, Mapping) or set(state) != set(expected):
            given = sorted(state) if isinstance(state, Mapping) else type(state).__name__
            raise StateError(
                f"{where}: expected controller state for parts {sorted(expected)} of mode {self.mode!r}, got {given}."
            )
        for part, arrays in expected.items():
            given_part = state[part]
            if not isinstance(given_part, Mapping) or set(given_part) != set(arrays):
                raise StateError(f"{where}: expected keys {sorted(arrays)} for part {part!r}, got {given_part!r:.80}.")
            for key, array in arrays.items():
                value = np.asarray(given_part[key])
                if value.shape != array.shape or value.dtype.kind not in "fiu" or not np.all(np.isfinite(value)):
                    raise StateError(
                        f"{where}: expected finite {part}.{key} of shape {array.shape}, got shape {value.shape}, dtype {value.dtype}."
                    )

    def set_state(self, state: Mapping[str, Any]) -> None:
        for name, controller in self.parts.items():
            controller.set_state(dict(state.get(name, {})))


#: Per action entry, the combined controller's ``(clip low, clip high, scale, offset)``.
EntryConstants = tuple[float, float, float, float]


def _part_targets(
    entries: slice, constants: list[EntryConstants], terms: SingleTerms, part: PDJointPosController
) -> Callable[[list[float], list[float]], list[float]] | None:
    """The targets of ``part`` for :meth:`CombinedController._fuse_single`: a call of the
    whole action and the measured ``qpos`` (Python floats) returning a new list of the
    part's targets: its entries (``entries`` of the action) clipped, scaled and shifted
    as :meth:`CombinedController._to_raw_single` does (``constants``: its entries'),
    then the operations of :meth:`PDJointPosController.single_apply
    <robot_agents.controllers.joint.PDJointPosController.single_apply>` in its order
    (``terms``). For the parts the robots have: a plain part clipped to its limits from
    its measured positions, its current targets or nothing (absolute); a plain part's one unclipped absolute entry; a mimic's unclipped absolute
    targets without offsets. ``None`` for another part (the parts' own calls stay).

    The comprehensions' ``zip`` calls take no ``strict=``: their lengths are equal by
    construction, and the keyword costs ~0.2 us a call here."""
    start, stop = entries.start, entries.stop
    multipliers, offsets, bounds = terms.multipliers, terms.offsets, terms.bounds
    addresses = terms.qpos
    first, end = addresses[0], addresses[0] + len(addresses)
    base = terms.base
    if multipliers is None and offsets is None and bounds is not None:  # a plain part clipped to its limits
        limited = [(*c, *b) for c, b in zip(constants, bounds, strict=True)]
        # what the change adds to, read per call: the measured positions (a slice where
        # the part's joints are consecutive in qpos, else gathered: Fetch's body) or the
        # part's current targets
        starts: Callable[[list[float]], list[float]] | None = None
        if base == PDJointPosController._FROM_MEASURED:
            if addresses == list(range(first, end)):
                starts = operator.itemgetter(slice(first, end))
            else:

                def starts(qpos: list[float]) -> list[float]:
                    return [qpos[a] for a in addresses]

        elif base == PDJointPosController._FROM_TARGET:

            def starts(qpos: list[float]) -> list[float]:
                row: list[float] = part.target_qpos.tolist()[0]
                return row

        if starts is not None:
            added = starts

            def added_clipped(values: list[float], qpos: list[float]) -> list[float]:
                return [
                    low
                    if (t := p + ((lo if v < lo else hi if v > hi else v) * s + o)) < low
                    else high
                    if t > high
                    else t
                    for p, v, (lo, hi, s, o, low, high) in zip(added(qpos), values[start:stop], limited)  # noqa: B905
                ]

            return added_clipped

        def absolute_clipped(values: list[float], qpos: list[float]) -> list[float]:
            return [
                low if (t := (lo if v < lo else hi if v > hi else v) * s + o) < low else high if t > high else t
                for v, (lo, hi, s, o, low, high) in zip(values[start:stop], limited)  # noqa: B905
            ]

        return absolute_clipped
    if base != PDJointPosController._ABSOLUTE or offsets is not None or bounds is not None:
        return None
    lo, hi, s, o = constants[0]  # (a gripper's one entry)
    if multipliers is None:
        if stop - start != 1:
            return None

        def absolute_entry(values: list[float], qpos: list[float]) -> list[float]:
            v = values[start]
            return [(lo if v < lo else hi if v > hi else v) * s + o]

        return absolute_entry

    def mimic_absolute(values: list[float], qpos: list[float]) -> list[float]:
        v = values[start]
        entry = (lo if v < lo else hi if v > hi else v) * s + o
        return [m * entry for m in multipliers]

    return mimic_absolute
