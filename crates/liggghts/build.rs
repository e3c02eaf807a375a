//! Emits the link flags for Debian's libliggghts only when the `link` feature is on, so the
//! default build needs no LIGGGHTS at all.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    if std::env::var_os("CARGO_FEATURE_LINK").is_some() {
        println!("cargo:rustc-link-lib=dylib=liggghts");
    }
}
