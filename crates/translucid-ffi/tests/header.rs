//! The committed header must be what cbindgen makes of the current source, and its names must
//! follow the rules its opening comment states (functions, structure types, macros).

use std::collections::BTreeSet;
use std::path::PathBuf;

fn header_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../include/translucid.h")
}

/// What cbindgen makes of the crate now (the name tests read this, not the committed file, so
/// that they judge the source even before the header is regenerated).
fn generated_header() -> String {
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
    String::from_utf8(generated).expect("the header is UTF-8")
}

#[test]
fn committed_header_is_fresh() {
    let generated = generated_header();
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

const STRUCTURE_TYPE: &str = "TRANSLUCID_STRUCTURE_TYPE_";

/// The `TRANSLUCID_STRUCTURE_TYPE_*` enumerators, without the prefix.
fn structure_types(header: &str) -> Vec<String> {
    let start = header
        .find("enum translucid_structure_type")
        .expect("the header defines enum translucid_structure_type");
    let body = &header[start..];
    let body = &body[..body.find("};").expect("the enum ends")];
    body.lines()
        .map(str::trim)
        .filter_map(|line| line.strip_prefix(STRUCTURE_TYPE))
        .filter_map(|line| line.split_once(" = "))
        .map(|(name, _)| name.to_owned())
        .collect()
}

/// Every struct the header defines (with a body), without the `translucid_` prefix, and its
/// body's text.
fn structs(header: &str) -> Vec<(String, &str)> {
    let mut found = Vec::new();
    let mut rest = header;
    while let Some(at) = rest.find("typedef struct translucid_") {
        rest = &rest[at + "typedef struct translucid_".len()..];
        let Some((name, after)) = rest.split_once(' ') else {
            break;
        };
        // `typedef struct translucid_context translucid_context;` is opaque: no body.
        if !after.starts_with('{') {
            continue;
        }
        let end = after.find("\n}").expect("the struct ends");
        found.push((name.to_owned(), &after[..end]));
    }
    found
}

fn has_s_type(body: &str) -> bool {
    body.lines().any(|line| line.trim() == "uint32_t s_type;")
}

/// Each `TRANSLUCID_STRUCTURE_TYPE_X` tags the struct `translucid_x`: the name says which
/// struct to zero-initialise and fill, as Vulkan's `VK_STRUCTURE_TYPE_*` do.
#[test]
fn structure_types_are_named_after_their_structures() {
    let header = generated_header();
    let types = structure_types(&header);
    assert!(!types.is_empty(), "no structure types found in the header");
    let structs = structs(&header);
    let tagged: BTreeSet<&str> = structs
        .iter()
        .filter(|(_, body)| has_s_type(body))
        .map(|(name, _)| name.as_str())
        // The header of every chained struct, which any structure type may begin.
        .filter(|name| *name != "base_in_structure")
        .collect();
    let mut wrong = Vec::new();
    for t in &types {
        let name = t.to_ascii_lowercase();
        if !tagged.contains(name.as_str()) {
            wrong.push(format!(
                "{STRUCTURE_TYPE}{t} names no struct translucid_{name} with an s_type"
            ));
        }
    }
    for name in &tagged {
        let t = name.to_ascii_uppercase();
        if !types.contains(&t) {
            wrong.push(format!(
                "struct translucid_{name} has an s_type but no {STRUCTURE_TYPE}{t}"
            ));
        }
    }
    // The s_type each struct documents is its own.
    for (name, body) in &structs {
        let own = format!("{STRUCTURE_TYPE}{}", name.to_ascii_uppercase());
        for (at, _) in body.match_indices(STRUCTURE_TYPE) {
            let named: String = body[at..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if named != own && named != STRUCTURE_TYPE {
                wrong.push(format!(
                    "struct translucid_{name} documents {named}, not {own}"
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// The functions the header declares.
fn functions(header: &str) -> Vec<String> {
    let start = header
        .find("extern \"C\" {")
        .expect("the header declares functions");
    header[start..]
        .lines()
        .skip(1)
        // Declarations start at the line's start; doc comments and arguments do not.
        .filter(|line| line.starts_with(|c: char| c.is_ascii_alphabetic()))
        .filter_map(|line| line.split_once('('))
        .filter_map(|(before, _)| before.rsplit([' ', '*']).next())
        .filter(|name| name.starts_with("translucid_"))
        .map(str::to_owned)
        .collect()
}

/// The rule the header's opening comment states: `translucid_<object>_<verb>[_<what>]`, but
/// for the few functions that only name a constant.
#[test]
fn functions_are_named_object_verb_what() {
    const OBJECTS: &[&str] = &[
        "context", "mesh", "texture", "material", "frame", "host", "method",
    ];
    const VERBS: &[&str] = &[
        "create", "destroy", "get", "update", "render", "read", "write", "record", "complete",
        "abandon", "prepare", "trim",
    ];
    const NAMES_OF_CONSTANTS: &[&str] = &[
        "translucid_version",
        "translucid_version_string",
        "translucid_result_string",
        "translucid_method_name",
    ];
    let header = generated_header();
    let functions = functions(&header);
    assert!(
        functions.iter().any(|f| f == "translucid_context_create"),
        "the header's functions were not found: {functions:?}"
    );
    let wrong: Vec<&String> = functions
        .iter()
        .filter(|f| !NAMES_OF_CONSTANTS.contains(&f.as_str()))
        .filter(|f| {
            let mut words = f.split('_').skip(1);
            let object = words.next().unwrap_or_default();
            let verb = words.next().unwrap_or_default();
            !(OBJECTS.contains(&object) && VERBS.contains(&verb))
        })
        .collect();
    assert!(
        wrong.is_empty(),
        "not translucid_<object>_<verb>[_<what>] (objects {OBJECTS:?}, verbs {VERBS:?}): \
         {wrong:?}"
    );
}

/// Macros are `TRANSLUCID_*`: a lower-case one is a Rust constant cbindgen wrote out by mistake
/// (an array of Rust names that C does not know).
#[test]
fn macros_are_upper_case() {
    let header = generated_header();
    let wrong: Vec<&str> = header
        .lines()
        .filter_map(|line| line.strip_prefix("#define "))
        .filter_map(|rest| rest.split([' ', '(']).next())
        .filter(|name| !name.starts_with("TRANSLUCID_") || *name != name.to_ascii_uppercase())
        .collect();
    assert!(wrong.is_empty(), "macros not named TRANSLUCID_*: {wrong:?}");
}
