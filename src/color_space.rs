//! The colour space of an image a graph samples: how its stored values become the numbers
//! the graph reads.
//!
//! - `srgb`: the values are sRGB-encoded colour; they are decoded to linear light with the
//!   IEC 61966-2-1 transfer function (alpha is kept as stored). The default for PNG and JPEG
//!   files: 8- and 16-bit colour images are sRGB by convention.
//! - `linear`: the values are linear-light colour, read unchanged. The default for Radiance
//!   HDR and OpenEXR files.
//! - `data`: the values are not colour (roughness, metalness, height, a normal map, a mask)
//!   and are never transformed: a texel stored as 128 in an 8-bit PNG reads 128/255.
//!
//! `linear` and `data` read the same numbers today; they differ in what they say (a tool
//! may colour-manage `linear` images, never `data` ones). Blender's Image Texture node has
//! the same choice ("sRGB", "Linear", "Non-Color"); glTF 2.0 fixes it per slot (base colour
//! sRGB, the rest linear data).
//!
//! A texture is bound under a key ([`ColorSpace::key`]): the path as the graph writes it
//! when the image is read in its file type's default space, else the path and `#` and the
//! space (`textures/brick_height.png#data`), so that one file read in two spaces is two
//! textures.
//!
//! Keys are unambiguous because the image paths that would make them ambiguous are refused
//! when a graph is loaded ([`texture_key_conflict`]): a path with `|` (a file `a.png|b.png`
//! would have the key of the mip chain `["a.png", "b.png"]`), a path ending in `#` and a
//! space's name (a file `a.png#data` would have the key of `a.png` read as data), and a mip
//! level named `scene:…` (a one-level chain `["scene:refraction"]` would have the key of the
//! scene texture).

use serde::{Deserialize, Serialize};

/// How an image's stored values are read: sRGB-decoded colour, linear colour, or data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
#[serde(expecting = "a colour space: \"srgb\", \"linear\" or \"data\"")]
pub enum ColorSpace {
    /// sRGB-encoded colour, decoded to linear light.
    Srgb,
    /// Linear-light colour, read unchanged.
    Linear,
    /// Not colour: read unchanged, never colour-managed.
    Data,
}

impl ColorSpace {
    /// Every space, in the order of [`ColorSpace::NAMES`].
    pub const ALL: [ColorSpace; 3] = [ColorSpace::Srgb, ColorSpace::Linear, ColorSpace::Data];
    /// The names the graph format writes.
    pub const NAMES: [&'static str; 3] = ["srgb", "linear", "data"];

    /// The space's name in the graph format.
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The space named `name`, if any.
    pub fn parse(name: &str) -> Option<ColorSpace> {
        Self::ALL.into_iter().find(|s| s.name() == name)
    }

    /// Whether values are decoded from sRGB to linear light.
    pub const fn decodes_srgb(self) -> bool {
        matches!(self, ColorSpace::Srgb)
    }

    /// The space an image is read in when its reference names none, by the extension of
    /// its path (the first level's, for a mip chain): linear for `.hdr` and `.exr`, sRGB
    /// for everything else (PNG and JPEG).
    pub fn default_for(path: &str) -> ColorSpace {
        let first = path.split('|').next().unwrap_or(path);
        let ext = first.rsplit('.').next().unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "hdr" | "exr" => ColorSpace::Linear,
            _ => ColorSpace::Srgb,
        }
    }

    /// The key of an image bound as `source_key` (its path, or a chain's paths joined by
    /// `|`) read in `space`: `source_key` itself where `space` is absent or the path's
    /// default, else `source_key#space`.
    pub fn key(source_key: &str, space: Option<ColorSpace>) -> String {
        match space {
            Some(s) if s != Self::default_for(source_key) => format!("{source_key}#{}", s.name()),
            _ => source_key.to_owned(),
        }
    }

    /// The path part and the space of texture key `key` (the inverse of [`ColorSpace::key`]).
    pub fn of_key(key: &str) -> (&str, ColorSpace) {
        match key.rsplit_once('#') {
            Some((path, name)) => match Self::parse(name) {
                Some(space) => (path, space),
                None => (key, Self::default_for(key)),
            },
            None => (key, Self::default_for(key)),
        }
    }
}

/// Why the image paths of `source` would give a texture key that another source also has
/// (see the module doc), in words for the user; `None` where its key is its own.
pub fn texture_key_conflict(source: &crate::document::TextureSource) -> Option<String> {
    use crate::document::TextureSource;
    let chain = matches!(source, TextureSource::MipChain(_));
    source.files().into_iter().find_map(|path| {
        if path.contains('|') {
            let levels: Vec<String> = path.split('|').map(|l| format!("\"{l}\"")).collect();
            Some(format!(
                "texture '{path}': an image path may not contain '|', which joins the levels of \
                 a mip chain in texture keys (the file would share its key with the chain [{}]): \
                 rename the file",
                levels.join(", ")
            ))
        } else if let Some((head, space)) = path.rsplit_once('#')
            && ColorSpace::parse(space).is_some()
        {
            Some(format!(
                "texture '{path}': an image path may not end in '#{space}', which marks the \
                 colour space in texture keys (the file would share its key with '{head}' read \
                 with \"color_space\": \"{space}\"): rename the file"
            ))
        } else if chain && path.starts_with(TextureSource::SCENE) {
            Some(format!(
                "texture level '{path}': a mip level may not start with '{}', which names the \
                 renderer's scene textures: rename the file",
                TextureSource::SCENE
            ))
        } else {
            None
        }
    })
}

impl std::fmt::Display for ColorSpace {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_follow_the_file_type() {
        assert_eq!(ColorSpace::default_for("a/b.png"), ColorSpace::Srgb);
        assert_eq!(ColorSpace::default_for("b.JPG"), ColorSpace::Srgb);
        assert_eq!(ColorSpace::default_for("sky.hdr"), ColorSpace::Linear);
        assert_eq!(ColorSpace::default_for("x.EXR|y.exr"), ColorSpace::Linear);
        assert_eq!(ColorSpace::default_for("noext"), ColorSpace::Srgb);
    }

    #[test]
    fn keys_mark_only_a_space_other_than_the_default_and_parse_back() {
        assert_eq!(ColorSpace::key("t/a.png", None), "t/a.png");
        assert_eq!(
            ColorSpace::key("t/a.png", Some(ColorSpace::Srgb)),
            "t/a.png"
        );
        assert_eq!(
            ColorSpace::key("t/a.png", Some(ColorSpace::Data)),
            "t/a.png#data"
        );
        assert_eq!(ColorSpace::key("e.exr", Some(ColorSpace::Linear)), "e.exr");
        assert_eq!(
            ColorSpace::key("e.exr", Some(ColorSpace::Srgb)),
            "e.exr#srgb"
        );
        for key in [
            "t/a.png",
            "t/a.png#data",
            "e.exr",
            "e.exr#srgb",
            "a.png|b.png#linear",
        ] {
            let (path, space) = ColorSpace::of_key(key);
            assert_eq!(ColorSpace::key(path, Some(space)), key);
        }
        // A `#` that names no space is part of the path.
        assert_eq!(
            ColorSpace::of_key("odd#name.png"),
            ("odd#name.png", ColorSpace::Srgb)
        );
    }
}
