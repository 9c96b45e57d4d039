"""Road-friction presets for the plant's ``road_friction`` input (dimensionless).

``road_friction`` scales the tyre's Magic Formula peak factor D (Pacejka's
friction scaling factor lambda_mu, Pacejka 2012 section 4.3.2). The presets sit
in the ranges of peak road-tyre friction in Wong, *Theory of Ground Vehicles*,
4th ed., Table 1.3 (dry asphalt 0.8-0.9, wet asphalt 0.5-0.7, snow packed 0.2)
relative to the dry value, and match the D factors of the commonly quoted
Magic Formula sets (dry 1.0, snow 0.3) from Pacejka's typical coefficients.
"""

ROAD_FRICTION_PRESETS: dict[str, float] = {"dry": 1.0, "wet": 0.6, "snow": 0.3}
