//! CFDEM's `checkCouplingInterval` (CFDEM-PUBLIC's and CFDEM-PFM's
//! `forceModel/checkCouplingInterval`, listed in `forceModels`, it exerts no force): every few
//! coupling steps it compares the coupling interval with the particles' relaxation time and
//! reports, in CFDEM's terms:
//!
//! * the **particle relaxation time** τ_p = ρ_p d²/(18 μ) / scaleDrag (Stokes; d the diameter
//!   of the parcel's particles d/CG, μ = ρ ν of the cell holding the centre, ρ_p `rhoP` or, when
//!   it is not given, the particle's own density), its minimum over the particles in the mesh;
//! * the **acceleration number** Δt_c / min τ_p, Δt_c = couplingInterval · Δt_DEM: the
//!   fraction of its relaxation time a particle spends under one frozen drag force; above
//!   `maxAccNr` (CFDEM-PUBLIC's default 0.005; PFM warns above 0.1) the coupling interval is
//!   too long;
//! * the smallest ratio of cell to parcel volume V_cell,min / (π d_max³/6) (below
//!   `minAllowedVcellByVparcel`, default 3, the cells are too small for a cell-based voidage;
//!   above `largeVcellByVparcel`, default 10⁴, CFDEM recommends `centre`);
//! * the particles' Stokes numbers St = τ_p |U − v| / d, their minimum and maximum;
//! * the particle CFL number max |v| Δt_c / V_cell,min^(1/3) (above `maxPCFL`, default 1, a
//!   particle crosses more than a cell per coupling interval);
//! * the fluid's CFL number max |U| Δt_CFD / V^(1/3) over the cells (CFDEM measures it with the
//!   face fluxes, ½ Σ_f |φ_f| Δt / V; foamgrain's coupler holds the cell velocities: on a
//!   uniform hexahedral mesh with the flow along an axis the two agree) and the expected CFL
//!   `UmaxExpected` Δt_CFD / V_min^(1/3), each against `maxCFL` (default 1).
//!
//! Differences from CFDEM, on purpose: CFDEM-PUBLIC's τ_p uses a radius variable it never sets
//! (`scaledRad = -1`, so its τ_p is ρ_p·4/(18 μ), independent of the particle); foamgrain uses
//! the particle's diameter as PFM's version does. CFDEM-PUBLIC's check that the fluid velocity
//! changes little along a particle's path over one interval (|∇U| max|v| Δt_c, `maxRelVelChange`)
//! and its 2-D domain-size and moving-mesh notes are not made (the coupler holds no ∇U; foamgrain
//! has no moving meshes). CFDEM-PUBLIC reads no collision time either: the DEM's own steps
//! (Rayleigh, Hertz) are `foamgrain timestep`'s ([`crate::timestep`]).

use mesh::v3::V3;

/// `checkCouplingIntervalProps` (module docs; CFDEM-PUBLIC's defaults).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalCheckSettings {
    /// `rhoP`, kg/m³: the particle density of τ_p; `None`: each particle's own.
    pub rho_p: Option<f64>,
    /// `warnOnly` (default true): a limit exceeded is a warning; false: an error ending the run.
    pub warn_only: bool,
    /// `maxCFL` (default 1).
    pub max_cfl: f64,
    /// `maxPCFL` (default 1).
    pub max_pcfl: f64,
    /// `maxAccNr` (default 0.005).
    pub max_acc_nr: f64,
    /// `UmaxExpected`, m/s, if given.
    pub u_max_expected: Option<f64>,
    /// `minAllowedVcellByVparcel` (default 3).
    pub min_vcell_by_vparcel: f64,
    /// `largeVcellByVparcel` (default 10⁴).
    pub large_vcell_by_vparcel: f64,
    /// `timeInterval`, s: the check runs every ⌊timeInterval/Δt_c⌋ coupling steps (default
    /// 10 Δt_c), from the first.
    pub time_interval: Option<f64>,
}

impl Default for IntervalCheckSettings {
    fn default() -> Self {
        IntervalCheckSettings {
            rho_p: None,
            warn_only: true,
            max_cfl: 1.0,
            max_pcfl: 1.0,
            max_acc_nr: 0.005,
            u_max_expected: None,
            min_vcell_by_vparcel: 3.0,
            large_vcell_by_vparcel: 1e4,
            time_interval: None,
        }
    }
}

impl IntervalCheckSettings {
    /// Coupling steps between two checks for the coupling interval `dt_c` (s): ⌊timeInterval /
    /// Δt_c⌋, at least 1 (CFDEM's default timeInterval is 10 Δt_c).
    pub fn every(&self, dt_c: f64) -> u64 {
        let t = self.time_interval.unwrap_or(10.0 * dt_c);
        ((t / dt_c) * (1.0 + 1e-12)).floor().max(1.0) as u64
    }
}

/// What the check is computed from (SI units); the particle slices are one entry per particle,
/// `cell` the cell holding its centre (`None` outside the mesh: not counted).
#[derive(Clone, Copy, Debug)]
pub struct IntervalCheckInput<'a> {
    /// Particle radii, m.
    pub radius: &'a [f64],
    /// Particle densities, kg/m³.
    pub density: &'a [f64],
    /// Particle velocities, m/s.
    pub velocity: &'a [V3],
    /// The cell of each particle's centre.
    pub cell: &'a [Option<u32>],
    /// The fluid velocity at each particle as its drag saw it (CFDEM: U of the centre's cell),
    /// m/s.
    pub u_particle: &'a [V3],
    /// Fluid velocity per cell, m/s, for the fluid's CFL number (empty on a rank that does
    /// not hold the fluid).
    pub u: &'a [V3],
    /// Cell volumes, m³ (the cells of `cell`).
    pub volumes: &'a [f64],
    /// The volumes of the cells `u` is given on, m³: `volumes`, unless the coupler holds a
    /// part of the mesh while `u` is the whole fluid's (coupler rank 0 with grainPisoFoam on
    /// several ranks, [`crate::part`]).
    pub fluid_volumes: &'a [f64],
    /// max |U|/∛V over the fluid's cells (1/s) where the fluid computed it because `u` is not
    /// the current fluid (coupler rank 0 in grainPisoFoam's sparse exchange, which sends it no
    /// cell field): the CFL is then this × `dt_cfd`, and `u` is not read. `None`: from `u`.
    pub u_by_size: Option<f64>,
    /// Fluid density, kg/m³.
    pub rho: f64,
    /// Kinematic viscosity, m²/s.
    pub nu: f64,
    /// Coarse-graining factor CG (the particles' diameter is d/CG), 1 without.
    pub cg: f64,
    /// `scaleDrag`, 1 without.
    pub scale_drag: f64,
    /// The coupling interval Δt_c, s.
    pub dt_coupling: f64,
    /// The fluid's time step, s.
    pub dt_cfd: f64,
}

/// The quantities of one check (module docs). Minima over no particle are +∞, maxima −∞ /
/// `None` where the quantity is undefined; on several ranks combine them with
/// [`IntervalCheck::extremes`] / [`IntervalCheck::from_extremes`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalCheck {
    /// min τ_p, s.
    pub min_tau_p: f64,
    /// min, max Stokes number.
    pub min_st: f64,
    /// Largest Stokes number.
    pub max_st: f64,
    /// Largest parcel diameter, m.
    pub max_d_parcel: f64,
    /// Smallest volume of a cell holding a particle, m³.
    pub min_vcell: f64,
    /// Largest particle speed, m/s.
    pub max_speed: f64,
    /// Largest |U| Δt_CFD / V^(1/3) over the cells.
    pub cfl: f64,
    /// Smallest cell volume of the mesh, m³.
    pub min_vcell_mesh: f64,
    /// The coupling interval, s.
    pub dt_coupling: f64,
    /// The fluid's step, s.
    pub dt_cfd: f64,
}

impl IntervalCheck {
    /// The check of `input` with the particle density `rho_p` (`None`: each particle's own).
    pub fn compute(input: &IntervalCheckInput<'_>, rho_p: Option<f64>) -> IntervalCheck {
        let mu = input.rho * input.nu;
        let mut c = IntervalCheck {
            min_tau_p: f64::INFINITY,
            min_st: f64::INFINITY,
            max_st: f64::NEG_INFINITY,
            max_d_parcel: f64::NEG_INFINITY,
            min_vcell: f64::INFINITY,
            max_speed: f64::NEG_INFINITY,
            cfl: f64::NEG_INFINITY,
            min_vcell_mesh: f64::INFINITY,
            dt_coupling: input.dt_coupling,
            dt_cfd: input.dt_cfd,
        };
        for (i, cell) in input.cell.iter().enumerate() {
            let Some(cell) = cell else { continue };
            let (cell, d) = (*cell as usize, 2.0 * input.radius[i]);
            let d_real = d / input.cg;
            let rho_p = rho_p.unwrap_or(input.density[i]);
            let tau =
                closures::timestep::stokes_relaxation_time(rho_p, d_real, mu) / input.scale_drag;
            c.min_tau_p = c.min_tau_p.min(tau);
            c.max_d_parcel = c.max_d_parcel.max(d);
            c.min_vcell = c.min_vcell.min(input.volumes[cell]);
            // CFDEM divides by the parcel's diameter 2r
            let st = tau * (input.u_particle[i] - input.velocity[i]).norm() / d;
            c.min_st = c.min_st.min(st);
            c.max_st = c.max_st.max(st);
            c.max_speed = c.max_speed.max(input.velocity[i].norm());
        }
        for (u, v) in input.u.iter().zip(input.fluid_volumes) {
            if input.u_by_size.is_none() {
                c.cfl = c.cfl.max(u.norm() * input.dt_cfd / v.cbrt());
            }
            c.min_vcell_mesh = c.min_vcell_mesh.min(*v);
        }
        if let Some(x) = input.u_by_size {
            c.cfl = x * input.dt_cfd;
        }
        c
    }

    /// Δt_c / min τ_p (0 without particles).
    pub fn acc_nr(&self) -> f64 {
        match self.min_tau_p.is_finite() {
            true => self.dt_coupling / self.min_tau_p,
            false => 0.0,
        }
    }

    /// V_cell,min / (π d_max³ / 6), `None` without particles.
    pub fn vcell_by_vparcel(&self) -> Option<f64> {
        let d = self.max_d_parcel;
        (d > 0.0).then(|| self.min_vcell / (std::f64::consts::PI * d * d * d / 6.0))
    }

    /// max |v| Δt_c / V_cell,min^(1/3) (0 without particles).
    pub fn particle_cfl(&self) -> f64 {
        match self.max_speed.is_finite() && self.min_vcell.is_finite() {
            true => self.max_speed * self.dt_coupling / self.min_vcell.cbrt(),
            false => 0.0,
        }
    }

    /// The values to reduce over ranks by a maximum (minima negated), in a fixed order.
    pub fn extremes(&self) -> [f64; 8] {
        [
            -self.min_tau_p,
            -self.min_st,
            self.max_st,
            self.max_d_parcel,
            -self.min_vcell,
            self.max_speed,
            self.cfl,
            -self.min_vcell_mesh,
        ]
    }

    /// The check from [`IntervalCheck::extremes`] reduced by a maximum.
    pub fn from_extremes(&self, x: [f64; 8]) -> IntervalCheck {
        IntervalCheck {
            min_tau_p: -x[0],
            min_st: -x[1],
            max_st: x[2],
            max_d_parcel: x[3],
            min_vcell: -x[4],
            max_speed: x[5],
            cfl: x[6],
            min_vcell_mesh: -x[7],
            ..*self
        }
    }

    /// The report's lines and, separately, the limits exceeded (one sentence each, CFDEM's
    /// wording), for the settings `s`.
    pub fn report(&self, s: &IntervalCheckSettings) -> (Vec<String>, Vec<String>) {
        let mut info = vec!["checkCouplingInterval:".to_owned()];
        let mut over = Vec::new();
        info.push(format!("max. CFL = {}", self.cfl));
        if self.cfl > s.max_cfl {
            over.push(format!(
                "CFL exceeds maximum allowed value: {}, and reached the value: {}",
                s.max_cfl, self.cfl
            ));
        }
        if let Some(u) = s.u_max_expected {
            let expected = u * self.dt_cfd / self.min_vcell_mesh.cbrt();
            info.push(format!(
                "max. expected CFL (based on UmaxExpected) = {expected}"
            ));
            if expected > s.max_cfl {
                over.push(format!(
                    "Expected CFL (based on UmaxExpected) exceeds maximum allowed value: {}, \
                     and reached the value: {expected}",
                    s.max_cfl
                ));
            }
        }
        let acc = self.acc_nr();
        info.push(format!(
            "min. occurring particle relaxation time [s]: {}",
            self.min_tau_p
        ));
        info.push(format!("coupling interval [s]: {}", self.dt_coupling));
        info.push(format!(
            "max. occurring acceleration nr (coupling time [s] / min. particle relaxation time \
             [s]): {acc}"
        ));
        if acc > s.max_acc_nr {
            over.push(format!(
                "The max. acceleration nr (coupling time / particle relaxation time) exceeds the \
                 maximum allowed value {}, and reached the value: {acc}; use a shorter coupling \
                 interval",
                s.max_acc_nr
            ));
        }
        if let Some(r) = self.vcell_by_vparcel() {
            info.push(format!("min. ratio of Vcell / Vparcel is {r}"));
            if r < s.min_vcell_by_vparcel {
                over.push(format!(
                    "The min. ratio of Vcell / Vparcel is below the minimum allowed value {}, \
                     and reached the value: {r}",
                    s.min_vcell_by_vparcel
                ));
            } else if r > s.large_vcell_by_vparcel {
                info.push(format!(
                    "The ratio of Vcell / Vparcel is above {}: for efficiency the voidfraction \
                     model centre is recommended",
                    s.large_vcell_by_vparcel
                ));
            }
            info.push(format!(
                "min./max. Stokes Nr: {} / {}",
                self.min_st, self.max_st
            ));
        }
        let pcfl = self.particle_cfl();
        info.push(format!("max. particle coupling CFL Nr: {pcfl}"));
        if pcfl > s.max_pcfl {
            over.push(format!(
                "The max. particle coupling CFL number is above the maximum allowed value {}, \
                 and reached the value: {pcfl}",
                s.max_pcfl
            ));
        }
        (info, over)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two cells (1e-6 and 8e-6 m³, U = (1, 0, 0) and (0, 2, 0) m/s) and three glass beads.
    struct Beads {
        volumes: [f64; 2],
        u: [V3; 2],
        u_particle: [V3; 3],
        velocity: [V3; 3],
    }

    impl Beads {
        fn new() -> Beads {
            let u = [V3::new(1.0, 0.0, 0.0), V3::new(0.0, 2.0, 0.0)];
            Beads {
                volumes: [1e-6, 8e-6],
                u,
                u_particle: [u[0], u[1], u[1]],
                velocity: [
                    V3::new(0.0, 0.0, 0.5),
                    V3::new(0.0, 0.0, 0.0),
                    V3::new(9.0, 0.0, 0.0),
                ],
            }
        }

        /// The beads in the cells `cell`, air, Δt_c = 1e-4 s, Δt_CFD = 1e-3 s.
        fn input<'a>(&'a self, cell: &'a [Option<u32>]) -> IntervalCheckInput<'a> {
            IntervalCheckInput {
                radius: &[0.5e-3, 1e-3, 1e-3],
                density: &[2500.0, 2500.0, 2500.0],
                velocity: &self.velocity,
                cell,
                u_particle: &self.u_particle,
                u: &self.u,
                volumes: &self.volumes,
                fluid_volumes: &self.volumes,
                u_by_size: None,
                rho: 1.2,
                nu: 1.5e-5,
                cg: 1.0,
                scale_drag: 1.0,
                dt_coupling: 1e-4,
                dt_cfd: 1e-3,
            }
        }
    }

    /// Two glass beads in air, worked by hand: d = 1 mm, ρ_p = 2500 kg/m³, ρ = 1.2 kg/m³,
    /// ν = 1.5e-5 m²/s ⇒ μ = 1.8e-5 Pa·s, τ_p = 2500·1e-6/(18·1.8e-5) = 7.716049382716049 s;
    /// the second bead (d = 2 mm) has 4τ. Δt_c = 1e-4 s ⇒ Δt_c/τ = 1.296e-5.
    #[test]
    fn hand_computed_values() {
        let beads = Beads::new();
        let input = beads.input(&[Some(0), Some(1), None]);
        let c = IntervalCheck::compute(&input, None);
        let tau = 7.716049382716049;
        assert!((c.min_tau_p - tau).abs() < 1e-14 * tau);
        assert!((c.acc_nr() - 1.296e-5).abs() < 1e-18);
        // St = τ |U − v| / d: bead 1 |(1, 0, −0.5)| = √1.25 over 1 mm; bead 2 4τ·2 / 2 mm
        let st1 = tau * 1.25f64.sqrt() / 1e-3;
        let st2 = 4.0 * tau * 2.0 / 2e-3;
        assert!((c.min_st - st1).abs() < 1e-12 * st1, "{} {st1}", c.min_st);
        assert!((c.max_st - st2).abs() < 1e-12 * st2);
        // Vcell,min / Vparcel,max = 1e-6 / (π 8e-9 / 6) = 238.73241463784300
        let r = c.vcell_by_vparcel().unwrap();
        assert!((r - 238.732414637843).abs() < 1e-9, "{r}");
        // particle CFL: max |v| in the mesh 0.5 m/s · 1e-4 s / 1e-2 m = 5e-3 (the bead at
        // 9 m/s is outside)
        assert!((c.particle_cfl() - 5e-3).abs() < 1e-15);
        // fluid CFL: max(1·1e-3/1e-2, 2·1e-3/2e-2) = 0.1
        assert!((c.cfl - 0.1).abs() < 1e-14);
        // given max |U|/∛V (the solver's, when u is not current): 250 1/s · 1e-3 s, u unread
        let given = IntervalCheck::compute(
            &IntervalCheckInput {
                u_by_size: Some(250.0),
                ..input
            },
            None,
        );
        assert_eq!(given.cfl, 0.25);
        assert_eq!(given.min_vcell_mesh, c.min_vcell_mesh);
        let (_, over) = c.report(&IntervalCheckSettings::default());
        assert!(over.is_empty(), "{over:?}");
        // rhoP given: τ scales with it; CG = 2: the real diameter halves, τ/4; scaleDrag 2: τ/2
        let c = IntervalCheck::compute(
            &IntervalCheckInput {
                cg: 2.0,
                scale_drag: 2.0,
                ..input
            },
            Some(5000.0),
        );
        assert!((c.min_tau_p - tau * 2.0 / 4.0 / 2.0).abs() < 1e-14 * tau);
        // the limits: Δt_c = 0.1 s is 1.296e-2 of τ, above 0.005
        let long = IntervalCheck::compute(
            &IntervalCheckInput {
                dt_coupling: 0.1,
                ..input
            },
            None,
        );
        let (_, over) = long.report(&IntervalCheckSettings::default());
        assert_eq!(over.len(), 2, "{over:?}"); // acceleration nr and particle CFL 5
        assert!(over[0].contains("acceleration nr") && over[0].contains("0.01296"));
    }

    #[test]
    fn ranks_reduce_to_the_whole() {
        let beads = Beads::new();
        let whole = IntervalCheck::compute(&beads.input(&[Some(0), Some(1), None]), None);
        let a = IntervalCheck::compute(&beads.input(&[Some(0), None, None]), None);
        let b = IntervalCheck::compute(&beads.input(&[None, Some(1), None]), None);
        let (xa, xb) = (a.extremes(), b.extremes());
        let x: Vec<f64> = xa.iter().zip(xb).map(|(p, q)| p.max(q)).collect();
        assert_eq!(a.from_extremes(x.try_into().unwrap()), whole);
    }

    #[test]
    fn every_counts_coupling_steps() {
        let s = IntervalCheckSettings::default();
        assert_eq!(s.every(1e-4), 10);
        let s = IntervalCheckSettings {
            time_interval: Some(3e-3),
            ..s
        };
        assert_eq!(s.every(1e-3), 3);
        assert_eq!(s.every(1e-2), 1);
    }
}
