"""What a design's links and drives carry, as one value: the link section (and its sizing), the
material, the payload at the tool and the duty over the operating range."""

from __future__ import annotations

from dataclasses import dataclass, replace

from qsm.embodiment.strength.material import Material
from qsm.embodiment.strength.sizing import SizingSettings
from qsm.physics.cad import CadSettings
from qsm.physics.duty import Duty, DutySettings, duty_cycle
from qsm.physics.workspace import OperatingRange


@dataclass(frozen=True)
class LoadCase:
    """``cad``: the link section and solids; ``sizing``: None for the fixed section, else the
    bounds of the sections sized by strength; ``material``; ``payload_kg`` at E (kg);
    ``duty``: the motion the arm must serve (its sampling over the operating range);
    ``largest_scale``: the largest factor on ``cad``'s section that ``cad.sized`` allows (with
    either section mode: the realisation may grow a section for the tolerance)."""

    cad: CadSettings
    material: Material
    payload_kg: float
    duty: DutySettings
    sizing: SizingSettings | None = None
    largest_scale: float = 1.0

    def cycle(self) -> Duty:
        """The duty's samples (:func:`qsm.physics.duty.duty_cycle`)."""
        return duty_cycle(self.duty)

    def with_duty(self, duty: DutySettings) -> LoadCase:
        """This load case over another duty (the optimisation's coarser one, say)."""
        return replace(self, duty=duty)

    @property
    def operating_range(self) -> OperatingRange:
        """The motors' ranges the duty samples."""
        d = self.duty
        return OperatingRange((d.theta1_min_deg, d.theta1_max_deg), d.theta2_min_deg)
