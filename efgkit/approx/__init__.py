"""The approximation: MLS shape functions and everything that shapes them.

``weights`` and ``bases`` (the MLS ingredients), ``mls`` and ``kernels`` (the shape
functions and derivatives, numpy and compiled), ``crack_rules`` and ``hole_rules``
(how supports see cracks and holes), ``tip_functions`` and ``enrichment`` (crack-tip
enrichment), ``shape`` (values and derivatives at points as sparse operators) and
``approximation`` (all of it for one discretisation, at any points).
"""
