//! Every image-based-lighting texture a graph can ask for (`scene:environment`,
//! `scene:environment_ggx`, `scene:brdf_lut`, `scene:environment_sh`), made once from a
//! scene's environment exactly as a render binds them, for apps that bind the contract
//! themselves (`matgraph bake-env`, docs/integration.md "Scene textures"): the texels of every
//! level as little-endian RGBA f32, and a manifest that says what each file holds and how the
//! WGSL reads it. With a view ([`bake_environment`]'s `view`) also the screen-space passes
//! (`scene:background`, `scene:refraction`, `scene:reflection`) of the scene's camera at
//! that frame size. No I/O here: the caller writes [`BakedEnvironment::files`].

use super::{
    ENVIRONMENT_TEXTURES, RenderError, SCREEN_TEXTURES, environment_map, scene_texture_size,
    screen_texture,
};
use crate::scene::Scene;
use crate::scene::ibl::{GGX_LEVELS, LUT_SIZE, SH_TEXELS};
use crate::texture::{Texture, TextureSet};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The manifest's `schema`.
pub const MANIFEST_SCHEMA: &str = "matgraph-environment/1";

/// The manifest's file name in the folder `matgraph bake-env` writes.
pub const MANIFEST_FILE: &str = "manifest.json";

/// What `matgraph bake-env` writes beside the texel files: `manifest.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvironmentManifest {
    /// [`MANIFEST_SCHEMA`].
    pub schema: String,
    /// What was baked, in the user's words (a graph file, a scene preset, an image).
    pub source: String,
    /// How every texel file is laid out.
    pub texels: String,
    /// The equirectangular mapping of `scene:environment` and `scene:environment_ggx`.
    pub equirect: String,
    /// One entry per scene texture: the four made from the environment, then, baked with a
    /// view, the three screen-space passes.
    pub textures: Vec<BakedTexture>,
}

/// One baked scene texture in the manifest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakedTexture {
    /// The texture's key in graphs and in the contract's `textures` (`scene:environment`, …).
    pub name: String,
    /// Level 0's width in texels.
    pub width: u32,
    /// Level 0's height in texels.
    pub height: u32,
    /// The number of levels (upload every one; do not regenerate them).
    pub mip_levels: u32,
    /// What the texels hold.
    pub holds: String,
    /// How the bundled nodes' WGSL reads it (uv, lod, wrap, filter).
    pub lookup: String,
    /// The levels, largest first.
    pub levels: Vec<BakedLevel>,
}

/// One level's file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BakedLevel {
    /// File name, relative to the manifest's folder.
    pub file: String,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width · height · 16`.
    pub bytes: u64,
}

/// The baked textures and their manifest.
#[derive(Clone, Debug)]
pub struct BakedEnvironment {
    /// The textures, keyed by their `scene:` names, as a render binds them.
    pub textures: TextureSet,
    /// What [`BakedEnvironment::files`] holds.
    pub manifest: EnvironmentManifest,
}

/// What each texture holds and how it is read, by its name without `scene:`.
fn description(short: &str) -> (String, String) {
    let (holds, lookup) = match short {
        "environment" => (
            "the scene's surroundings as radiance (linear RGB, alpha 1): in a ball scene the room \
             seen from the ball's centre, elsewhere the sky or environment image; levels: the \
             exact area average down to 1 × 1 (a 2 × 2 box; an odd side 2n + 1 → n averages \
             texels 2i, 2i + 1, 2i + 2 with weights (n − i, n, i + 1)/(2n + 1); \
             src/texture.rs `downsample`)"
                .to_owned(),
            "uv = equirect_uv(direction); wrap and filter as the graph's node says (the contract's \
             sampler); lod as the node computes it (env_ggx_monte_carlo: ½ log₂(Ωs/Ωp) + 1)"
                .to_owned(),
        ),
        "environment_ggx" => (
            format!(
                "the environment prefiltered for GGX by the split sum (Karis 2013, n = v = r): \
                 level k at perceptual roughness k/{}, {} importance samples a texel \
                 (scene::ibl::prefilter_ggx)",
                GGX_LEVELS - 1,
                crate::scene::ibl::GGX_SAMPLES
            ),
            format!(
                "uv = equirect_uv(reflection direction), lod = {}·clamp(roughness, 0, 1), \
                 clamp-to-edge, linear mag/min/mipmap (trilinear)",
                GGX_LEVELS - 1
            ),
        ),
        "brdf_lut" => (
            format!(
                "the split sum's BRDF table: texel (i, j) holds (A, B, 0, 1) with specular = \
                 F0·A + B, at n·v = i/{m} and roughness = j/{m} (GGX, height-correlated Smith, \
                 Schlick's Fresnel; integrated in f64)",
                m = LUT_SIZE - 1
            ),
            format!(
                "uv = (½ + x·{m}) / {LUT_SIZE} for x = (clamp(n·v, 0, 1), clamp(roughness, 0, 1)), \
                 clamp-to-edge, bilinear, lod 0",
                m = LUT_SIZE - 1
            ),
        ),
        "environment_sh" => (
            format!(
                "the irradiance as {SH_TEXELS} spherical-harmonic coefficients of bands 0–2 \
                 (Ramamoorthi & Hanrahan 2001), texel k = coefficient k in the order Y00, Y1-1, \
                 Y10, Y11, Y2-2, Y2-1, Y20, Y21, Y22 with y up, already times Â_l/π: \
                 Σ c_k Y_k(n) is E(n)/π, what a white Lambert surface reflects"
            ),
            format!(
                "texel k at uv = ((k + ½)/{SH_TEXELS}, ½), clamp-to-edge, nearest, lod 0"
            ),
        ),
        "background" | "refraction" | "reflection" => {
            let what = match short {
                "background" => {
                    "the frame without the material surface: the rest of the scene (room, \
                     floor, seabed, sky, environment) as the camera sees it"
                }
                "refraction" => {
                    "the seabed and what lies under the water with the water removed, as the \
                     camera sees it (through the flat water by Snell's law, 1.00/1.33, when the \
                     scene's water asks; docs/rendering.md); without water the background"
                }
                _ => {
                    "the scene above the water mirrored about the water plane, so that the \
                     water pixel reads its reflection at its own screen uv (a planar \
                     reflection); without water the background"
                }
            };
            (
                format!(
                    "{what}: radiance (linear RGB, alpha 1), one sample through each pixel's \
                     centre of the frame the view gives (the camera of view.json, at \
                     matgraph::render::scene_texture_size of the view: the view's size, or \
                     scaled so the longer side is {}), rows from the top; levels: box mips by \
                     the same filter as scene:environment's, from level 0 down to 1 × 1",
                    super::SCENE_TEXTURE_MAX
                ),
                "uv = screen_uv (the fragment's clip.xy / viewport: (0, 0) top left), \
                 possibly offset by the graph (distortion); wrap, filter and lod as the \
                 graph's node says (the contract's sampler)"
                    .to_owned(),
            )
        }
        _ => unreachable!("description of a texture the manifest does not list"),
    };
    (holds, lookup)
}

/// The texture `name` of a baked set: [`bake_environment`] inserts every name the manifest
/// lists.
fn named<'a>(set: &'a TextureSet, name: &str) -> &'a Texture {
    set.index_of(name)
        .and_then(|k| set.get(k))
        .expect("a baked set holds every texture its manifest lists")
}

/// Bakes every environment texture of `scene` (with `image` the loaded image of an image
/// environment), the same texels a CPU or GPU render of a graph in `scene` binds, and with
/// `view` = `(width, height)` the screen-space passes ([`SCREEN_TEXTURES`]) a
/// `width × height` render binds (the scene's camera, at [`scene_texture_size`] of the
/// frame); `source` names what was baked in the manifest.
pub fn bake_environment(
    scene: &Scene,
    image: Option<Arc<Texture>>,
    source: &str,
    view: Option<(u32, u32)>,
) -> Result<BakedEnvironment, RenderError> {
    let lookup = image.map(crate::scene::image_lookup);
    let lookup: Option<&crate::scene::EnvLookup> =
        lookup.as_ref().map(|f| f as &crate::scene::EnvLookup);
    let map = environment_map(scene, lookup)?;
    let mut textures = TextureSet::new();
    super::insert_environment_textures(&mut textures, &ENVIRONMENT_TEXTURES, map)?;
    let mut names: Vec<&str> = ENVIRONMENT_TEXTURES.to_vec();
    if let Some((width, height)) = view {
        let (w, h) = scene_texture_size(width, height);
        let passes = scene.scene_textures_with(w, h, lookup);
        for (short, image) in SCREEN_TEXTURES.into_iter().zip([
            &passes.background,
            &passes.refraction,
            &passes.reflection,
        ]) {
            let name = format!("{}{short}", crate::document::TextureSource::SCENE);
            textures.insert(name, screen_texture(image)?)?;
        }
        names.extend(SCREEN_TEXTURES);
    }
    let entries = names
        .iter()
        .map(|short| {
            let name = format!("{}{short}", crate::document::TextureSource::SCENE);
            let texture = named(&textures, &name);
            let (holds, lookup) = description(short);
            BakedTexture {
                width: texture.width(),
                height: texture.height(),
                mip_levels: texture.level_count() as u32,
                holds,
                lookup,
                levels: texture
                    .levels()
                    .iter()
                    .enumerate()
                    .map(|(k, level)| BakedLevel {
                        file: format!("{short}_{k}.rgba32f"),
                        width: level.width,
                        height: level.height,
                        bytes: level.width as u64 * level.height as u64 * 16,
                    })
                    .collect(),
                name,
            }
        })
        .collect();
    Ok(BakedEnvironment {
        textures,
        manifest: EnvironmentManifest {
            schema: MANIFEST_SCHEMA.to_owned(),
            source: source.to_owned(),
            texels: "each level a file of width·height texels, rows from the top, each texel \
                     R, G, B, A as little-endian IEEE 754 binary32 (16 bytes); upload as \
                     rgba16float (round to nearest even) or rgba32float with float32-filterable"
                .to_owned(),
            equirect: "u = 0.5 + atan2(d.x, -d.z) / 2π, v = acos(d.y) / π for a unit direction \
                       d (y up; -z at the image centre, +x at u = 0.75; the zenith on the top row)"
                .to_owned(),
            textures: entries,
        },
    })
}

impl BakedEnvironment {
    /// The manifest as pretty-printed JSON (fields in a fixed order), with a final newline.
    pub fn manifest_json(&self) -> String {
        let mut text =
            serde_json::to_string_pretty(&self.manifest).expect("the manifest serialises");
        text.push('\n');
        text
    }

    /// Every file to write into the output folder: the levels' texels, then
    /// [`MANIFEST_FILE`]; the same scene gives the same bytes.
    pub fn files(&self) -> Vec<(String, Vec<u8>)> {
        let mut files = Vec::new();
        for entry in &self.manifest.textures {
            let texture = named(&self.textures, &entry.name);
            for (level, file) in texture.levels().iter().zip(&entry.levels) {
                let bytes: Vec<u8> = level
                    .data
                    .iter()
                    .flatten()
                    .flat_map(|c| c.to_le_bytes())
                    .collect();
                files.push((file.file.clone(), bytes));
            }
        }
        files.push((MANIFEST_FILE.to_owned(), self.manifest_json().into_bytes()));
        files
    }
}
