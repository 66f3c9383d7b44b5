//! Socket types and the one table of implicit conversions between them.
//!
//! | from \ to      | float | vec2 | vec3 | vec4 | color | int | bool |
//! |----------------|-------|------|------|------|-------|-----|------|
//! | float          | =     | bcast| bcast| bcast| bcast | ✗   | ✗    |
//! | vec2           | ✗     | =    | ext  | ✗    | ext   | ✗   | ✗    |
//! | vec3           | ✗     | xy   | =    | ✗    | id    | ✗   | ✗    |
//! | vec4           | ✗     | ✗    | ✗    | =    | ✗     | ✗   | ✗    |
//! | color          | luma  | xy   | id   | ✗    | =     | ✗   | ✗    |
//! | int            | exact | bcast| bcast| bcast| bcast | =   | ✗    |
//! | bool           | 0 / 1 | bcast| bcast| bcast| bcast | ✗   | =    |
//!
//! `bcast` copies the scalar into every component; `id` reinterprets the three components;
//! `ext` appends `z = 0` and `xy` drops `z`: Blender's habit, where a uv is the vector
//! `(u, v, 0)` and an image texture reads the `x` and `y` of the vector it is given, so
//! `geometry.uv → mapping → image_texture.uv` wires as it does in Blender; `luma` is Rec. 709
//! relative luminance `0.2126 r + 0.7152 g + 0.0722 b` (Blender's colour → float rule). A
//! vector never narrows to a float implicitly: use `split`, `length` or `dot`, so the choice
//! is visible in the graph. Every other pair is an error that names both ends of the link.

use std::fmt;

/// The type of a socket (an input or output port) or of a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum SocketType {
    /// One `f32`.
    Float,
    /// Two `f32` components.
    Vec2,
    /// Three `f32` components.
    Vec3,
    /// Four `f32` components.
    Vec4,
    /// Linear (scene-referred) RGB, three `f32` components.
    Color,
    /// A signed integer; enum inputs are ints with named choices.
    Int,
    /// A boolean.
    Bool,
}

/// Every socket type, in declaration order.
pub const ALL_TYPES: [SocketType; 7] = [
    SocketType::Float,
    SocketType::Vec2,
    SocketType::Vec3,
    SocketType::Vec4,
    SocketType::Color,
    SocketType::Int,
    SocketType::Bool,
];

/// Rec. 709 luminance weights used by the colour → float conversion.
pub const LUMA_709: [f32; 3] = [0.2126, 0.7152, 0.0722];

impl SocketType {
    /// Number of `f32` lanes a value of this type occupies.
    pub const fn width(self) -> usize {
        match self {
            SocketType::Float | SocketType::Int | SocketType::Bool => 1,
            SocketType::Vec2 => 2,
            SocketType::Vec3 | SocketType::Color => 3,
            SocketType::Vec4 => 4,
        }
    }

    /// The name used in graph files, docs and messages.
    pub const fn name(self) -> &'static str {
        match self {
            SocketType::Float => "float",
            SocketType::Vec2 => "vec2",
            SocketType::Vec3 => "vec3",
            SocketType::Vec4 => "vec4",
            SocketType::Color => "color",
            SocketType::Int => "int",
            SocketType::Bool => "bool",
        }
    }

    /// Parses a name written by [`SocketType::name`].
    pub fn from_name(name: &str) -> Option<SocketType> {
        ALL_TYPES.into_iter().find(|t| t.name() == name)
    }

    /// The implicit conversion from `self` to `to`, or `None` when the link is an error.
    pub fn conversion_to(self, to: SocketType) -> Option<Conversion> {
        use SocketType::*;
        if self == to {
            return Some(Conversion::Identity);
        }
        match (self, to) {
            (Vec3, Color) | (Color, Vec3) => Some(Conversion::Identity),
            (Float | Int | Bool, Float) => Some(Conversion::Identity),
            (Float | Int | Bool, Vec2 | Vec3 | Vec4 | Color) => Some(Conversion::Broadcast),
            (Color, Float) => Some(Conversion::Luminance),
            (Vec2, Vec3 | Color) => Some(Conversion::Extend),
            (Vec3 | Color, Vec2) => Some(Conversion::Truncate),
            _ => None,
        }
    }
}

impl fmt::Display for SocketType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How a value changes on its way along a link (see the module table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Conversion {
    /// The lanes are used as they are.
    Identity,
    /// A scalar copied into every component.
    Broadcast,
    /// Rec. 709 luminance of a colour.
    Luminance,
    /// A vec2 as the vector `(x, y, 0)`.
    Extend,
    /// A three-component vector's `(x, y)`.
    Truncate,
}

impl Conversion {
    /// Applies the conversion to lanes `src` of type `from`, producing `to`'s lanes.
    pub fn apply(self, src: [f32; 4], to: SocketType) -> [f32; 4] {
        match self {
            Conversion::Identity => src,
            Conversion::Extend | Conversion::Truncate => [src[0], src[1], 0.0, 0.0],
            Conversion::Broadcast => {
                let mut out = [0.0; 4];
                out[..to.width()].fill(src[0]);
                out
            }
            Conversion::Luminance => [
                LUMA_709[0] * src[0] + LUMA_709[1] * src[1] + LUMA_709[2] * src[2],
                0.0,
                0.0,
                0.0,
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_never_narrow_to_float() {
        for t in [SocketType::Vec2, SocketType::Vec3, SocketType::Vec4] {
            assert_eq!(t.conversion_to(SocketType::Float), None);
        }
        assert_eq!(
            SocketType::Color.conversion_to(SocketType::Float),
            Some(Conversion::Luminance)
        );
    }

    #[test]
    fn uvs_extend_with_a_zero_z_and_vectors_truncate_to_their_xy() {
        use SocketType::*;
        assert_eq!(Vec2.conversion_to(Vec3), Some(Conversion::Extend));
        assert_eq!(Vec2.conversion_to(Color), Some(Conversion::Extend));
        assert_eq!(Vec3.conversion_to(Vec2), Some(Conversion::Truncate));
        assert_eq!(Color.conversion_to(Vec2), Some(Conversion::Truncate));
        assert_eq!(Vec2.conversion_to(Vec4), None);
        assert_eq!(Vec4.conversion_to(Vec2), None);
        assert_eq!(
            Conversion::Extend.apply([0.25, -3.0, 7.0, 9.0], Vec3),
            [0.25, -3.0, 0.0, 0.0]
        );
        assert_eq!(
            Conversion::Truncate.apply([0.25, -3.0, 7.0, 0.0], Vec2),
            [0.25, -3.0, 0.0, 0.0]
        );
    }

    #[test]
    fn luminance_of_white_is_one() {
        let y = Conversion::Luminance.apply([1.0, 1.0, 1.0, 0.0], SocketType::Float)[0];
        assert!((y - 1.0).abs() < 1e-6);
    }

    #[test]
    fn names_round_trip() {
        for t in ALL_TYPES {
            assert_eq!(SocketType::from_name(t.name()), Some(t));
        }
    }
}
