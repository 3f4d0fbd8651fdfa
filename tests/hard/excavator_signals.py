"""Signals of the excavator that the soil and hydraulics variants are compared on."""
from __future__ import annotations

import numpy as np

CYLINDER_FORCES = ("boom_cyl.force_sensor.f", "stick_cyl.force_sensor.f", "bucket_cyl.force_sensor.f")
SOIL_FORCES = ("soil.F_x", "soil.F_y")
# Stiffness of the soil's static force laws: the Bekker moduli (vertical pressure-sinkage) and the
# Reece strength terms (cohesion, unit weight) of the cutting resistance. Damping c_v is not a
# stiffness and the payload density rho_soil is not a force law; both keep their defaults.
SOIL_FORCE_LAW = {"soil.k_c": 3e4, "soil.k_phi": 1.2e6, "soil.c_soil": 4000.0, "soil.gamma_s": 15700.0}
SHARP_CONTACT = {"soil.eps_c": 1e-6, "soil.v_t": 1e-4}
P_SUPPLY = 25e6
AREA_A, AREA_B = 3e-3, 2e-3


def stiffer_soil(factor: float) -> dict[str, float]:
    return {name: value * factor for name, value in SOIL_FORCE_LAW.items()}


def peak(result, name: str) -> float:
    return float(np.max(np.abs(result[name])))
