"""Canonical example systems of the papers, reused by tests, paper checks, benchmarks and docs
(one module per paper, as sympy.physics.mechanics keeps its ``models``).

acary_taha       the 3-ball chain (sec. 3), the planar pool (sec. 4) and Bernoulli's problem
seghete_murphey  two balls and a wall (equal masses, 1.1 : 1), the 3-ball and n-ball cradles, balls against a wall
"""
