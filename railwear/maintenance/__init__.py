"""Maintenance planning: re-profiling (wheel turning) as an action and policies over a wheel's
life, on the Fourier technique (layer 4; docs/maintenance.md).

- :mod:`~railwear.maintenance.turning`: the wheel's state, the cut rule, the residual after a
  turning, the triggers and a life under a policy (SI);
- :mod:`~railwear.maintenance.policy`: the policy file (TOML, validated) and the built-in ones;
- :mod:`~railwear.maintenance.plan`: ``railwear plan``, one wheel or a Monte Carlo over the service
  scatter at a band of growth multipliers, and its tables, text and figure.
"""
