//! Test support: std430 offsets of a struct in a GLSL include, so that tests can check the
//! `#[repr(C)]` mirrors against the shader source itself.

/// `(field, offset)` of every member of `struct name` in `src`, and the struct's size.
/// Knows the member types our layouts use; any other type fails the test that asks.
pub fn std430_offsets(src: &str, name: &str) -> (Vec<(String, usize)>, usize) {
    let start = src
        .find(&format!("struct {name} {{"))
        .unwrap_or_else(|| panic!("struct {name} not found"));
    let body = &src[start..start + src[start..].find("};").expect("struct end")];
    let mut offset = 0usize;
    let mut largest_align = 4;
    let mut out = Vec::new();
    for line in body.lines().skip(1) {
        let code = line.split("//").next().unwrap_or("").trim();
        let Some(decl) = code.strip_suffix(';') else {
            continue;
        };
        let mut parts = decl.split_whitespace();
        let (ty, field) = (parts.next().expect("type"), parts.next().expect("name"));
        let (size, align) = match ty {
            "float" | "int" | "uint" => (4, 4),
            "vec2" | "ivec2" | "uvec2" => (8, 8),
            "vec4" | "ivec4" | "uvec4" => (16, 16),
            "mat4" => (64, 16),
            "i64vec4" | "dvec4" => (32, 32),
            other => panic!("{name}.{field} has type {other}; teach glsl_layout its std430 layout"),
        };
        offset = offset.next_multiple_of(align);
        largest_align = largest_align.max(align);
        out.push((field.to_string(), offset));
        offset += size;
    }
    (out, offset.next_multiple_of(largest_align))
}
