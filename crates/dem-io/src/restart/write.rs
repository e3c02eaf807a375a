//! Writing a [`RestartFile`] in LIGGGHTS 3.8's layout ([the module docs](super#layout)).

use std::io::{self, Write};
use std::path::Path;

use super::{AtomRecord, FixAtomData, PairSection, RestartFile, ATOM_VALUES};
use crate::bounds::Boundary;

fn invalid(msg: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, msg)
}

/// Writes `file` to `path` atomically (the path keeps its old content or gets the whole new
/// file), creating missing parent directories as LIGGGHTS's `write_restart` does.
pub fn write_restart_file(path: &Path, file: &RestartFile) -> io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    check(file)?;
    atomic_write::write_atomically(path, |w| write_restart(w, file))
}

/// Checks what the layout cannot express, before anything is written.
fn check(f: &RestartFile) -> io::Result<()> {
    let n: usize = f.chunks.iter().sum();
    if f.chunks.is_empty() || n != f.atoms.len() {
        return Err(invalid(format!(
            "{} chunks hold {n} atoms, but there are {} (at least one chunk is needed)",
            f.chunks.len(),
            f.atoms.len()
        )));
    }
    if f.header.ntypes == 0 {
        return Err(invalid("no atom types".into()));
    }
    if let Some(PairSection::Gran { setflag, .. }) = &f.pair {
        let want = f.header.ntypes * (f.header.ntypes + 1) / 2;
        if setflag.len() != want {
            return Err(invalid(format!(
                "{} pair coefficient flags for {} types ({want} needed)",
                setflag.len(),
                f.header.ntypes
            )));
        }
    }
    if let Some(m) = &f.type_mass {
        if m.len() != f.header.ntypes {
            return Err(invalid(format!(
                "{} per-type masses for {} types",
                m.len(),
                f.header.ntypes
            )));
        }
    }
    if f.groups.iter().flatten().count() > 32 || f.groups.len() > 32 {
        return Err(invalid("more than 32 group slots".into()));
    }
    // the history length of each contact-history fix, from its first contact
    let dnum: Vec<Option<usize>> = (0..f.peratom_fixes.len())
        .map(|k| {
            f.atoms.iter().find_map(|a| match a.fix_data.get(k) {
                Some(FixAtomData::Contacts(cs)) => cs.first().map(|c| c.history.len()),
                _ => None,
            })
        })
        .collect();
    for a in &f.atoms {
        if a.fix_data.len() != f.peratom_fixes.len() {
            return Err(invalid(format!(
                "atom {} has data of {} fixes, {} per-atom fixes are declared",
                a.tag,
                a.fix_data.len(),
                f.peratom_fixes.len()
            )));
        }
        for (k, (d, fix)) in a.fix_data.iter().zip(&f.peratom_fixes).enumerate() {
            if let FixAtomData::Contacts(cs) = d {
                if let Some(c) = cs.iter().find(|c| Some(c.history.len()) != dnum[k]) {
                    return Err(invalid(format!(
                        "atom {}: fix {}: a contact with {} history values, others have {:?}",
                        a.tag,
                        fix.id,
                        c.history.len(),
                        dnum[k]
                    )));
                }
            }
            if d.stored_len() > fix.max_size {
                return Err(invalid(format!(
                    "atom {}: {} values of fix {} exceed its declared maximum {} \
                     (call update_max_sizes)",
                    a.tag,
                    d.stored_len(),
                    fix.id,
                    fix.max_size
                )));
            }
        }
        if a.atom_type == 0 || a.atom_type as usize > f.header.ntypes || a.tag == 0 {
            return Err(invalid(format!(
                "atom {} of type {} (types 1..={})",
                a.tag, a.atom_type, f.header.ntypes
            )));
        }
    }
    Ok(())
}

/// Little-endian byte sink with LIGGGHTS's record forms.
struct Out<'a, W: Write>(&'a mut W);

impl<W: Write> Out<'_, W> {
    fn i32(&mut self, v: i32) -> io::Result<()> {
        self.0.write_all(&v.to_le_bytes())
    }
    fn i64(&mut self, v: i64) -> io::Result<()> {
        self.0.write_all(&v.to_le_bytes())
    }
    fn f64(&mut self, v: f64) -> io::Result<()> {
        self.0.write_all(&v.to_le_bytes())
    }
    fn len(&mut self, n: usize, what: &str) -> io::Result<()> {
        let n = i32::try_from(n).map_err(|_| invalid(format!("{what} {n} exceeds an int")))?;
        self.i32(n)
    }
    fn string(&mut self, s: &str) -> io::Result<()> {
        if s.contains('\0') {
            return Err(invalid(format!("string {s:?} contains a NUL")));
        }
        self.len(s.len() + 1, "string length")?;
        self.0.write_all(s.as_bytes())?;
        self.0.write_all(&[0])
    }
    fn rec_i32(&mut self, flag: i32, v: i32) -> io::Result<()> {
        self.i32(flag)?;
        self.i32(v)
    }
    fn rec_i64(&mut self, flag: i32, v: i64) -> io::Result<()> {
        self.i32(flag)?;
        self.i64(v)
    }
    fn rec_f64(&mut self, flag: i32, v: f64) -> io::Result<()> {
        self.i32(flag)?;
        self.f64(v)
    }
    fn rec_str(&mut self, flag: i32, s: &str) -> io::Result<()> {
        self.i32(flag)?;
        self.string(s)
    }
}

/// Writes `file` in LIGGGHTS 3.8's layout: the header records in LIGGGHTS's order, then the
/// groups, type arrays, force fields, fixes and the atom chunks (`file.chunks`). A file read
/// by [`read_restart`](super::read_restart) is written back byte for byte.
pub fn write_restart<W: Write>(out: &mut W, file: &RestartFile) -> io::Result<()> {
    check(file)?;
    let h = &file.header;
    let o = &mut Out(out);
    let natoms = i64::try_from(file.atoms.len()).expect("atom count fits i64");
    let timestep = i64::try_from(h.timestep)
        .map_err(|_| invalid(format!("step {} exceeds a bigint", h.timestep)))?;
    o.rec_str(0, &h.version)?;
    o.rec_i32(1, 4)?;
    o.rec_i32(2, 4)?;
    o.rec_i32(3, 8)?;
    o.rec_str(4, &h.units)?;
    o.rec_i64(5, timestep)?;
    o.rec_i32(6, h.dimension)?;
    let nprocs = i32::try_from(file.chunks.len()).map_err(|_| invalid("too many chunks".into()))?;
    o.rec_i32(7, nprocs)?;
    for k in 0..3 {
        o.rec_i32(8 + k as i32, h.procgrid[k])?;
    }
    o.rec_i32(11, h.newton_pair)?;
    o.rec_i32(12, h.newton_bond)?;
    for k in 0..3 {
        o.rec_i32(
            13 + k as i32,
            i32::from(h.boundary[k][0] == Boundary::Periodic),
        )?;
    }
    for k in 0..6 {
        o.rec_i32(16 + k as i32, h.boundary[k / 2][k % 2].code())?;
    }
    o.rec_str(22, &h.atom_style)?;
    o.rec_i64(23, natoms)?;
    o.i32(24)?;
    o.len(h.ntypes, "number of atom types")?;
    // bonds, angles, dihedrals, impropers: none
    for flag in 25..=36 {
        if [25, 28, 31, 34].contains(&flag) {
            o.rec_i64(flag, 0)?;
        } else {
            o.rec_i32(flag, 0)?;
        }
    }
    for k in 0..3 {
        o.rec_f64(37 + 2 * k as i32, h.lo[k])?;
        o.rec_f64(38 + 2 * k as i32, h.hi[k])?;
    }
    for k in 0..3 {
        o.rec_f64(43 + k as i32, h.special_lj[k])?;
    }
    for k in 0..3 {
        o.rec_f64(46 + k as i32, h.special_coul[k])?;
    }
    if let Some(t) = h.tilt {
        for (flag, v) in (49..).zip(t) {
            o.rec_f64(flag, v)?;
        }
    }
    o.i32(-1)?;

    // groups: the named count, then the slots
    o.len(file.groups.iter().flatten().count(), "number of groups")?;
    for g in &file.groups {
        match g {
            Some(name) => o.string(name)?,
            None => o.i32(0)?,
        }
    }

    if let Some(m) = &file.type_mass {
        o.i32(0)?;
        for &v in m {
            o.f64(v)?;
        }
    }
    o.i32(-1)?;

    if let Some(PairSection::Gran { model, setflag }) = &file.pair {
        o.i32(0)?;
        o.string("gran")?;
        o.i64(model.hashcode())?;
        for &s in setflag {
            o.i32(s)?;
        }
    }
    o.i32(-1)?;

    o.len(file.global_fixes.len(), "number of fixes")?;
    for f in &file.global_fixes {
        o.string(&f.id)?;
        o.string(&f.style)?;
        o.len(f.state.len(), "fix state size")?;
        o.0.write_all(&f.state)?;
    }
    o.len(file.peratom_fixes.len(), "number of fixes")?;
    for f in &file.peratom_fixes {
        o.string(&f.id)?;
        o.string(&f.style)?;
        o.len(f.max_size, "per-atom size")?;
    }

    let mut buf: Vec<f64> = Vec::new();
    let mut start = 0;
    for &n in &file.chunks {
        buf.clear();
        for a in &file.atoms[start..start + n] {
            pack_atom(a, &mut buf);
        }
        o.len(buf.len(), "chunk size")?;
        let mut bytes = Vec::with_capacity(8 * buf.len().min(1 << 16));
        for part in buf.chunks(1 << 16) {
            bytes.clear();
            bytes.extend(part.iter().flat_map(|v| v.to_le_bytes()));
            o.0.write_all(&bytes)?;
        }
        start += n;
    }
    o.0.flush()
}

/// Appends one atom record.
fn pack_atom(a: &AtomRecord, buf: &mut Vec<f64>) {
    let start = buf.len();
    let bits = |v: i64| f64::from_bits(v as u64);
    buf.push(0.0);
    buf.extend_from_slice(&a.x);
    buf.push(bits(a.tag as i64));
    buf.push(bits(i64::from(a.atom_type)));
    buf.push(bits(a.mask));
    buf.push(bits(a.image));
    buf.extend_from_slice(&a.v);
    buf.push(a.radius);
    buf.push(a.rmass);
    buf.push(a.density);
    buf.extend_from_slice(&a.omega);
    debug_assert_eq!(buf.len() - start, ATOM_VALUES);
    for d in &a.fix_data {
        buf.push(d.stored_len() as f64);
        match d {
            FixAtomData::Contacts(cs) => {
                buf.push(bits(cs.len() as i64));
                for c in cs {
                    buf.push(bits(c.partner as i64));
                    buf.extend_from_slice(&c.history);
                }
            }
            FixAtomData::Values(v) => buf.extend_from_slice(v),
        }
    }
    buf[start] = (buf.len() - start) as f64;
}
