"""Fracture quantities from fields at points: the domain integrals and what uses them.

``integrals`` (J, interaction integrals for K_I, K_II and T, with crack-face terms),
``auxiliary_fields`` (their unit auxiliary fields), ``qfunctions`` (the weight
functions q with analytic gradients, seed 001), ``sif`` (a tip's result over several
domains, with its verdict), ``extrapolation`` (near-tip estimates from stresses and
openings) and ``volumes`` (nodal volumes of point-wise integrals). The dynamic J' and
the growth criteria belong here too.
"""
