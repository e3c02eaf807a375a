//! LIGGGHTS restart files: the file Debian's LIGGGHTS 3.8.0 wrote (`tests/fixtures/dem/restart/`)
//! read against LIGGGHTS's own full-precision text of the same state, written back byte for
//! byte, a round trip of the writer, and refused inputs (truncated, not a restart file, another
//! atom style or version, a corrupt atom record) with the file and byte offset named.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use dem_io::restart::{
    read_restart, read_restart_from, write_restart, write_restart_file, AtomRecord, Contact,
    FixAtomData, GranModel, PairSection, RestartErrorKind, RestartFile, IMAGE_DEFAULT,
};
use dem_io::{read_snapshot, Boundary, ReadOptions, Selection};

fn fixture(name: &str) -> PathBuf {
    testkit::fixture("dem/restart").join(name)
}

fn liggghts_file() -> RestartFile {
    read_restart(fixture("restart.25000")).unwrap()
}

const WALLS: [&str; 5] = ["floor", "xlo", "xhi", "ylo", "yhi"];

#[test]
fn header_and_sections_of_a_debian_file() {
    let f = liggghts_file();
    let h = &f.header;
    assert!(h
        .version
        .starts_with("Version LIGGGHTS-PUBLIC 3.8.0, compiled"));
    assert_eq!(h.units, "si");
    assert_eq!(h.timestep, 25000);
    assert_eq!(h.dimension, 3);
    assert_eq!(h.atom_style, "granular");
    assert_eq!(h.ntypes, 2);
    assert_eq!(h.boundary, [[Boundary::Fixed; 2]; 3]);
    assert_eq!((h.lo, h.hi), ([0.0; 3], [0.004, 0.004, 0.008]));
    assert_eq!(h.tilt, None);
    assert_eq!(f.groups, [Some("all".to_string())]);
    assert_eq!(f.type_mass, None);
    assert_eq!(
        f.pair,
        Some(PairSection::Gran {
            model: GranModel::HERTZ_HISTORY,
            setflag: vec![1, 1, 1]
        })
    );
    assert_eq!(f.chunks, [40]);
    assert_eq!(f.atoms.len(), 40);
    // fixes: the walls' histories, the templates, the insertion and the contact history
    let global: Vec<(&str, &str)> = f
        .global_fixes
        .iter()
        .map(|g| (g.id.as_str(), g.style.as_str()))
        .collect();
    assert_eq!(global.len(), 10);
    assert_eq!(global[0], ("history_floor", "property/atom"));
    assert_eq!(global[9], ("contacthistory", "contacthistory"));
    assert_eq!(
        f.global_fix("contacthistory", "contacthistory")
            .unwrap()
            .values()
            .unwrap()[0],
        3.0
    );
    let peratom: Vec<(&str, usize)> = f
        .peratom_fixes
        .iter()
        .map(|p| (p.id.as_str(), p.max_size))
        .collect();
    assert_eq!(
        &peratom[..5],
        WALLS.map(|w| (&*format!("history_{w}").leak(), 4))
    );
    assert_eq!(peratom[5].0, "contacthistory");
    for a in &f.atoms {
        assert_eq!((a.mask, a.image), (1, IMAGE_DEFAULT));
    }
}

/// The values of the file equal, bit for bit, LIGGGHTS's `dump custom` of the same state at
/// `%.17g` (which round-trips a double): positions, velocities, angular velocities, radius,
/// mass, density, type, and the five walls' contact history.
#[test]
fn atoms_equal_liggghts_dump_of_the_same_state() {
    let f = liggghts_file();
    let s = read_snapshot(
        fixture("state.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    assert_eq!(s.timestep, 25000);
    let col = |name: &str| s.column(name).unwrap();
    let row: HashMap<u64, usize> = col("id")
        .iter()
        .enumerate()
        .map(|(k, &id)| (id as u64, k))
        .collect();
    assert_eq!(row.len(), f.atoms.len());
    let mut wall_contacts = 0;
    for a in &f.atoms {
        let k = row[&a.tag];
        assert_eq!(a.atom_type as f64, col("type")[k]);
        for (d, name) in ["x", "y", "z"].iter().enumerate() {
            assert_eq!(a.x[d], col(name)[k], "atom {} {name}", a.tag);
            assert_eq!(a.v[d], col(&format!("v{name}"))[k]);
            assert_eq!(a.omega[d], col(&format!("omega{name}"))[k]);
        }
        assert_eq!(a.radius, col("radius")[k]);
        assert_eq!(a.rmass, col("mass")[k]);
        assert_eq!(a.density, col("density")[k]);
        for (w, wall) in WALLS.iter().enumerate() {
            let FixAtomData::Values(h) = &a.fix_data[w] else {
                panic!("wall history is plain values")
            };
            for (d, v) in h.iter().enumerate() {
                assert_eq!(*v, col(&format!("f_history_{wall}[{}]", d + 1))[k]);
            }
            wall_contacts += usize::from(h.iter().any(|&v| v != 0.0));
        }
    }
    assert!(wall_contacts >= 10, "{wall_contacts} wall contacts");
}

/// `dump local` of `compute pair/gran/local id history`: one row per contact `id1 id2 0
/// shear_x shear_y shear_z`, the history as seen from id1.
fn liggghts_contacts() -> Vec<(u64, u64, [f64; 3])> {
    let text = std::fs::read_to_string(fixture("contacts.txt")).unwrap();
    let mut lines = text.lines().skip_while(|l| !l.starts_with("ITEM: ENTRIES"));
    lines.next();
    lines
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            (v[0] as u64, v[1] as u64, [v[3], v[4], v[5]])
        })
        .collect()
}

/// Every contact LIGGGHTS lists is in both atoms' contact-history blocks, with the history
/// as LIGGGHTS computed it on the first atom's side and negated on the other. The blocks hold
/// more: pairs that separated since the last neighbour-list build keep their (stale) history
/// in LIGGGHTS 3.8 until the next build, and are written too; all of them are apart now.
#[test]
fn contact_history_equals_liggghts_pair_list() {
    let f = liggghts_file();
    let x: HashMap<u64, ([f64; 3], f64)> =
        f.atoms.iter().map(|a| (a.tag, (a.x, a.radius))).collect();
    let overlap = |i: u64, j: u64| {
        let ((a, ra), (b, rb)) = (x[&i], x[&j]);
        let d = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        ra + rb - d
    };
    let contacts = liggghts_contacts();
    assert!(contacts.len() >= 15, "{} contacts", contacts.len());
    let k = f.peratom_fix("contacthistory").unwrap();
    let blocks: HashMap<u64, &Vec<Contact>> = f
        .atoms
        .iter()
        .map(|a| match &a.fix_data[k] {
            FixAtomData::Contacts(c) => (a.tag, c),
            FixAtomData::Values(_) => panic!("contact history is split into contacts"),
        })
        .collect();
    let find = |holder: u64, partner: u64| -> Vec<f64> {
        blocks[&holder]
            .iter()
            .find(|c| c.partner == partner)
            .unwrap_or_else(|| panic!("atom {holder} lacks partner {partner}"))
            .history
            .clone()
    };
    for &(i, j, h) in &contacts {
        assert_eq!(find(i, j), h.to_vec(), "{i}–{j}");
        assert_eq!(find(j, i), h.map(|v| -v).to_vec(), "{j}–{i}");
    }
    let listed: std::collections::HashSet<(u64, u64)> = contacts
        .iter()
        .flat_map(|&(i, j, _)| [(i, j), (j, i)])
        .collect();
    let mut stale = 0;
    for (&i, cs) in &blocks {
        for c in cs.iter() {
            if !listed.contains(&(i, c.partner)) {
                assert!(overlap(i, c.partner) < 0.0, "{i}–{} overlaps", c.partner);
                stale += 1;
            }
        }
    }
    for &(i, j, _) in &contacts {
        assert!(overlap(i, j) > 0.0);
    }
    let stored: usize = blocks.values().map(|c| c.len()).sum();
    assert_eq!(stored, 2 * contacts.len() + stale);
    assert_eq!((contacts.len(), stale / 2), (17, 13));
}

/// The file of a run on two MPI ranks has one chunk per rank; it reads like the serial one:
/// the values of LIGGGHTS's dump of the same state, each contact on both sides (negated), and
/// it is written back to the same bytes.
#[test]
fn two_rank_file_reads_and_writes_back() {
    let path = fixture("restart_2proc.25000");
    let f = read_restart(&path).unwrap();
    assert_eq!(f.chunks.len(), 2);
    assert!(f.chunks.iter().all(|&n| n > 0), "{:?}", f.chunks);
    assert_eq!(f.header.procgrid, [2, 1, 1]);
    let s = read_snapshot(
        fixture("state_2proc.txt"),
        &ReadOptions::default(),
        Selection::Last,
    )
    .unwrap();
    let row: HashMap<u64, usize> = s
        .column("id")
        .unwrap()
        .iter()
        .enumerate()
        .map(|(k, &id)| (id as u64, k))
        .collect();
    assert_eq!(row.len(), f.atoms.len());
    for a in &f.atoms {
        let k = row[&a.tag];
        for (d, c) in ["x", "y", "z"].iter().enumerate() {
            assert_eq!(a.x[d], s.column(c).unwrap()[k]);
            assert_eq!(a.v[d], s.column(&format!("v{c}")).unwrap()[k]);
            assert_eq!(a.omega[d], s.column(&format!("omega{c}")).unwrap()[k]);
        }
    }
    let k = f.peratom_fix("contacthistory").unwrap();
    let blocks: HashMap<u64, &Vec<Contact>> = f
        .atoms
        .iter()
        .map(|a| match &a.fix_data[k] {
            FixAtomData::Contacts(c) => (a.tag, c),
            FixAtomData::Values(_) => panic!("contacts expected"),
        })
        .collect();
    let mut n = 0;
    for (&i, cs) in &blocks {
        for c in cs.iter() {
            let back = blocks[&c.partner].iter().find(|b| b.partner == i).unwrap();
            let neg: Vec<f64> = c.history.iter().map(|v| -v).collect();
            assert_eq!(back.history, neg);
            n += 1;
        }
    }
    assert!(n >= 20, "{n}");
    let mut out = Vec::new();
    write_restart(&mut out, &f).unwrap();
    assert!(out == std::fs::read(&path).unwrap());
}

/// What is read is written back to the same bytes.
#[test]
fn liggghts_file_is_written_back_byte_for_byte() {
    let bytes = std::fs::read(fixture("restart.25000")).unwrap();
    let mut out = Vec::new();
    write_restart(&mut out, &liggghts_file()).unwrap();
    assert_eq!(out.len(), bytes.len());
    assert!(out == bytes, "first difference at byte {:?}", {
        out.iter().zip(&bytes).position(|(a, b)| a != b)
    });
}

/// A file made here (two chunks, an empty one, shrink-wrapped box, groups with an empty
/// slot, per-type masses, contacts with six history values, a fix of unknown meaning) is read
/// back equal.
#[test]
fn written_files_read_back_equal() {
    let mut f = liggghts_file();
    f.header.timestep = 123_456_789_012;
    f.header.boundary = [
        [Boundary::ShrinkMin, Boundary::Shrink],
        [Boundary::Fixed, Boundary::Fixed],
        [Boundary::Shrink, Boundary::ShrinkMin],
    ];
    f.groups = vec![Some("all".into()), None, Some("mobile".into())];
    f.type_mass = Some(vec![1.5, 2.5]);
    f.pair = Some(PairSection::Gran {
        model: GranModel::from_hashcode(790659).unwrap(),
        setflag: vec![1, 0, 1],
    });
    let k = f.peratom_fix("contacthistory").unwrap();
    let mut g = f.global_fixes.pop().unwrap();
    g.state = [6.0f64, 2.0].iter().flat_map(|v| v.to_le_bytes()).collect();
    f.global_fixes.push(g);
    for a in &mut f.atoms {
        a.mask = 1 | 4;
        if let FixAtomData::Contacts(cs) = &mut a.fix_data[k] {
            for c in cs.iter_mut() {
                c.history.extend([1e-9, -2e-9, 3e-9]);
            }
        }
        a.fix_data
            .push(FixAtomData::Values(vec![a.radius, -0.0, f64::MIN_POSITIVE]));
    }
    f.peratom_fixes.push(dem_io::restart::PerAtomFix {
        id: "something".into(),
        style: "property/atom".into(),
        max_size: 0,
    });
    f.update_max_sizes();
    f.chunks = vec![25, 0, 15];
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sub/dir/copy.restart");
    write_restart_file(&path, &f).unwrap();
    let back = read_restart(&path).unwrap();
    assert_eq!(back, f);
    // -0.0 kept as such
    assert!(matches!(
        back.atoms[0].fix_data.last(),
        Some(FixAtomData::Values(v)) if v[1].is_sign_negative()
    ));
}

/// The writer refuses what the layout cannot hold instead of writing a file LIGGGHTS would
/// misread.
#[test]
fn writer_refuses_inconsistent_content() {
    let mut f = liggghts_file();
    f.chunks = vec![39];
    assert!(write_restart(&mut Vec::new(), &f).is_err());
    let mut f = liggghts_file();
    f.peratom_fixes[0].max_size = 1;
    let e = write_restart(&mut Vec::new(), &f).unwrap_err();
    assert!(e.to_string().contains("update_max_sizes"), "{e}");
    let mut f = liggghts_file();
    f.atoms[3].atom_type = 3;
    assert!(write_restart(&mut Vec::new(), &f).is_err());
}

fn read_bytes(bytes: &[u8]) -> Result<RestartFile, dem_io::restart::RestartError> {
    read_restart_from(bytes, Path::new("test.restart"), bytes.len() as u64)
}

/// A file cut anywhere is refused as truncated (or, within the atom chunk, as a chunk that
/// does not fit the rest of the file), naming the file and an offset inside it.
#[test]
fn truncated_files_are_refused_with_their_offset() {
    let bytes = std::fs::read(fixture("restart.25000")).unwrap();
    for cut in [0, 3, 10, 200, 580, 1000, 1180, 5000, bytes.len() - 1] {
        let e = read_bytes(&bytes[..cut]).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with("test.restart"), "{msg}");
        match e.kind {
            RestartErrorKind::Truncated { .. } | RestartErrorKind::BadRecord(_) => {}
            RestartErrorKind::NotRestart { .. } if cut < 16 => {}
            ref k => panic!("cut at {cut}: {k:?}"),
        }
        let offset = e.offset.unwrap();
        assert!(offset <= cut as u64, "cut at {cut}: offset {offset}");
    }
    let path = fixture("restart.25000");
    let dir = tempfile::tempdir().unwrap();
    let short = dir.path().join("short.restart");
    std::fs::write(&short, &std::fs::read(&path).unwrap()[..5000]).unwrap();
    let e = read_restart(&short).unwrap_err();
    assert!(e.to_string().contains("short.restart (byte "), "{e}");
    assert!(matches!(
        e.kind,
        RestartErrorKind::Truncated { .. } | RestartErrorKind::BadRecord(_)
    ));
}

#[test]
fn other_files_are_not_restart_files() {
    let e = read_restart(fixture("state.txt")).unwrap_err();
    assert!(matches!(e.kind, RestartErrorKind::NotRestart { .. }), "{e}");
    assert_eq!(e.offset, Some(0));
    assert!(e.to_string().contains("ITEM: TIMESTEP"), "{e}");
    let e = read_bytes(b"").unwrap_err();
    assert!(matches!(e.kind, RestartErrorKind::NotRestart { .. }), "{e}");
    let e = read_bytes(b"LammpS RestartT\x01\x00\x00\x00").unwrap_err();
    assert!(matches!(e.kind, RestartErrorKind::NewerLammps), "{e}");
    // a binary dump of LIGGGHTS
    let e = read_restart(testkit::fixture("liggghts/settle.bin")).unwrap_err();
    assert!(matches!(e.kind, RestartErrorKind::NotRestart { .. }), "{e}");
}

/// Replaces `from` by `to` (same length) at its first occurrence.
fn patched(from: &[u8], to: &[u8]) -> Vec<u8> {
    let mut b = std::fs::read(fixture("restart.25000")).unwrap();
    let at = b.windows(from.len()).position(|w| w == from).unwrap();
    b[at..at + to.len()].copy_from_slice(to);
    b
}

#[test]
fn another_atom_style_or_version_is_refused() {
    let b = patched(b"granular\0", b"ellipsoi\0");
    let e = read_bytes(&b).unwrap_err();
    assert!(
        matches!(&e.kind, RestartErrorKind::UnsupportedAtomStyle { found } if found == "ellipsoi"),
        "{e}"
    );
    let style_at = b.windows(8).position(|w| w == b"ellipsoi").unwrap() as u64;
    assert_eq!(e.offset, Some(style_at - 8), "the record's flag");
    assert!(e.to_string().contains("atom style `ellipsoi`"), "{e}");

    let e = read_bytes(&patched(b"3.8.0,", b"3.7.1,")).unwrap_err();
    assert!(
        matches!(&e.kind, RestartErrorKind::UnsupportedVersion { found } if found.contains("3.7.1")),
        "{e}"
    );
    let e = read_bytes(&patched(b"LIGGGHTS-PUBLIC", b"LAMMPS-PUBLICXX")).unwrap_err();
    assert!(
        matches!(e.kind, RestartErrorKind::UnsupportedVersion { .. }),
        "{e}"
    );
}

#[test]
fn corrupt_atom_records_are_refused() {
    let bytes = std::fs::read(fixture("restart.25000")).unwrap();
    let f = liggghts_file();
    // the first atom record starts 4 bytes into the chunk: its length value
    let n = f.atoms.len();
    let chunk_values: usize = f.atoms.iter().map(record_len).sum();
    let first = bytes.len() - 8 * chunk_values;
    let mut b = bytes.clone();
    b[first..first + 8].copy_from_slice(&5.0f64.to_le_bytes());
    let e = read_bytes(&b).unwrap_err();
    assert!(
        matches!(e.kind, RestartErrorKind::BadAtom { index: 0, .. }),
        "{e}"
    );
    assert_eq!(e.offset, Some(first as u64));
    // a type outside 1..=2
    let mut b = bytes.clone();
    let at = first + 5 * 8;
    b[at..at + 8].copy_from_slice(&7i64.to_le_bytes());
    let e = read_bytes(&b).unwrap_err();
    assert!(e.to_string().contains("type 7 outside 1..=2"), "{e}");
    assert_eq!(e.offset, Some(at as u64));
    // a wall block longer than its fix declares
    let mut b = bytes.clone();
    let at = first + 17 * 8;
    b[at..at + 8].copy_from_slice(&9.0f64.to_le_bytes());
    let e = read_bytes(&b).unwrap_err();
    assert!(
        e.to_string().contains("fix history_floor block length"),
        "{e}"
    );
    assert_eq!(n, 40);
}

fn record_len(a: &AtomRecord) -> usize {
    17 + a
        .fix_data
        .iter()
        .map(FixAtomData::stored_len)
        .sum::<usize>()
}
