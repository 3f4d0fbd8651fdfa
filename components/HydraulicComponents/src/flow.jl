# dyadc's own Julia for the flow laws of HydraulicComponents (names as Dyad's package has them).

# A signed power that stays smooth through zero: x |x|^(index - 1) for |x| >> delta, linear in x
# (slope delta^(index - 1)) near zero.
reg_pow(x, index, delta = 1) = x * (x^2 + delta^2)^((index - 1) / 2)

# Darcy friction factor of a duct of hydraulic diameter d_h: shape_factor / Re when laminar
# (64 for a round tube), a Petukhov-type law when turbulent, blended by a smooth step from
# Re = 2000 to 3000. Re is floored at 1 so that a resting fluid has a finite factor.
function friction_factor(m_flow, area, d_h, viscosity, shape_factor)
  Re = max(abs(m_flow) * d_h / (area * viscosity), 1)
  laminar = shape_factor / Re
  turbulent = (shape_factor / 64) / (0.79 * log(Re) - 1.64)^2
  w = (Re - 2000) / 1000
  if Re <= 2000
    return laminar
  elseif Re >= 3000
    return turbulent
  else
    return laminar + (turbulent - laminar) * w^2 * (3 - 2 * w)
  end
end
