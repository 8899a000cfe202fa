//! The GLB container (glTF 2.0 §4.4): split into chunks so that the JSON chunk can be mutated
//! structurally, and packed back with correct lengths and padding, or deliberately broken.

use crate::rng::Rng;

pub const MAGIC: &[u8; 4] = b"glTF";
pub const JSON: u32 = 0x4E4F_534A;
pub const BIN: u32 = 0x004E_4942;

#[derive(Clone, Debug, PartialEq)]
pub struct Chunk {
    pub kind: u32,
    /// The chunk's bytes as stored, padding included.
    pub data: Vec<u8>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Glb {
    pub version: u32,
    pub chunks: Vec<Chunk>,
}

fn word(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

impl Glb {
    /// Splits a well-formed container; `None` when the header or a chunk header is broken
    /// (such a seed is then only mutated as raw bytes).
    pub fn parse(bytes: &[u8]) -> Option<Self> {
        if !bytes.starts_with(MAGIC) || word(bytes, 8)? as usize != bytes.len() {
            return None;
        }
        let version = word(bytes, 4)?;
        let mut chunks = Vec::new();
        let mut at = 12;
        while at < bytes.len() {
            let size = word(bytes, at)? as usize;
            let kind = word(bytes, at + 4)?;
            let data = bytes.get(at + 8..(at + 8).checked_add(size)?)?.to_vec();
            at += 8 + size;
            chunks.push(Chunk { kind, data });
        }
        Some(Self { version, chunks })
    }

    /// The first JSON chunk's text, padding trimmed.
    pub fn json(&self) -> Option<&[u8]> {
        let chunk = self.chunks.iter().find(|c| c.kind == JSON)?;
        let end = chunk
            .data
            .iter()
            .rposition(|&b| b != b' ' && b != 0)
            .map_or(0, |i| i + 1);
        Some(&chunk.data[..end])
    }

    pub fn set_json(&mut self, text: Vec<u8>) {
        match self.chunks.iter_mut().find(|c| c.kind == JSON) {
            Some(chunk) => chunk.data = text,
            None => self.chunks.insert(
                0,
                Chunk {
                    kind: JSON,
                    data: text,
                },
            ),
        }
    }

    pub fn bin_mut(&mut self) -> Option<&mut Vec<u8>> {
        self.chunks
            .iter_mut()
            .find(|c| c.kind == BIN)
            .map(|c| &mut c.data)
    }

    /// A valid container: each chunk padded to 4 bytes (JSON with spaces, others with
    /// zeros), every length computed. A parsed, unmodified file packs to its own bytes.
    pub fn pack(&self) -> Vec<u8> {
        let padded = |c: &Chunk| c.data.len().div_ceil(4) * 4;
        let total = 12 + self.chunks.iter().map(|c| 8 + padded(c)).sum::<usize>();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&self.version.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        for chunk in &self.chunks {
            out.extend_from_slice(&(padded(chunk) as u32).to_le_bytes());
            out.extend_from_slice(&chunk.kind.to_le_bytes());
            out.extend_from_slice(&chunk.data);
            let pad = if chunk.kind == JSON { b' ' } else { 0 };
            out.resize(out.len() + padded(chunk) - chunk.data.len(), pad);
        }
        out
    }

    /// Packs the container with one header field or structure deliberately wrong, and says
    /// which.
    pub fn pack_broken(&self, rng: &mut Rng) -> (Vec<u8>, String) {
        let mut glb = self.clone();
        let note = match rng.below(7) {
            0 => {
                glb.version = rng.pick_copy(&[0, 1, 3, u32::MAX]);
                format!("GLB version {}", glb.version)
            }
            1 => {
                glb.chunks.retain(|c| c.kind != BIN);
                "GLB without its BIN chunk".to_string()
            }
            2 => {
                glb.chunks.push(Chunk {
                    kind: rng.pick_copy(&[BIN, JSON, 0x1234_5678]),
                    data: vec![0; rng.below(4) * 4],
                });
                "GLB with an extra chunk".to_string()
            }
            3 => {
                glb.chunks.reverse();
                "GLB chunks in reverse order".to_string()
            }
            4 => {
                let chunk = rng.below(glb.chunks.len());
                if let Some(c) = glb.chunks.get_mut(chunk) {
                    let others: Vec<u32> = [0, BIN, JSON, u32::MAX]
                        .into_iter()
                        .filter(|&k| k != c.kind)
                        .collect();
                    c.kind = rng.pick_copy(&others);
                }
                format!("GLB chunk {chunk} with a different type")
            }
            _ => {
                // Header words written wrong after packing: lengths that lie.
                let mut bytes = glb.pack();
                let chunk_header = 12 + self.chunks.first().map_or(0, |c| 8 + c.data.len());
                let at = rng.pick_copy(&[8, 12, chunk_header.min(bytes.len().saturating_sub(4))]);
                let value = rng.pick_copy(&[
                    0,
                    1,
                    3,
                    u32::MAX,
                    0x8000_0000,
                    word(&bytes, at).unwrap_or(0).wrapping_add(4),
                    word(&bytes, at).unwrap_or(0).wrapping_sub(4),
                    word(&bytes, at).unwrap_or(0).wrapping_add(1),
                ]);
                if let Some(slot) = bytes.get_mut(at..at + 4) {
                    slot.copy_from_slice(&value.to_le_bytes());
                }
                if rng.chance(0.3) {
                    let keep = rng.below(bytes.len().min(40));
                    bytes.truncate(keep);
                    return (bytes, format!("GLB cut to {keep} bytes"));
                }
                return (
                    bytes,
                    format!("GLB header word at byte {at} set to {value}"),
                );
            }
        };
        (glb.pack(), note)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn vendored_glbs() -> Vec<PathBuf> {
        let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        crate::corpus::find_files(&[scenes])
            .into_iter()
            .filter(|p| p.extension().is_some_and(|e| e == "glb"))
            .collect()
    }

    #[test]
    fn unmutated_glb_round_trips_byte_for_byte() {
        let files = vendored_glbs();
        assert!(!files.is_empty(), "no vendored .glb under assets/scenes");
        for path in files {
            let bytes = std::fs::read(&path).expect("read vendored glb");
            let glb = Glb::parse(&bytes).expect("vendored glb parses");
            assert!(glb.json().is_some(), "{}: no JSON chunk", path.display());
            assert!(
                glb.pack() == bytes,
                "{} does not round-trip",
                path.display()
            );
        }
    }

    #[test]
    fn repacked_json_is_padded_and_lengths_are_right() {
        let mut glb = Glb {
            version: 2,
            chunks: vec![Chunk {
                kind: BIN,
                data: vec![1, 2, 3, 4, 5],
            }],
        };
        glb.set_json(b"{\"a\":1}".to_vec());
        let bytes = glb.pack();
        assert_eq!(bytes.len() % 4, 0);
        assert_eq!(word(&bytes, 8), Some(bytes.len() as u32));
        let back = Glb::parse(&bytes).expect("repacked glb parses");
        assert_eq!(back.json(), Some(&b"{\"a\":1}"[..]));
        assert_eq!(back.chunks[0].data, b"{\"a\":1} ");
        assert_eq!(back.chunks[1].data, [1, 2, 3, 4, 5, 0, 0, 0]);
    }

    #[test]
    fn broken_containers_are_broken() {
        let glb = Glb {
            version: 2,
            chunks: vec![
                Chunk {
                    kind: JSON,
                    data: b"{}  ".to_vec(),
                },
                Chunk {
                    kind: BIN,
                    data: vec![0; 8],
                },
            ],
        };
        let good = glb.pack();
        let mut rng = Rng::new(11);
        for _ in 0..50 {
            let (bytes, note) = glb.pack_broken(&mut rng);
            assert!(bytes != good, "{note} left the container intact");
        }
    }
}
