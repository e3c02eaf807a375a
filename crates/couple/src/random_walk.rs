//! CFDEM-PFM's `KochHillRWDrag`: Koch–Hill drag on a fluid velocity that carries a turbulent
//! fluctuation from a random walk (the eddy-interaction model) in the fluid's k–ε fields.
//!
//! Each particle keeps a fluctuation u′ and the time until which it holds. At a coupling
//! exchange at time t, a particle inside the mesh whose time has come draws a new one, from k
//! and ε of the cell holding its centre (PFM's `KochHillRWDrag::setForce`):
//!
//! * u′_i = ξ_i √(2k/3), ξ_i independent standard normal numbers (isotropic turbulence);
//! * the eddy lifetime τ_e = 2 C_L k/ε (`cl`, C_L; the Lagrangian integral time T_L = C_L k/ε
//!   is half of it), or with `randomTauE` τ_e = −C_L (k/ε) ln r, r uniform in (0, 1) (mean
//!   C_L k/ε);
//! * the eddy size L_e = C_μ^0.63 k^1.5/ε with C_μ = 0.09 (PFM's exponent; Gosman & Ioannides
//!   1981 have C_μ^0.75), and the particle's crossing time t_cr = −τ_p ln(1 − L_e/(τ_p |u − v|))
//!   when L_e < τ_p |u − v| (τ_p = ρ_p d²/(18 μ), ρ_p `rhoP` or the particle's own density);
//! * the fluctuation holds until t + min(τ_e, t_cr) (τ_e when the particle cannot cross the
//!   eddy).
//!
//! The drag law then sees u + u′: β from Koch–Hill at the slip |u + u′ − v| and the force
//! β (u + u′ − v) (PFM's `Ufluid += partUfluct`). foamgrain hands the fluid the same momentum
//! the particle receives: the implicit part β (U − Us) on the cell's mean velocity and β u′
//! in the explicit source f (PFM leaves u′ in its `Ufluid` of the implicit force). With k = 0
//! the drag is `KochHillDrag`'s, bit for bit.
//!
//! For a fluid tracer (no slip, so no crossing) in homogeneous frozen turbulence with a fixed
//! τ_e, the displacement after n eddies is a sum of n independent N(0, σ²τ_e²) steps per axis,
//! σ² = 2k/3: ⟨X²⟩ = σ² τ_e t at t = n τ_e, Taylor's (1921) dispersion 2σ² T t with the
//! integral time T = τ_e/2 of the eddy model's triangular autocorrelation (`tests/` check it by
//! Monte Carlo).
//!
//! The random numbers are a counter-based stream (SplitMix64 of the seed, the particle's tag
//! and its number of draws), so a run is reproducible and independent of the number of
//! threads and of the particles' order. PFM's default C_L is not set (an uninitialised member);
//! foamgrain's is 0.15, the value ANSYS Fluent documents for k–ε (T_L ≈ 0.15 k/ε).

use crate::forces::Physics;
use crate::interpolate::{Interpolation, Placement};
use crate::sides::{FluidState, ParticleState, Turbulence};
use mesh::v3::V3;
use std::collections::HashMap;

/// `KochHillRWDragProps` beyond the drag's own keys.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomWalkSettings {
    /// `cl`: C_L of τ_e = 2 C_L k/ε (default 0.15, module docs).
    pub cl: f64,
    /// `rhoP`, kg/m³: ρ_p of the crossing time; `None`: each particle's own density.
    pub rho_p: Option<f64>,
    /// `randomTauE`: τ_e drawn from an exponential distribution of mean C_L k/ε.
    pub random_tau_e: bool,
    /// The random stream's seed (fixed: a run is reproducible).
    pub seed: u64,
}

impl Default for RandomWalkSettings {
    fn default() -> Self {
        RandomWalkSettings {
            cl: 0.15,
            rho_p: None,
            random_tau_e: false,
            seed: 0x5eed_2028,
        }
    }
}

/// PFM's C_μ of the eddy size L_e = C_μ^0.63 k^1.5/ε.
const C_MU: f64 = 0.09;

/// One particle's current eddy.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Eddy {
    /// The fluctuation u′, m/s.
    u: V3,
    /// The time until which it holds, s.
    until: f64,
    /// Draws so far (the stream's counter).
    draws: u64,
}

/// The random walk's state: each particle's eddy, by tag.
#[derive(Clone, Debug, Default)]
pub struct RandomWalk {
    settings: RandomWalkSettings,
    eddies: HashMap<u64, Eddy>,
}

/// What one exchange needs per particle: the cell of its centre (`None` outside the mesh)
/// and the mean fluid velocity at it, m/s.
#[derive(Clone, Copy, Debug)]
pub struct AtParticles<'a> {
    /// The cell of each particle's centre.
    pub cell: &'a [Option<u32>],
    /// The mean fluid velocity at each particle (the drag's interpolation), m/s.
    pub u: &'a [V3],
}

impl RandomWalk {
    /// A walk with `settings` and no particle yet.
    pub fn new(settings: RandomWalkSettings) -> RandomWalk {
        RandomWalk {
            settings,
            eddies: HashMap::new(),
        }
    }

    /// The settings.
    pub fn settings(&self) -> RandomWalkSettings {
        self.settings
    }

    /// [`RandomWalk::fluctuations`] at the exchange at time `t` (s, from the run's start: only
    /// differences of it matter) with the drag's interpolation of U; the fluid's k and ε are
    /// required (the coupler checks them before).
    pub fn at_exchange(
        &mut self,
        t: f64,
        physics: &Physics,
        placement: &Placement,
        fluid: &FluidState<'_>,
        particles: &ParticleState<'_>,
    ) -> Vec<V3> {
        let rule = (physics.forces.drag).map_or(Interpolation::Cell, |d| d.interpolation);
        let u: Vec<V3> = (0..particles.len())
            .map(|i| placement.value_at(fluid.u, i, rule).unwrap_or_default())
            .collect();
        let at = AtParticles {
            cell: &placement.centre,
            u: &u,
        };
        let turbulence = fluid.turbulence.expect("the coupler checks k and ε first");
        self.fluctuations(t, particles, at, turbulence, physics.nu * physics.rho)
    }

    /// The fluctuation u′ of every particle at the exchange at time `t` (s), drawing new eddies
    /// where their time has come (module docs); zero outside the mesh. `mu` is the fluid's
    /// dynamic viscosity, Pa·s. Particles that have left are forgotten.
    pub fn fluctuations(
        &mut self,
        t: f64,
        particles: &ParticleState<'_>,
        at: AtParticles<'_>,
        turbulence: Turbulence<'_>,
        mu: f64,
    ) -> Vec<V3> {
        let mut out = vec![V3::zeros(); particles.len()];
        let mut kept = HashMap::with_capacity(particles.len());
        for (i, u_out) in out.iter_mut().enumerate() {
            let Some(cell) = at.cell[i] else { continue };
            let tag = particles.ids[i];
            let mut eddy = self.eddies.get(&tag).copied().unwrap_or(Eddy {
                until: f64::NEG_INFINITY,
                ..Eddy::default()
            });
            if t >= eddy.until {
                let (k, eps) = (
                    turbulence.k[cell as usize].max(0.0),
                    turbulence.epsilon[cell as usize],
                );
                let d = 2.0 * particles.radius[i];
                let rho_p = self.settings.rho_p.unwrap_or(particles.density[i]);
                let slip = (at.u[i] - particles.velocity[i]).norm();
                eddy = self.draw(
                    tag,
                    eddy.draws,
                    t,
                    k,
                    eps,
                    rho_p * d * d / (18.0 * mu),
                    slip,
                );
            }
            *u_out = eddy.u;
            kept.insert(tag, eddy);
        }
        self.eddies = kept;
        out
    }

    /// A new eddy for particle `tag` (its `draws`-th) at time `t` in turbulence (k, ε), for a
    /// particle of relaxation time `tau_p` (s) at slip `slip` (m/s).
    #[allow(clippy::too_many_arguments)]
    fn draw(&self, tag: u64, draws: u64, t: f64, k: f64, eps: f64, tau_p: f64, slip: f64) -> Eddy {
        let mut stream = Stream::new(self.settings.seed, tag, draws);
        let sigma = (2.0 * k / 3.0).sqrt();
        let u = V3::new(stream.normal(), stream.normal(), stream.normal()) * sigma;
        let eps = eps.max(f64::MIN_POSITIVE);
        let cl = self.settings.cl;
        let tau_e = match self.settings.random_tau_e {
            true => -cl * k / eps * stream.uniform_open().ln(),
            false => 2.0 * cl * k / eps,
        };
        let length = C_MU.powf(0.63) * k.powf(1.5) / eps;
        let reach = tau_p * slip;
        let hold = match length < reach {
            true => tau_e.min(-tau_p * (1.0 - length / reach).ln()),
            false => tau_e,
        };
        Eddy {
            u,
            until: t + hold,
            draws: draws + 1,
        }
    }
}

/// A counter-based random stream: SplitMix64 over (seed, tag, draw), each call the next value.
struct Stream {
    state: u64,
}

impl Stream {
    fn new(seed: u64, tag: u64, draw: u64) -> Stream {
        let mut s = Stream {
            state: seed ^ tag.wrapping_mul(0x9E37_79B9_7F4A_7C15),
        };
        s.state = s.next_u64() ^ draw.wrapping_mul(0xD1B5_4A32_D192_ED69);
        Stream {
            state: s.next_u64(),
        }
    }

    /// SplitMix64 (Steele, Lea & Flood 2014).
    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1) (53 random bits, never 0 or 1).
    fn uniform_open(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box–Muller, the cosine branch).
    fn normal(&mut self) -> f64 {
        let (a, b) = (self.uniform_open(), self.uniform_open());
        (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stream's normal numbers have mean 0, variance 1 and kurtosis 3 within their sampling
    /// errors (4 standard errors: √(1/n), √(2/n), √(96/n) for n draws), and a particle's draws
    /// do not depend on the others'.
    #[test]
    fn stream_is_standard_normal() {
        let n = 200_000;
        let mut x = Vec::with_capacity(n);
        for tag in 0..(n / 4) as u64 {
            let mut s = Stream::new(7, tag, 3);
            x.extend((0..4).map(|_| s.normal()));
        }
        let nf = n as f64;
        let mean = x.iter().sum::<f64>() / nf;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / nf;
        let kurt = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / nf / (var * var);
        assert!(mean.abs() < 4.0 * (1.0 / nf).sqrt(), "{mean}");
        assert!((var - 1.0).abs() < 4.0 * (2.0 / nf).sqrt(), "{var}");
        assert!((kurt - 3.0).abs() < 4.0 * (96.0 / nf).sqrt(), "{kurt}");
        let mut a = Stream::new(7, 11, 0);
        let mut b = Stream::new(7, 11, 0);
        assert_eq!(a.next_u64(), b.next_u64());
        assert_ne!(
            Stream::new(7, 11, 1).next_u64(),
            Stream::new(7, 12, 1).next_u64()
        );
    }

    /// The eddy's lifetime and crossing time by hand: k = 0.06 m²/s², ε = 0.09 m²/s³,
    /// C_L = 0.15 ⇒ τ_e = 2·0.15·0.06/0.09 = 0.2 s; L_e = 0.09^0.63·0.06^1.5/0.09 =
    /// 0.219368·0.0146969/0.09 = 0.0358226 m. A particle of τ_p = 0.1 s at slip 1 m/s reaches
    /// τ_p |u − v| = 0.1 m > L_e: t_cr = −0.1 ln(1 − 0.358226) = 0.0443519 s < τ_e.
    #[test]
    fn eddy_times_by_hand() {
        let w = RandomWalk::new(RandomWalkSettings::default());
        let (k, eps) = (0.06, 0.09);
        let e = w.draw(1, 0, 2.0, k, eps, 0.1, 0.0);
        assert!((e.until - 2.2).abs() < 1e-14, "{}", e.until);
        let length = 0.09f64.powf(0.63) * 0.06f64.powf(1.5) / 0.09;
        assert!((length - 0.0358226).abs() < 1e-7, "{length}");
        let e = w.draw(1, 0, 2.0, k, eps, 0.1, 1.0);
        let t_cr = -0.1 * (1.0 - length / 0.1).ln();
        assert!((t_cr - 0.0443519).abs() < 1e-7, "{t_cr}");
        assert!((e.until - (2.0 + t_cr)).abs() < 1e-14);
        assert_eq!(e.draws, 1);
    }

    /// Taylor dispersion (module docs): N fluid tracers (no slip: no crossing) in frozen
    /// homogeneous turbulence, exchanges every Δt = τ_e/10, positions advanced by u′ Δt; after
    /// n = 20 eddies ⟨X²⟩ per axis = σ² τ_e t with σ² = 2k/3. The displacement is Gaussian, so
    /// the sample mean of X² has the relative standard error √(2/N) (1.6 % for N = 8000, three
    /// axes pooled: 0.91 %); tolerance 4 standard errors. With randomTauE (exponential
    /// lifetimes of mean C_L k/ε, rounded up to the exchanges) the long-time diffusivity is
    /// σ² E[τ²]/E[τ] per unit time: for the exponential lifetimes rounded up to whole
    /// exchanges, E[τ²]/E[τ] is computed in closed form below.
    #[test]
    fn tracer_dispersion_is_taylors() {
        let (k, eps) = (0.06, 0.09);
        let n = 8_000usize;
        let ids: Vec<u64> = (0..n as u64).collect();
        let zeros = vec![V3::zeros(); n];
        let radius = vec![1e-6; n];
        let density = vec![1000.0; n];
        let cell = vec![Some(0u32); n];
        let particles = ParticleState {
            ids: &ids,
            position: &zeros,
            velocity: &zeros,
            radius: &radius,
            density: &density,
            temperature: None,
        };
        let turbulence = Turbulence {
            k: &[k],
            epsilon: &[eps],
        };
        let at = AtParticles {
            cell: &cell,
            u: &zeros,
        };
        let sigma2 = 2.0 * k / 3.0;
        let mut w = RandomWalk::new(RandomWalkSettings::default());
        let tau_e = 2.0 * 0.15 * k / eps;
        // exchanges at t = j·Δt; the eddy drawn at j holds while t < t_j + τ_e, i.e. for 10
        // exchanges (the times carry no rounding that moves a boundary: τ_e/Δt = 10 exactly
        // within 1e-15 and the `until` test is ≥)
        let dt = tau_e / 10.0;
        let steps = 200;
        let mut x = vec![V3::zeros(); n];
        for j in 0..steps {
            // the j-th exchange's time, slightly past the boundary so that round-off in
            // j·Δt cannot keep an eddy one exchange longer
            let t = j as f64 * dt * (1.0 + 1e-12);
            let u = w.fluctuations(t, &particles, at, turbulence, 1e-3);
            for (x, u) in x.iter_mut().zip(&u) {
                *x += u * dt;
            }
        }
        let t = steps as f64 * dt;
        let want = sigma2 * tau_e * t;
        let got = x.iter().map(|x| x.norm_squared()).sum::<f64>() / (3.0 * n as f64);
        let se = (2.0 / (3.0 * n as f64)).sqrt();
        assert!(
            (got / want - 1.0).abs() < 4.0 * se,
            "{got} vs {want}: {:+.2} % (4 SE = {:.2} %)",
            100.0 * (got / want - 1.0),
            400.0 * se
        );
        // with randomTauE: lifetimes τ = −C_L (k/ε) ln r hold for m = ⌈τ/Δt⌉ exchanges
        // (m ≥ 1); P(m) = e^(−(m−1)a) − e^(−m a), a = Δt/(C_L k/ε); the displacement per eddy
        // is u′ m Δt, so ⟨X²⟩/t → σ² Δt E[m²]/E[m], with E[m] = 1/(1 − q), E[m²] =
        // (1 + q)/(1 − q)², q = e^(−a) (geometric distribution)
        let mut w = RandomWalk::new(RandomWalkSettings {
            random_tau_e: true,
            ..RandomWalkSettings::default()
        });
        let mean_tau = 0.15 * k / eps;
        let dt = mean_tau / 2.0;
        let q = (-dt / mean_tau).exp();
        let ratio = (1.0 + q) / (1.0 - q);
        let steps = 300;
        let mut x = vec![V3::zeros(); n];
        for j in 0..steps {
            let u = w.fluctuations(j as f64 * dt, &particles, at, turbulence, 1e-3);
            for (x, u) in x.iter_mut().zip(&u) {
                *x += u * dt;
            }
        }
        let t = steps as f64 * dt;
        // the last eddies are cut at t: a bias of order one eddy in the run (E[m] = 2.5 steps
        // of 300): within 3 %
        let want = sigma2 * dt * ratio * t;
        let got = x.iter().map(|x| x.norm_squared()).sum::<f64>() / (3.0 * n as f64);
        assert!(
            (got / want - 1.0).abs() < 0.03 + 4.0 * se,
            "randomTauE: {got} vs {want}"
        );
    }
}
