# dyadc's own Julia for the media of HydraulicComponents, read (never run) by compiler/julia/.
# Field names and defaults follow Dyad's published HydraulicComponents so that a medium written
# for it (`IsothermalCompressible(bulk_modulus = 1e9, let_gas = false)`) means the same here.

abstract type AbstractMedium end

# A liquid whose density grows linearly with gauge pressure at a constant temperature.
@kwdef struct IsothermalCompressible <: AbstractMedium
  density = 997                  # kg/m3 at the reference pressure
  pressure = 100325              # reference pressure, Pa
  bulk_modulus = 2e9             # Pa, above the reference pressure
  bulk_modulus_gas = 1.01325e5   # Pa, below it when `let_gas` (a soft, gassy liquid)
  density_exponent = 1           # kept for compatibility: the law here is linear
  viscosity = 0.0010016          # dynamic viscosity, Pa.s
  let_gas = true                 # below the reference pressure use `bulk_modulus_gas`
  gas_density = 0.0073955        # kept for compatibility
  gas_pressure = -1000           # kept for compatibility
end

# rho(p) = rho_ref (1 + (p - p_ref) / beta)
function density(medium::IsothermalCompressible, p)
  @unpack density, pressure, bulk_modulus, bulk_modulus_gas, let_gas = medium
  beta = ifelse(let_gas & (p <= pressure), bulk_modulus_gas, bulk_modulus)
  return density + density * (p - pressure) / beta
end

# The inverse of `density`: p(rho) = p_ref + beta (rho / rho_ref - 1)
function pressure(medium::IsothermalCompressible, rho)
  @unpack density, pressure, bulk_modulus, bulk_modulus_gas, let_gas = medium
  beta = ifelse(let_gas & (rho <= density), bulk_modulus_gas, bulk_modulus)
  return pressure + beta * (rho - density) / density
end

function viscosity(medium::IsothermalCompressible)
  @unpack viscosity = medium
  return viscosity
end
