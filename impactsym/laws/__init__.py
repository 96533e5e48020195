"""Impact laws. One law per module; each validates its input (``impactsym.mechanics``) and
answers exactly for exact input, in floats for float input, and at a chosen mpmath precision
on request.

reflection   the single-impact map G_u and the restitution map G_u(e) (Seghete & Murphey sec. II-A)
two_surface  two-surface impacts in O(1): exact counts ceil(psi/beta), exit velocities (sec. III-B, III-C)
"""
