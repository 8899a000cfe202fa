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

/// CRC-32 (IEEE), as PNG chunks carry it; table-driven, since bombs are megabytes.
fn crc32(bytes: &[u8]) -> u32 {
    const TABLE: [u32; 256] = {
        let mut table = [0u32; 256];
        let mut i = 0;
        while i < 256 {
            let mut c = i as u32;
            let mut k = 0;
            while k < 8 {
                c = if c & 1 != 0 {
                    (c >> 1) ^ 0xEDB8_8320
                } else {
                    c >> 1
                };
                k += 1;
            }
            table[i] = c;
            i += 1;
        }
        table
    };
    let mut crc = 0xFFFF_FFFFu32;
    for &b in bytes {
        crc = TABLE[((crc ^ u32::from(b)) & 0xFF) as usize] ^ (crc >> 8);
    }
    !crc
}

/// Deflate bits, least significant first (RFC 1951 §3.1.1).
struct Bits {
    out: Vec<u8>,
    acc: u64,
    len: u32,
}

impl Bits {
    /// Writes `count` bits of `value`, lowest first.
    fn put(&mut self, value: u32, count: u32) {
        self.acc |= u64::from(value) << self.len;
        self.len += count;
        while self.len >= 8 {
            self.out.push(self.acc as u8);
            self.acc >>= 8;
            self.len -= 8;
        }
    }

    /// Writes a Huffman code, which deflate stores most significant bit first.
    fn code(&mut self, code: u32, count: u32) {
        let reversed = code.reverse_bits() >> (32 - count);
        self.put(reversed, count);
    }

    fn finish(mut self) -> Vec<u8> {
        if self.len > 0 {
            self.out.push(self.acc as u8);
        }
        self.out
    }
}

/// A valid, all-zero (transparent black) RGBA8 PNG of `width` x `height`: a few megabytes
/// that decode to up to 1 GiB, since every row is zeros that deflate's 258-byte copies
/// repeat for 13 bits each. What a size check on the header alone lets through.
pub fn png_bomb(width: u32, height: u32) -> Vec<u8> {
    // Each row: filter type 0, then four zero bytes a pixel.
    let raw = u64::from(height) * (1 + 4 * u64::from(width));
    let mut bits = Bits {
        out: Vec::with_capacity((raw / 158) as usize + 64),
        acc: 0,
        len: 0,
    };
    bits.put(1, 1); // final block
    bits.put(1, 2); // fixed Huffman codes
    bits.code(0x30, 8); // literal 0
    let mut left = raw.saturating_sub(1);
    while left >= 258 {
        bits.code(0xC5, 8); // length 258 (symbol 285)
        bits.code(0, 5); // distance 1
        left -= 258;
    }
    for _ in 0..left {
        bits.code(0x30, 8);
    }
    bits.code(0, 7); // end of block
    let mut zlib = vec![0x78, 0x01];
    zlib.extend(bits.finish());
    // Adler-32 of zeros: a stays 1, b adds 1 per byte.
    let adler = (((raw % 65521) as u32) << 16) | 1;
    zlib.extend_from_slice(&adler.to_be_bytes());

    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut chunk = |kind: &[u8; 4], data: &[u8]| {
        png.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let start = png.len();
        png.extend_from_slice(kind);
        png.extend_from_slice(data);
        let crc = crc32(&png[start..]);
        png.extend_from_slice(&crc.to_be_bytes());
    };
    let mut ihdr = Vec::with_capacity(13);
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 6, 0, 0, 0]); // 8-bit RGBA, deflate, no filter, no interlace
    chunk(b"IHDR", &ihdr);
    chunk(b"IDAT", &zlib);
    chunk(b"IEND", &[]);
    png
}

/// Sizes for [`png_bomb`]: the largest a header check allows, in both orientations, and
/// just past it.
pub const BOMB_SIZES: &[(u32, u32)] = &[
    (16384, 16384),
    (16384, 16384),
    (16384, 8192),
    (8192, 8192),
    (16384, 1),
    (16385, 16385),
];

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
    fn png_bombs_decode_to_zeros_of_their_size() {
        for (w, h) in [(1, 1), (7, 3), (64, 64), (300, 2)] {
            let png = png_bomb(w, h);
            let image = image::load_from_memory(&png).expect("the bomb is a valid PNG");
            assert_eq!((image.width(), image.height()), (w, h));
            assert!(image.to_rgba8().into_raw().iter().all(|&b| b == 0));
        }
        // 1 GiB of pixels in a few megabytes.
        assert!(png_bomb(16384, 16384).len() < 8 << 20);
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
