//! Particles read from a LIGGGHTS `dump custom` snapshot (through `dem-io`), e.g. to restart a
//! coupled run from a bed LIGGGHTS packed.

use dem_io::Snapshot;
use mesh::v3::V3;

use crate::error::DemError;
use crate::particles::NewParticle;

/// The particles of `snap` (`id type x y z vx vy vz radius` at least; `omegax…` if present).
/// The density comes from the `density` column, else from `mass` and the radius, else from
/// `density_per_type[type − 1]` (kg/m³); a particle with none of these is an error naming it.
pub fn particles_from_snapshot(
    snap: &Snapshot,
    density_per_type: &[f64],
) -> Result<Vec<NewParticle>, DemError> {
    let p = snap.particles()?;
    let mut out = Vec::with_capacity(p.len());
    for i in 0..p.len() {
        let r = p.radius[i];
        let density = match (&p.density, &p.mass) {
            (Some(d), _) => d[i],
            (None, Some(m)) => m[i] / (4.0 / 3.0 * std::f64::consts::PI * r * r * r),
            (None, None) => *density_per_type
                .get((p.atom_type[i] as usize).wrapping_sub(1))
                .ok_or_else(|| DemError::Particle {
                    id: p.id[i],
                    message: format!(
                        "{}: no density or mass column and no density given for type {}",
                        snap.source().display(),
                        p.atom_type[i]
                    ),
                })?,
        };
        out.push(NewParticle {
            id: p.id[i],
            atom_type: p.atom_type[i],
            x: p.position[i].into(),
            v: p.velocity[i].into(),
            omega: p.omega.as_ref().map_or(V3::zeros(), |w| w[i].into()),
            radius: r,
            density,
        });
    }
    Ok(out)
}
