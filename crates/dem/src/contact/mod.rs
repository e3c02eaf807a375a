//! Contact forces between two spheres or a sphere and a wall: `pair_style gran model hertz
//! tangential history [cohesion sjkr] [rolling_friction cdt|epsd2]`, the LIGGGHTS 3.x contact
//! model family, one sub-model per module.
//!
//! Geometry convention (as LIGGGHTS): `n` is the unit normal pointing from j (or from the wall)
//! to i; δ = Rᵢ + Rⱼ − r is the overlap (r the centre distance; for a wall r is the distance of
//! the centre to the wall and Rⱼ = 0); the contact radii are cᵢ = Rᵢ − δ/2, cⱼ = Rⱼ − δ/2.
//! The relative velocity of the contact points is vᵣ = vᵢ − vⱼ + n × (cᵢωᵢ + cⱼωⱼ), split into
//! vₙ = vᵣ·n and vₜ = vᵣ − vₙn. Forces returned act on i; j receives the opposite force.

pub mod hertz;
pub mod rolling;
pub mod sjkr;
pub mod tangential;

use mesh::v3::V3;

use crate::material::PairCoeffs;

/// The optional parts of the contact model, as selected on the `pair_style gran` /
/// `fix wall/gran` line.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactModel {
    /// `cohesion sjkr`.
    pub cohesion: bool,
    /// `rolling_friction cdt|epsd2`.
    pub rolling: Option<RollingModel>,
    /// `tangential_damping off` sets this to false (LIGGGHTS default: on).
    pub no_tangential_damping: bool,
    /// `limitForce on`: negative (attractive) normal contact forces are clipped to 0.
    pub limit_force: bool,
}

/// Rolling-friction models.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RollingModel {
    /// `cdt`: constant directional torque (Ai et al. 2011, model A).
    Cdt,
    /// `epsd2`: elastic–plastic spring–dashpot without the dashpot (Ai et al. 2011, model C).
    Epsd2,
}

/// How an evaluation of the contact forces treats the history.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HistoryUse {
    /// A time step: the history advances by dt.
    Advance,
    /// A run's set-up (LIGGGHTS's `setup`, e.g. the first run after `read_restart` of a
    /// LIGGGHTS file): the history is used, not advanced, exactly as LIGGGHTS 3.8 does. This
    /// does not give the forces of the step that left the history (the velocities are a half
    /// step later; a slipping contact may count as sticking; `epsd2` adds its increment again).
    Setup,
    /// The forces of the step that left this history, evaluated again at that step's
    /// velocities (a restart file of the native DEM records them): the history is not
    /// advanced, a spring at the Coulomb limit within round-off counts as slipping, and `epsd2`
    /// returns its stored torque, so the forces are those of the step to round-off.
    Replay,
}

/// History carried by a contact between steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct History {
    /// Accumulated tangential displacement (m).
    pub shear: V3,
    /// Rolling resistance torque of `epsd2` (N·m).
    pub roll: V3,
}

/// State of one contact as seen from i.
#[derive(Debug, Clone, Copy)]
pub struct ContactInput {
    /// Unit normal from j (or the wall) to i.
    pub n: V3,
    /// Centre distance r (m); for a wall the distance from i's centre to the wall.
    pub r: f64,
    /// Overlap δ > 0 (m).
    pub deltan: f64,
    /// Radius of i (m).
    pub radi: f64,
    /// Radius of j (m); 0 for a wall.
    pub radj: f64,
    /// Effective radius R* (m): RᵢRⱼ/(Rᵢ+Rⱼ), Rᵢ for a wall.
    pub reff: f64,
    /// Effective mass m* (kg): mᵢmⱼ/(mᵢ+mⱼ), mᵢ for a wall.
    pub meff: f64,
    /// vᵢ − vⱼ (m/s).
    pub vrel: V3,
    /// ωᵢ (rad/s).
    pub omega_i: V3,
    /// ωⱼ (rad/s); zero for a wall.
    pub omega_j: V3,
    /// Whether j is a wall.
    pub is_wall: bool,
}

/// Force and torques of one contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactOutput {
    /// Force on i (N); j receives the opposite.
    pub force: V3,
    /// Torque on i (N·m).
    pub torque_i: V3,
    /// Torque on j (N·m).
    pub torque_j: V3,
}

/// Evaluates one contact (normal, cohesion, tangential, rolling, in LIGGGHTS's order) and,
/// with [`HistoryUse::Advance`], advances its history by `dt` (s).
#[inline]
pub fn contact_force(
    model: &ContactModel,
    c: &PairCoeffs,
    inp: &ContactInput,
    hist: &mut History,
    dt: f64,
    history: HistoryUse,
) -> ContactOutput {
    let n = inp.n;
    let cri = inp.radi - 0.5 * inp.deltan;
    let crj = if inp.is_wall {
        0.0
    } else {
        inp.radj - 0.5 * inp.deltan
    };
    let vn = inp.vrel.dot(&n);
    let vt = inp.vrel - (vn * n);
    let wr = if inp.is_wall {
        cri * inp.omega_i
    } else {
        (cri * inp.omega_i) + (crj * inp.omega_j)
    };
    let vtr = vt + n.cross(&wr);

    let k = hertz::hertz_coeffs(
        inp.deltan,
        inp.reff,
        inp.meff,
        c.y_eff,
        c.g_eff,
        c.beta,
        !model.no_tangential_damping,
    );
    let mut fn_ = k.kn * inp.deltan - k.gamma_n * vn;
    if model.limit_force && fn_ < 0.0 {
        fn_ = 0.0;
    }
    let mut fn_total = fn_;
    if model.cohesion {
        fn_total += sjkr::sjkr_force(
            c.cohesion_energy_density,
            inp.r,
            inp.radi,
            inp.radj,
            inp.is_wall,
        );
    }
    let ft = tangential::history_force(
        &mut hist.shear,
        n,
        vtr,
        k.kt,
        k.gamma_t,
        c.friction * fn_.abs(),
        dt,
        history,
    );
    let tor = n.cross(&ft);
    let mut out = ContactOutput {
        force: ((fn_total * n) + ft),
        torque_i: (-cri * tor),
        torque_j: (-crj * tor),
    };
    if let Some(rolling) = model.rolling {
        // LIGGGHTS uses ωᵢ − ωⱼ between particles and cᵢωᵢ/r at a wall.
        let w = if inp.is_wall {
            cri / inp.r * inp.omega_i
        } else {
            inp.omega_i - inp.omega_j
        };
        let t = match rolling {
            RollingModel::Cdt => {
                rolling::cdt_torque(c.rolling_friction, k.kn * inp.deltan, inp.reff, w, n)
            }
            RollingModel::Epsd2 => rolling::epsd2_torque(
                &mut hist.roll,
                c.rolling_friction,
                fn_,
                k.kt,
                inp.reff,
                w,
                n,
                dt,
                history,
            ),
        };
        out.torque_i -= t;
        out.torque_j += t;
    }
    out
}
