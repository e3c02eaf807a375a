//! The CFD coupling fixes: `couple/cfd` and `couple/cfd/force[/implicit]`.

use super::super::args::int;
use super::super::{Failure, Session};
use super::Fix;

pub(super) fn couple_cfd(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    session.registry.add_cfd_fix();
    let mut k = 4;
    while k < w.len() {
        match w[k].as_str() {
            "couple_every" => {
                if int(w, k + 1, "couple_every")? == 0 {
                    return Err("couple_every must be ≥ 1".into());
                }
                k += 2;
            }
            "mpi" => k += 1,
            "file" => k += 2,
            o => return Err(format!("couple/cfd keyword `{o}` is not supported").into()),
        }
    }
    Ok(())
}

pub(super) fn couple_cfd_force(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    session.registry.add_force_fix(&fix.id);
    Ok(())
}
