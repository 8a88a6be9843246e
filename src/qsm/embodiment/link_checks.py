"""Whether every link of a design holds its loads over the duty, for one design or thousands.

:class:`StrengthCheck` bundles what the check needs (section, material, requirements, payload and
duty) and evaluates designs in chunks, every step vectorised over the chunk: link mass properties
(:func:`qsm.physics.cad.batch_mass_properties`), the loop state, the joint loads
(:mod:`qsm.embodiment.loads`) and the link stresses (:mod:`qsm.embodiment.strength`). It gives
Stage 2's strength columns (:data:`STRENGTH_COLUMNS`) and the optimisation's g13.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from qsm.embodiment.loads import Inertials, joint_loads, link_motion
from qsm.embodiment.material import DEFAULT_MATERIAL, DEFAULT_STRENGTH, Material, StrengthSettings
from qsm.embodiment.strength import Section, link_strength
from qsm.mechanisms.dataset import JOINT_COLUMNS, STRENGTH_COLUMNS
from qsm.physics.cad import DEFAULT_CAD, CadSettings, batch_mass_properties
from qsm.physics.duty import Duty, duty_cycle
from qsm.physics.dynamics import MIN_SIN_TRANSMISSION, loop_state
from qsm.physics.kinematics import LINK_NAMES, as_design

#: Violation g13 gives a design whose loop does not close or is singular over the duty.
UNDEFINED_VIOLATION = 10.0
#: Designs evaluated together (memory: about 0.4 MB per design on the default duty).
CHUNK = 128


@dataclass(frozen=True)
class StrengthCheck:
    """What the link check needs: the CAD section, the material, the requirements, the payload
    (kg) at E and the duty."""

    cad: CadSettings = DEFAULT_CAD
    material: Material = DEFAULT_MATERIAL
    strength: StrengthSettings = DEFAULT_STRENGTH
    payload_kg: float = 5.0
    duty: Duty = field(default_factory=duty_cycle)

    @property
    def allowable_stress_pa(self) -> float:
        """Largest allowed stress (Pa)."""
        return self.strength.allowable_stress_pa(self.material)

    def _chunk(self, d: NDArray[np.float64]) -> dict[str, NDArray]:
        sec = Section.of(self.cad, self.strength)
        inertials = Inertials(*batch_mass_properties(d, self.cad))
        du = self.duty
        state = loop_state(d, du.theta, du.dtheta, du.ddtheta)
        motion = link_motion(d, state)
        loads = joint_loads(d, inertials, self.payload_kg, state, motion)
        per_link = link_strength(d, sec, self.material, self.strength, inertials, loads, motion)
        bad = ~state.closes.all(-1) | (
            np.nan_to_num(state.sin_transmission).min(-1) < MIN_SIN_TRANSMISSION
        )
        yield_pa = self.material.yield_strength_pa
        out: dict[str, NDArray] = {}
        util = []
        for link, res in per_link.items():
            with np.errstate(divide="ignore"):
                out[f"buckling_factor_{link}"] = res.euler_N / res.compression_N
            out[f"stress_peak_{link}_MPa"] = res.stress_pa / 1e6
            out[f"safety_factor_{link}"] = yield_pa / res.stress_pa
            stress_u = res.stress_pa * self.strength.safety_factor / yield_pa
            buckle_u = res.compression_N * self.strength.buckling_safety_factor / res.euler_N
            util.append(np.maximum(stress_u, buckle_u))
            labels = np.array([*res.labels, "buckling"], dtype=object)
            out[f"_check_{link}"] = np.where(buckle_u > stress_u, labels[-1], labels[res.where])
        utils = np.stack(util, -1)
        out["strength_utilisation"] = utils.max(-1)
        weakest = utils.argmax(-1)
        out["weakest_link"] = np.asarray(LINK_NAMES, dtype=object)[weakest]
        checks = np.stack([out.pop(f"_check_{k}") for k in LINK_NAMES], -1)
        out["weakest_check"] = np.take_along_axis(checks, weakest[:, None], -1)[:, 0]
        forces = loads._asdict()
        for suffix, name in JOINT_COLUMNS.items():
            out[f"joint_force_peak_{suffix}_N"] = np.hypot(*np.moveaxis(forces[name], -1, 0)).max(
                -1
            )
        for col in out.values():
            if col.dtype.kind == "f":
                col[bad] = np.nan
        out["holds_loads"] = out["strength_utilisation"] <= 1.0
        return out

    def evaluate(self, designs: ArrayLike) -> pd.DataFrame:
        """:data:`STRENGTH_COLUMNS` of designs (N, 6) m; NaN (and not holding) where the loop
        does not close or is singular on the duty."""
        d = np.atleast_2d(as_design(designs))
        parts = [self._chunk(d[k : k + CHUNK]) for k in range(0, len(d), CHUNK)]
        if not parts:
            return pd.DataFrame(columns=list(STRENGTH_COLUMNS))
        table = {k: np.concatenate([p[k] for p in parts]) for k in STRENGTH_COLUMNS}
        return pd.DataFrame(table)

    def violation(self, designs: ArrayLike) -> NDArray[np.float64]:
        """g13: strength utilisation - 1 of designs (N, 6) m (<= 0 holds), or
        :data:`UNDEFINED_VIOLATION` where it is undefined."""
        d = np.atleast_2d(as_design(designs))
        util = (
            np.concatenate(
                [
                    self._chunk(d[k : k + CHUNK])["strength_utilisation"]
                    for k in range(0, len(d), CHUNK)
                ]
            )
            if len(d)
            else np.zeros(0)
        )
        return np.where(np.isfinite(util), util - 1.0, UNDEFINED_VIOLATION)


def with_strength(table: pd.DataFrame, designs: ArrayLike, check: StrengthCheck) -> pd.DataFrame:
    """``table`` (dynamics results, one row per design of ``designs`` (N, 6) m) with
    :data:`STRENGTH_COLUMNS` appended for its rows whose ``status`` is 'ok' (NaN elsewhere)."""
    ok = table["status"].eq("ok").to_numpy()
    out = pd.DataFrame(index=table.index, columns=list(STRENGTH_COLUMNS), dtype=float)
    strength = check.evaluate(np.asarray(designs, dtype=float)[ok])
    for key in STRENGTH_COLUMNS:
        values: Any = strength[key].to_numpy()
        if values.dtype.kind in "OUb":
            out[key] = out[key].astype(object)
        out.loc[ok, key] = values
    out["holds_loads"] = out["holds_loads"].eq(True)
    return pd.concat([table, out], axis=1)
