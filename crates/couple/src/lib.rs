//! The coupler between a particle side (DEM) and a fluid side (CFD).
//!
//! Owns: the typed coupling configuration read from CFDEM-style `constant/couplingProperties`,
//! interpolation of fluid fields to particles, the per-particle forces (via `closures`) and the
//! momentum exchange fields (Ksl, Us, f) distributed with the voidage kernel's cell shares, the
//! `ParticleSide` / `FluidSide` traits, the coupling step and schedule, and the one-way `dump
//! replay` particle side.
