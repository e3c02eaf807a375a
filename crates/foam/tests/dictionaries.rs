//! Dictionary features: #include, #inputMode, #remove, $var scoping, uniform lists, patterns,
//! gzip, and errors that name the file and line.

use foam::{parse_bytes, parse_file, Dict, Item, Value};
use std::path::Path;

fn parse(s: &str) -> Dict {
    parse_bytes(s.as_bytes(), Path::new("test.dict"))
        .unwrap()
        .body
}

fn err(s: &str) -> String {
    parse_bytes(s.as_bytes(), Path::new("test.dict"))
        .unwrap_err()
        .to_string()
}

#[test]
fn variables_are_scoped_like_openfoam() {
    let d = parse(
        "a 1; vel (1 2 3);\n\
         sub { a 2; b $a; c $..a; d $:vel; inner { e $a; } }\n\
         copy $sub;\n\
         g ${a}; h $:sub.inner.e;",
    );
    let sub = d.dict("sub").unwrap();
    assert_eq!(sub.f64("b").unwrap(), 2.0); // nearest scope first
    assert_eq!(sub.f64("c").unwrap(), 1.0); // $..a: parent scope
    assert_eq!(sub.vector("d").unwrap(), [1.0, 2.0, 3.0]);
    assert_eq!(sub.dict("inner").unwrap().f64("e").unwrap(), 2.0);
    assert_eq!(d.f64("h").unwrap(), 2.0); // $:a.b.c walks from the top
    assert_eq!(d.dict("copy").unwrap(), sub); // a dictionary variable copies the dictionary
    assert_eq!(d.f64("g").unwrap(), 1.0);
    let merged = parse("base { x 1; y 2; } derived { $base; y 3; }");
    let der = merged.dict("derived").unwrap();
    assert_eq!((der.f64("x").unwrap(), der.f64("y").unwrap()), (1.0, 3.0));
    assert!(
        err("a $nope;").contains("line 1")
            && err("a $nope;").contains("undefined variable `$nope`")
    );
}

#[test]
fn input_modes_and_remove() {
    let d = parse("a 1; s { x 1; y 1; } a 2; s { y 2; z 2; }");
    assert_eq!(d.f64("a").unwrap(), 2.0);
    let s = d.dict("s").unwrap();
    assert_eq!(s.keys().collect::<Vec<_>>(), ["x", "y", "z"]); // merge keeps order
    assert_eq!(s.f64("y").unwrap(), 2.0);
    let d = parse("s { x 1; } #inputMode overwrite s { y 2; }");
    assert_eq!(d.dict("s").unwrap().keys().collect::<Vec<_>>(), ["y"]);
    let d = parse("a 1; #inputMode protect a 2;");
    assert_eq!(d.f64("a").unwrap(), 1.0);
    let f = parse_bytes(b"a 1; #inputMode warn a 2;", Path::new("w")).unwrap();
    assert_eq!(f.body.f64("a").unwrap(), 1.0);
    assert!(f.warnings[0].contains("duplicate entry `a`"));
    assert!(err("a 1;\n#inputMode error\na 2;").contains("line 3"));
    let d = parse("a 1; b 2; c 3; #remove (a c)");
    assert_eq!(d.keys().collect::<Vec<_>>(), ["b"]);
    assert!(err("#calc \"1+1\";").contains("`#calc` is not supported"));
}

#[test]
fn includes_resolve_relative_to_the_including_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("inc")).unwrap();
    std::fs::write(
        dir.path().join("inc/common"),
        "FoamFile { version 2.0; format ascii; class dictionary; object common; }\nnu 1e-05; rho 10; #include \"more\"",
    )
    .unwrap();
    std::fs::write(dir.path().join("inc/more"), "g (0 0 -9.81);").unwrap();
    std::fs::write(
        dir.path().join("main"),
        "#include \"inc/common\"\nmu #calcless;\n",
    )
    .unwrap();
    // `#calcless` is an unsupported directive inside a value: clear error with the line.
    let e = parse_file(&dir.path().join("main"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("main: line 2") && e.contains("#calcless"), "{e}");
    std::fs::write(
        dir.path().join("main"),
        "#include \"inc/common\"\n#includeIfPresent \"absent\"\nnuCopy $nu;\n",
    )
    .unwrap();
    let d = parse_file(&dir.path().join("main")).unwrap().body;
    assert_eq!(d.keys().collect::<Vec<_>>(), ["nu", "rho", "g", "nuCopy"]);
    assert_eq!(d.vector("g").unwrap(), [0.0, 0.0, -9.81]);
    assert_eq!(d.f64("nuCopy").unwrap(), 1e-5);
    std::fs::write(dir.path().join("loop"), "#include \"loop\"").unwrap();
    let e = parse_file(&dir.path().join("loop"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("nested deeper"), "{e}");
    std::fs::write(dir.path().join("missing"), "a 1;\n#include \"nothere\"").unwrap();
    let e = parse_file(&dir.path().join("missing"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("missing: line 2") && e.contains("nothere"),
        "{e}"
    );
}

#[test]
fn lists_dimensions_and_patterns() {
    let d = parse(
        "dims [0 1 -1 0 0 0 0];\n\
         groups 2{wall};\n\
         l 3(1 2 3);\n\
         t List<scalar> 3{0.5};\n\
         v List<vector> 2((1 2 3) (4 5 6));\n\
         \"(left|right)Wall\" { type slip; }\n\
         empty ();\n\
         flag;\n",
    );
    assert_eq!(
        d.item("dims").unwrap(),
        &Item::Dims(
            [0, 1, -1, 0, 0, 0, 0]
                .iter()
                .map(|&x| Item::Label(x))
                .collect()
        )
    );
    assert_eq!(
        d.item("groups").unwrap(),
        &Item::List(vec![Item::Word("wall".into()); 2])
    );
    // As in OpenFOAM, a count before a list stays a token of its own: `arc 0 5 (x y z)` in a
    // blockMeshDict is a vertex label followed by a point, not a list of five.
    let l = d.stream("l").unwrap();
    assert_eq!(l[0], Item::Label(3));
    assert_eq!(l[1].as_f64_list().unwrap(), [1.0, 2.0, 3.0]);
    let arc = parse("edges (arc 0 5 (0.4 0.1 0) arc 1 3 (1 2 3));");
    let Item::List(e) = arc.item("edges").unwrap() else {
        panic!()
    };
    assert_eq!(e[2], Item::Label(5));
    assert_eq!(e[7].as_vector(), Some([1.0, 2.0, 3.0]));
    // `$var` at keyword position without `;`, and `$U` found through a pattern keyword.
    let sv = parse(
        "solvers { \"(U|k)\" { tol 1e-6; } wall { a 1; } UFinal { $U; relTol 0; } g { $wall } }",
    );
    let s = sv.dict("solvers").unwrap();
    assert_eq!(s.dict("UFinal").unwrap().f64("tol").unwrap(), 1e-6);
    assert_eq!(s.dict("g").unwrap().f64("a").unwrap(), 1.0);
    assert_eq!(d.stream("t").unwrap()[1], Item::Scalars(vec![0.5; 3]));
    assert_eq!(
        d.stream("v").unwrap()[1],
        Item::Vectors(vec![[1., 2., 3.], [4., 5., 6.]])
    );
    assert_eq!(
        d.resolve("leftWall", &[]).unwrap().keyword,
        "(left|right)Wall"
    );
    assert_eq!(d.item("empty").unwrap(), &Item::List(vec![]));
    assert_eq!(d.get("flag"), Some(&Value::Stream(vec![])));
}

#[test]
fn malformed_text_is_reported_with_its_line() {
    let cases = [
        ("a 1;\nb (1 2;\n", "line 2"),
        ("a { b 1;\n", "never closed"),
        ("a 1\n", "not ended by `;`"),
        (
            "x List<scalar> 2(1 abc);",
            "expected a scalar, found word `abc`",
        ),
        ("x List<vector> 1((1 2));", "component 2 should be a number"),
        ("x 1.2.3;", "malformed number `1.2.3`"),
        ("}", "expected a keyword"),
        ("a \"open;", "string is never closed"),
        ("x List<scalar> 99999999(1);", "impossible"),
    ];
    for (text, want) in cases {
        let e = err(text);
        assert!(e.starts_with("test.dict: line "), "{text:?}: {e}");
        assert!(e.contains(want), "{text:?}: {e}");
    }
}

#[test]
fn gzipped_files_are_read_transparently() {
    use std::io::Write;
    let dir = tempfile::tempdir().unwrap();
    let f = std::fs::File::create(dir.path().join("d.gz")).unwrap();
    let mut gz = flate2::write::GzEncoder::new(f, flate2::Compression::default());
    gz.write_all(b"a 42;").unwrap();
    gz.finish().unwrap();
    let d = parse_file(&dir.path().join("d")).unwrap().body;
    assert_eq!(d.label("a").unwrap(), 42);
}
