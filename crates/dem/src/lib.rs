//! Native discrete element method for spheres, parameterised like LIGGGHTS.
//!
//! Owns: particle state, velocity-Verlet integration, Hertz–Mindlin contacts with tangential
//! history (LIGGGHTS's parameterisation from E, ν, e, μ per type pair), cohesion and rolling
//! friction, plane and cylinder walls, linked-cell neighbour search, insertion, per-particle
//! coupling forces, and the subset of a LIGGGHTS input deck that drives it.
