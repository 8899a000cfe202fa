//! What every compiled shader may ask of a device, read from its SPIR-V: no 64-bit floats
//! anywhere (consumer GPUs run them at 1/16 to 1/64 rate, some have none), so that no method
//! needs `shaderFloat64`. Specialization constants do not change a module's types or
//! capabilities, so checking each module covers every variant the host builds from it.

use std::path::{Path, PathBuf};

const OP_CAPABILITY: u32 = 17;
const OP_TYPE_FLOAT: u32 = 22;
const CAPABILITY_FLOAT64: u32 = 10;

/// Every `.spv` file under `dir`.
fn modules(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).expect("read the shader folder") {
        let path = entry.expect("a folder entry").path();
        if path.is_dir() {
            found.extend(modules(&path));
        } else if path.extension().is_some_and(|e| e == "spv") {
            found.push(path);
        }
    }
    found
}

/// The module's instructions as (opcode, operands).
fn instructions(words: &[u32]) -> Vec<(u32, &[u32])> {
    let mut out = Vec::new();
    let mut at = 5; // past the header
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        assert!(count > 0 && at + count <= words.len(), "malformed SPIR-V");
        out.push((words[at] & 0xFFFF, &words[at + 1..at + count]));
        at += count;
    }
    out
}

/// What in `words` uses 64-bit floats.
fn float64_uses(words: &[u32]) -> Vec<String> {
    instructions(words)
        .into_iter()
        .filter_map(|(op, operands)| match (op, operands) {
            (OP_CAPABILITY, [CAPABILITY_FLOAT64]) => Some("the Float64 capability".into()),
            (OP_TYPE_FLOAT, [_, 64, ..]) => Some("a 64-bit float type".into()),
            _ => None,
        })
        .collect()
}

#[test]
fn no_shader_uses_64_bit_floats() {
    let root = Path::new(env!("OUT_DIR")).join("shaders");
    let modules = modules(&root);
    assert!(
        modules.len() > 30,
        "{} modules under {}",
        modules.len(),
        root.display()
    );
    let mut offenders = Vec::new();
    for path in modules {
        let bytes = std::fs::read(&path).expect("read a module");
        let words = ash::util::read_spv(&mut std::io::Cursor::new(bytes)).expect("SPIR-V");
        let uses = float64_uses(&words);
        if !uses.is_empty() {
            offenders.push(format!("{}: {}", path.display(), uses.join(", ")));
        }
    }
    assert!(offenders.is_empty(), "{}", offenders.join("\n"));
}

#[test]
fn the_check_finds_a_64_bit_float() {
    // A header, OpCapability Float64, OpTypeFloat %1 64.
    let words = [
        0x0723_0203,
        0x0001_0500,
        0,
        2,
        0,
        2 << 16 | 17,
        10,
        3 << 16 | 22,
        1,
        64,
    ];
    assert_eq!(float64_uses(&words).len(), 2);
}
