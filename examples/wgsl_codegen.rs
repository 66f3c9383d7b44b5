//! Load a graph file and get WGSL a wgpu app can use, with its uniform layout.
//!
//! Run: `cargo run --example wgsl_codegen [GRAPH] [compute|fragment]`
//! (default `graphs/fresnel_glass.json`, compute).

use matgraph::Registry;
use matgraph::wgsl::{Binding, Entry, UniformSource, WgslOptions, generate};
use std::error::Error;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/graphs/fresnel_glass.json"
        ))
    });
    let entry = match args.next().as_deref() {
        Some("fragment") => Entry::Fragment,
        _ => Entry::Compute,
    };
    let graph = matgraph::io::load_graph(&path, Registry::builtin())?;
    let shader = generate(
        &graph,
        &WgslOptions {
            entry,
            ..Default::default()
        },
    )?;

    println!("{}", shader.source);
    println!("// --- what the app binds (group 0) ---");
    for (binding, b) in &shader.bindings {
        let what = match b {
            Binding::Params => format!("uniform MgParams, {} bytes", shader.uniforms.size),
            Binding::Dispatch => "uniform MgDispatch { count: u32, row: u32 }".into(),
            Binding::Geometry => format!(
                "storage array<f32>: the attributes planar, {} floats per sample, lane c of sample i at (offset + c) * count + i; offsets {:?}",
                matgraph::wgsl::geometry_lanes(&shader.attributes),
                matgraph::wgsl::geometry_layout(&shader.attributes)
                    .iter()
                    .map(|(a, k)| (a.name(), *k))
                    .collect::<Vec<_>>()
            ),
            Binding::Output => format!(
                "storage array<f32>: {} planar columns",
                shader.output_columns()
            ),
            Binding::TextureTexels => {
                "storage array<f32>: texels (TexturePack::texel_bytes)".into()
            }
            Binding::TextureLevels => {
                "storage array<vec4<u32>>: mip levels (TexturePack::level_bytes)".into()
            }
            Binding::TextureTable => format!(
                "storage array<vec2<u32>>: textures {:?} in this order",
                shader.textures
            ),
            Binding::Frame => "uniform MgFrame: camera, viewport, time, light count".into(),
            Binding::Lights => "storage array<MgLight>: the lights".into(),
            Binding::Sampler(wrap, filter) => format!("sampler: {wrap:?} wrap, {filter:?} filter"),
            Binding::Texture(k) => {
                format!("texture_2d<f32>: {:?}", shader.textures.get(*k as usize))
            }
        };
        println!("// binding {binding}: {what}");
    }
    println!("// --- MgParams layout (from naga) ---");
    for f in &shader.uniforms.fields {
        let from = match &f.source {
            UniformSource::Parameter(name) => format!("parameter '{name}'"),
            UniformSource::Fixed => "fixed (unexposed parameter node)".to_owned(),
            UniformSource::Time => "the batch's time".to_owned(),
            UniformSource::Table(rows) => format!("a node's constant table of {} rows", rows.len()),
        };
        println!(
            "// offset {:>3}: {} ({}) <- {from}, default {}",
            f.offset,
            f.field,
            f.wgsl_type(),
            f.default
        );
    }
    Ok(())
}
