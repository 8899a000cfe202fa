//! Meshes as quads: the unit the bin rasterizer works on.
//!
//! A quad `[a, b, c, d]` is the two triangles `(a, b, c)` and `(a, c, d)` sharing the diagonal
//! `a–c`. A lone triangle `(a, b, c)` is stored as the degenerate quad `[a, b, c, c]`, whose
//! second triangle has no area and covers nothing.

use glam::{Vec2, Vec3, Vec4};
use std::collections::HashMap;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub name: String,
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    /// Linear RGBA vertex colours, multiplied into the base colour.
    pub colours: Option<Vec<Vec4>>,
    pub uvs: Option<Vec<Vec2>>,
    pub quads: Vec<[u32; 4]>,
}

/// The largest texture coordinate a mesh may have: 2^24, past which an f32 holds no
/// fraction of a texture (and near 1e30 the hardware sampler's derivatives overflow).
pub const MAX_UV: f32 = 16_777_216.0;

impl Mesh {
    /// A mesh from a triangle list, paired into quads by [`pair_triangles`].
    pub fn from_triangles(
        name: impl Into<String>,
        positions: Vec<Vec3>,
        triangles: &[[u32; 3]],
    ) -> Self {
        Self {
            name: name.into(),
            positions,
            quads: pair_triangles(triangles),
            ..Self::default()
        }
    }

    /// A mesh from quads given directly.
    pub fn from_quads(name: impl Into<String>, positions: Vec<Vec3>, quads: Vec<[u32; 4]>) -> Self {
        Self {
            name: name.into(),
            positions,
            quads,
            ..Self::default()
        }
    }

    /// The one or two triangles of quad `q`; the second is `None` for a degenerate quad.
    pub fn quad_triangles(q: [u32; 4]) -> [Option<[u32; 3]>; 2] {
        let second = (q[3] != q[2] && q[3] != q[0]).then_some([q[0], q[2], q[3]]);
        [Some([q[0], q[1], q[2]]), second]
    }

    /// Quad `q` with the winding of its triangles reversed: the same triangles, in the same
    /// order, each turning the other way (a lone triangle stays one). Triangle 0 (0, 1, 2)
    /// becomes (2, 1, 0) and triangle 1 (0, 2, 3) becomes (2, 0, 3).
    pub fn reversed_quad(q: [u32; 4]) -> [u32; 4] {
        [q[2], q[1], q[0], q[3]]
    }

    /// Number of triangles with distinct corner indices.
    pub fn triangle_count(&self) -> usize {
        self.quads
            .iter()
            .map(|&q| Self::quad_triangles(q).iter().flatten().count())
            .sum()
    }

    /// Checks indices, attribute lengths, that positions are finite and that texture
    /// coordinates and colours are within their limits ([`MAX_UV`],
    /// [`crate::shading::MAX_COLOUR`]).
    pub fn validate(&self) -> Result<(), String> {
        let n = self.positions.len();
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(format!(
                "position {i} is not finite: {:?}",
                self.positions[i].to_array()
            ));
        }
        let check_len = |what: &str, len: Option<usize>| match len {
            Some(l) if l != n => Err(format!("{what} has {l} entries for {n} positions")),
            _ => Ok(()),
        };
        check_len("normals", self.normals.as_ref().map(Vec::len))?;
        check_len("colours", self.colours.as_ref().map(Vec::len))?;
        check_len("uvs", self.uvs.as_ref().map(Vec::len))?;
        if let Some(normals) = &self.normals {
            if let Some(i) = normals.iter().position(|v| !v.is_finite()) {
                return Err(format!("normal {i} is not finite"));
            }
        }
        if let Some(uvs) = &self.uvs {
            if let Some(i) = uvs
                .iter()
                .position(|v| !v.is_finite() || v.abs().max_element() > MAX_UV)
            {
                return Err(format!(
                    "uv {i} is {:?}: texture coordinates must be within ±{MAX_UV}",
                    uvs[i].to_array()
                ));
            }
        }
        if let Some(colours) = &self.colours {
            if let Some(i) = colours.iter().position(|&v| !crate::shading::is_colour(v)) {
                return Err(format!(
                    "colour {i} is {:?}: each channel must be in [0, {}]",
                    colours[i].to_array(),
                    crate::shading::MAX_COLOUR
                ));
            }
        }
        for (qi, q) in self.quads.iter().enumerate() {
            if let Some(&bad) = q.iter().find(|&&i| i as usize >= n) {
                return Err(format!(
                    "quad {qi} uses vertex {bad}, mesh has {n} vertices"
                ));
            }
        }
        Ok(())
    }
}

/// Pairs triangles that share an edge into quads, greedily in input order; triangles left
/// without a partner become degenerate quads.
///
/// Two triangles pair when one has the directed edge `u→v` and the other `v→u` (consistent
/// winding), so the quad keeps both triangles' orientation; the quad is rotated so that the
/// shared edge is its diagonal `q[0]–q[2]`.
pub fn pair_triangles(triangles: &[[u32; 3]]) -> Vec<[u32; 4]> {
    // Directed edge -> triangles having it.
    let mut by_edge: HashMap<(u32, u32), Vec<usize>> = HashMap::with_capacity(triangles.len() * 3);
    for (t, tri) in triangles.iter().enumerate() {
        for e in 0..3 {
            by_edge
                .entry((tri[e], tri[(e + 1) % 3]))
                .or_default()
                .push(t);
        }
    }
    let mut paired = vec![false; triangles.len()];
    let mut quads = Vec::with_capacity(triangles.len() / 2 + 1);
    for (t, tri) in triangles.iter().enumerate() {
        if paired[t] {
            continue;
        }
        paired[t] = true;
        let degenerate = tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0];
        // Among the unpaired neighbours, take the one with the fewest unpaired neighbours of
        // its own (it has the fewest other chances), preferring the next triangle on ties:
        // exporters usually emit a quad's two halves one after the other.
        let unpaired_neighbours = |o: usize| {
            let ot = triangles[o];
            (0..3)
                .filter_map(|e| by_edge.get(&(ot[(e + 1) % 3], ot[e])))
                .flatten()
                .filter(|&&n| !paired[n] && n != o)
                .count()
        };
        let partner = (0..3)
            .filter(|_| !degenerate)
            .flat_map(|e| {
                let (u, v) = (tri[e], tri[(e + 1) % 3]);
                let others = by_edge.get(&(v, u)).map(Vec::as_slice).unwrap_or(&[]);
                others
                    .iter()
                    .copied()
                    .filter(|&o| !paired[o])
                    .map(move |o| (e, o))
            })
            .min_by_key(|&(_, o)| (unpaired_neighbours(o), o != t + 1, o));
        match partner {
            Some((e, other)) => {
                paired[other] = true;
                // Rotate ours so the shared edge u→v is (q[2]→q[0]): q = [v, w, u, x].
                let u = tri[e];
                let v = tri[(e + 1) % 3];
                let w = tri[(e + 2) % 3];
                let o = triangles[other];
                let x = o.iter().copied().find(|&i| i != u && i != v).unwrap_or(u);
                quads.push([v, w, u, x]);
            }
            None => quads.push([tri[0], tri[1], tri[2], tri[2]]),
        }
    }
    quads
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each triangle of a reversed quad is the original one turning the other way, in the
    /// same place, and lone triangles stay lone.
    #[test]
    fn a_reversed_quad_keeps_its_triangles_and_turns_them() {
        let turned = |t: [u32; 3]| [[t[0], t[2], t[1]], [t[1], t[0], t[2]], [t[2], t[1], t[0]]];
        for q in [[0, 1, 2, 3], [0, 1, 2, 2], [0, 1, 2, 0]] {
            let before = Mesh::quad_triangles(q);
            let after = Mesh::quad_triangles(Mesh::reversed_quad(q));
            for (b, a) in before.iter().zip(&after) {
                match (b, a) {
                    (Some(b), Some(a)) => assert!(turned(*b).contains(a), "{q:?}: {b:?} {a:?}"),
                    (None, None) => {}
                    _ => panic!("{q:?}: {before:?} became {after:?}"),
                }
            }
        }
    }

    fn triangles_of(quads: &[[u32; 4]]) -> Vec<[u32; 3]> {
        quads
            .iter()
            .flat_map(|&q| Mesh::quad_triangles(q).into_iter().flatten())
            .collect()
    }

    /// Same triangle up to rotation (winding kept).
    fn same(a: [u32; 3], b: [u32; 3]) -> bool {
        (0..3).any(|r| (0..3).all(|i| a[i] == b[(i + r) % 3]))
    }

    #[test]
    fn two_triangles_of_a_square_make_one_quad() {
        let tris = [[0, 1, 2], [0, 2, 3]];
        let quads = pair_triangles(&tris);
        assert_eq!(quads.len(), 1);
        let back = triangles_of(&quads);
        assert_eq!(back.len(), 2);
        for t in tris {
            assert!(back.iter().any(|&b| same(b, t)), "{t:?} lost in {quads:?}");
        }
    }

    #[test]
    fn pairing_keeps_every_triangle_once_with_its_winding() {
        // A 3x3 grid of squares, each split into two triangles, plus one lone triangle.
        let mut tris = Vec::new();
        for y in 0..3u32 {
            for x in 0..3u32 {
                let i = y * 4 + x;
                tris.push([i, i + 1, i + 5]);
                tris.push([i, i + 5, i + 4]);
            }
        }
        tris.push([100, 101, 102]);
        let quads = pair_triangles(&tris);
        assert!(
            quads.len() <= 10,
            "only {} of 19 triangles paired",
            19 - quads.len()
        );
        let mut back = triangles_of(&quads);
        assert_eq!(back.len(), tris.len());
        for t in &tris {
            let k = back
                .iter()
                .position(|&b| same(b, *t))
                .expect("triangle lost");
            back.swap_remove(k);
        }
    }

    #[test]
    fn opposite_winding_does_not_pair() {
        let quads = pair_triangles(&[[0, 1, 2], [0, 1, 3]]);
        assert_eq!(quads, vec![[0, 1, 2, 2], [0, 1, 3, 3]]);
    }

    #[test]
    fn validate_rejects_out_of_range_index_and_nan() {
        let mut m = Mesh::from_quads("q", vec![Vec3::ZERO; 3], vec![[0, 1, 2, 3]]);
        assert!(m.validate().expect_err("invalid mesh").contains("vertex 3"));
        m.quads = vec![[0, 1, 2, 2]];
        m.positions[1].x = f32::NAN;
        assert!(m
            .validate()
            .expect_err("invalid mesh")
            .contains("not finite"));
    }
}
