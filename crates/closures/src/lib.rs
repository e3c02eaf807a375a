//! Fluid–particle closures: pure functions of local fluid and particle state.
//!
//! Owns: drag laws (force per particle as β·(u_f − v_p), β in kg/s), the other fluid–particle
//! forces (pressure gradient, viscous stress divergence, buoyancy, virtual mass, lift) and the
//! model A / B / Bfull formulations (Zhou et al. 2010), and the DEM time-step criteria (Rayleigh,
//! Hertz) and particle relaxation time. No mesh, no I/O: callers pass numbers in SI units.
