"""The link material and the strength requirements every printed part is checked against.

Default material: Stratasys ABS-M30, FDM. Stratasys publishes a tensile strength of 36 MPa
(ASTM D638, XZ build orientation) and a modulus of 2.4 GPa ("ABS-M30 Production-Grade
Thermoplastic for FDM 3D Printers", Stratasys spec sheet); an independent ISO 527 test found about
10 % less, and printed parts are weaker across layers than along them (vendors' guides: 30-70 %).
The defaults, 31 MPa and 2.2 GPa, assume the plates are printed flat (layers in the mechanism
plane, the XY / XZ orientations), which loads the layers along their length.
"""

from __future__ import annotations

from dataclasses import dataclass

from qsm.schema.defaults import default


@dataclass(frozen=True)
class Material:
    """An isotropic printed material (SI units).

    name: label for outputs. density_kg_m3: default 1040 (ABS-M30).
    youngs_modulus_pa: default 2.2e9. poisson_ratio: default 0.35.
    yield_strength_pa: strength the safety factors refer to, default 31e6.
    """

    name: str = default("material.name")
    density_kg_m3: float = default("material.density_kg_m3")
    youngs_modulus_pa: float = default("material.youngs_modulus_pa")
    poisson_ratio: float = default("material.poisson_ratio")
    yield_strength_pa: float = default("material.yield_strength_pa")

    def __post_init__(self) -> None:
        if min(self.density_kg_m3, self.youngs_modulus_pa, self.yield_strength_pa) <= 0:
            raise ValueError("density, Young's modulus and yield strength must be positive")
        if not 0.0 < self.poisson_ratio < 0.5:
            raise ValueError("poisson_ratio must lie in (0, 0.5)")


@dataclass(frozen=True)
class StrengthSettings:
    """What a link must hold (dimensionless factors, SI units).

    safety_factor: peak stress at most yield_strength / safety_factor, default 2.
    buckling_safety_factor: Euler load at least this multiple of the peak compression, default 3
        (printed columns are less straight and less uniform than the Euler model assumes).
    lug_stress_concentration: peak over nominal net-section stress of a pin-loaded bore, default
        3.0 (Peterson's Stress Concentration Factors, pin-loaded lugs: about 2.5-3 for close-fitting
        pins at bore / boss diameter 0.3-0.5; the upper end, as printed bores fit loosely).
    corner_stress_concentration: peak over beam stress at the upper arm's inside corner (its
        "bar at the corner" and "bar below the corner" cuts) with the CAD fillet of
        ``cad.corner_fillet_ratio`` 0.25; default 3.0, from plane-stress FE of the filleted
        plates (docs/strength.md).
    bearing_safety_factor: static safety factor s0 = C0 / P0 of the joint bearings, default 2
        (SKF's guideline for quiet running; :mod:`qsm.embodiment.parts.bearings`).
    boss_wall_m: printed wall between a bearing seat and the boss's edge, default 4 mm.
    pin_yield_strength_pa: yield strength of the steel pins and motor shafts in the bores, default
        235 MPa (S235, EN 10025-2); sizes the bores with the bearing safety factor.
    """

    safety_factor: float = default("strength.safety_factor")
    buckling_safety_factor: float = default("strength.buckling_safety_factor")
    lug_stress_concentration: float = default("strength.lug_stress_concentration")
    corner_stress_concentration: float = default("strength.corner_stress_concentration")
    bearing_safety_factor: float = default("strength.bearing_safety_factor")
    boss_wall_m: float = default("strength.boss_wall_m")
    pin_yield_strength_pa: float = default("strength.pin_yield_strength_pa")

    def __post_init__(self) -> None:
        factors = (
            self.safety_factor,
            self.buckling_safety_factor,
            self.lug_stress_concentration,
            self.corner_stress_concentration,
        )
        if min(factors) < 1:
            raise ValueError("safety factors and the stress concentrations must be at least 1")
        if not (self.bearing_safety_factor > 0 and self.boss_wall_m > 0):
            raise ValueError("bearing_safety_factor and boss_wall_m must be positive")

    def allowable_stress_pa(self, material: Material) -> float:
        """Largest allowed stress (Pa) in ``material``."""
        return material.yield_strength_pa / self.safety_factor


DEFAULT_MATERIAL = Material()
DEFAULT_STRENGTH = StrengthSettings()
