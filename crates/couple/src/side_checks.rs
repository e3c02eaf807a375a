//! The coupler's checks of what the two sides hand it: equal array lengths, finite particle
//! velocities and positive densities, and the side errors named by side.

use crate::error::CoupleError;
use crate::sides::ParticleState;
use rayon::prelude::*;

pub(crate) fn particle_err(source: crate::error::SideError) -> CoupleError {
    CoupleError::Side {
        side: "particle",
        source,
    }
}

pub(crate) fn fluid_err(source: crate::error::SideError) -> CoupleError {
    CoupleError::Side {
        side: "fluid",
        source,
    }
}

/// The first of `arrays` (name, length) whose length is not `expected`, as an error.
pub(crate) fn same_lengths(
    expected: usize,
    arrays: &[(&'static str, usize)],
) -> Result<(), CoupleError> {
    match arrays.iter().find(|(_, len)| *len != expected) {
        Some(&(what, found)) => Err(CoupleError::Length {
            what,
            expected,
            found,
        }),
        None => Ok(()),
    }
}

/// Equal lengths, finite velocities and positive finite densities; the first bad particle as
/// an error naming its index and id. (Positions and radii are checked by the voidage.)
pub(crate) fn check_particles(p: &ParticleState<'_>) -> Result<(), CoupleError> {
    let n = p.ids.len();
    same_lengths(
        n,
        &[
            ("particle positions", p.position.len()),
            ("particle velocities", p.velocity.len()),
            ("particle radii", p.radius.len()),
            ("particle densities", p.density.len()),
        ],
    )?;
    let valid = |i: usize| {
        p.velocity[i].iter().all(|x| x.is_finite())
            && p.density[i].is_finite()
            && p.density[i] > 0.0
    };
    if let Some(i) = (0..n).into_par_iter().find_first(|&i| !valid(i)) {
        let message = if !p.velocity[i].iter().all(|x| x.is_finite()) {
            format!("non-finite velocity {:?}", p.velocity[i])
        } else {
            format!("density {} is not a positive number", p.density[i])
        };
        return Err(CoupleError::Particle {
            index: i,
            id: Some(p.ids[i]),
            message,
        });
    }
    Ok(())
}
