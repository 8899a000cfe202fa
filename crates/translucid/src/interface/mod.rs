//! The shader interface, declared once: the structures host and shaders share, the constants
//! both read, the specialization constants and the descriptor bindings. Each is written here in
//! Rust; `build.rs` compiles this module too and writes the GLSL includes the shaders use
//! (`$OUT_DIR/interface/interface_*.glsl`), so the two sides cannot drift. A structure whose
//! Rust layout differs from the std430 layout its GLSL twin gets does not compile.
//!
//! This module depends on nothing but `std` and `bytemuck`, since the build script compiles it
//! on its own.

#![deny(unsafe_code)]

/// The GLSL types a shared structure's fields may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlslType {
    Float,
    Int,
    Uint,
    Vec2,
    Vec3,
    Vec4,
    Ivec2,
    Ivec4,
    Uvec2,
    Uvec4,
    Mat4,
    I64vec4,
    Dvec4,
}

impl GlslType {
    /// Size and alignment in bytes under std430.
    pub const fn size_align(self) -> (usize, usize) {
        match self {
            Self::Float | Self::Int | Self::Uint => (4, 4),
            Self::Vec2 | Self::Ivec2 | Self::Uvec2 => (8, 8),
            Self::Vec3 => (12, 16),
            Self::Vec4 | Self::Ivec4 | Self::Uvec4 => (16, 16),
            Self::Mat4 => (64, 16),
            Self::I64vec4 | Self::Dvec4 => (32, 32),
        }
    }

    pub const fn name(self) -> &'static str {
        match self {
            Self::Float => "float",
            Self::Int => "int",
            Self::Uint => "uint",
            Self::Vec2 => "vec2",
            Self::Vec3 => "vec3",
            Self::Vec4 => "vec4",
            Self::Ivec2 => "ivec2",
            Self::Ivec4 => "ivec4",
            Self::Uvec2 => "uvec2",
            Self::Uvec4 => "uvec4",
            Self::Mat4 => "mat4",
            Self::I64vec4 => "i64vec4",
            Self::Dvec4 => "dvec4",
        }
    }
}

/// One field of a shared structure.
pub struct Field {
    /// The Rust name; GLSL's is its camel case.
    pub name: &'static str,
    pub ty: GlslType,
    /// Elements of an array field; 0 for a single value.
    pub len: usize,
    pub doc: &'static [&'static str],
}

/// A structure both sides read: a `#[repr(C)]` Rust struct and its GLSL twin.
pub struct StructDecl {
    pub glsl: &'static str,
    pub doc: &'static [&'static str],
    pub fields: &'static [Field],
}

impl StructDecl {
    /// Whether fields at `offsets`, in a struct of `size` bytes, are where std430 puts them.
    pub const fn matches(&self, offsets: &[usize], size: usize) -> bool {
        if offsets.len() != self.fields.len() {
            return false;
        }
        let mut offset: usize = 0;
        let mut largest: usize = 4;
        let mut i = 0;
        while i < self.fields.len() {
            let field = &self.fields[i];
            let (mut bytes, align) = field.ty.size_align();
            if field.len > 0 {
                // Array elements are padded to their alignment; a lone vec3 is not.
                bytes = bytes.next_multiple_of(align) * field.len;
            }
            offset = offset.next_multiple_of(align);
            if offsets[i] != offset {
                return false;
            }
            if align > largest {
                largest = align;
            }
            offset += bytes;
            i += 1;
        }
        size == offset.next_multiple_of(largest)
    }
}

/// A constant both sides read, a `#define` in GLSL.
pub struct Constant {
    pub name: &'static str,
    pub value: ConstantValue,
    pub doc: &'static [&'static str],
}

/// A constant's value as GLSL writes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstantValue {
    /// With a `u` suffix.
    Uint(u32),
    Int(i32),
    Float(f32),
}

impl std::fmt::Display for ConstantValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Uint(v) => write!(f, "{v}u"),
            Self::Int(v) => write!(f, "{v}"),
            Self::Float(v) => write!(f, "{v:?}"),
        }
    }
}

/// What kind of descriptor a binding is, with what its GLSL declaration needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BindingType {
    /// `uniform <glsl> <name>`: a uniform texel buffer (`usamplerBuffer`, `samplerBuffer`).
    Texels { glsl: &'static str },
    /// `layout(<format>) uniform <access> <glsl> <name>`: a storage texel buffer.
    StorageTexels(Storage),
    /// `layout(std430) <qualifiers> buffer <name> { <members> }`: a storage buffer.
    Buffer {
        qualifiers: &'static str,
        members: &'static [&'static str],
        /// The block's instance name, or "" for none (members are then global names).
        instance: &'static str,
    },
    /// `layout(std140) uniform <name> { <members> }`: a uniform buffer.
    Uniform { members: &'static [&'static str] },
    /// `uniform <glsl> <name>[count]`: combined image samplers.
    Sampled { glsl: &'static str, count: u32 },
    /// `layout(<format>) uniform <access> <glsl> <name>`: a storage image.
    StorageImage(Storage),
}

/// What the declaration of a storage image or storage texel buffer names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Storage {
    /// The image format (`rgba32ui`).
    pub format: &'static str,
    /// `readonly`, `writeonly` or nothing.
    pub access: &'static str,
    /// The GLSL type (`uimageBuffer`, `image2D`).
    pub glsl: &'static str,
}

/// One binding of a descriptor set: its number is its place in the set's list, and the host
/// writes it by `name` (the GLSL variable, or the block's name for buffers).
pub struct Binding {
    pub name: &'static str,
    pub ty: BindingType,
    pub doc: &'static [&'static str],
}

impl Binding {
    pub const fn texels(name: &'static str, glsl: &'static str) -> Self {
        Self::new(name, BindingType::Texels { glsl })
    }

    pub const fn storage_texels(name: &'static str, storage: [&'static str; 3]) -> Self {
        Self::new(name, BindingType::StorageTexels(Storage::of(storage)))
    }

    pub const fn buffer(
        name: &'static str,
        qualifiers: &'static str,
        members: &'static [&'static str],
    ) -> Self {
        Self::new(
            name,
            BindingType::Buffer {
                qualifiers,
                members,
                instance: "",
            },
        )
    }

    /// [`Self::buffer`] whose block has an instance name: `<name> { ... } <instance>`.
    pub const fn buffer_instance(
        name: &'static str,
        qualifiers: &'static str,
        members: &'static [&'static str],
        instance: &'static str,
    ) -> Self {
        Self::new(
            name,
            BindingType::Buffer {
                qualifiers,
                members,
                instance,
            },
        )
    }

    pub const fn uniform(name: &'static str, members: &'static [&'static str]) -> Self {
        Self::new(name, BindingType::Uniform { members })
    }

    pub const fn sampled(name: &'static str, glsl: &'static str, count: u32) -> Self {
        Self::new(name, BindingType::Sampled { glsl, count })
    }

    pub const fn image(name: &'static str, storage: [&'static str; 3]) -> Self {
        Self::new(name, BindingType::StorageImage(Storage::of(storage)))
    }

    const fn new(name: &'static str, ty: BindingType) -> Self {
        Self { name, ty, doc: &[] }
    }

    /// The same, with comment lines for the GLSL.
    pub const fn doc(self, doc: &'static [&'static str]) -> Self {
        Self { doc, ..self }
    }
}

impl Storage {
    /// `[format, access, glsl]`.
    const fn of([format, access, glsl]: [&'static str; 3]) -> Self {
        Self {
            format,
            access,
            glsl,
        }
    }
}

/// A descriptor set both sides use.
pub struct SetDecl {
    /// The set's number in the pipeline layouts that use it, as GLSL writes it: a number, or
    /// a name the including shader defines (where pipelines bind the set at different places).
    pub set: &'static str,
    /// The set whose bindings come first, for a set that is another with more (their GLSL is
    /// that set's include and this one's).
    pub extends: Option<&'static SetDecl>,
    /// This set's own bindings, numbered after those of the set it extends.
    pub bindings: &'static [Binding],
}

impl SetDecl {
    /// A set of `bindings` alone, at `set`.
    pub const fn new(set: &'static str, bindings: &'static [Binding]) -> Self {
        Self {
            set,
            extends: None,
            bindings,
        }
    }

    /// Binding numbers before this set's own: those of the sets it extends.
    pub fn first_binding(&self) -> usize {
        self.extends.map_or(0, |base| base.all_bindings().len())
    }

    /// Every binding, the extended set's first, by number.
    pub fn all_bindings(&self) -> Vec<&'static Binding> {
        let mut all = self
            .extends
            .map_or_else(Vec::new, |base| base.all_bindings());
        all.extend(self.bindings.iter());
        all
    }
}

/// One generated include: what it declares, in order.
pub struct Include {
    /// File name under `$OUT_DIR/interface/`.
    pub file: &'static str,
    /// The Rust module it comes from, named in its header.
    pub source: &'static str,
    pub constants: &'static [Constant],
    pub structs: &'static [&'static StructDecl],
    pub sets: Vec<&'static SetDecl>,
    /// Declarations the module writes itself (the specialization constants).
    pub more: Option<fn() -> String>,
    /// Includes it needs first.
    pub needs: &'static [&'static str],
}

/// Every generated include.
pub fn includes() -> Vec<Include> {
    vec![
        scene::include(),
        scene::set_include(),
        raster::include(),
        bins::include(),
        bins::set_include(),
        bins::texture_array_include(),
        bins::composite_include(),
        exact::include(),
        specialization::include(),
    ]
    .into_iter()
    .chain(methods::includes())
    .collect()
}

/// `first_texel` as `firstTexel`.
pub fn camel_case(name: &str) -> String {
    let mut out = String::with_capacity(name.len());
    let mut upper = false;
    for c in name.chars() {
        if c == '_' {
            upper = true;
        } else if upper {
            out.extend(c.to_uppercase());
            upper = false;
        } else {
            out.push(c);
        }
    }
    out
}

fn comment(out: &mut String, indent: &str, doc: &[&str]) {
    for line in doc {
        let line = line.strip_prefix(' ').unwrap_or(line);
        out.push_str(format!("{indent}// {line}").trim_end());
        out.push('\n');
    }
}

/// The GLSL text of `include`.
pub fn glsl(include: &Include) -> String {
    let guard = include.file.replace('.', "_").to_uppercase();
    let mut out = format!(
        "// Generated by build.rs from crates/translucid/src/interface/{}: edit that, not this.\n\
         #ifndef TRANSLUCID_{guard}\n#define TRANSLUCID_{guard}\n\n",
        include.source
    );
    for need in include.needs {
        out.push_str(&format!("#include \"{need}\"\n"));
    }
    if include.structs.iter().any(|s| {
        s.fields
            .iter()
            .any(|f| matches!(f.ty, GlslType::I64vec4 | GlslType::Dvec4))
    }) {
        out.push_str("#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require\n\n");
    }
    for (i, c) in include.constants.iter().enumerate() {
        if i > 0 && !c.doc.is_empty() {
            out.push('\n');
        }
        comment(&mut out, "", c.doc);
        out.push_str(&format!("#define {} {}\n", c.name, c.value));
    }
    for s in include.structs {
        out.push('\n');
        comment(&mut out, "", s.doc);
        out.push_str(&format!("struct {} {{\n", s.glsl));
        for f in s.fields {
            comment(&mut out, "    ", f.doc);
            let array = if f.len > 0 {
                format!("[{}]", f.len)
            } else {
                String::new()
            };
            out.push_str(&format!(
                "    {} {}{array};\n",
                f.ty.name(),
                camel_case(f.name)
            ));
        }
        out.push_str("};\n");
    }
    if let Some(more) = include.more {
        out.push_str(&more());
    }
    for set in &include.sets {
        for (i, b) in set.bindings.iter().enumerate() {
            out.push('\n');
            comment(&mut out, "", b.doc);
            out.push_str(&binding_glsl(set.set, set.first_binding() + i, b));
        }
    }
    out.push_str("\n#endif\n");
    out
}

/// `word `, or nothing for no word.
fn then_space(word: &str) -> String {
    if word.is_empty() {
        String::new()
    } else {
        format!("{word} ")
    }
}

/// ` word`, or nothing for no word.
fn space_then(word: &str) -> String {
    if word.is_empty() {
        String::new()
    } else {
        format!(" {word}")
    }
}

/// A block's members, a line each.
fn block(members: &[&str]) -> String {
    members.iter().map(|m| format!("    {m};\n")).collect()
}

/// The GLSL declaration of binding `number` of set `set`.
fn binding_glsl(set: &str, number: usize, b: &Binding) -> String {
    let at = format!("set = {set}, binding = {number}");
    let name = b.name;
    match b.ty {
        BindingType::Texels { glsl } => format!("layout({at}) uniform {glsl} {name};\n"),
        BindingType::StorageTexels(Storage {
            format,
            access,
            glsl,
        })
        | BindingType::StorageImage(Storage {
            format,
            access,
            glsl,
        }) => format!(
            "layout({at}, {format}) uniform {}{glsl} {name};\n",
            then_space(access)
        ),
        BindingType::Buffer {
            qualifiers,
            members,
            instance,
        } => format!(
            "layout({at}, std430) {}buffer {name} {{\n{}}}{};\n",
            then_space(qualifiers),
            block(members),
            space_then(instance)
        ),
        BindingType::Uniform { members } => {
            format!(
                "layout({at}, std140) uniform {name} {{\n{}}};\n",
                block(members)
            )
        }
        BindingType::Sampled { glsl, count } => {
            let array = if count > 1 {
                format!("[{count}]")
            } else {
                String::new()
            };
            format!("layout({at}) uniform {glsl} {name}{array};\n")
        }
    }
}

/// Declares a `#[repr(C)]` struct shared with the shaders, with its GLSL twin's description
/// (`GLSL`), and fails to compile if the Rust layout is not std430's. Fields take GLSL types,
/// arrays as `uint[LEN]`.
macro_rules! shader_struct {
    (@rust float) => { f32 };
    (@rust int) => { i32 };
    (@rust uint) => { u32 };
    (@rust vec2) => { [f32; 2] };
    (@rust vec3) => { [f32; 3] };
    (@rust vec4) => { [f32; 4] };
    (@rust ivec2) => { [i32; 2] };
    (@rust ivec4) => { [i32; 4] };
    (@rust uvec2) => { [u32; 2] };
    (@rust uvec4) => { [u32; 4] };
    (@rust mat4) => { [f32; 16] };
    (@rust i64vec4) => { [i64; 4] };
    (@rust dvec4) => { [f64; 4] };
    (@glsl float) => { $crate::interface::GlslType::Float };
    (@glsl int) => { $crate::interface::GlslType::Int };
    (@glsl uint) => { $crate::interface::GlslType::Uint };
    (@glsl vec2) => { $crate::interface::GlslType::Vec2 };
    (@glsl vec3) => { $crate::interface::GlslType::Vec3 };
    (@glsl vec4) => { $crate::interface::GlslType::Vec4 };
    (@glsl ivec2) => { $crate::interface::GlslType::Ivec2 };
    (@glsl ivec4) => { $crate::interface::GlslType::Ivec4 };
    (@glsl uvec2) => { $crate::interface::GlslType::Uvec2 };
    (@glsl uvec4) => { $crate::interface::GlslType::Uvec4 };
    (@glsl mat4) => { $crate::interface::GlslType::Mat4 };
    (@glsl i64vec4) => { $crate::interface::GlslType::I64vec4 };
    (@glsl dvec4) => { $crate::interface::GlslType::Dvec4 };
    (@field $ty:ident) => { shader_struct!(@rust $ty) };
    (@field $ty:ident [$len:expr]) => { [shader_struct!(@rust $ty); ($len) as usize] };
    (@len) => { 0 };
    (@len $len:expr) => { ($len) as usize };
    (
        $(#[doc = $doc:literal])*
        $(#[derive($($derive:ident),*)])?
        pub struct $rust:ident as $glsl:ident {
            $(
                $(#[doc = $fdoc:literal])*
                pub $field:ident: $ty:ident $([$len:expr])?,
            )*
        }
    ) => {
        $(#[doc = $doc])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable $($(, $derive)*)?)]
        pub struct $rust {
            $(
                $(#[doc = $fdoc])*
                pub $field: shader_struct!(@field $ty $([$len])?),
            )*
        }

        impl $rust {
            /// The GLSL twin of this structure.
            pub const GLSL: $crate::interface::StructDecl = $crate::interface::StructDecl {
                glsl: stringify!($glsl),
                doc: &[$($doc),*],
                fields: &[$(
                    $crate::interface::Field {
                        name: stringify!($field),
                        ty: shader_struct!(@glsl $ty),
                        len: shader_struct!(@len $($len)?),
                        doc: &[$($fdoc),*],
                    }
                ),*],
            };
        }

        const _: () = assert!(
            $rust::GLSL.matches(
                &[$(std::mem::offset_of!($rust, $field)),*],
                std::mem::size_of::<$rust>(),
            ),
            concat!(stringify!($rust), " is not laid out as std430 lays out ", stringify!($glsl)),
        );
    };
}

/// Declares constants both sides read, and `CONSTANTS`, their list for the GLSL include.
/// Each is a `u32`, an `i32` or an `f32`; `u32 as int` is a `u32` in Rust written as a GLSL
/// `int` (for sizes the shaders use in int arithmetic).
macro_rules! shader_constants {
    (@value $name:ident u32) => { $crate::interface::ConstantValue::Uint($name) };
    (@value $name:ident i32) => { $crate::interface::ConstantValue::Int($name) };
    (@value $name:ident f32) => { $crate::interface::ConstantValue::Float($name) };
    (@value $name:ident u32 int) => {
        $crate::interface::ConstantValue::Int({
            assert!($name <= i32::MAX as u32);
            $name as i32
        })
    };
    ($(
        $(#[doc = $doc:literal])*
        pub const $name:ident: $ty:ident $(as $glsl:ident)? = $value:expr;
    )*) => {
        $(
            $(#[doc = $doc])*
            pub const $name: $ty = $value;
        )*

        /// The constants above, for the GLSL include.
        pub const CONSTANTS: &[$crate::interface::Constant] = &[$(
            $crate::interface::Constant {
                name: stringify!($name),
                value: shader_constants!(@value $name $ty $($glsl)?),
                doc: &[$($doc),*],
            }
        ),*];
    };
}

// After the macros, which they use.
pub mod bins;
pub mod exact;
pub mod methods;
pub mod raster;
pub mod scene;
pub mod specialization;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_turn_camel_case() {
        assert_eq!(camel_case("first_texel"), "firstTexel");
        assert_eq!(camel_case("z_ndc"), "zNdc");
        assert_eq!(camel_case("flags"), "flags");
    }

    #[test]
    fn std430_pads_arrays_and_aligns_wide_types() {
        const FIELDS: &[Field] = &[
            Field {
                name: "a",
                ty: GlslType::Uint,
                len: 0,
                doc: &[],
            },
            Field {
                name: "b",
                ty: GlslType::Uint,
                len: 3,
                doc: &[],
            },
            Field {
                name: "c",
                ty: GlslType::Vec2,
                len: 2,
                doc: &[],
            },
            Field {
                name: "d",
                ty: GlslType::Vec3,
                len: 0,
                doc: &[],
            },
            Field {
                name: "e",
                ty: GlslType::Uint,
                len: 0,
                doc: &[],
            },
            Field {
                name: "f",
                ty: GlslType::Vec3,
                len: 2,
                doc: &[],
            },
        ];
        let s = StructDecl {
            glsl: "S",
            doc: &[],
            fields: FIELDS,
        };
        assert!(s.matches(&[0, 4, 16, 32, 44, 48], 80));
        assert!(!s.matches(&[0, 4, 16, 32, 44, 48], 72));
        assert!(!s.matches(&[0, 4, 16, 32, 48, 64], 96));
    }
}
