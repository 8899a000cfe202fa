//! One fuzz case: a seed drawn from the corpus and mutated — its JSON structurally, its
//! bytes (main file, GLB BIN chunk, .bin and image files) raw, its GLB container re-packed
//! or deliberately broken. Everything is drawn from the case's own generator, so a case is
//! rebuilt exactly from the run's seed and its number.

pub mod bytes;
pub mod json;

use crate::corpus::{Format, Seed};
use crate::glb::Glb;
use crate::rng::Rng;
use serde_json::Value;
use std::ops::Range;
use std::path::PathBuf;

/// The mutant's file name without extension; URIs may name it.
pub const MAIN_STEM: &str = "mutant";

#[derive(Debug)]
pub struct Mutant {
    /// Index of the seed in the corpus.
    pub seed: usize,
    pub format: Format,
    /// The mutated `.gltf`/`.glb` file.
    pub main: Vec<u8>,
    /// Files beside it (relative paths) whose mutated bytes replace the seed's.
    pub overrides: Vec<(PathBuf, Vec<u8>)>,
    /// What was done, in order.
    pub notes: Vec<String>,
}

impl Mutant {
    pub fn file_name(&self) -> String {
        format!("{MAIN_STEM}.{}", self.format.extension())
    }

    pub fn describe(&self) -> String {
        self.notes.join("; ")
    }
}

/// Builds a case from `seeds` with `rng`.
pub fn make(seeds: &[Seed], rng: &mut Rng) -> Mutant {
    let index = rng.below(seeds.len());
    let seed = &seeds[index];
    let mut mutant = Mutant {
        seed: index,
        format: seed.format,
        main: seed.bytes.clone(),
        overrides: Vec::new(),
        notes: vec![format!("seed {}", seed.path.display())],
    };
    let has_data = !seed.siblings.is_empty() || seed.glb.as_ref().is_some_and(|g| bin(g).is_some());
    let roll = rng.below(100);
    let (structural, data, raw) = match roll {
        _ if seed.json.is_none() => (false, has_data && rng.chance(0.3), true),
        0..=54 => (true, false, rng.chance(0.1)),
        55..=69 => (false, false, true),
        70..=89 if has_data => (false, true, false),
        70..=89 => (true, false, false),
        _ => (true, has_data, false),
    };
    let mut doc = seed.json.clone();
    // Some data cases swap one drawn texture's image, or all of them, for a decompression
    // bomb: each is within the size limit, together they may not be.
    let bomb = match (data && rng.chance(0.2), seed.json.as_ref()) {
        (true, Some(original)) => {
            let mut images = drawn_images(original);
            if rng.chance(0.5) && !images.is_empty() {
                images = vec![images[rng.below(images.len())]];
            }
            let (w, h) = rng.pick_copy(bytes::BOMB_SIZES);
            (!images.is_empty()).then(|| (images, w, h, bytes::png_bomb(w, h)))
        }
        _ => None,
    };
    if structural {
        if let Some(doc) = doc.as_mut() {
            let ctx = json::Context {
                self_name: &mutant.file_name(),
                siblings: seed
                    .siblings
                    .iter()
                    .map(|s| s.rel.to_string_lossy().into_owned())
                    .collect(),
            };
            mutant.notes.extend(json::mutate(doc, rng, &ctx));
        }
    }
    // A GLB's bomb goes at the end of its BIN chunk, through a new bufferView.
    let bin_len = seed.glb.as_ref().and_then(bin).map_or(0, <[u8]>::len);
    let glb_bomb = match (&bomb, seed.format, doc.as_mut()) {
        (Some((images, w, h, png)), Format::Glb, Some(doc)) => {
            let offset = bin_len.div_ceil(4) * 4;
            point_images_at_end(doc, images, offset, png.len()).map(|()| {
                mutant.notes.push(format!(
                    "images {images:?} = a {w}x{h} all-zero PNG of {} bytes in the BIN chunk",
                    png.len()
                ));
                (offset, png)
            })
        }
        _ => None,
    };
    let rewritten = structural || glb_bomb.is_some();
    // The JSON text: re-serialised when mutated, else the seed's own bytes.
    let mut text = match (&doc, rewritten) {
        (Some(doc), true) => serde_json::to_vec(doc).unwrap_or_default(),
        _ => match seed.format {
            Format::Gltf => seed.bytes.clone(),
            Format::Glb => seed
                .glb
                .as_ref()
                .and_then(Glb::json)
                .unwrap_or_default()
                .to_vec(),
        },
    };
    if structural && raw {
        mutant
            .notes
            .push(format!("JSON text: {}", bytes::mutate(&mut text, rng)));
    }
    match (seed.format, &seed.glb) {
        (Format::Glb, Some(glb)) if rewritten || data => {
            let mut glb = glb.clone();
            glb.set_json(text);
            match (glb_bomb, glb.bin_mut()) {
                (Some((offset, png)), Some(chunk)) => {
                    chunk.resize(offset, 0);
                    chunk.extend_from_slice(png);
                }
                _ if data => mutate_bin(&mut glb, seed.json.as_ref(), rng, &mut mutant.notes),
                _ => {}
            }
            mutant.main = if rng.chance(0.1) {
                let (bytes, note) = glb.pack_broken(rng);
                mutant.notes.push(note);
                bytes
            } else {
                glb.pack()
            };
        }
        (Format::Gltf, _) if structural => mutant.main = text,
        _ => {}
    }
    if data && seed.format == Format::Gltf {
        // Every bombed image that is a file beside the seed is replaced.
        let files: Vec<PathBuf> = match (&bomb, seed.json.as_ref()) {
            (Some((images, ..)), Some(original)) => images
                .iter()
                .filter_map(|&i| original.get("images")?.get(i)?.get("uri")?.as_str())
                .filter_map(crate::corpus::uri_to_relative)
                .filter(|rel| seed.siblings.iter().any(|s| &s.rel == rel))
                .collect(),
            _ => Vec::new(),
        };
        match &bomb {
            Some((_, w, h, png)) if !files.is_empty() => {
                let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
                mutant.notes.push(format!(
                    "{} = a {w}x{h} all-zero PNG of {} bytes",
                    names.join(", "),
                    png.len()
                ));
                let mut files = files;
                files.dedup();
                mutant
                    .overrides
                    .extend(files.into_iter().map(|rel| (rel, png.clone())));
            }
            _ => mutate_sibling(seed, rng, &mut mutant),
        }
    }
    if raw && !structural {
        let note = bytes::mutate(&mut mutant.main, rng);
        mutant.notes.push(format!("raw: {note}"));
    }
    mutant
}

/// The BIN chunk's bytes, if there is one.
fn bin(glb: &Glb) -> Option<&[u8]> {
    glb.chunks
        .iter()
        .find(|c| c.kind == crate::glb::BIN)
        .map(|c| &c.data[..])
}

/// The byte ranges of buffer 0 (the BIN chunk in a GLB) that images and accessors occupy,
/// from the seed's unmutated JSON: flips aimed there hit headers and vertex data instead of
/// being spread thinly over megabytes.
fn view_ranges(doc: &Value, key: &str) -> Vec<Range<usize>> {
    let views = doc.get("bufferViews").and_then(Value::as_array);
    let range = |view: usize| -> Option<Range<usize>> {
        let v = views?.get(view)?;
        if v.get("buffer").and_then(Value::as_u64) != Some(0) {
            return None;
        }
        let start = v.get("byteOffset").and_then(Value::as_u64).unwrap_or(0) as usize;
        let len = v.get("byteLength").and_then(Value::as_u64)? as usize;
        Some(start..start.checked_add(len)?)
    };
    doc.get(key)
        .and_then(Value::as_array)
        .into_iter()
        .flatten()
        .filter_map(|item| range(item.get("bufferView")?.as_u64()? as usize))
        .collect()
}

fn mutate_bin(glb: &mut Glb, doc: Option<&Value>, rng: &mut Rng, notes: &mut Vec<String>) {
    let images = doc.map(|d| view_ranges(d, "images")).unwrap_or_default();
    let accessors = doc.map(|d| view_ranges(d, "accessors")).unwrap_or_default();
    let Some(data) = glb.bin_mut() else {
        return;
    };
    let len = data.len();
    let fits = |r: &&Range<usize>| r.end <= len && r.start < r.end;
    let image = rng.pick(&images).filter(fits).cloned();
    let accessor = rng.pick(&accessors).filter(fits).cloned();
    match (rng.below(4), image, accessor) {
        (0 | 1, Some(r), _) => {
            let note = match bytes::image_header(&mut data[r.clone()], rng) {
                Some(note) => note,
                None => bytes::mutate_in(data, r.clone(), rng),
            };
            notes.push(format!("BIN image at {}..{}: {note}", r.start, r.end));
        }
        (2, _, Some(r)) => {
            let note = bytes::mutate_in(data, r, rng);
            notes.push(format!("BIN accessor data: {note}"));
        }
        _ if rng.chance(0.2) => {
            let note = bytes::mutate(data, rng);
            notes.push(format!("BIN chunk: {note}"));
        }
        _ => {
            let note = bytes::mutate_in(data, 0..len, rng);
            notes.push(format!("BIN chunk: {note}"));
        }
    }
}

fn mutate_sibling(seed: &Seed, rng: &mut Rng, mutant: &mut Mutant) {
    let Some(sibling) = rng.pick(&seed.siblings) else {
        return;
    };
    let mut data = sibling.bytes.clone();
    let name = sibling.rel.display();
    let header = if rng.chance(0.5) {
        bytes::image_header(&mut data, rng)
    } else {
        None
    };
    let note = match header {
        Some(note) => note,
        None => bytes::mutate(&mut data, rng),
    };
    mutant.notes.push(format!("{name}: {note}"));
    mutant.overrides.push((sibling.rel.clone(), data));
}

/// The images materials draw as base colour (the only textures translucid decodes).
fn drawn_images(doc: &Value) -> Vec<usize> {
    let Some(materials) = doc.get("materials").and_then(Value::as_array) else {
        return Vec::new();
    };
    let mut images: Vec<usize> = materials
        .iter()
        .filter_map(|m| {
            let texture = m
                .get("pbrMetallicRoughness")?
                .get("baseColorTexture")?
                .get("index")?
                .as_u64()?;
            doc.get("textures")?
                .get(texture as usize)?
                .get("source")?
                .as_u64()
                .map(|i| i as usize)
        })
        .collect();
    images.sort_unstable();
    images.dedup();
    images
}

/// Makes `images` read `length` bytes at `offset` of buffer 0 (the BIN chunk) through one
/// new bufferView, and grows the buffer to hold them.
fn point_images_at_end(
    doc: &mut Value,
    images: &[usize],
    offset: usize,
    length: usize,
) -> Option<()> {
    let views = doc.get_mut("bufferViews")?.as_array_mut()?;
    views.push(serde_json::json!({ "buffer": 0, "byteOffset": offset, "byteLength": length }));
    let view = views.len() - 1;
    let buffer = doc.get_mut("buffers")?.get_mut(0)?.as_object_mut()?;
    buffer.insert("byteLength".into(), (offset + length).into());
    for &image in images {
        let img = doc.get_mut("images")?.get_mut(image)?.as_object_mut()?;
        img.remove("uri");
        img.insert("bufferView".into(), view.into());
        img.insert("mimeType".into(), "image/png".into());
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corpus() -> Vec<Seed> {
        let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        crate::corpus::load(&[scenes]).expect("vendored corpus")
    }

    #[test]
    fn a_case_is_determined_by_seed_and_number() {
        let seeds = corpus();
        for case in 0..40 {
            let a = make(&seeds, &mut Rng::for_case(99, case));
            let b = make(&seeds, &mut Rng::for_case(99, case));
            assert_eq!(a.notes, b.notes);
            assert!(a.main == b.main, "case {case} differs between two builds");
            assert_eq!(a.overrides, b.overrides);
        }
    }

    #[test]
    fn bombs_replace_drawn_images_in_both_formats() {
        let seeds = corpus();
        let (mut in_glb, mut in_gltf) = (false, false);
        for case in 0..3000 {
            let m = make(&seeds, &mut Rng::for_case(3, case));
            if !m.describe().contains("all-zero PNG") {
                continue;
            }
            match m.format {
                Format::Glb if !in_glb => {
                    let glb = Glb::parse(&m.main).expect("a bomb GLB is a valid container");
                    let doc: Value =
                        serde_json::from_slice(glb.json().expect("JSON chunk")).expect("JSON");
                    let bin = bin(&glb).expect("BIN chunk");
                    let view = doc["bufferViews"]
                        .as_array()
                        .and_then(|v| v.last())
                        .expect("view");
                    let start = view["byteOffset"].as_u64().expect("offset") as usize;
                    assert!(bin[start..].starts_with(b"\x89PNG"), "case {case}");
                    in_glb = true;
                }
                Format::Gltf if !in_gltf => {
                    let (_, png) = m.overrides.first().expect("the image file is replaced");
                    assert!(png.starts_with(b"\x89PNG"), "case {case}");
                    in_gltf = true;
                }
                _ => {}
            }
            if in_glb && in_gltf {
                return;
            }
        }
        panic!("no bomb in both formats (glb {in_glb}, gltf {in_gltf})");
    }

    #[test]
    fn most_mutants_still_parse_as_gltf_json_or_glb() {
        let seeds = corpus();
        let cases = 300;
        let mut parseable = 0;
        for case in 0..cases {
            let m = make(&seeds, &mut Rng::for_case(7, case));
            let text = match m.format {
                Format::Gltf => Some(m.main.clone()),
                Format::Glb => Glb::parse(&m.main).and_then(|g| g.json().map(<[u8]>::to_vec)),
            };
            if text.is_some_and(|t| serde_json::from_slice::<Value>(&t).is_ok()) {
                parseable += 1;
            }
        }
        // Raw flips of the main file and broken containers make the rest.
        assert!(
            parseable * 100 >= cases * 65,
            "only {parseable} of {cases} parse"
        );
    }
}
