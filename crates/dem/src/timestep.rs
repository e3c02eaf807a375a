//! DEM time-step criteria (seed 002, Madden 2020, eqs. 10–11; `fix check/timestep/gran`).
//!
//! - Rayleigh time t_R = πR√(ρ/G)/(0.1631ν + 0.8766), G = E/(2(1+ν)) the shear modulus: the
//!   time a Rayleigh surface wave needs to cross a particle (Li, Xu & Thornton 2005). Seed 002
//!   prints eq. 10 with `g`: it is this shear modulus, not gravity.
//! - Hertz time t_H = 2.87 (m*²/(R* Y*² v))^{1/5}, the duration of an elastic Hertz impact at
//!   normal speed v (Johnson, *Contact Mechanics*, 1985, eq. 11.24: t = 2.87 (m*²/(R*E*²v))^{1/5});
//!   seed 002 prints the exponent as 2, a typesetting slip (the dimension is only right for 1/5).
//!
//! Units: m, kg/m³, Pa, m/s → s.

/// Rayleigh time (s) of a sphere of radius `r` (m), density `rho` (kg/m³), Young's modulus
/// `e` (Pa), Poisson ratio `nu`.
pub fn rayleigh_time(r: f64, rho: f64, e: f64, nu: f64) -> f64 {
    let g = e / (2.0 * (1.0 + nu));
    std::f64::consts::PI * r * (rho / g).sqrt() / (0.1631 * nu + 0.8766)
}

/// Hertz contact time (s) for effective mass `meff` (kg), effective radius `reff` (m),
/// effective modulus `y_eff` (Pa) and impact speed `v` (m/s).
pub fn hertz_time(meff: f64, reff: f64, y_eff: f64, v: f64) -> f64 {
    2.87 * (meff * meff / (reff * y_eff * y_eff * v)).powf(0.2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rayleigh_of_the_ergun_particles() {
        // R = 0.5 mm, ρ = 2000, E = 5e6, ν = 0.45: G = 1.7241e6 Pa, √(ρ/G) = 0.034059 s/m,
        // denominator 0.950 → t_R = π·5e-4·0.034059/0.950 = 5.631e-5 s.
        let t = rayleigh_time(5e-4, 2000.0, 5e6, 0.45);
        assert!((t - 5.631e-5).abs() < 1e-8, "{t}");
    }
}
