//! Output fixes: `print` ([`crate::deck::print`]).

use crate::deck::print::FixPrint;

use super::super::{Failure, Session};
use super::Fix;

pub(super) fn print(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let p = FixPrint::new(w, &session.workdir)?;
    session.prints.retain(|q| q.id != p.id);
    session.prints.push(p);
    Ok(())
}
