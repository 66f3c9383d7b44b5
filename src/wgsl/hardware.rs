//! The hardware texture mode: one `texture_2d<f32>` per texture slot and one sampler per
//! (wrap, filter) pair, read by `textureSampleLevel` behind the same `mg_sample_texture(tex,
//! uv, lod, wrap, filt)` the exact mode defines, so texture nodes need no change.
//!
//! A sampler for (wrap, filter) has address mode repeat, clamp-to-edge or mirror-repeat on u
//! and v, and for bilinear linear mag, min and mipmap filters (trilinear), for nearest nearest
//! ones. Vulkan, Metal and D3D select a nearest mip level as ⌈lod + ½⌉ − 1 and clamp lod to
//! the view's levels, as the CPU sampler does; what differs from the CPU is the texel
//! format's quantisation and the hardware's filter-weight precision (measured in
//! docs/integration.md).

use super::Binding;
use crate::texture::{Filter, Wrap};
use std::fmt::Write;

/// Emits the sampler and texture bindings from binding `first` (samplers first, in `combos`
/// order, then the `count` texture slots) and `mg_sample_texture`.
pub(super) fn emit(
    out: &mut String,
    count: u32,
    combos: &[(Wrap, Filter)],
    first: u32,
    bindings: &mut Vec<(u32, Binding)>,
) {
    let mut b = first;
    let combos: Vec<(Wrap, Filter)> = if combos.is_empty() {
        vec![(Wrap::Repeat, Filter::Bilinear)]
    } else {
        combos.to_vec()
    };
    for &(w, f) in &combos {
        let binding = Binding::Sampler(w, f);
        let _ = writeln!(
            out,
            "@group(0) @binding({b}) var {}: sampler;",
            binding.variable()
        );
        bindings.push((b, binding));
        b += 1;
    }
    for k in 0..count {
        let _ = writeln!(
            out,
            "@group(0) @binding({b}) var mg_tex_{k}: texture_2d<f32>;"
        );
        bindings.push((b, Binding::Texture(k)));
        b += 1;
    }
    out.push('\n');
    for k in 0..count {
        let _ = writeln!(
            out,
            "fn mg_tex_sample_{k}(uv: vec2<f32>, lod: f32, wrap: u32, filt: u32) -> vec4<f32> {{"
        );
        for (i, &(w, f)) in combos.iter().enumerate() {
            let call = format!(
                "textureSampleLevel(mg_tex_{k}, {}, uv, lod)",
                Binding::Sampler(w, f).variable()
            );
            if i + 1 == combos.len() {
                let _ = writeln!(out, "    return {call};");
            } else {
                let _ = writeln!(
                    out,
                    "    if ({} && {}) {{\n        return {call};\n    }}",
                    wrap_test(w),
                    filter_test(f)
                );
            }
        }
        out.push_str("}\n\n");
    }
    out.push_str(
        "fn mg_sample_texture(tex: u32, uv: vec2<f32>, lod: f32, wrap: u32, filt: u32) -> vec4<f32> {\n",
    );
    // A NaN or negative lod reads level 0, as on the CPU (a NaN lod is undefined in hardware).
    out.push_str("    let l = select(0.0, lod, lod > 0.0);\n    switch tex {\n");
    for k in 0..count {
        let _ = writeln!(
            out,
            "        case {k}u: {{\n            return mg_tex_sample_{k}(uv, l, wrap, filt);\n        }}"
        );
    }
    out.push_str("        default: {\n            return vec4<f32>(0.0);\n        }\n    }\n}\n");
}

/// The WGSL test that the runtime `wrap` selects `w` (0 repeat, 1 clamp, anything else mirror).
fn wrap_test(w: Wrap) -> &'static str {
    match w {
        Wrap::Repeat => "wrap == 0u",
        Wrap::Clamp => "wrap == 1u",
        Wrap::Mirror => "wrap >= 2u",
    }
}

/// The WGSL test that the runtime `filt` selects `f` (0 nearest, anything else bilinear).
fn filter_test(f: Filter) -> &'static str {
    match f {
        Filter::Nearest => "filt == 0u",
        Filter::Bilinear => "filt != 0u",
    }
}
