//! Insertion fixes: `insert/pack`, `insert/rate/region`, `insert/stream` (their arguments are
//! read by [`crate::deck::insertion`]).

use crate::deck::insertion::{self, PackFix};
use crate::insert_rate::InsertRate;

use super::super::{Failure, Session};
use super::Fix;

pub(super) fn insert_pack(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let ins = match insertion::insert_pack(&id, w, &session.known())? {
        PackFix::Once(ins) => ins,
        PackFix::Every(spec) => return add_rate(session, &id, spec),
    };
    match &mut session.sim {
        Some(s) => s.add_insertion(ins),
        None => session.pending.inserts.push(ins),
    }
    Ok(())
}

pub(super) fn insert_rate(session: &mut Session<'_>, fix: Fix<'_>) -> Result<(), Failure> {
    let w = fix.words;
    let id = fix.id;
    let style = fix.style;
    let ins = match style {
        "insert/stream" => insertion::insert_stream(&id, w, &session.known())?,
        _ => insertion::insert_rate(&id, w, &session.known())?,
    };
    add_rate(session, &id, ins)
}

/// A scheduled insertion (rate, stream, or `insert/pack … insert_every K`).
fn add_rate(session: &mut Session<'_>, id: &str, ins: InsertRate) -> Result<(), Failure> {
    session.registry.add_insert_fix(id);
    match &mut session.sim {
        Some(s) => s.add_rate_insertion(ins)?,
        None => session.pending.rate_inserts.push(ins),
    }
    Ok(())
}
