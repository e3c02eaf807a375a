//! Property tests: random dictionaries survive write → read exactly in both formats, and no
//! truncation or corruption of real files makes a reader panic.

use foam::{parse_bytes, Arch, Dict, Format, Header, Item, Value};
use proptest::prelude::*;
use std::path::{Path, PathBuf};

fn word() -> impl Strategy<Value = String> {
    "[a-zA-Z][a-zA-Z0-9_]{0,8}".prop_filter("not a directive word", |w| {
        !matches!(w.as_str(), "inf" | "nan" | "FoamFile")
    })
}

fn finite() -> impl Strategy<Value = f64> {
    prop_oneof![
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
        -1e6..1e6f64,
        Just(0.0),
        Just(-0.0),
    ]
}

fn leaf() -> impl Strategy<Value = Item> {
    prop_oneof![
        word().prop_map(Item::Word),
        "[ -~&&[^\"\\\\]]{0,10}".prop_map(Item::Str),
        any::<i64>().prop_map(Item::Label),
        finite().prop_map(Item::Scalar),
        prop::collection::vec(any::<i64>().prop_map(Item::Label), 0..7).prop_map(Item::Dims),
    ]
}

/// Generic items, nested lists included.
fn item() -> impl Strategy<Value = Item> {
    leaf().prop_recursive(3, 24, 12, |inner| {
        prop::collection::vec(inner, 0..14).prop_map(Item::List)
    })
}

/// Typed lists with the `List<T>` word that announces them, as in real files.
fn typed() -> impl Strategy<Value = Vec<Item>> {
    let w = |s: &str| Item::Word(s.into());
    prop_oneof![
        prop::collection::vec(finite(), 0..20)
            .prop_map(move |v| vec![w("List<scalar>"), Item::Scalars(v)]),
        prop::collection::vec(prop::array::uniform3(finite()), 0..10)
            .prop_map(move |v| vec![w("List<vector>"), Item::Vectors(v)]),
        prop::collection::vec(-1_000_000i64..1_000_000, 0..20)
            .prop_map(move |v| vec![w("List<label>"), Item::Labels(v)]),
    ]
}

fn stream() -> impl Strategy<Value = Vec<Item>> {
    prop::collection::vec(
        prop_oneof![3 => item().prop_map(|i| vec![i]), 1 => typed()],
        1..4,
    )
    .prop_map(|parts| parts.into_iter().flatten().collect())
}

fn dict(depth: u32) -> BoxedStrategy<Dict> {
    let stream = stream().prop_map(Value::Stream);
    let value = if depth == 0 {
        stream.boxed()
    } else {
        prop_oneof![3 => stream, 1 => dict(depth - 1).prop_map(Value::Dict)].boxed()
    };
    prop::collection::vec((word(), value), 0..6)
        .prop_map(|kv| {
            let mut d = Dict::new();
            for (k, v) in kv {
                d.set(&k, v);
            }
            d
        })
        .boxed()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn dictionaries_round_trip(d in dict(2), binary in any::<bool>()) {
        let h = Header {
            format: if binary { Format::Binary } else { Format::Ascii },
            arch: Arch::default(),
            class: "dictionary".into(),
            object: "d".into(),
            location: String::new(),
            note: None,
        };
        let bytes = foam::writer::dict_file_bytes(&h, &d).unwrap();
        let back = parse_bytes(&bytes, Path::new("d")).unwrap();
        prop_assert_eq!(back.header.unwrap().format, h.format);
        prop_assert_eq!(back.body, d);
    }

    #[test]
    fn garbage_never_panics(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        let _ = parse_bytes(&bytes, Path::new("g"));
    }
}

fn fixture(rel: &str) -> PathBuf {
    testkit::fixture("foam").join(rel)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]

    /// Truncating or flipping a byte of any real mesh file gives Ok or Err, never a panic.
    #[test]
    fn damaged_real_files_never_panic(
        case in prop::sample::select(vec!["cavity", "cavity-binary"]),
        file in prop::sample::select(vec!["points", "faces", "owner", "neighbour", "boundary"]),
        cut in 0.0..1.0f64,
        flip in any::<(usize, u8)>(),
    ) {
        let src = fixture(case).join("constant/polyMesh");
        let dir = tempfile::tempdir().unwrap();
        for f in ["points", "faces", "owner", "neighbour", "boundary"] {
            let mut b = std::fs::read(src.join(f)).unwrap();
            if f == file {
                let n = (b.len() as f64 * cut) as usize;
                if flip.0 % 2 == 0 { b.truncate(n); } else if !b.is_empty() { let i = flip.0 % b.len(); b[i] = flip.1; }
            }
            std::fs::write(dir.path().join(f), b).unwrap();
        }
        let _ = foam::read_poly_mesh(dir.path());
    }
}
