//! The image-based-lighting tables of the last few environment maps, so that the frames of
//! an animation and the editor's preview, which redraw the same room, prefilter it once.
//! Keyed by the map's texels (a 64-bit hash of their bits): a map that changes at all is a
//! new entry.

use crate::memo::Memo;
use crate::scene::ibl;
use crate::texture::{Image, Texture, TextureError};
use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// The key of `map`: its size and the bits of every texel.
pub(super) fn key(map: &Image) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (map.width, map.height).hash(&mut h);
    for t in &map.data {
        t.map(f32::to_bits).hash(&mut h);
    }
    h.finish()
}

/// `scene:environment_ggx` of the map with key `key` ([`ibl::environment_ggx`] of `source`).
pub(super) fn environment_ggx(key: u64, source: &Texture) -> Result<Arc<Texture>, TextureError> {
    static GGX: Memo<u64, Arc<Texture>, 4> = Memo::new();
    GGX.get_or_make(key, || ibl::environment_ggx(source).map(Arc::new))
}

/// The irradiance coefficients of the map with key `key` ([`ibl::sh_irradiance`]).
pub(super) fn sh_irradiance(key: u64, source: &Texture) -> [[f32; 3]; 9] {
    static SH: Memo<u64, [[f32; 3]; 9], 4> = Memo::new();
    SH.get_or(key, || ibl::sh_irradiance(source, ibl::SH_LEVEL))
}
