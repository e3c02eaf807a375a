//! Reading a restart file into a [`RestartFile`] (layout: [the module docs](super#layout)).

use std::fs::File;
use std::io::{self, BufReader, Read};
use std::path::{Path, PathBuf};

use super::error::{RestartError, RestartErrorKind as K};
use super::{
    AtomRecord, Contact, FixAtomData, FixState, GranModel, Header, PairSection, PerAtomFix,
    RestartFile, ATOM_VALUES, CONTACT_HISTORY_STYLE,
};
use crate::bounds::Boundary;

/// Names of the header records by flag, for messages.
const RECORD: [&str; 52] = [
    "version",
    "smallint size",
    "tagint size",
    "bigint size",
    "units",
    "timestep",
    "dimension",
    "number of processes",
    "processor grid x",
    "processor grid y",
    "processor grid z",
    "newton pair",
    "newton bond",
    "x periodicity",
    "y periodicity",
    "z periodicity",
    "x-lo boundary",
    "x-hi boundary",
    "y-lo boundary",
    "y-hi boundary",
    "z-lo boundary",
    "z-hi boundary",
    "atom style",
    "number of atoms",
    "number of atom types",
    "number of bonds",
    "number of bond types",
    "bonds per atom",
    "number of angles",
    "number of angle types",
    "angles per atom",
    "number of dihedrals",
    "number of dihedral types",
    "dihedrals per atom",
    "number of impropers",
    "number of improper types",
    "impropers per atom",
    "xlo",
    "xhi",
    "ylo",
    "yhi",
    "zlo",
    "zhi",
    "special lj 1-2",
    "special lj 1-3",
    "special lj 1-4",
    "special coul 1-2",
    "special coul 1-3",
    "special coul 1-4",
    "xy tilt",
    "xz tilt",
    "yz tilt",
];

/// Header flags whose value is a string, a bigint or a double; all others are `int`.
const STRINGS: [i32; 3] = [0, 4, 22];
const BIGINTS: [i32; 6] = [5, 23, 25, 28, 31, 34];
const FIRST_DOUBLE: i32 = 37;
/// The last flag LIGGGHTS 3.8.0 always writes (special coul 1-4); 49–51 only for triclinic.
const LAST_REQUIRED: i32 = 48;

/// What the newer LAMMPS restart files start with.
const LAMMPS_MAGIC: &[u8] = b"LammpS RestartT";

/// Most group slots LIGGGHTS has.
const MAX_GROUP: usize = 32;

/// Reads the restart file at `path`.
pub fn read_restart(path: impl AsRef<Path>) -> Result<RestartFile, RestartError> {
    let path = path.as_ref();
    let io_err = |e| RestartError {
        file: path.to_path_buf(),
        offset: None,
        kind: K::Io(e),
    };
    let f = File::open(path).map_err(io_err)?;
    let len = f.metadata().map_err(io_err)?.len();
    read_restart_from(BufReader::new(f), path, len)
}

/// Reads a restart file of `len` bytes from `input`; `name` names it in errors.
pub fn read_restart_from(
    input: impl Read,
    name: &Path,
    len: u64,
) -> Result<RestartFile, RestartError> {
    let mut src = Src {
        r: input,
        pos: 0,
        len,
        name: name.to_path_buf(),
    };
    src.file()
}

/// A position-tracking reader over the file.
struct Src<R> {
    r: R,
    pos: u64,
    len: u64,
    name: PathBuf,
}

type Res<T> = Result<T, RestartError>;

impl<R: Read> Src<R> {
    fn err(&self, at: u64, kind: K) -> RestartError {
        RestartError::at(&self.name, at, kind)
    }

    fn remaining(&self) -> u64 {
        self.len.saturating_sub(self.pos)
    }

    fn fill(&mut self, buf: &mut [u8], what: &str) -> Res<()> {
        let start = self.pos;
        let mut got = 0;
        while got < buf.len() {
            match self.r.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.err(start + got as u64, K::Io(e))),
            }
        }
        self.pos += got as u64;
        if got < buf.len() {
            return Err(self.err(
                start,
                K::Truncated {
                    expected: format!("{what} ({} bytes, {got} present)", buf.len()),
                },
            ));
        }
        Ok(())
    }

    fn i32(&mut self, what: &str) -> Res<i32> {
        let mut b = [0u8; 4];
        self.fill(&mut b, what)?;
        Ok(i32::from_le_bytes(b))
    }

    fn i64(&mut self, what: &str) -> Res<i64> {
        let mut b = [0u8; 8];
        self.fill(&mut b, what)?;
        Ok(i64::from_le_bytes(b))
    }

    fn f64(&mut self, what: &str) -> Res<f64> {
        let mut b = [0u8; 8];
        self.fill(&mut b, what)?;
        Ok(f64::from_le_bytes(b))
    }

    /// A count that must be ≥ 0 and, with `unit` bytes per item, fit in the rest of the file.
    fn count(&mut self, what: &str, unit: u64) -> Res<usize> {
        let at = self.pos;
        let n = self.i32(what)?;
        if n < 0 {
            return Err(self.err(at, K::BadRecord(format!("{what} {n} is negative"))));
        }
        let need = (n as u64).saturating_mul(unit);
        if need > self.remaining() {
            return Err(self.err(
                at,
                K::Truncated {
                    expected: format!(
                        "{what} {n} needs {need} bytes, {} are left",
                        self.remaining()
                    ),
                },
            ));
        }
        Ok(n as usize)
    }

    fn bytes(&mut self, n: usize, what: &str) -> Res<Vec<u8>> {
        if n as u64 > self.remaining() {
            return Err(self.err(
                self.pos,
                K::Truncated {
                    expected: format!("{what} ({n} bytes, {} present)", self.remaining()),
                },
            ));
        }
        let mut v = vec![0u8; n];
        self.fill(&mut v, what)?;
        Ok(v)
    }

    /// A length-prefixed, NUL-terminated string.
    fn string(&mut self, what: &str) -> Res<String> {
        let at = self.pos;
        let n = self.count(&format!("length of the {what}"), 1)?;
        let b = self.bytes(n, what)?;
        match b.split_last() {
            Some((0, text)) if !text.contains(&0) => String::from_utf8(text.to_vec())
                .map_err(|_| self.err(at, K::BadRecord(format!("the {what} is not UTF-8")))),
            _ => Err(self.err(
                at,
                K::BadRecord(format!("the {what} ({n} bytes) does not end with its NUL")),
            )),
        }
    }

    fn file(&mut self) -> Res<RestartFile> {
        let header = self.header()?;
        let groups = self.groups()?;
        let type_mass = self.type_arrays(header.header.ntypes)?;
        let pair = self.force_fields(header.header.ntypes)?;
        let global_fixes = self.global_fixes()?;
        let peratom_at = self.pos;
        let peratom_fixes = self.peratom_fixes()?;
        let layouts = block_layouts(&peratom_fixes, &global_fixes)
            .map_err(|m| self.err(peratom_at, K::BadRecord(m)))?;
        let mut atoms = Vec::new();
        let mut chunks = Vec::with_capacity(header.nprocs.min(1 << 16));
        for c in 0..header.nprocs {
            let before = atoms.len();
            self.chunk(c, header.nprocs, &header.header, &layouts, &mut atoms)?;
            chunks.push(atoms.len() - before);
        }
        if atoms.len() as u64 != header.natoms {
            return Err(self.err(
                header.natoms_offset,
                K::AtomCount {
                    header: header.natoms,
                    found: atoms.len() as u64,
                },
            ));
        }
        if self.remaining() > 0 {
            return Err(self.err(self.pos, K::TrailingBytes(self.remaining())));
        }
        Ok(RestartFile {
            header: header.header,
            groups,
            type_mass,
            pair,
            global_fixes,
            peratom_fixes,
            atoms,
            chunks,
        })
    }

    /// The header section: the version record, then every header record up to the flag −1,
    /// checked as a granular LIGGGHTS 3.8 file has them.
    fn header(&mut self) -> Res<ReadHeader> {
        let version = self.version()?;
        let r = self.records()?;
        let tilts = self.check_records(&r)?;
        let timestep = u64::try_from(r.bigs[5]).map_err(|_| {
            self.err(
                r.rec_at[5],
                K::BadRecord(format!("negative step {}", r.bigs[5])),
            )
        })?;
        let natoms = u64::try_from(r.bigs[23]).map_err(|_| {
            self.err(
                r.natoms_offset,
                K::BadRecord(format!("negative number of atoms {}", r.bigs[23])),
            )
        })?;
        let ntypes = usize::try_from(r.ints[24])
            .ok()
            .filter(|&n| n >= 1)
            .ok_or_else(|| {
                self.err(
                    r.rec_at[24],
                    K::BadRecord(format!("number of atom types {}", r.ints[24])),
                )
            })?;
        let nprocs = usize::try_from(r.ints[7])
            .ok()
            .filter(|&n| n >= 1 && (n as u64) * 4 <= self.remaining())
            .ok_or_else(|| {
                self.err(
                    r.rec_at[7],
                    K::BadRecord(format!("number of processes {} (chunks)", r.ints[7])),
                )
            })?;
        let boundary = self.boundary(&r.ints, &r.rec_at)?;
        let d = |f: usize| r.doubles[f - FIRST_DOUBLE as usize];
        Ok(ReadHeader {
            header: Header {
                version,
                units: r.units,
                timestep,
                dimension: r.ints[6],
                procgrid: [r.ints[8], r.ints[9], r.ints[10]],
                newton_pair: r.ints[11],
                newton_bond: r.ints[12],
                boundary,
                atom_style: r.atom_style,
                ntypes,
                lo: [d(37), d(39), d(41)],
                hi: [d(38), d(40), d(42)],
                special_lj: [d(43), d(44), d(45)],
                special_coul: [d(46), d(47), d(48)],
                tilt: (tilts == 3).then(|| [d(49), d(50), d(51)]),
            },
            natoms,
            natoms_offset: r.natoms_offset,
            nprocs,
        })
    }

    /// The first record, which must be the version (flag 0, a length, "Version …") of
    /// LIGGGHTS 3.8.
    fn version(&mut self) -> Res<String> {
        let mut first = [0u8; 16];
        let n = (self.remaining().min(16)) as usize;
        self.fill(&mut first[..n], "the first record")?;
        if first[..n].starts_with(LAMMPS_MAGIC) {
            return Err(self.err(0, K::NewerLammps));
        }
        let flag = (n >= 4).then(|| i32::from_le_bytes(first[..4].try_into().expect("4")));
        let len = (n >= 8).then(|| i32::from_le_bytes(first[4..8].try_into().expect("4")));
        let looks = flag == Some(0)
            && len.is_some_and(|l| (9..=4096).contains(&l))
            && n == 16
            && first[8..16] == *b"Version ";
        if !looks {
            return Err(self.err(
                0,
                K::NotRestart {
                    found: show(&first[..n]),
                },
            ));
        }
        let len = len.expect("checked") as usize;
        let mut version = b"Version ".to_vec();
        version.extend(self.bytes(len - 8, "the version string")?);
        let version = match version.split_last() {
            Some((0, t)) if !t.contains(&0) => String::from_utf8_lossy(t).into_owned(),
            _ => {
                return Err(self.err(
                    4,
                    K::BadRecord("the version string does not end with its NUL".into()),
                ))
            }
        };
        if !is_liggghts_38(&version) {
            return Err(self.err(8, K::UnsupportedVersion { found: version }));
        }
        Ok(version)
    }

    /// The header records after the version, up to the flag −1 (each known flag at most
    /// once; the atom style granular or sphere).
    fn records(&mut self) -> Res<Records> {
        let mut seen = [false; RECORD.len()];
        seen[0] = true;
        // where each record starts, for messages about its value
        let mut rec_at = [0u64; RECORD.len()];
        let mut ints = [0i32; 37];
        let mut bigs = [0i64; 37];
        let mut doubles = [0f64; 15];
        let mut units = String::new();
        let mut atom_style = String::new();
        let mut natoms_offset = 0;
        loop {
            let at = self.pos;
            let flag = self.i32("a header flag")?;
            if flag == -1 {
                break;
            }
            let Some(name) = usize::try_from(flag).ok().and_then(|f| RECORD.get(f)) else {
                return Err(self.err(
                    at,
                    K::UnknownFlag {
                        section: "header",
                        flag,
                    },
                ));
            };
            let f = flag as usize;
            if seen[f] {
                return Err(self.err(at, K::BadRecord(format!("second {name} record"))));
            }
            seen[f] = true;
            rec_at[f] = at;
            if STRINGS.contains(&flag) {
                let s = self.string(name)?;
                match flag {
                    4 => units = s,
                    22 => {
                        if s != "granular" && s != "sphere" {
                            return Err(self.err(at, K::UnsupportedAtomStyle { found: s }));
                        }
                        atom_style = s;
                    }
                    _ => unreachable!("version is read above and not repeated"),
                }
            } else if BIGINTS.contains(&flag) {
                if flag == 23 {
                    natoms_offset = at;
                }
                bigs[f] = self.i64(name)?;
            } else if flag >= FIRST_DOUBLE {
                doubles[f - FIRST_DOUBLE as usize] = self.f64(name)?;
            } else {
                ints[f] = self.i32(name)?;
            }
        }
        Ok(Records {
            seen,
            rec_at,
            ints,
            bigs,
            doubles,
            units,
            atom_style,
            natoms_offset,
        })
    }

    /// Checks that every record LIGGGHTS 3.8.0 writes is there, the tilts all or none, the
    /// integer sizes LIGGGHTS's and no bonds, angles, dihedrals or impropers; returns the
    /// number of tilt records.
    fn check_records(&self, r: &Records) -> Res<usize> {
        let Records {
            seen,
            rec_at,
            ints,
            bigs,
            ..
        } = r;
        for f in 1..=LAST_REQUIRED as usize {
            if !seen[f] {
                return Err(self.err(self.pos - 4, K::MissingRecord(RECORD[f])));
            }
        }
        let tilts = seen[49..].iter().filter(|&&s| s).count();
        if tilts != 0 && tilts != 3 {
            return Err(self.err(
                self.pos - 4,
                K::BadRecord("a triclinic box needs all three tilt records".into()),
            ));
        }
        for (f, want) in [(1, 4), (2, 4), (3, 8)] {
            if ints[f] != want {
                return Err(self.err(
                    rec_at[f],
                    K::IntegerSize {
                        what: RECORD[f],
                        found: ints[f],
                        expected: want,
                    },
                ));
            }
        }
        for f in [25, 28, 31, 34] {
            if bigs[f] != 0 {
                return Err(self.err(
                    rec_at[f],
                    K::BadRecord(format!("{} = {} in a granular file", RECORD[f], bigs[f])),
                ));
            }
        }
        for f in [26, 27, 29, 30, 32, 33, 35, 36] {
            if ints[f] != 0 {
                return Err(self.err(
                    rec_at[f],
                    K::BadRecord(format!("{} = {} in a granular file", RECORD[f], ints[f])),
                ));
            }
        }
        Ok(tilts)
    }

    /// The boundary codes of the faces, consistent with the axes' periodicity records.
    fn boundary(&self, ints: &[i32; 37], rec_at: &[u64; RECORD.len()]) -> Res<[[Boundary; 2]; 3]> {
        let mut boundary = [[Boundary::Periodic; 2]; 3];
        for k in 0..6 {
            let code = ints[16 + k];
            boundary[k / 2][k % 2] = Boundary::from_code(code).ok_or_else(|| {
                self.err(
                    rec_at[16 + k],
                    K::BadRecord(format!("{} code {code} (0..=3)", RECORD[16 + k])),
                )
            })?;
            let periodic = ints[13 + k / 2];
            if periodic != i32::from(boundary[k / 2][k % 2] == Boundary::Periodic) {
                return Err(self.err(
                    rec_at[13 + k / 2],
                    K::BadRecord(format!(
                        "{} {periodic} contradicts the {} `{}`",
                        RECORD[13 + k / 2],
                        RECORD[16 + k],
                        boundary[k / 2][k % 2]
                    )),
                ));
            }
        }
        Ok(boundary)
    }

    fn groups(&mut self) -> Res<Vec<Option<String>>> {
        let at = self.pos;
        let n = self.count("number of groups", 4)?;
        if n > MAX_GROUP {
            return Err(self.err(
                at,
                K::BadRecord(format!("{n} groups (LIGGGHTS has {MAX_GROUP} at most)")),
            ));
        }
        let mut slots = Vec::new();
        let mut named = 0;
        while named < n {
            if slots.len() == MAX_GROUP {
                return Err(self.err(
                    self.pos,
                    K::BadRecord(format!("{n} groups need more than {MAX_GROUP} slots")),
                ));
            }
            let at = self.pos;
            let len = self.i32("the length of a group name")?;
            if len == 0 {
                slots.push(None);
                continue;
            }
            let len = usize::try_from(len)
                .map_err(|_| self.err(at, K::BadRecord(format!("group name length {len}"))))?;
            let b = self.bytes(len, "a group name")?;
            match b.split_last() {
                Some((0, t)) if !t.contains(&0) => {
                    slots.push(Some(String::from_utf8_lossy(t).into_owned()))
                }
                _ => {
                    return Err(self.err(
                        at,
                        K::BadRecord("a group name does not end with its NUL".into()),
                    ))
                }
            }
            named += 1;
        }
        Ok(slots)
    }

    fn type_arrays(&mut self, ntypes: usize) -> Res<Option<Vec<f64>>> {
        let mut mass = None;
        loop {
            let at = self.pos;
            match self.i32("a type-array flag")? {
                -1 => return Ok(mass),
                0 if mass.is_none() => {
                    if (ntypes as u64) * 8 > self.remaining() {
                        return Err(self.err(
                            self.pos,
                            K::Truncated {
                                expected: format!("{ntypes} per-type masses"),
                            },
                        ));
                    }
                    let m = (0..ntypes)
                        .map(|_| self.f64("a per-type mass"))
                        .collect::<Res<Vec<_>>>()?;
                    mass = Some(m);
                }
                flag => {
                    return Err(self.err(
                        at,
                        K::UnknownFlag {
                            section: "type arrays",
                            flag,
                        },
                    ))
                }
            }
        }
    }

    fn force_fields(&mut self, ntypes: usize) -> Res<Option<PairSection>> {
        let mut pair = None;
        loop {
            let at = self.pos;
            let flag = self.i32("a force-field flag")?;
            let kind = match flag {
                -1 => return Ok(pair),
                0 => "pair",
                1 => "bond",
                2 => "angle",
                3 => "dihedral",
                4 => "improper",
                _ => {
                    return Err(self.err(
                        at,
                        K::UnknownFlag {
                            section: "force fields",
                            flag,
                        },
                    ))
                }
            };
            let style = self.string(&format!("{kind} style"))?;
            if kind != "pair" || style != "gran" || pair.is_some() {
                return Err(self.err(at, K::UnsupportedStyle { kind, style }));
            }
            let code_at = self.pos;
            let code = self.i64("the contact model code")?;
            let model = GranModel::from_hashcode(code).ok_or_else(|| {
                self.err(
                    code_at,
                    K::BadRecord(format!(
                        "contact model code {code} is not one LIGGGHTS makes"
                    )),
                )
            })?;
            let npairs = ntypes * (ntypes + 1) / 2;
            if npairs as u64 * 4 > self.remaining() {
                return Err(self.err(
                    self.pos,
                    K::Truncated {
                        expected: format!("{npairs} pair coefficient flags"),
                    },
                ));
            }
            let setflag = (0..npairs)
                .map(|_| self.i32("a pair coefficient flag"))
                .collect::<Res<Vec<_>>>()?;
            pair = Some(PairSection::Gran { model, setflag });
        }
    }

    fn global_fixes(&mut self) -> Res<Vec<FixState>> {
        let n = self.count("number of fixes with a global state", 12)?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            let id = self.string("fix id")?;
            let style = self.string("fix style")?;
            let len = self.count(&format!("size of the state of fix {id}"), 1)?;
            let state = self.bytes(len, &format!("the state of fix {id}"))?;
            v.push(FixState { id, style, state });
        }
        Ok(v)
    }

    fn peratom_fixes(&mut self) -> Res<Vec<PerAtomFix>> {
        let n = self.count("number of fixes with per-atom data", 12)?;
        let mut v = Vec::with_capacity(n);
        for _ in 0..n {
            let id = self.string("fix id")?;
            let style = self.string("fix style")?;
            let at = self.pos;
            let m = self.i32(&format!("largest per-atom size of fix {id}"))?;
            let max_size = usize::try_from(m).ok().filter(|&m| m >= 1).ok_or_else(|| {
                self.err(
                    at,
                    K::BadRecord(format!("largest per-atom size {m} of fix {id}")),
                )
            })?;
            v.push(PerAtomFix {
                id,
                style,
                max_size,
            });
        }
        Ok(v)
    }

    /// Reads chunk `c` and appends its atoms.
    fn chunk(
        &mut self,
        c: usize,
        nchunks: usize,
        header: &Header,
        layouts: &[Layout],
        atoms: &mut Vec<AtomRecord>,
    ) -> Res<()> {
        let at = self.pos;
        let n = self.count(&format!("size of atom chunk {} of {nchunks}", c + 1), 8)?;
        let raw = self.bytes(n * 8, "atom values")?;
        let values: Vec<f64> = raw
            .chunks_exact(8)
            .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes")))
            .collect();
        let base = at + 4;
        let mut m = 0;
        while m < n {
            let index = atoms.len() as u64;
            let bad = |at: usize, message: String| {
                RestartError::at(
                    &self.name,
                    base + 8 * at as u64,
                    K::BadAtom { index, message },
                )
            };
            let size = values[m];
            let size = whole(size)
                .filter(|&s| s >= ATOM_VALUES && s <= n - m)
                .ok_or_else(|| {
                    bad(
                        m,
                        format!(
                            "record length {size} (at least {ATOM_VALUES}, at most the {} \
                             values left in the chunk)",
                            n - m
                        ),
                    )
                })?;
            let r = &values[m..m + size];
            let bits = |k: usize| r[k].to_bits() as i64;
            let tag = u64::try_from(bits(4))
                .ok()
                .filter(|&t| t >= 1)
                .ok_or_else(|| bad(m + 4, format!("atom tag {} (≥ 1 expected)", bits(4))))?;
            let atom_type = u32::try_from(bits(5))
                .ok()
                .filter(|&t| t >= 1 && t as usize <= header.ntypes)
                .ok_or_else(|| {
                    bad(
                        m + 5,
                        format!("atom {tag}: type {} outside 1..={}", bits(5), header.ntypes),
                    )
                })?;
            let mut fix_data = Vec::with_capacity(layouts.len());
            let mut p = ATOM_VALUES;
            for l in layouts {
                let block_at = m + p;
                if p >= size {
                    return Err(bad(
                        block_at,
                        format!(
                            "atom {tag}: the record ends before the data of fix {}",
                            l.id
                        ),
                    ));
                }
                let len = whole(r[p])
                    .filter(|&s| s >= 1 && s <= size - p && s <= l.max_size)
                    .ok_or_else(|| {
                        bad(
                            block_at,
                            format!(
                                "atom {tag}: fix {} block length {} (1..={} expected, {} left \
                                 in the record)",
                                l.id,
                                r[p],
                                l.max_size,
                                size - p
                            ),
                        )
                    })?;
                let block = &r[p + 1..p + len];
                fix_data.push(match l.dnum {
                    Some(dnum) => FixAtomData::Contacts(
                        contacts(block, dnum)
                            .map_err(|e| bad(block_at, format!("atom {tag}: fix {}: {e}", l.id)))?,
                    ),
                    None => FixAtomData::Values(block.to_vec()),
                });
                p += len;
            }
            if p != size {
                return Err(bad(
                    m + p,
                    format!(
                        "atom {tag}: {} values follow the data of the {} per-atom fixes",
                        size - p,
                        layouts.len()
                    ),
                ));
            }
            atoms.push(AtomRecord {
                x: [r[1], r[2], r[3]],
                tag,
                atom_type,
                mask: bits(6),
                image: bits(7),
                v: [r[8], r[9], r[10]],
                radius: r[11],
                rmass: r[12],
                density: r[13],
                omega: [r[14], r[15], r[16]],
                fix_data,
            });
            m += size;
        }
        Ok(())
    }
}

/// The header records as read, by flag: whether each was seen, where it starts, its value
/// (`int`s, bigints and doubles by flag; the two strings after the version).
struct Records {
    seen: [bool; RECORD.len()],
    rec_at: [u64; RECORD.len()],
    ints: [i32; 37],
    bigs: [i64; 37],
    doubles: [f64; 15],
    units: String,
    atom_style: String,
    /// Where the number of atoms is (for messages about it).
    natoms_offset: u64,
}

/// The header with what reading the rest needs.
struct ReadHeader {
    header: Header,
    natoms: u64,
    natoms_offset: u64,
    nprocs: usize,
}

/// How to read one per-atom fix's blocks.
struct Layout {
    id: String,
    max_size: usize,
    /// `Some(dnum)` for the contact history.
    dnum: Option<usize>,
}

fn block_layouts(fixes: &[PerAtomFix], globals: &[FixState]) -> Result<Vec<Layout>, String> {
    fixes
        .iter()
        .map(|f| {
            let dnum = if f.style == CONTACT_HISTORY_STYLE {
                let state = globals
                    .iter()
                    .find(|g| g.id == f.id && g.style == f.style)
                    .and_then(FixState::values)
                    .ok_or_else(|| {
                        format!(
                            "fix {} ({}) has per-atom data but no global state giving the \
                             number of history values",
                            f.id, f.style
                        )
                    })?;
                let dnum = state.first().copied().and_then(whole).ok_or_else(|| {
                    format!("fix {}: number of history values {:?}", f.id, state.first())
                })?;
                Some(dnum)
            } else {
                None
            };
            Ok(Layout {
                id: f.id.clone(),
                max_size: f.max_size,
                dnum,
            })
        })
        .collect()
}

/// Splits a contact-history block: count, then (partner tag, `dnum` values) per contact.
fn contacts(block: &[f64], dnum: usize) -> Result<Vec<Contact>, String> {
    let Some(&first) = block.first() else {
        return Err("empty block (the number of contacts is missing)".into());
    };
    let n = first.to_bits() as i64;
    let n = usize::try_from(n).map_err(|_| format!("number of contacts {n}"))?;
    if n.checked_mul(dnum + 1).and_then(|v| v.checked_add(1)) != Some(block.len()) {
        return Err(format!(
            "{n} contacts of {dnum} values need {} values, the block has {}",
            n.saturating_mul(dnum + 1).saturating_add(1),
            block.len()
        ));
    }
    block[1..]
        .chunks_exact(dnum + 1)
        .map(|c| {
            let tag = c[0].to_bits() as i64;
            let partner = u64::try_from(tag)
                .ok()
                .filter(|&t| t >= 1)
                .ok_or_else(|| format!("partner tag {tag}"))?;
            Ok(Contact {
                partner,
                history: c[1..].to_vec(),
            })
        })
        .collect()
}

/// A double that holds a non-negative whole number (a length LIGGGHTS stores as a value).
fn whole(v: f64) -> Option<usize> {
    (v >= 0.0 && v.fract() == 0.0 && v < 1e15).then_some(v as usize)
}

/// Whether a version string is LIGGGHTS 3.8.x: `Version LIGGGHTS-<name> 3.8.<…>`.
fn is_liggghts_38(v: &str) -> bool {
    let mut w = v.split(' ');
    w.next() == Some("Version")
        && w.next().is_some_and(|n| n.starts_with("LIGGGHTS"))
        && w.next().is_some_and(|n| n.starts_with("3.8."))
}

/// The first bytes of a file for a message: as text if printable, else hex.
fn show(b: &[u8]) -> String {
    if !b.is_empty()
        && b.iter()
            .all(|c| c.is_ascii_graphic() || c.is_ascii_whitespace())
    {
        format!("the text {:?}", String::from_utf8_lossy(b))
    } else if b.is_empty() {
        "nothing (empty file)".into()
    } else {
        let hex: Vec<String> = b.iter().map(|c| format!("{c:02x}")).collect();
        format!("bytes {}", hex.join(" "))
    }
}
