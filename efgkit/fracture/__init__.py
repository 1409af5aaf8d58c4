"""Fracture quantities from fields at points: the domain integrals and what uses them.

``integrals`` (J, interaction integrals for K_I, K_II and T, with crack-face terms),
``auxiliary_fields`` (their unit auxiliary fields), ``qfunctions`` (the weight
functions q with analytic gradients, seed 001), ``sif`` (a tip's result over several
domains, with its verdict), ``extrapolation`` (near-tip estimates from stresses and
openings, for a moving tip too) and ``volumes`` (nodal volumes of point-wise integrals);
``dynamic`` (the dynamic J' of Nishioka and Atluri and the interaction integral with
inertia), ``velocity`` (the crack-speed functions and K from J') and ``dynamic_tip``
(a tip's dynamic SIFs at one instant over several domains). The growth criteria belong
here too.
"""
