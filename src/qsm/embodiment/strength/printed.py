"""The printed material as it behaves in the arm: weaker across its layers, and creeping under
the loads it holds.

``material`` gives the short-term values along the layers of a plate printed flat (layers in the
mechanism plane). Two behaviours of a printed part go beyond them:

* **Across the layers.** The loads a plate takes at its holes and faces are checked against the
  in-plane allowable times :attr:`PrintedMaterial.across_layers_strength_factor` (the maker's
  ZX over XZ tensile strength), a conservative assumption: the clamp of a washer or a screw's
  head presses the layers together, and the bearing pressure of a pin's shank in its printed
  bore and of a hub's screws or inserts in their holes acts within the layers, but the pins and
  screws tilt under their loads, so the face layers carry the most and the bond between the
  layers shares the load among them; no bearing strength of printed ABS-M30 by orientation was
  found to use instead. The links' in-plane bending and tension, and a bearing seat's hoop
  stress, run along the layers and keep the in-plane allowable: each load is derated once.
* **Creep.** Under a held load the printed links' strain grows: after ``t`` hours it is the
  elastic strain times ``1 + phi(t)``, with Findley's power law ``phi(t) = phi_1000 (t / 1000 h)^n``
  (linear viscoelasticity: the creep of a sum of loads is the sum of their creeps). The arm holds
  its links' weight always and the payload for ``payload_share`` of its service time.
"""

from __future__ import annotations

from dataclasses import dataclass

from qsm.schema.defaults import default

#: Hours of the reference time of :attr:`PrintedMaterial.creep_coefficient_1000h`.
REFERENCE_HOURS = 1000.0


@dataclass(frozen=True)
class PrintedMaterial:
    """How the printed parts behave beyond the short-term in-plane values (dimensionless factors).

    build_orientation: how every plate is printed ("flat": on its face, layers in the mechanism
        plane). across_layers_strength_factor: the across-layer allowable over the in-plane one.
    service_time_h: hours the arm holds its loads before its creep is judged.
    creep_coefficient_1000h: creep strain over elastic strain after 1000 h (phi_1000).
    creep_exponent: Findley's n. payload_share: share of the service time the tool holds the
        payload (1: always).
    """

    build_orientation: str = default("printed_material.build_orientation")
    across_layers_strength_factor: float = default("printed_material.across_layers_strength_factor")
    service_time_h: float = default("printed_material.creep.service_time_h")
    creep_coefficient_1000h: float = default("printed_material.creep.coefficient_1000h")
    creep_exponent: float = default("printed_material.creep.exponent")
    payload_share: float = default("printed_material.creep.payload_share")

    def __post_init__(self) -> None:
        if not 0.0 < self.across_layers_strength_factor <= 1.0:
            raise ValueError("across_layers_strength_factor must lie in (0, 1]")
        if min(self.service_time_h, self.creep_coefficient_1000h, self.creep_exponent) < 0:
            raise ValueError("the service time and the creep law's terms must not be negative")
        if not 0.0 <= self.payload_share <= 1.0:
            raise ValueError("payload_share must lie in [0, 1]")

    @property
    def creep_coefficient(self) -> float:
        """phi at the service time: creep strain over elastic strain (1)."""
        hours = self.service_time_h / REFERENCE_HOURS
        return self.creep_coefficient_1000h * hours**self.creep_exponent if hours > 0 else 0.0

    def across_layers_MPa(self, in_plane_MPa: float) -> float:
        """The allowable (MPa) of a load taken across the layers, from the in-plane one."""
        return in_plane_MPa * self.across_layers_strength_factor

    def record(self) -> dict[str, float | str]:
        """JSON-ready: the orientation, the factors and the creep at the service time."""
        return {
            "build_orientation": self.build_orientation,
            "across_layers_strength_factor": self.across_layers_strength_factor,
            "service_time_h": self.service_time_h,
            "creep_coefficient": self.creep_coefficient,
            "creep_modulus_factor": 1.0 / (1.0 + self.creep_coefficient),
            "payload_share": self.payload_share,
        }
