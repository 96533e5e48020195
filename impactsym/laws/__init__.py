"""Impact laws. One law per module; each validates its input (``impactsym.mechanics``) and
answers exactly for exact input, in floats for float input, and at a chosen mpmath precision
on request.

reflection     the single-impact map G_u and the restitution map G_u(e) (Seghete & Murphey sec. II-A)
sequential     every impact ordering of a corner impact, any k surfaces, and the selection (Seghete & Murphey sec. III)
two_surface    two-surface impacts in O(1): exact counts ceil(psi/beta), exit velocities (sec. III-B, III-C)
impulse_ratio  the impulse-ratio law for any M, H (Acary & Taha eq. 38)
classical      Newton/Moreau, Poisson, global energetic, Han-Gilmore sequential (Acary & Taha secs. 2.2, 3.2)
coupling       which contacts take part and which ratios vanish (Acary & Taha sec. 5, eqs. 41-45)
delassus       W = H M^-1 H^T and the exact arithmetic the multi-contact laws share
"""
