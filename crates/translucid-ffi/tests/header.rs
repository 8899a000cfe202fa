//! The committed header must be what cbindgen makes of the current source.

use std::path::PathBuf;

fn header_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../include/translucid.h")
}

#[test]
fn committed_header_is_fresh() {
    let crate_dir = env!("CARGO_MANIFEST_DIR");
    let config = cbindgen::Config::from_file(format!("{crate_dir}/cbindgen.toml"))
        .expect("crates/translucid-ffi/cbindgen.toml parses");
    let mut generated = Vec::new();
    cbindgen::Builder::new()
        .with_crate(crate_dir)
        .with_config(config)
        .generate()
        .expect("cbindgen can read crates/translucid-ffi")
        .write(&mut generated);
    let generated = String::from_utf8(generated).expect("the header is UTF-8");
    let path = header_path();
    if std::env::var("TRANSLUCID_BLESS").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &generated).expect("write include/translucid.h");
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "include/translucid.h is not what cbindgen makes of crates/translucid-ffi: you changed \
         an exported type or function (or its doc comment) without regenerating the header. Run\n\
         \n    TRANSLUCID_BLESS=1 cargo test -p translucid-ffi --test header\n\n\
         review the diff of include/translucid.h, and commit it."
    );
}
