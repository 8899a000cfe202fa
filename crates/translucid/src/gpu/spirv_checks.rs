//! What every compiled shader may ask of a device, read from its SPIR-V: no 64-bit floats
//! anywhere (consumer GPUs run them at 1/16 to 1/64 rate, some have none), so that no method
//! needs `shaderFloat64`. Specialization constants do not change a module's types or
//! capabilities, so checking each module covers every variant the host builds from it.
//! And what the mesh pipelines' stages hand on: every output the next stage reads, so that
//! validation finds nothing left unread (`Shader-OutputNotConsumed`).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

const OP_ENTRY_POINT: u32 = 15;
const OP_CAPABILITY: u32 = 17;
const OP_TYPE_FLOAT: u32 = 22;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const CAPABILITY_FLOAT64: u32 = 10;
const DECORATION_LOCATION: u32 = 30;
const STORAGE_INPUT: u32 = 1;
const STORAGE_OUTPUT: u32 = 3;

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

/// The locations of the entry point's variables of `storage` (input or output).
fn interface_locations(words: &[u32], storage: u32) -> BTreeSet<u32> {
    let ops = instructions(words);
    let interface: BTreeSet<u32> = ops
        .iter()
        .filter(|(op, _)| *op == OP_ENTRY_POINT)
        .flat_map(|(_, operands)| {
            // Model, id, a NUL-terminated name padded to words, then the interface ids.
            let name_words = operands[2..]
                .iter()
                .position(|w| w.to_le_bytes().contains(&0))
                .map_or(0, |p| p + 1);
            operands[2 + name_words..].iter().copied()
        })
        .collect();
    let of_storage: BTreeSet<u32> = ops
        .iter()
        .filter_map(|(op, operands)| match (*op, *operands) {
            (OP_VARIABLE, [_, id, class, ..]) if *class == storage => Some(*id),
            _ => None,
        })
        .collect();
    ops.iter()
        .filter_map(|(op, operands)| match (*op, *operands) {
            (OP_DECORATE, [id, DECORATION_LOCATION, location])
                if interface.contains(id) && of_storage.contains(id) =>
            {
                Some(*location)
            }
            _ => None,
        })
        .collect()
}

fn module_words(name: &str) -> Vec<u32> {
    let path = Path::new(env!("OUT_DIR"))
        .join("shaders")
        .join(format!("{name}.spv"));
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    ash::util::read_spv(&mut std::io::Cursor::new(bytes)).expect("SPIR-V")
}

/// Each mesh pipeline that orders fragments as the reference does: vertex, geometry and
/// fragment stage (`assets::MeshStages`), each stage's outputs all read by the next.
#[test]
fn mesh_stages_hand_on_only_what_the_next_stage_reads() {
    let pipelines = [
        [
            "scene/ordered.vert",
            "scene/ordered.geom",
            "linked_list/append.frag",
        ],
        [
            "scene/ordered.vert",
            "scene/ordered.geom",
            "depth_peeling/peel.frag",
        ],
        [
            "scene/ordered_order_only.vert",
            "scene/ordered_order_only.geom",
            "depth_peeling/first.frag",
        ],
        [
            "scene/ordered_order_only.vert",
            "scene/ordered_order_only.geom",
            "wavelet/bounds.frag",
        ],
        [
            "scene/ordered_unlit.vert",
            "scene/ordered_unlit.geom",
            "wavelet/accumulate_rank0.frag",
        ],
        [
            "scene/ordered_unlit.vert",
            "scene/ordered_unlit.geom",
            "wavelet/accumulate_rank3.frag",
        ],
        [
            "scene/ordered.vert",
            "scene/ordered.geom",
            "wavelet/shade_rank0.frag",
        ],
        [
            "scene/ordered.vert",
            "scene/ordered.geom",
            "wavelet/shade_rank3.frag",
        ],
    ];
    for stages in pipelines {
        for pair in stages.windows(2) {
            let written = interface_locations(&module_words(pair[0]), STORAGE_OUTPUT);
            let read = interface_locations(&module_words(pair[1]), STORAGE_INPUT);
            assert!(!written.is_empty(), "{} writes no location", pair[0]);
            let unread: Vec<_> = written.difference(&read).collect();
            assert!(
                unread.is_empty(),
                "{} writes locations {unread:?} that {} does not read",
                pair[0],
                pair[1]
            );
        }
    }
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
