//! The wavelet transmittance model on the CPU: the definition the shaders mirror
//! (`shaders/common/wavelet.glsl`, function for function) and the unit tests pin down.
//!
//! A pixel's absorbance `A(v) = Σ -ln T_i` over the fragments in front of normalized depth `v`
//! (0 at the pixel's nearest transparent fragment, 1 at its farthest) is a staircase. It is
//! stored as its projection onto the Haar basis of rank `r`: the scaling function plus levels
//! `0..=r` of wavelets, `N = 2^(r+1)` coefficients per colour channel, in heap order (index 0
//! is the scaling coefficient, level `j` holds indices `2^j .. 2^(j+1)`).
//!
//! Depth is placed in *cell space* `p = v · (N − 1)`, so the projection's N cells (each the
//! average of `A` over its width) cover events in the first `N − 1` and leave the last cell
//! behind every event: it holds the total absorbance, exactly, whatever the rank.
//!
//! - An event (absorbance `a` at `p`) projects to `a·(1 − p/N)` on the scaling coefficient and
//!   one coefficient per level: `rank + 2` additions, all additive, so order does not matter.
//! - Synthesis (the inverse Haar transform) turns the coefficients back into the N cell
//!   averages with constant indices only, which is what the shaders want.
//! - `A(p)` interpolates linearly between cell averages placed at the *far* end of their cells
//!   (`F(m)` at `p = m + 1`, with 0 at `p = 0`): a fragment sees the cells wholly in front of it
//!   and a share of its own cell. A lone event in cell `P` reads 0 up to `p = P`, then ramps to
//!   its full value at `p = P + 2` (two cells of blur: the price of N coefficients).
//! - A fragment's own share of the cell it sits in is `a·t·(1 − t)` at its own depth (`t` its
//!   position within the cell); the shading pass subtracts it (self-occlusion removal).

#![deny(unsafe_code)]

use glam::Vec3;

/// Highest rank supported: 16 coefficients per channel.
pub const MAX_RANK: u32 = 3;

/// Transmittance below which a channel counts as fully absorbed when turned into absorbance
/// (`-ln` of it is about 11.5, so one such fragment dims the rest by 1e-5).
pub const MIN_TRANSMITTANCE: f32 = 1e-5;

/// Coefficients (and cells) per colour channel at `rank`.
pub const fn coefficient_count(rank: u32) -> usize {
    2 << rank
}

/// Per-channel absorbance `-ln T` of a fragment's transmittance.
pub fn absorbance(transmittance: Vec3) -> Vec3 {
    -transmittance.max(Vec3::splat(MIN_TRANSMITTANCE)).ln()
}

/// Transmittance of an absorbance (clamped so rounding never makes it exceed 1).
pub fn transmittance(absorbance: Vec3) -> Vec3 {
    (-absorbance.max(Vec3::ZERO)).exp()
}

/// Normalized depth of `view_depth` between a pixel's nearest and farthest transparent
/// fragments; 0 when they coincide.
pub fn normalized_depth(view_depth: f32, nearest: f32, farthest: f32) -> f32 {
    let range = farthest - nearest;
    if range > 0.0 {
        ((view_depth - nearest) / range).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Cell-space position of normalized depth `v` (clamped to [0, 1]).
pub fn cell_position(v: f32, rank: u32) -> f32 {
    v.clamp(0.0, 1.0) * (coefficient_count(rank) - 1) as f32
}

/// The noise offset of pixel (x, y) in [0, 1): a fixed integer hash, so frames repeat.
pub fn pixel_noise(x: u32, y: u32) -> f32 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Cell-space position of `v` with depth noise: shifted towards the front by up to
/// `strength` cells, scaled by a tent that is 0 at both ends of the range (so the nearest and
/// farthest fragments stay put and the mapping stays monotonic). `strength` is clamped to
/// what keeps it monotonic; 0 turns noise off.
pub fn noisy_cell_position(v: f32, rank: u32, strength: f32, noise: f32) -> f32 {
    let v = v.clamp(0.0, 1.0);
    let p = cell_position(v, rank);
    let limit = 0.5 * (coefficient_count(rank) - 1) as f32;
    let tent = 2.0 * v.min(1.0 - v);
    p - strength.clamp(0.0, limit) * noise * tent
}

/// `√2^-j`: the scale of level-`j` wavelets' integrals.
fn level_scale(level: u32) -> f32 {
    (-0.5 * level as f32).exp2()
}

/// The coefficient updates of one event: `(index, addend)` for the scaling coefficient and
/// each level, `rank + 2` in all.
pub fn event_addends(p: f32, rank: u32, absorbance: Vec3) -> Vec<(usize, Vec3)> {
    let n = coefficient_count(rank) as f32;
    let u = p / n; // position on the unit interval, < (N − 1) / N
    let mut out = vec![(0, absorbance * (1.0 - u))];
    for level in 0..=rank {
        let width = (1u32 << level) as f32;
        let s = u * width;
        let k = s.floor().clamp(0.0, width - 1.0);
        let f = s - k;
        // ∫ of the wavelet from its start to u: a tent peaking at the wavelet's middle.
        let tent = if f < 0.5 { f } else { 1.0 - f };
        let index = (1usize << level) + k as usize;
        out.push((index, -absorbance * (level_scale(level) * tent)));
    }
    out
}

/// Adds one event to `coefficients` (length `coefficient_count(rank)`).
pub fn add_event(coefficients: &mut [Vec3], rank: u32, p: f32, absorbance: Vec3) {
    for (i, addend) in event_addends(p, rank, absorbance) {
        coefficients[i] += addend;
    }
}

/// The inverse Haar transform: the N cell averages of the absorbance staircase. Cell `m` is
/// the scaling coefficient plus, per level, the wavelet covering it, signed + in the first
/// half of its support (the shader's form: constant indices, no pyramid of temporaries).
pub fn synthesize(coefficients: &[Vec3], rank: u32) -> Vec<Vec3> {
    (0..coefficient_count(rank))
        .map(|m| {
            let mut v = coefficients[0];
            for level in 0..=rank {
                let shift = rank - level;
                let k = m >> (shift + 1);
                let sign = if (m >> shift) & 1 == 0 { 1.0 } else { -1.0 };
                v += coefficients[(1 << level) + k] * (sign * (0.5 * level as f32).exp2());
            }
            v
        })
        .collect()
}

/// Absorbance in front of cell-space position `p`, from the cell averages.
pub fn absorbance_at(cells: &[Vec3], p: f32) -> Vec3 {
    let last = cells.len() - 1;
    let p = p.clamp(0.0, last as f32);
    let m = (p.floor() as usize).min(last);
    let t = p - m as f32;
    let before = if m == 0 { Vec3::ZERO } else { cells[m - 1] };
    before.lerp(cells[m], t)
}

/// Absorbance in front of a fragment at `p` whose own absorbance is `own`, with its own
/// share removed: what the shading pass multiplies its radiance by (as transmittance).
pub fn absorbance_in_front(cells: &[Vec3], p: f32, own: Vec3) -> Vec3 {
    let last = cells.len() - 1;
    let p = p.clamp(0.0, last as f32);
    let t = p - (p.floor()).min(last as f32);
    (absorbance_at(cells, p) - own * (t * (1.0 - t))).max(Vec3::ZERO)
}

/// Absorbance behind every transparent fragment: the last cell, the exact total.
pub fn absorbance_behind_all(cells: &[Vec3]) -> Vec3 {
    cells[cells.len() - 1]
}

/// The first cell-space position at which every channel's absorbance reaches `limit`, if
/// any before the farthest fragment (p = N − 1). Fragments behind it are invisible.
pub fn opaque_position(cells: &[Vec3], limit: f32) -> Option<f32> {
    let mut crossing = [f32::INFINITY; 3];
    let mut before = Vec3::ZERO;
    for (m, &after) in cells[..cells.len() - 1].iter().enumerate() {
        for c in 0..3 {
            if crossing[c].is_infinite() && after[c] >= limit {
                // First segment where channel c reaches the limit: solve the linear ramp.
                let rise = after[c] - before[c];
                let t = if rise > 0.0 {
                    ((limit - before[c]) / rise).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                crossing[c] = m as f32 + t;
            }
        }
        before = after;
    }
    let p = crossing[0].max(crossing[1]).max(crossing[2]);
    p.is_finite().then_some(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RANKS: [u32; 4] = [0, 1, 2, 3];

    fn close(a: Vec3, b: Vec3, eps: f32) -> bool {
        (a - b).abs().max_element() <= eps
    }

    fn cells_of(events: &[(f32, Vec3)], rank: u32) -> Vec<Vec3> {
        let mut c = vec![Vec3::ZERO; coefficient_count(rank)];
        for &(v, a) in events {
            add_event(&mut c, rank, cell_position(v, rank), a);
        }
        synthesize(&c, rank)
    }

    /// A lone event is a step: nothing in front of the cell it falls in, all of it from two
    /// cell boundaries on, and exactly its own share at its own depth (which self-removal
    /// cancels).
    #[test]
    fn one_event_is_a_step_at_its_depth() {
        let a = Vec3::new(0.5, 1.0, 2.0);
        for rank in RANKS {
            let n = coefficient_count(rank);
            for i in 0..=40 {
                let v = i as f32 / 40.0;
                let cells = cells_of(&[(v, a)], rank);
                let p = cell_position(v, rank);
                let cell = p.floor();
                for j in 0..=200 {
                    let q = j as f32 / 200.0 * (n - 1) as f32;
                    let got = absorbance_at(&cells, q);
                    if q <= cell {
                        assert!(
                            close(got, Vec3::ZERO, 1e-5),
                            "rank {rank} v {v} q {q}: {got}"
                        );
                    } else if q >= cell + 2.0 {
                        assert!(close(got, a, 1e-5), "rank {rank} v {v} q {q}: {got}");
                    } else {
                        assert!(got.cmpge(Vec3::ZERO).all() && got.cmple(a + 1e-5).all());
                    }
                }
                assert!(close(absorbance_behind_all(&cells), a, 1e-5));
                assert!(close(absorbance_in_front(&cells, p, a), Vec3::ZERO, 1e-5));
            }
        }
    }

    /// The coefficients are sums: any order of the same events gives the same function.
    #[test]
    fn sums_do_not_depend_on_order() {
        let events: Vec<(f32, Vec3)> = (0..12)
            .map(|i| {
                let v = ((i * 7) % 12) as f32 / 11.0;
                (v, Vec3::new(0.1 * i as f32, 0.3, 1.0 - 0.05 * i as f32))
            })
            .collect();
        for rank in RANKS {
            let forward = cells_of(&events, rank);
            let mut reversed = events.clone();
            reversed.reverse();
            let mut shuffled = events.clone();
            shuffled.rotate_left(5);
            shuffled.swap(0, 7);
            for other in [cells_of(&reversed, rank), cells_of(&shuffled, rank)] {
                for (a, b) in forward.iter().zip(&other) {
                    assert!(close(*a, *b, 1e-5), "rank {rank}: {a} vs {b}");
                }
            }
        }
    }

    /// Past the last event the transmittance is the product of every fragment's, rank by rank.
    #[test]
    fn past_the_last_event_is_the_product_of_transmittances() {
        let ts = [
            Vec3::new(0.5, 0.9, 1.0),
            Vec3::new(0.2, 0.2, 0.7),
            Vec3::new(1.0, 0.0, 0.5),
            Vec3::new(0.8, 0.6, 0.4),
        ];
        let depths = [0.0, 0.13, 0.5, 0.61];
        let product = ts.iter().fold(Vec3::ONE, |acc, t| acc * *t);
        for rank in RANKS {
            let n = coefficient_count(rank);
            let events: Vec<_> = depths
                .iter()
                .zip(&ts)
                .map(|(&v, &t)| (v, absorbance(t)))
                .collect();
            let cells = cells_of(&events, rank);
            let behind = transmittance(absorbance_behind_all(&cells));
            let want = product.max(Vec3::splat(MIN_TRANSMITTANCE));
            assert!(
                close(behind, want, 1e-5),
                "rank {rank}: {behind} vs {product}"
            );
            // And from two cell boundaries past the last event to the far end.
            let last_cell = cell_position(0.61, rank).floor() + 2.0;
            if last_cell <= (n - 1) as f32 {
                let t = transmittance(absorbance_at(&cells, last_cell));
                assert!(close(t, want, 1e-4), "rank {rank} at the far end: {t}");
            }
        }
    }

    /// Synthesis inverts the projection: cell averages of a step are its covered fractions.
    #[test]
    fn cells_are_the_averages_of_the_step() {
        for rank in RANKS {
            let n = coefficient_count(rank);
            let p = 0.37 * (n - 1) as f32;
            let cells = cells_of(&[(0.37, Vec3::ONE)], rank);
            for (m, c) in cells.iter().enumerate() {
                let want = ((m + 1) as f32 - p).clamp(0.0, 1.0);
                assert!(
                    (c.x - want).abs() < 1e-5,
                    "rank {rank} cell {m}: {c} vs {want}"
                );
            }
        }
    }

    /// Depth of full absorption: where the sum of two opaque-ish layers crosses the limit.
    #[test]
    fn opaque_position_finds_the_crossing() {
        let rank = 3;
        let cells = cells_of(&[(0.2, Vec3::splat(5.0)), (0.6, Vec3::splat(5.0))], rank);
        let p = opaque_position(&cells, 8.0).expect("crosses");
        let second = cell_position(0.6, rank);
        assert!(p > second && p <= second.floor() + 2.0, "{p} vs {second}");
        assert!(opaque_position(&cells, 11.0).is_none());
        // One channel that never absorbs keeps every depth visible.
        let cells = cells_of(&[(0.2, Vec3::new(20.0, 20.0, 0.0))], rank);
        assert!(opaque_position(&cells, 8.0).is_none());
    }

    #[test]
    fn noise_keeps_the_ends_and_the_order() {
        for rank in RANKS {
            let last = (coefficient_count(rank) - 1) as f32;
            assert_eq!(noisy_cell_position(0.0, rank, 1.0, 0.9), 0.0);
            assert_eq!(noisy_cell_position(1.0, rank, 1.0, 0.9), last);
            let mut previous = -1.0;
            for i in 0..=100 {
                let p = noisy_cell_position(i as f32 / 100.0, rank, 4.0, 0.99);
                assert!(p >= previous, "rank {rank}: not monotonic at {i}");
                previous = p;
            }
        }
        let h = pixel_noise(3, 4);
        assert!((0.0..1.0).contains(&h) && h != pixel_noise(4, 3));
    }
}
