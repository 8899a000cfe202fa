//! Raw byte mutations, for any file (JSON text, GLB, .bin, images), and targeted ones for
//! image headers, whose sizes random flips rarely hit and whose CRCs they break.

use crate::rng::Rng;
use std::ops::Range;

/// 32-bit values that tend to break size and index arithmetic, and float bit patterns
/// (NaN, infinities, 1e30) for vertex data.
const INTERESTING_U32: &[u32] = &[
    0,
    1,
    0x7F,
    0x80,
    0xFF,
    0xFFFF,
    0x1_0000,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x7FC0_0000, // NaN
    0x7F80_0000, // +inf
    0xFF80_0000, // -inf
    0x7149_F2CA, // 1e30
    0xF149_F2CA, // -1e30
    0x0000_0001, // smallest subnormal
];

/// Mutates `data` in place with one to four raw edits, any of which may change its length;
/// returns what it did.
pub fn mutate(data: &mut Vec<u8>, rng: &mut Rng) -> String {
    let edits = rng.range(1, 4);
    let notes: Vec<String> = (0..edits).map(|_| edit(data, rng, true)).collect();
    notes.join(", ")
}

/// Like [`mutate`] but only inside `range` and without changing the length (bytes inside a
/// container whose offsets must stay put).
pub fn mutate_in(data: &mut [u8], range: Range<usize>, rng: &mut Rng) -> String {
    let end = range.end.min(data.len());
    let start = range.start.min(end);
    let mut window = data[start..end].to_vec();
    let edits = rng.range(1, 4);
    let notes: Vec<String> = (0..edits).map(|_| edit(&mut window, rng, false)).collect();
    data[start..end].copy_from_slice(&window);
    format!("{} (bytes {start}..{end})", notes.join(", "))
}

fn edit(data: &mut Vec<u8>, rng: &mut Rng, resize: bool) -> String {
    let len = data.len();
    if len == 0 {
        if resize {
            data.extend((0..rng.range(1, 16)).map(|_| rng.byte()));
            return format!("filled an empty file with {} random bytes", data.len());
        }
        return "nothing (empty)".to_string();
    }
    let at = rng.below(len);
    match rng.below(if resize { 9 } else { 5 }) {
        0 => {
            let flips = rng.range(1, 8);
            for _ in 0..flips {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
            format!("flipped {flips} bits")
        }
        1 => {
            let value = rng.pick_copy(&[0u8, 0xFF, 0x7F, 0x80, b'"', b'{', b'[', b'-', b'9']);
            data[at] = value;
            format!("byte {at} = {value:#04x}")
        }
        2 | 3 => {
            let value = rng.pick_copy(INTERESTING_U32);
            let at = at.min(len.saturating_sub(4));
            let bytes = value.to_le_bytes();
            let n = (len - at).min(4);
            data[at..at + n].copy_from_slice(&bytes[..n]);
            format!("u32 at {at} = {value:#x}")
        }
        4 => {
            let n = rng.range(1, 64).min(len - at);
            for b in &mut data[at..at + n] {
                *b = rng.byte();
            }
            format!("{n} random bytes at {at}")
        }
        5 => {
            data.truncate(at);
            format!("truncated to {at} bytes")
        }
        6 => {
            let n = rng.range(1, 256);
            let junk: Vec<u8> = (0..n).map(|_| rng.byte()).collect();
            data.splice(at..at, junk);
            format!("inserted {n} random bytes at {at}")
        }
        7 => {
            let n = rng.range(1, 256).min(len - at);
            data.drain(at..at + n);
            format!("deleted {n} bytes at {at}")
        }
        _ => {
            let n = rng.range(1, 1024).min(len - at);
            let copy = data[at..at + n].to_vec();
            let to = rng.below(len);
            data.splice(to..to, copy);
            format!("copied {n} bytes from {at} to {to}")
        }
    }
}

/// Rewrites an encoded image's declared size (PNG IHDR with its CRC fixed, or a JPEG
/// start-of-frame), so that decoders see plausible headers with extreme dimensions. `None`
/// when the bytes are neither.
pub fn image_header(data: &mut [u8], rng: &mut Rng) -> Option<String> {
    const SIZES: &[u32] = &[0, 1, 16384, 16385, 32768, 65535, 0x7FFF_FFFF, 0xFFFF_FFFF];
    if data.starts_with(b"\x89PNG\r\n\x1a\n") && data.get(12..16) == Some(b"IHDR") {
        let (w, h) = (rng.pick_copy(SIZES), rng.pick_copy(SIZES));
        let (w, h) = match rng.below(3) {
            0 => (w, h),
            1 => (w, 1),
            _ => (1, h),
        };
        data.get_mut(16..20)?.copy_from_slice(&w.to_be_bytes());
        data.get_mut(20..24)?.copy_from_slice(&h.to_be_bytes());
        let mut note = format!("PNG IHDR {w}x{h}");
        if rng.chance(0.3) {
            // Bit depth and colour type, valid pairs and not.
            let depth = rng.pick_copy(&[1u8, 2, 4, 8, 16, 3, 0]);
            let colour = rng.pick_copy(&[0u8, 2, 3, 4, 6, 5, 7]);
            data[24] = depth;
            data[25] = colour;
            note.push_str(&format!(", depth {depth}, colour type {colour}"));
        }
        let crc = crc32(data.get(12..29)?);
        data.get_mut(29..33)?.copy_from_slice(&crc.to_be_bytes());
        return Some(note);
    }
    if data.starts_with(&[0xFF, 0xD8]) {
        // Start of frame (baseline, extended, progressive): FF C0/C1/C2, length, precision,
        // height, width.
        let sof = data
            .windows(2)
            .position(|w| w[0] == 0xFF && matches!(w[1], 0xC0..=0xC2))?;
        let (w, h) = (
            rng.pick_copy(&[0u16, 1, 16384, 16385, 65535]),
            rng.pick_copy(&[0u16, 1, 16384, 16385, 65535]),
        );
        data.get_mut(sof + 5..sof + 7)?
            .copy_from_slice(&h.to_be_bytes());
        data.get_mut(sof + 7..sof + 9)?
            .copy_from_slice(&w.to_be_bytes());
        return Some(format!("JPEG frame {w}x{h}"));
    }
    None
}

/// CRC-32 (IEEE), as PNG chunks carry it.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_matches_png() {
        // The IHDR of a 1x1 8-bit RGBA PNG and the CRC every encoder writes for it.
        let ihdr = b"IHDR\x00\x00\x00\x01\x00\x00\x00\x01\x08\x06\x00\x00\x00";
        assert_eq!(crc32(ihdr), 0x1F15_C489);
    }

    #[test]
    fn in_place_mutation_keeps_length_and_range() {
        let mut rng = Rng::new(5);
        for _ in 0..200 {
            let mut data = vec![0xAAu8; 64];
            mutate_in(&mut data, 16..32, &mut rng);
            assert_eq!(data.len(), 64);
            assert!(data[..16].iter().chain(&data[32..]).all(|&b| b == 0xAA));
        }
    }
}
