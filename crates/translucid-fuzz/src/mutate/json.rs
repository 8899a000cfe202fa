//! Structural mutations of a glTF JSON document: each one edits the parsed tree the way a
//! broken exporter or a hostile file would (extreme numbers, dangling indices, missing
//! required keys, wrong enums, cyclic or exploding node graphs, hostile URIs, inconsistent
//! accessors...), so the result is still JSON and gets past the parser to the importer.

use crate::rng::Rng;
use serde_json::{json, Map, Value};

/// What a mutation may refer to by name.
pub struct Context<'a> {
    /// The mutant's own file name (a URI naming it makes the file its own buffer).
    pub self_name: &'a str,
    /// Files beside the seed, by relative path.
    pub siblings: Vec<String>,
}

type Op = fn(&mut Value, &mut Rng, &Context) -> Option<String>;

/// Each operation with a weight; an operation that does not apply (nothing to edit)
/// returns `None` and another is drawn.
const OPS: &[(Op, u32)] = &[
    (extreme_number, 6),
    (index_out_of_range, 6),
    (delete_key, 5),
    (enum_value, 5),
    (node_graph, 4),
    (uri, 4),
    (accessor, 6),
    (buffer_view, 4),
    (sparse, 3),
    (camera, 3),
    (image, 3),
    (material, 3),
    (extensions, 2),
    (transform, 3),
    (type_confusion, 2),
    (array_shape, 3),
    (primitive, 4),
    (morph_and_skin, 2),
];

/// Applies one to three structural mutations to `doc`; returns a note for each.
pub fn mutate(doc: &mut Value, rng: &mut Rng, ctx: &Context) -> Vec<String> {
    let count = rng.pick_copy(&[1, 1, 1, 2, 2, 3]);
    let total: u32 = OPS.iter().map(|(_, w)| w).sum();
    let mut notes = Vec::new();
    for _ in 0..count {
        for _attempt in 0..16 {
            let mut ticket = (rng.next_u64() % u64::from(total)) as u32;
            let op = OPS
                .iter()
                .find(|(_, w)| {
                    let hit = ticket < *w;
                    ticket = ticket.saturating_sub(*w);
                    hit
                })
                .map_or(OPS[0].0, |(op, _)| *op);
            if let Some(note) = op(doc, rng, ctx) {
                notes.push(note);
                break;
            }
        }
    }
    notes
}

// ---- paths into the tree ----

#[derive(Clone, Debug, PartialEq)]
enum Seg {
    Key(String),
    Index(usize),
}

type JPath = Vec<Seg>;

fn show(path: &[Seg]) -> String {
    let mut out = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) if out.is_empty() => out.push_str(k),
            Seg::Key(k) => {
                out.push('.');
                out.push_str(k);
            }
            Seg::Index(i) => out.push_str(&format!("[{i}]")),
        }
    }
    if out.is_empty() {
        "(root)".into()
    } else {
        out
    }
}

/// Every value below the root, depth first. Long arrays of numbers (matrices, min/max)
/// count once per element, which is fine: they are rare in glTF JSON.
fn paths(root: &Value) -> Vec<JPath> {
    fn walk(v: &Value, path: &mut JPath, out: &mut Vec<JPath>) {
        match v {
            Value::Object(map) => {
                for (k, child) in map {
                    path.push(Seg::Key(k.clone()));
                    out.push(path.clone());
                    walk(child, path, out);
                    path.pop();
                }
            }
            Value::Array(items) => {
                for (i, child) in items.iter().enumerate() {
                    path.push(Seg::Index(i));
                    out.push(path.clone());
                    walk(child, path, out);
                    path.pop();
                }
            }
            _ => {}
        }
    }
    let mut out = Vec::new();
    walk(root, &mut Vec::new(), &mut out);
    out
}

fn get<'v>(root: &'v Value, path: &[Seg]) -> Option<&'v Value> {
    path.iter().try_fold(root, |v, seg| match seg {
        Seg::Key(k) => v.get(k),
        Seg::Index(i) => v.get(i),
    })
}

fn get_mut<'v>(root: &'v mut Value, path: &[Seg]) -> Option<&'v mut Value> {
    path.iter().try_fold(root, |v, seg| match seg {
        Seg::Key(k) => v.get_mut(k),
        Seg::Index(i) => v.get_mut(i),
    })
}

fn last_key(path: &[Seg]) -> Option<&str> {
    match path.last() {
        Some(Seg::Key(k)) => Some(k),
        _ => None,
    }
}

fn len_of(doc: &Value, key: &str) -> usize {
    doc.get(key).and_then(Value::as_array).map_or(0, Vec::len)
}

/// A random element of the top-level array `key`, as an object.
fn pick_object<'v>(
    doc: &'v mut Value,
    key: &str,
    rng: &mut Rng,
) -> Option<(usize, &'v mut Map<String, Value>)> {
    let items = doc.get_mut(key)?.as_array_mut()?;
    let i = rng.below(items.len());
    Some((i, items.get_mut(i)?.as_object_mut()?))
}

/// The top-level array `key`, created empty when missing.
fn array_of<'v>(doc: &'v mut Value, key: &str) -> Option<&'v mut Vec<Value>> {
    let map = doc.as_object_mut()?;
    let entry = map.entry(key).or_insert_with(|| json!([]));
    if !entry.is_array() {
        *entry = json!([]);
    }
    entry.as_array_mut()
}

// ---- values ----

/// Numbers that break arithmetic: zero, negatives, 32-bit and 53-bit boundaries, huge
/// counts, huge floats, NaN and infinity as strings (JSON has no literal for them).
fn extreme(rng: &mut Rng) -> Value {
    match rng.below(22) {
        0 => json!(0),
        1 => json!(-1),
        2 => json!(2_147_483_648u64),
        3 => json!(2_147_483_647u64),
        4 => json!(4_294_967_297u64),
        5 => json!(4_294_967_295u64),
        6 => json!(1e30),
        7 => json!(-1e30),
        8 => json!("NaN"),
        9 => json!(1_000_000_000u64),
        10 => json!(9_007_199_254_740_993u64),
        11 => json!(i64::MIN),
        12 => json!(u64::MAX),
        13 => json!(1e308),
        14 => json!(-0.0),
        15 => json!(0.5),
        16 => json!("Infinity"),
        17 => json!(65536),
        18 => json!(16385),
        19 => json!(1e-45),
        20 => json!(-1e308),
        _ => json!(rng.next_u64() % 1_000_000),
    }
}

/// A replacement index for an array of `len` elements: mostly out of range, sometimes a
/// different valid one.
fn bad_index(len: usize, rng: &mut Rng) -> Value {
    match rng.below(9) {
        0 => json!(len),
        1 => json!(len + 1),
        2 => json!(len + 1000),
        3 => json!(-1),
        4 => json!(2_147_483_648u64),
        5 => json!(4_294_967_296u64),
        6 => json!(u64::MAX),
        7 => json!(0.5),
        _ => json!(rng.below(len.max(1))),
    }
}

// ---- operations ----

fn extreme_number(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let numbers: Vec<JPath> = paths(doc)
        .into_iter()
        .filter(|p| get(doc, p).is_some_and(Value::is_number))
        .collect();
    let path = rng.pick(&numbers)?.clone();
    let value = extreme(rng);
    *get_mut(doc, &path)? = value.clone();
    Some(format!("{} = {value}", show(&path)))
}

/// The top-level array an index-valued key refers into.
fn index_target(path: &[Seg]) -> Option<&'static str> {
    const KEYS: &[(&str, &str)] = &[
        ("node", "nodes"),
        ("mesh", "meshes"),
        ("accessor", "accessors"),
        ("indices", "accessors"),
        ("bufferView", "bufferViews"),
        ("buffer", "buffers"),
        ("material", "materials"),
        ("source", "images"),
        ("sampler", "samplers"),
        ("camera", "cameras"),
        ("skin", "skins"),
        ("scene", "scenes"),
        ("index", "textures"),
        ("inverseBindMatrices", "accessors"),
        ("skeleton", "nodes"),
        ("input", "accessors"),
        ("output", "accessors"),
    ];
    let n = path.len();
    if let Some(key) = last_key(path) {
        if let Some((_, target)) = KEYS.iter().find(|(k, _)| *k == key) {
            return Some(target);
        }
        // An attribute (or a morph target's) names an accessor.
        let parent = n.checked_sub(2).map(|i| &path[i]);
        let grandparent = n.checked_sub(3).map(|i| &path[i]);
        if parent == Some(&Seg::Key("attributes".into()))
            || grandparent == Some(&Seg::Key("targets".into()))
        {
            return Some("accessors");
        }
        return None;
    }
    // Array elements: children, joints, a scene's roots.
    match n.checked_sub(2).map(|i| &path[i]) {
        Some(Seg::Key(k)) if k == "children" || k == "joints" => Some("nodes"),
        Some(Seg::Key(k)) if k == "nodes" && n == 4 => Some("nodes"),
        _ => None,
    }
}

fn index_out_of_range(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let slots: Vec<(JPath, &str)> = paths(doc)
        .into_iter()
        .filter(|p| get(doc, p).is_some_and(Value::is_u64))
        .filter_map(|p| index_target(&p).map(|t| (p, t)))
        .collect();
    let (path, target) = rng.pick(&slots)?.clone();
    let value = bad_index(len_of(doc, target), rng);
    *get_mut(doc, &path)? = value.clone();
    Some(format!(
        "{} = {value} ({target} has {})",
        show(&path),
        len_of(doc, target)
    ))
}

/// Keys glTF requires (or that hold everything together): removing them tests every
/// "missing field" path.
const REQUIRED: &[&str] = &[
    "asset",
    "version",
    "buffer",
    "byteLength",
    "componentType",
    "count",
    "type",
    "primitives",
    "attributes",
    "POSITION",
    "bufferView",
    "mimeType",
    "uri",
    "nodes",
    "source",
    "index",
    "perspective",
    "orthographic",
    "yfov",
    "znear",
    "xmag",
    "ymag",
    "indices",
    "values",
    "mesh",
    "scenes",
    "scene",
    "buffers",
    "bufferViews",
    "accessors",
    "meshes",
    "materials",
    "images",
    "textures",
    "samplers",
    "sparse",
];

fn delete_key(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let all: Vec<JPath> = paths(doc)
        .into_iter()
        .filter(|p| last_key(p).is_some())
        .collect();
    let required: Vec<JPath> = all
        .iter()
        .filter(|p| last_key(p).is_some_and(|k| REQUIRED.contains(&k)))
        .cloned()
        .collect();
    let pool = if rng.chance(0.7) && !required.is_empty() {
        &required
    } else {
        &all
    };
    let path = rng.pick(pool)?.clone();
    let (key, parent) = path.split_last()?;
    let Seg::Key(key) = key else { return None };
    get_mut(doc, parent)?.as_object_mut()?.remove(key)?;
    Some(format!("deleted {}", show(&path)))
}

fn enum_value(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    const ACCESSOR_TYPES: &[&str] = &[
        "SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4", "vec3", "", "MAT5",
    ];
    const CAMERA_TYPES: &[&str] = &["perspective", "orthographic", "fisheye", ""];
    let choices = |key: &str, current: &Value| -> Vec<Value> {
        let strings = |s: &[&str]| s.iter().map(|v| json!(v)).collect();
        let numbers = |n: &[i64]| n.iter().map(|v| json!(v)).collect();
        match key {
            "componentType" => numbers(&[5120, 5121, 5122, 5123, 5125, 5126, 5124, 0, -1, 5127]),
            "type" if current.as_str().is_some_and(|s| s.starts_with(['p', 'o'])) => {
                strings(CAMERA_TYPES)
            }
            "type" => strings(ACCESSOR_TYPES),
            "mode" => numbers(&[0, 1, 2, 3, 4, 5, 6, 7, 255, -1]),
            "alphaMode" => strings(&["OPAQUE", "MASK", "BLEND", "blend", "ADD", ""]),
            "target" => numbers(&[34962, 34963, 0, 1]),
            "magFilter" => numbers(&[9728, 9729, 9984, 0]),
            "minFilter" => numbers(&[9728, 9729, 9984, 9985, 9986, 9987, 0, 10000]),
            "wrapS" | "wrapT" => numbers(&[33071, 33648, 10497, 0, 1]),
            "mimeType" => strings(&[
                "image/png",
                "image/jpeg",
                "image/ktx2",
                "image/webp",
                "text/plain",
                "",
            ]),
            "interpolation" => strings(&["LINEAR", "STEP", "CUBICSPLINE", "X"]),
            "path" => strings(&["translation", "rotation", "scale", "weights", "x"]),
            "normalized" => vec![json!(true), json!(false), json!(1)],
            "doubleSided" => vec![json!(true), json!(false), json!("yes")],
            _ => Vec::new(),
        }
    };
    let slots: Vec<JPath> = paths(doc)
        .into_iter()
        .filter(|p| {
            let current = get(doc, p).unwrap_or(&Value::Null);
            last_key(p).is_some_and(|k| !choices(k, current).is_empty())
        })
        .collect();
    let path = rng.pick(&slots)?.clone();
    let key = last_key(&path)?.to_string();
    let options = choices(&key, get(doc, &path)?);
    let value = rng.pick(&options)?.clone();
    *get_mut(doc, &path)? = value.clone();
    Some(format!("{} = {value}", show(&path)))
}

/// The default scene's root list, created when missing.
fn scene_roots(doc: &mut Value) -> Option<&mut Vec<Value>> {
    let scene = doc.get("scene").and_then(Value::as_u64).unwrap_or(0) as usize;
    let scenes = array_of(doc, "scenes")?;
    if scenes.is_empty() {
        scenes.push(json!({ "nodes": [] }));
    }
    let index = scene.min(scenes.len() - 1);
    let map = scenes.get_mut(index)?.as_object_mut()?;
    let roots = map.entry("nodes").or_insert_with(|| json!([]));
    if !roots.is_array() {
        *roots = json!([]);
    }
    roots.as_array_mut()
}

fn children_of(doc: &mut Value, node: usize) -> Option<&mut Vec<Value>> {
    let map = doc.get_mut("nodes")?.get_mut(node)?.as_object_mut()?;
    let children = map.entry("children").or_insert_with(|| json!([]));
    if !children.is_array() {
        *children = json!([]);
    }
    children.as_array_mut()
}

/// A node with a mesh, else any node.
fn leaf_node(doc: &Value, rng: &mut Rng) -> Option<usize> {
    let nodes = doc.get("nodes")?.as_array()?;
    let with_mesh: Vec<usize> = (0..nodes.len())
        .filter(|&i| nodes[i].get("mesh").is_some())
        .collect();
    match rng.pick(&with_mesh) {
        Some(&i) => Some(i),
        None if nodes.is_empty() => None,
        None => Some(rng.below(nodes.len())),
    }
}

fn node_graph(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let count = len_of(doc, "nodes");
    let leaf = leaf_node(doc, rng)?;
    match rng.below(7) {
        0 => {
            // A cycle: some descendant of `a` (or `a` itself) gets `a` as a child.
            let a = rng.below(count);
            let mut b = a;
            for _ in 0..rng.below(4) {
                let kids: Vec<usize> = doc["nodes"][b]
                    .get("children")
                    .and_then(Value::as_array)
                    .map(|k| {
                        k.iter()
                            .filter_map(|v| v.as_u64())
                            .map(|v| v as usize)
                            .collect()
                    })
                    .unwrap_or_default();
                match rng.pick(&kids) {
                    Some(&k) if k < count => b = k,
                    _ => break,
                }
            }
            children_of(doc, b)?.push(json!(a));
            scene_roots(doc)?.push(json!(a));
            Some(format!(
                "cycle: node {b} has ancestor-or-self node {a} as a child"
            ))
        }
        1 => {
            // A doubling DAG: level k has two nodes, each the parent of both at level k-1,
            // so the top expands to 2^levels instances of the leaf.
            let levels = rng.pick_copy(&[8, 16, 21, 22, 23, 30, 40, 64]);
            let nodes = array_of(doc, "nodes")?;
            let (mut a, mut b) = (leaf, leaf);
            for _ in 0..levels {
                let next = nodes.len();
                nodes.push(json!({ "children": [a, b] }));
                nodes.push(json!({ "children": [a, b] }));
                (a, b) = (next, next + 1);
            }
            scene_roots(doc)?.push(json!(a));
            Some(format!("doubling DAG of {levels} levels over node {leaf}"))
        }
        2 => {
            // A deep chain of single children.
            let depth = rng.pick_copy(&[1000, 50_000, 200_000]);
            let nodes = array_of(doc, "nodes")?;
            let mut below = leaf;
            for _ in 0..depth {
                nodes.push(json!({ "children": [below] }));
                below = nodes.len() - 1;
            }
            scene_roots(doc)?.push(json!(below));
            Some(format!("chain of {depth} nodes over node {leaf}"))
        }
        3 => {
            let parent = rng.below(count);
            children_of(doc, parent)?.push(json!(leaf));
            Some(format!(
                "node {leaf} also a child of node {parent} (two parents)"
            ))
        }
        4 => {
            let times = rng.pick_copy(&[2, 100, 100_000]);
            let roots = scene_roots(doc)?;
            roots.extend(std::iter::repeat_n(json!(leaf), times));
            Some(format!("scene lists node {leaf} {times} more times"))
        }
        5 => {
            children_of(doc, leaf)?.push(json!(leaf));
            Some(format!("node {leaf} is its own child"))
        }
        _ => {
            let node = rng.below(count);
            children_of(doc, node)?.extend([json!(leaf), json!(leaf)]);
            Some(format!("node {node} lists child {leaf} twice"))
        }
    }
}

fn hostile_uri(rng: &mut Rng, ctx: &Context) -> String {
    let base64 = |rng: &mut Rng, n: usize| -> String {
        const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        (0..n)
            .map(|_| char::from(ALPHABET[rng.below(ALPHABET.len())]))
            .collect()
    };
    match rng.below(30) {
        0 => "/dev/zero".into(),
        1 => "/dev/urandom".into(),
        2 => "/proc/self/fd/1".into(),
        3 => "/proc/self/fd/0".into(),
        4 => "/proc/self/mem".into(),
        5 => "/proc/self/exe".into(),
        6 => "/".into(),
        7 => ".".into(),
        8 => "..".into(),
        9 => String::new(),
        10 => "a".repeat(rng.pick_copy(&[255, 256, 4096, 100_000])),
        11 => format!(
            "data:application/octet-stream;base64,{}!!{}",
            base64(rng, 5),
            base64(rng, 3)
        ),
        12 => {
            let n = rng.pick_copy(&[0, 1, 2, 3, 5, 4096]);
            format!("data:application/octet-stream;base64,{}", base64(rng, n))
        }
        13 => "data:,".into(),
        14 => format!("data:image/png;base64,iVBORw0KGgo{}", base64(rng, 40)),
        15 => "data:".into(),
        16 => "file:///etc/passwd".into(),
        17 => "file:///dev/zero".into(),
        18 => "%".into(),
        19 => "%ZZ".into(),
        20 => "%00x.bin".into(),
        21 => "%2e%2e/%2e%2e/%2e%2e/%2e%2e/dev/zero".into(),
        22 => "../../../../../../../../dev/zero".into(),
        23 => "http://127.0.0.1/x.bin".into(),
        24 => ctx.self_name.into(),
        25 => "does-not-exist.bin".into(),
        26 => "x?y#z".into(),
        27 => "%FF%FE.bin".into(),
        28 => format!(
            "data:application/octet-stream;base64,{}",
            "A".repeat(1 << 20)
        ),
        _ => match rng.pick(&ctx.siblings) {
            Some(s) => s.clone(),
            None => ctx.self_name.into(),
        },
    }
}

fn uri(doc: &mut Value, rng: &mut Rng, ctx: &Context) -> Option<String> {
    let key = if rng.chance(0.5) { "buffers" } else { "images" };
    let value = hostile_uri(rng, ctx);
    let (i, item) = pick_object(doc, key, rng)?;
    if key == "images" && rng.chance(0.5) {
        item.remove("bufferView");
        item.remove("mimeType");
    }
    let shown: String = value.chars().take(60).collect();
    let note = format!(
        "{key}[{i}].uri = {shown:?} ({} chars)",
        value.chars().count()
    );
    item.insert("uri".into(), json!(value));
    Some(note)
}

fn accessor(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let views = len_of(doc, "bufferViews");
    let (i, acc) = pick_object(doc, "accessors", rng)?;
    let count = acc.get("count").and_then(Value::as_u64).unwrap_or(1);
    let (field, value) = match rng.below(9) {
        0 => (
            "componentType",
            json!(rng.pick_copy(&[5120, 5121, 5122, 5123, 5125, 5126, 5124, 0])),
        ),
        1 => (
            "type",
            json!(rng.pick_copy(&["SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"])),
        ),
        2 => (
            "count",
            json!(rng.pick_copy(&[
                0,
                1,
                2,
                3,
                count.saturating_sub(1),
                count + 1,
                count * 2,
                1_000_000_000,
                1 << 31,
                (1 << 32) + 1,
                u64::MAX,
                1 << 24,
                (1 << 24) + 1,
            ])),
        ),
        3 => (
            "byteOffset",
            json!(rng.pick_copy(&[1u64, 2, 3, 4, 12, 1 << 20, 1 << 31, u64::MAX])),
        ),
        4 => ("normalized", json!(rng.chance(0.5))),
        5 => ("min", json!([extreme(rng), "x", null])),
        6 => ("max", json!([])),
        7 => {
            acc.remove("bufferView");
            return Some(format!("deleted accessors[{i}].bufferView"));
        }
        _ => ("bufferView", json!(rng.below(views.max(1)))),
    };
    let note = format!("accessors[{i}].{field} = {value}");
    acc.insert(field.into(), value);
    Some(note)
}

fn buffer_view(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let buffers = len_of(doc, "buffers");
    if rng.chance(0.25) {
        let (i, buffer) = pick_object(doc, "buffers", rng)?;
        let length = buffer
            .get("byteLength")
            .and_then(Value::as_u64)
            .unwrap_or(0);
        let value = json!(rng.pick_copy(&[
            0,
            1,
            length.saturating_sub(1),
            length + 1,
            length * 2,
            1 << 31,
            1 << 40,
            u64::MAX
        ]));
        buffer.insert("byteLength".into(), value.clone());
        return Some(format!("buffers[{i}].byteLength = {value}"));
    }
    let (i, view) = pick_object(doc, "bufferViews", rng)?;
    let length = view.get("byteLength").and_then(Value::as_u64).unwrap_or(0);
    let (field, value) = match rng.below(5) {
        0 => (
            "byteOffset",
            json!(rng.pick_copy(&[1u64, 3, 4, 1 << 20, 1 << 31, u64::MAX, length])),
        ),
        1 => (
            "byteLength",
            json!(rng.pick_copy(&[
                0,
                1,
                3,
                length.saturating_sub(1),
                length + 1,
                1 << 31,
                u64::MAX
            ])),
        ),
        2 => (
            "byteStride",
            json!(rng.pick_copy(&[0u64, 1, 2, 3, 4, 5, 252, 256, 1024, 1 << 31])),
        ),
        3 => ("buffer", bad_index(buffers, rng)),
        _ => ("target", json!(rng.pick_copy(&[34962, 34963, 0]))),
    };
    let note = format!("bufferViews[{i}].{field} = {value}");
    view.insert(field.into(), value);
    Some(note)
}

fn sparse(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let views = len_of(doc, "bufferViews");
    let (i, acc) = pick_object(doc, "accessors", rng)?;
    let count = acc.get("count").and_then(Value::as_u64).unwrap_or(1);
    let sparse_count = rng.pick_copy(&[1, 2, count, count + 1, 1_000_000_000, 1 << 31, 0]);
    let offset = |rng: &mut Rng| rng.pick_copy(&[0u64, 0, 4, 1 << 31, u64::MAX]);
    let sparse = json!({
        "count": sparse_count,
        "indices": {
            "bufferView": rng.below(views + 1),
            "byteOffset": offset(rng),
            "componentType": rng.pick_copy(&[5121, 5123, 5125, 5125, 5126, 5120, 0]),
        },
        "values": {
            "bufferView": rng.below(views + 1),
            "byteOffset": offset(rng),
        },
    });
    let zero_filled = rng.chance(0.4);
    if zero_filled {
        acc.remove("bufferView");
    }
    let note = format!(
        "accessors[{i}].sparse = {sparse}{}",
        if zero_filled { ", no bufferView" } else { "" }
    );
    acc.insert("sparse".into(), sparse);
    Some(note)
}

fn camera(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let perspective = json!({ "yfov": 0.8, "znear": 0.1, "zfar": 100.0, "aspectRatio": 1.5 });
    let orthographic = json!({ "xmag": 1.0, "ymag": 1.0, "znear": 0.1, "zfar": 100.0 });
    let mut cam = match rng.below(4) {
        0 => json!({ "type": "perspective", "orthographic": orthographic }),
        1 => json!({ "type": "orthographic", "perspective": perspective }),
        _ => json!({ "type": "perspective", "perspective": perspective }),
    };
    let field = rng.pick_copy(&["yfov", "znear", "zfar", "aspectRatio", "none"]);
    let mut note = format!("camera {}", cam["type"]);
    if let Some(p) = cam.get_mut("perspective").and_then(Value::as_object_mut) {
        if field != "none" {
            let value = if rng.chance(0.2) {
                // Tiny, and at or past a half turn (yfov, aspect ratio).
                let pi = std::f64::consts::PI;
                json!(rng.pick_copy(&[1e-30, pi, pi + 1e-6, 3.2, 100.0]))
            } else {
                extreme(rng)
            };
            note.push_str(&format!(", {field} = {value}"));
            p.insert(field.into(), value);
        }
        if rng.chance(0.3) {
            p.remove("zfar");
            note.push_str(", no zfar");
        }
    }
    let cameras = array_of(doc, "cameras")?;
    cameras.push(cam);
    let index = cameras.len() - 1;
    // On a root node, so that the importer meets it first; the node keeps its own mesh.
    let root = scene_roots(doc)?.first().and_then(Value::as_u64);
    let node = root.map_or_else(|| leaf_node(doc, rng), |r| Some(r as usize))?;
    doc.get_mut("nodes")?
        .get_mut(node)?
        .as_object_mut()?
        .insert("camera".into(), json!(index));
    Some(format!("{note}, on node {node}"))
}

fn image(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let views = len_of(doc, "bufferViews");
    let (i, img) = pick_object(doc, "images", rng)?;
    let note = match rng.below(4) {
        0 => {
            img.remove("mimeType");
            "no mimeType".to_string()
        }
        1 => {
            let view = rng.below(views + 1);
            img.remove("uri");
            img.insert("bufferView".into(), json!(view));
            img.insert("mimeType".into(), json!("image/png"));
            format!("bufferView {view} instead of its uri")
        }
        2 => {
            img.insert("uri".into(), json!("x.png"));
            img.insert("bufferView".into(), json!(0));
            "both uri and bufferView".to_string()
        }
        _ => {
            let mime = rng.pick_copy(&["image/jpeg", "image/png", "image/gif", "", "x"]);
            img.insert("mimeType".into(), json!(mime));
            format!("mimeType {mime:?}")
        }
    };
    Some(format!("images[{i}]: {note}"))
}

fn material(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let textures = len_of(doc, "textures");
    let (i, mat) = pick_object(doc, "materials", rng)?;
    let (what, value) = match rng.below(8) {
        0 => (
            "pbrMetallicRoughness.baseColorFactor",
            json!([extreme(rng), extreme(rng), 1.0, extreme(rng)]),
        ),
        1 => (
            "pbrMetallicRoughness.baseColorTexture",
            json!({ "index": bad_index(textures, rng), "texCoord": rng.pick_copy(&[0u64, 1, 7, 1 << 31, u64::MAX]) }),
        ),
        2 => ("alphaCutoff", extreme(rng)),
        3 => (
            "extensions.KHR_materials_transmission",
            json!({ "transmissionFactor": extreme(rng) }),
        ),
        4 => (
            "extensions.KHR_materials_volume",
            json!({
                "thicknessFactor": extreme(rng),
                "attenuationDistance": extreme(rng),
                "attenuationColor": [extreme(rng), 0.5, 0.5],
            }),
        ),
        5 => (
            "extensions.KHR_materials_ior",
            json!({ "ior": extreme(rng) }),
        ),
        6 => ("extensions.KHR_materials_unlit", json!({})),
        _ => ("pbrMetallicRoughness.baseColorFactor", json!([0.5, 0.5])),
    };
    let (head, tail) = what.split_once('.').unwrap_or((what, ""));
    if tail.is_empty() {
        mat.insert(head.into(), value.clone());
    } else {
        let inner = mat.entry(head).or_insert_with(|| json!({}));
        if !inner.is_object() {
            *inner = json!({});
        }
        inner.as_object_mut()?.insert(tail.into(), value.clone());
        if head == "extensions" {
            let used = array_of(doc, "extensionsUsed")?;
            used.push(json!(tail));
        }
    }
    Some(format!("materials[{i}].{what} = {value}"))
}

fn extensions(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let name = rng.pick_copy(&[
        "KHR_materials_volume",
        "KHR_materials_transmission",
        "KHR_draco_mesh_compression",
        "EXT_meshopt_compression",
        "KHR_texture_transform",
        "KHR_mesh_quantization",
        "",
    ]);
    let list = rng.pick_copy(&["extensionsRequired", "extensionsUsed"]);
    array_of(doc, list)?.push(json!(name));
    Some(format!("{list} += {name:?}"))
}

fn transform(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let (i, node) = pick_object(doc, "nodes", rng)?;
    let (field, value) = match rng.below(6) {
        0 => {
            let mut m: Vec<Value> = [
                1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.,
            ]
            .iter()
            .map(|&v: &f64| json!(v))
            .collect();
            let slot = rng.below(16);
            m[slot] = extreme(rng);
            ("matrix", json!(m))
        }
        1 => ("matrix", json!(vec![0.0; 16])),
        2 => ("translation", json!([extreme(rng), 0.0, extreme(rng)])),
        3 => (
            "rotation",
            json!(rng.pick_copy(&[[0.0; 4], [1e30, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0]])),
        ),
        4 => ("scale", json!([extreme(rng), extreme(rng), 1.0])),
        _ => ("scale", json!([0.0, 0.0, 0.0])),
    };
    let note = format!("nodes[{i}].{field} = {value}");
    node.insert(field.into(), value);
    Some(note)
}

fn type_confusion(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let all = paths(doc);
    let path = rng.pick(&all)?.clone();
    let value = match rng.below(8) {
        0 => Value::Null,
        1 => json!(true),
        2 => json!("string"),
        3 => json!([]),
        4 => json!({}),
        5 => json!([1, 2, 3]),
        6 => json!({ "a": 1 }),
        _ => json!("x".repeat(10_000)),
    };
    let kind = match &value {
        Value::String(s) if s.len() > 10 => "a 10000-character string".to_string(),
        v => v.to_string(),
    };
    *get_mut(doc, &path)? = value;
    Some(format!("{} = {kind}", show(&path)))
}

fn array_shape(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let arrays: Vec<JPath> = paths(doc)
        .into_iter()
        .filter(|p| {
            get(doc, p)
                .and_then(Value::as_array)
                .is_some_and(|a| !a.is_empty())
        })
        .collect();
    let path = rng.pick(&arrays)?.clone();
    let items = get_mut(doc, &path)?.as_array_mut()?;
    let at = rng.below(items.len());
    let note = match rng.below(5) {
        0 => {
            let copy = items[at].clone();
            items.push(copy);
            "duplicated an element".to_string()
        }
        1 => {
            items.clear();
            "emptied".to_string()
        }
        2 => {
            items.truncate(1);
            "cut to one element".to_string()
        }
        3 => {
            // Repeated, but within a few MB of JSON.
            let size = items[at].to_string().len().max(1);
            let times = (4_000_000 / size).clamp(1, 100_000);
            let copy = items[at].clone();
            items.extend(std::iter::repeat_n(copy, times));
            format!("element {at} repeated {times} times")
        }
        _ => {
            items.remove(at);
            format!("removed element {at}")
        }
    };
    Some(format!("{}: {note}", show(&path)))
}

fn primitive(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let accessors = len_of(doc, "accessors");
    let materials = len_of(doc, "materials");
    let (m, mesh) = pick_object(doc, "meshes", rng)?;
    let prims = mesh.get_mut("primitives")?.as_array_mut()?;
    let p = rng.below(prims.len());
    let prim = prims.get_mut(p)?.as_object_mut()?;
    let attrs = prim.get("attributes").and_then(Value::as_object).cloned();
    let note = match rng.below(7) {
        0 => {
            let mode = rng.pick_copy(&[0, 1, 2, 3, 4, 5, 6]);
            prim.insert("mode".into(), json!(mode));
            format!("mode {mode}")
        }
        1 => {
            prim.remove("indices");
            "no indices".to_string()
        }
        2 => {
            // Indices read from a vertex attribute (floats, or the wrong size).
            let any = attrs.as_ref()?.values().next()?.clone();
            prim.insert("indices".into(), any.clone());
            format!("indices = attribute accessor {any}")
        }
        3 => {
            let semantic = rng.pick_copy(&[
                "TEXCOORD_0",
                "TEXCOORD_1",
                "TEXCOORD_4294967295",
                "TEXCOORD_99999999999",
                "COLOR_0",
                "NORMAL",
                "TANGENT",
                "POSITION",
                "JOINTS_0",
                "WEIGHTS_0",
                "_CUSTOM",
            ]);
            let target = rng.below(accessors.max(1));
            let map = prim.entry("attributes").or_insert_with(|| json!({}));
            map.as_object_mut()?.insert(semantic.into(), json!(target));
            format!("attributes.{semantic} = accessor {target}")
        }
        4 => {
            let index = prim.get("indices").cloned();
            let map = prim.entry("attributes").or_insert_with(|| json!({}));
            let value = index.unwrap_or(json!(0));
            map.as_object_mut()?
                .insert("POSITION".into(), value.clone());
            format!("POSITION = the indices accessor {value}")
        }
        5 => {
            prim.insert("attributes".into(), json!({}));
            "no attributes".to_string()
        }
        _ => {
            let value = bad_index(materials, rng);
            prim.insert("material".into(), value.clone());
            format!("material = {value}")
        }
    };
    Some(format!("meshes[{m}].primitives[{p}]: {note}"))
}

fn morph_and_skin(doc: &mut Value, rng: &mut Rng, _: &Context) -> Option<String> {
    let accessors = len_of(doc, "accessors");
    let nodes = len_of(doc, "nodes");
    if rng.chance(0.5) {
        let (m, mesh) = pick_object(doc, "meshes", rng)?;
        let target = rng.below(accessors + 1);
        mesh.insert("weights".into(), json!([extreme(rng)]));
        let prim = mesh.get_mut("primitives")?.get_mut(0)?.as_object_mut()?;
        prim.insert("targets".into(), json!([{ "POSITION": target }]));
        return Some(format!(
            "meshes[{m}]: morph target POSITION = accessor {target}"
        ));
    }
    let skin = json!({
        "joints": [rng.below(nodes + 1), rng.below(nodes + 1)],
        "inverseBindMatrices": rng.below(accessors + 1),
    });
    let skins = array_of(doc, "skins")?;
    skins.push(skin.clone());
    let index = skins.len() - 1;
    let node = leaf_node(doc, rng)?;
    doc.get_mut("nodes")?
        .get_mut(node)?
        .as_object_mut()?
        .insert("skin".into(), json!(index));
    Some(format!("nodes[{node}].skin = {skin}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vendored cow: meshes, materials, a texture, an image, buffers.
    fn spot() -> Value {
        let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/scenes/spot/spot_blend.gltf");
        let text = std::fs::read(path).expect("vendored spot");
        serde_json::from_slice(&text).expect("spot JSON")
    }

    fn context() -> Context<'static> {
        Context {
            self_name: "mutant.gltf",
            siblings: vec!["spot.bin".into(), "spot_texture.png".into()],
        }
    }

    #[test]
    fn same_seed_same_mutant() {
        for seed in 0..50 {
            let (mut a, mut b) = (spot(), spot());
            let na = mutate(&mut a, &mut Rng::new(seed), &context());
            let nb = mutate(&mut b, &mut Rng::new(seed), &context());
            assert_eq!(na, nb);
            assert!(a == b, "seed {seed} gave two different mutants");
        }
    }

    #[test]
    fn mutants_change_the_document_and_stay_json() {
        let original = spot();
        let mut changed = 0;
        for seed in 0..300 {
            let mut doc = original.clone();
            let notes = mutate(&mut doc, &mut Rng::new(seed), &context());
            assert!(!notes.is_empty(), "seed {seed}: no mutation applied");
            let text = serde_json::to_vec(&doc).expect("serialises");
            let back: Value = serde_json::from_slice(&text).expect("still JSON");
            if back != original {
                changed += 1;
            }
        }
        // A mutation may write back the value that was there (a valid index, say).
        assert!(changed > 270, "only {changed} of 300 mutants differ");
    }

    #[test]
    fn every_operation_applies_to_a_real_file() {
        for (i, (op, _)) in OPS.iter().enumerate() {
            let applied = (0..20).any(|seed| {
                let mut doc = spot();
                op(&mut doc, &mut Rng::new(seed), &context()).is_some()
            });
            assert!(applied, "operation {i} never applied");
        }
    }

    #[test]
    fn index_slots_are_recognised() {
        let key = |k: &str| Seg::Key(k.into());
        let attr = vec![
            key("meshes"),
            Seg::Index(0),
            key("primitives"),
            Seg::Index(0),
            key("attributes"),
            key("POSITION"),
        ];
        assert_eq!(index_target(&attr), Some("accessors"));
        let child = vec![key("nodes"), Seg::Index(2), key("children"), Seg::Index(0)];
        assert_eq!(index_target(&child), Some("nodes"));
        let root = vec![key("scenes"), Seg::Index(0), key("nodes"), Seg::Index(0)];
        assert_eq!(index_target(&root), Some("nodes"));
        assert_eq!(index_target(&[key("asset"), key("version")]), None);
    }
}
