//! The contract as JSON (`matgraph wgsl FILE --contract out.json`): everything an app in
//! another language needs to bind the render module. Schema `matgraph-contract/1`, specified
//! in docs/integration.md; deterministic (fields in declaration order, no maps).

use super::Material;
use super::layout::{
    StageCounts, TANGENT_ATTRIBUTES, TANGENT_STRIDE, VERTEX_ATTRIBUTES, VERTEX_STRIDE,
    binding_type, min_binding_size,
};
use super::limits::ModuleLimits;
use crate::parameter_info::ParameterInfo;
use crate::wgsl::render::{
    FRAME_BINDING, FRAME_SIZE, LIGHT_DIRECTIONAL, LIGHT_MIN_DISTANCE, LIGHT_POINT, LIGHT_STRIDE,
    LIGHTS_BINDING, NORMAL_STEP, PARAMS_BINDING,
};
use crate::wgsl::{Binding, ParameterClamp, ShaderModule, UniformSource, wgsl_type};
use serde::{Deserialize, Serialize};

/// The schema name written in every contract.
pub const CONTRACT_SCHEMA: &str = "matgraph-contract/1";

/// The contract of one material (see docs/integration.md for every field).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Contract {
    /// Always [`CONTRACT_SCHEMA`].
    pub schema: String,
    /// The graph's name.
    pub graph: String,
    /// `hardware` or `exact`.
    pub texture_mode: String,
    /// The renderer options that shaped the module (docs/integration.md, "Options for
    /// renderers"): those on that change it for this graph; absent when none does.
    #[serde(default, skip_serializing_if = "RenderOptions::is_default")]
    pub options: RenderOptions,
    /// Entry point names.
    pub entry_points: EntryPoints,
    /// The one vertex buffer of `mg_vertex`.
    pub vertex_buffer: VertexBuffer,
    /// The second vertex buffer (slot 1), present only when the graph reads the tangent
    /// frame (`geometry.tangent` or `bitangent_sign`): the MikkTSpace tangent (xyz) and
    /// bitangent sign (w) per vertex.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tangent_buffer: Option<VertexBuffer>,
    /// The colour target `mg_fragment` writes.
    pub color_target: ColorTarget,
    /// How to draw the mesh: culling, the depth pre-pass and the colour pass's depth state
    /// (docs/integration.md, "Drawing the mesh"). A contract written before this field reads
    /// back with the pipeline its outputs call for ([`Contract::from_json`]).
    #[serde(default)]
    pub pipeline: Pipeline,
    /// Members of `MgGeometry` (the attributes the graph reads), in order.
    pub geometry: Vec<Member>,
    /// Members of `MgOutputs` of the render module, with their roles.
    pub outputs: Vec<Output>,
    /// The bindings, all in group 0.
    pub bindings: Vec<BindingEntry>,
    /// `MgParams`, the parameter block (binding 0).
    pub parameters: Block,
    /// `MgFrame`, the per-draw uniform (binding 1).
    pub frame: Block,
    /// `MgLight`, one record of the lights buffer (binding 2).
    pub lights: Lights,
    /// The textures, in slot order.
    pub textures: Vec<Texture>,
    /// Per-stage binding counts (all bindings are visible to both stages).
    pub per_stage: PerStage,
    /// The device limits the module needs, named as `wgpu::Limits` fields (absent in a
    /// contract written before it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<ModuleLimits>,
    /// The normal rebuild's relative step (m per m of |position|∞, at least 1 m).
    pub normal_step: f32,
    /// The hook functions an app may replace.
    pub hooks: Vec<String>,
}

/// The contract of a library module (`mg_material` for an app's own shader) or of the
/// compute entry (`mg_compute`, batch evaluation): `matgraph wgsl FILE --entry
/// library|compute --contract out.json`. Same schema name as [`Contract`], told apart by
/// `module`; docs/integration.md, "The contract JSON".
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModuleContract {
    /// Always [`CONTRACT_SCHEMA`].
    pub schema: String,
    /// `library` or `compute`.
    pub module: String,
    /// The graph's name.
    pub graph: String,
    /// `hardware` or `exact` (a compute module binds textures as the exact mode does).
    pub texture_mode: String,
    /// The function an app calls (`mg_material`) or the entry point (`mg_compute`).
    pub function: String,
    /// The compute entry's workgroup size in x (absent for a library).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub workgroup_size: Option<u32>,
    /// Members of `MgGeometry`, in order; for the compute entry each with its lane offset
    /// in `mg_geometry`.
    pub geometry: Vec<GeometryMember>,
    /// Lanes (floats per sample) of `mg_geometry` (compute entry only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry_lanes: Option<u32>,
    /// The outputs, in `MgOutputs` order; for the compute entry each with its first column
    /// in `mg_out`.
    pub outputs: Vec<ModuleOutput>,
    /// Columns (floats per sample) of `mg_out` (compute entry only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output_columns: Option<u32>,
    /// The bindings, all in group 0.
    pub bindings: Vec<BindingEntry>,
    /// `MgParams`, the parameter block (binding 0).
    pub parameters: Block,
    /// The textures, in slot order (the compute entry's are packed into `mg_texels`,
    /// `mg_levels` and `mg_textures` in this order).
    pub textures: Vec<Texture>,
    /// Per-stage binding counts.
    pub per_stage: PerStage,
    /// The device limits the module needs, named as `wgpu::Limits` fields.
    pub limits: ModuleLimits,
}

/// A member of `MgGeometry` in a [`ModuleContract`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeometryMember {
    /// The attribute (`position`, `normal`, `uv`, …).
    pub name: String,
    /// WGSL type.
    pub wgsl_type: String,
    /// The value to write when the app has none (`matgraph nodes` lists them).
    pub default: serde_json::Value,
    /// Lane offset in `mg_geometry` (compute entry): lane `c` of sample `i` is the f32 at
    /// `(offset + c) · count + i`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset: Option<u32>,
}

/// An output in a [`ModuleContract`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModuleOutput {
    /// The graph output's name (or `NODE.OUTPUT`).
    pub name: String,
    /// Its `MgOutputs` member.
    pub member: String,
    /// WGSL type.
    pub wgsl_type: String,
    /// First column in `mg_out` (compute entry): lane `c` of sample `i` is the f32 at
    /// `(column + c) · count + i`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub column: Option<u32>,
}

impl ModuleContract {
    /// The contract of a library or compute module generated from `graph` (with `clamp`, as
    /// its [`crate::wgsl::WgslOptions`] said).
    pub fn new(
        graph: &crate::Graph,
        module: &ShaderModule,
        clamp: ParameterClamp,
    ) -> ModuleContract {
        let info = crate::parameter_info::parameter_info(graph);
        let textures = super::textures::infos(module, false);
        ModuleContract::of(&graph.name, module, &info, clamp, &textures)
    }

    /// The contract of `module` (a library or compute module generated from a graph whose
    /// exposed parameters are `info`), with `textures` its texture slots.
    pub(super) fn of(
        graph: &str,
        module: &ShaderModule,
        info: &[ParameterInfo],
        clamp: ParameterClamp,
        textures: &[super::TextureInfo],
    ) -> ModuleContract {
        let compute = module.entry == crate::wgsl::Entry::Compute;
        let layout = crate::wgsl::geometry_layout(&module.attributes);
        ModuleContract {
            schema: CONTRACT_SCHEMA.into(),
            module: module.entry.name().into(),
            graph: graph.into(),
            texture_mode: module.entry.texture_mode().name().into(),
            function: module.entry.function().into(),
            workgroup_size: compute.then_some(crate::wgsl::WORKGROUP_SIZE),
            geometry: layout
                .iter()
                .map(|&(a, offset)| GeometryMember {
                    name: a.name().into(),
                    wgsl_type: wgsl_type(a.ty()).into(),
                    default: a.default_value().to_json(),
                    offset: compute.then_some(offset),
                })
                .collect(),
            geometry_lanes: compute.then(|| crate::wgsl::geometry_lanes(&module.attributes)),
            outputs: module
                .outputs
                .iter()
                .map(|o| ModuleOutput {
                    name: o.name.clone(),
                    member: o.field.clone(),
                    wgsl_type: wgsl_type(o.ty).into(),
                    column: compute.then_some(o.column),
                })
                .collect(),
            output_columns: compute.then(|| module.output_columns()),
            bindings: binding_entries(module),
            parameters: parameter_block(module, info, clamp),
            textures: texture_entries(textures),
            per_stage: PerStage::from(StageCounts::of(module)),
            limits: ModuleLimits::of(module),
        }
    }

    /// Pretty JSON, two-space indent, newline-terminated: the same bytes for the same input.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a contract serialises");
        s.push('\n');
        s
    }
}

/// The renderer options of [`super::MaterialOptions`] that change the render module.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RenderOptions {
    /// The varyings are interpolated per sample (`--sample-shading`).
    #[serde(default)]
    pub sample_shading: bool,
    /// The vertex buffer holds displaced positions and normals; `mg_vertex` does not
    /// displace (`--displaced-vertices`).
    #[serde(default)]
    pub displaced_vertices: bool,
    /// No tangent buffer: the fragment stage derives the tangent frame
    /// (`--derived-tangents`).
    #[serde(default)]
    pub derived_tangents: bool,
}

impl RenderOptions {
    /// All off (the default module).
    pub fn is_default(&self) -> bool {
        *self == RenderOptions::default()
    }
}

/// How an app draws the mesh with the render module (docs/integration.md, "Drawing the
/// mesh"): what matgraph's own GPU renderer does, in WebGPU's depth convention (0 near, 1
/// far; an app with reversed depth swaps `less` for `greater`).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pipeline {
    /// `none`: both windings are drawn, an open surface is seen from either side as on the
    /// CPU (`back` is never written: culling would be an app's optimisation for closed
    /// meshes, and does not hide the far part of a concave one).
    pub cull_mode: String,
    /// Draw the mesh's depth first (a depth-only pass of `mg_vertex`, no fragment stage,
    /// compare `less`, depth written), then the colour pass over it: true for a graph with
    /// an `alpha` output, so that only the nearest surface of the mesh blends over what lies
    /// behind, as on the CPU (without it back faces and far surfaces blend too).
    pub depth_prepass: bool,
    /// The colour pass's depth compare: `less`, or `less-equal` over the pre-pass's depth
    /// (the clip position is `@invariant`, so both passes compute the same depth).
    pub depth_compare: String,
    /// Whether the colour pass writes depth (not over a pre-pass, which wrote it).
    pub depth_write: bool,
}

impl Default for Pipeline {
    /// An opaque graph's pipeline.
    fn default() -> Self {
        Pipeline::for_alpha(false)
    }
}

impl Pipeline {
    /// The pipeline of a graph with (`true`) or without an `alpha` output.
    pub fn for_alpha(alpha: bool) -> Pipeline {
        Pipeline {
            cull_mode: "none".into(),
            depth_prepass: alpha,
            depth_compare: if alpha { "less-equal" } else { "less" }.into(),
            depth_write: !alpha,
        }
    }

    /// [`Pipeline::cull_mode`] for wgpu.
    pub fn wgpu_cull_mode(&self) -> Option<wgpu::Face> {
        (self.cull_mode == "back").then_some(wgpu::Face::Back)
    }

    /// [`Pipeline::depth_compare`] for wgpu.
    pub fn wgpu_depth_compare(&self) -> wgpu::CompareFunction {
        match self.depth_compare.as_str() {
            "less-equal" => wgpu::CompareFunction::LessEqual,
            "equal" => wgpu::CompareFunction::Equal,
            "always" => wgpu::CompareFunction::Always,
            _ => wgpu::CompareFunction::Less,
        }
    }
}

/// Entry point names.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EntryPoints {
    /// The vertex entry.
    pub vertex: String,
    /// The fragment entry.
    pub fragment: String,
    /// The material function.
    pub material: String,
}

/// A vertex buffer layout.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VertexBuffer {
    /// Bytes per vertex.
    pub array_stride: u64,
    /// `vertex`.
    pub step_mode: String,
    /// The attributes.
    pub attributes: Vec<VertexAttribute>,
}

/// One vertex attribute.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VertexAttribute {
    /// What it holds.
    pub name: String,
    /// `@location`.
    pub shader_location: u32,
    /// WebGPU vertex format.
    pub format: String,
    /// Byte offset in the vertex.
    pub offset: u64,
}

/// The colour target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ColorTarget {
    /// `@location` of the output.
    pub location: u32,
    /// What the output holds.
    pub holds: String,
    /// Blend factors for colour: `[src, dst]`, operation add.
    pub blend_color: [String; 2],
    /// Blend factors for alpha: `[src, dst]`, operation add.
    pub blend_alpha: [String; 2],
}

/// A struct member.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Member {
    /// Member name.
    pub name: String,
    /// WGSL type.
    pub wgsl_type: String,
}

/// An output of the render module.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Output {
    /// The graph output's name.
    pub name: String,
    /// Its `MgOutputs` member.
    pub member: String,
    /// WGSL type.
    pub wgsl_type: String,
    /// `color`, `emission`, `alpha` or `displacement`.
    pub role: String,
    /// What the role's value is measured in: `radiance` (colour and emission: linear
    /// radiance, in the units of the lights' `color`), `fraction` (alpha: coverage, 0 to 1),
    /// `m` (displacement: a world-space offset in metres); absent for an output without a
    /// role.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// `linear-rec709` for colour and emission (scene-referred linear RGB, Rec. 709 / sRGB
    /// primaries, not encoded); absent otherwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub color_space: Option<String>,
}

/// One binding of group 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BindingEntry {
    /// Always 0.
    pub group: u32,
    /// Binding number.
    pub binding: u32,
    /// The WGSL variable.
    pub name: String,
    /// `uniform-buffer`, `read-only-storage-buffer`, `storage-buffer` (the compute entry's
    /// `mg_out`), `filtering-sampler` or `texture-2d-float`.
    pub kind: String,
    /// `["vertex", "fragment"]`, or `["compute"]` in a compute module's contract.
    pub visibility: Vec<String>,
    /// Smallest buffer size in bytes (uniforms), else absent.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_binding_size: Option<u64>,
    /// A sampler's address mode (`repeat`, `clamp-to-edge`, `mirror-repeat`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub address_mode: Option<String>,
    /// A sampler's mag, min and mipmap filter (`linear` or `nearest`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filter: Option<String>,
    /// A texture binding's slot.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub texture_slot: Option<u32>,
}

/// A uniform struct's layout.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Block {
    /// Its binding (absent: the module has no such block).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub binding: Option<u32>,
    /// Size in bytes (the buffer must hold at least this, rounded up to 16).
    pub size: u32,
    /// The parameter block only: `hard-range` when the module clamps each parameter
    /// member to its `hard_range` before use, `none` when it reads them as written
    /// (`matgraph wgsl --no-clamp`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clamp: Option<String>,
    /// Members in order.
    pub members: Vec<BlockMember>,
}

/// A member of a uniform struct.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockMember {
    /// Member name.
    pub name: String,
    /// WGSL type (bools are `u32` 0 or 1).
    pub wgsl_type: String,
    /// Byte offset.
    pub offset: u32,
    /// `parameter` (set by name), `fixed` (the file's value), `time`, `table` (a node's
    /// constant table, its rows in `default`), or `frame`/`light`.
    pub source: String,
    /// The parameter name, for `parameter` members.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameter: Option<String>,
    /// The value written when the app sets none (parameter blocks); a table's rows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub default: Option<serde_json::Value>,
    /// What a `parameter` member means (`scalar`, `color`, `direction`, `point`, `vector`,
    /// `integer`, `choice`, `bool`; [`crate::parameter_info::ParameterKind`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
    /// Its physical unit, absent when dimensionless.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub unit: Option<String>,
    /// The range a slider covers, `[min, max]` per component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<[f32; 2]>,
    /// The range every component must lie in: the CPU refuses a value outside, the module
    /// clamps to it (see [`Block::clamp`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hard_range: Option<[f32; 2]>,
    /// A `choice` member's value names, by index.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub choices: Vec<String>,
    /// What it means, from the graph file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub doc: Option<String>,
    /// The group the editor shows it in.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub group: Option<String>,
}

/// The lights buffer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Lights {
    /// Its binding.
    pub binding: u32,
    /// Bytes per record.
    pub stride: u32,
    /// Members of a record.
    pub members: Vec<BlockMember>,
    /// `kind` of a directional light.
    pub directional: u32,
    /// `kind` of a point light.
    pub point: u32,
    /// Distance (m) below which a point light's 1/d² falloff is clamped.
    pub min_distance: f32,
}

/// A texture slot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Texture {
    /// Slot index.
    pub slot: u32,
    /// The key: the graph's path, a chain's paths joined by `|`, or `scene:NAME`.
    pub name: String,
    /// `file` or `scene`.
    pub source: String,
    /// How the image's values are read: `srgb` (decoded to linear light), `linear` or
    /// `data` (unchanged); scene textures are `linear`.
    pub color_space: String,
    /// Format of the hardware mode (`rgba8unorm-srgb`, `rgba8unorm`, `rgba16float`,
    /// `rgba32float`).
    pub format: String,
    /// Binding of its texture (hardware mode).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub binding: Option<u32>,
    /// Width of level 0, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<u32>,
    /// Height of level 0, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<u32>,
    /// Mip levels (all uploaded), when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mip_levels: Option<u32>,
}

/// Per-stage binding counts.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerStage {
    /// Uniform buffers (WebGPU default limit 12).
    pub uniform_buffers: u32,
    /// Storage buffers (limit 8).
    pub storage_buffers: u32,
    /// Sampled textures (limit 16).
    pub sampled_textures: u32,
    /// Samplers (limit 16).
    pub samplers: u32,
}

impl From<StageCounts> for PerStage {
    fn from(c: StageCounts) -> PerStage {
        PerStage {
            uniform_buffers: c.uniform_buffers,
            storage_buffers: c.storage_buffers,
            sampled_textures: c.sampled_textures,
            samplers: c.samplers,
        }
    }
}

impl Contract {
    /// Pretty JSON, two-space indent, newline-terminated: the same bytes for the same input.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a contract serialises");
        s.push('\n');
        s
    }

    /// Parses a contract written by [`Contract::to_json`]. One written before the
    /// `pipeline` field gets the pipeline its outputs call for (the depth pre-pass where an
    /// output has the role `alpha`); one without `options` was compiled with all off.
    pub fn from_json(text: &str) -> Result<Contract, serde_json::Error> {
        /// Whether the text names a pipeline (other fields are checked by `Contract`).
        #[derive(Deserialize)]
        struct Probe {
            #[serde(default)]
            pipeline: Option<serde::de::IgnoredAny>,
        }
        let mut c: Contract = serde_json::from_str(text)?;
        if serde_json::from_str::<Probe>(text)?.pipeline.is_none() {
            c.pipeline = Pipeline::for_alpha(c.outputs.iter().any(|o| o.role == "alpha"));
        }
        Ok(c)
    }
}

fn member(name: &str, wgsl_type: &str, offset: u32, source: &str) -> BlockMember {
    BlockMember {
        name: name.into(),
        wgsl_type: wgsl_type.into(),
        offset,
        source: source.into(),
        parameter: None,
        default: None,
        kind: None,
        unit: None,
        range: None,
        hard_range: None,
        choices: Vec::new(),
        doc: None,
        group: None,
    }
}

/// A constant table's rows as JSON arrays of four shortest-round-trip numbers.
fn table_json(rows: &[[f32; 4]]) -> serde_json::Value {
    let row = |r: &[f32; 4]| r.iter().map(|&x| crate::value::json_f32(x)).collect();
    serde_json::Value::Array(
        rows.iter()
            .map(|r| serde_json::Value::Array(row(r)))
            .collect(),
    )
}

/// The bindings of `module`'s group 0, in binding order.
fn binding_entries(module: &ShaderModule) -> Vec<BindingEntry> {
    let mut bindings: Vec<&(u32, Binding)> = module.bindings.iter().collect();
    bindings.sort_by_key(|(b, _)| *b);
    bindings
        .into_iter()
        .map(|(b, k)| {
            let kind = match binding_type(module, k) {
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    ..
                } => "uniform-buffer",
                wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    ..
                } => "storage-buffer",
                wgpu::BindingType::Buffer { .. } => "read-only-storage-buffer",
                wgpu::BindingType::Sampler(_) => "filtering-sampler",
                _ => "texture-2d-float",
            };
            let min_binding_size = min_binding_size(module, k);
            let (address_mode, filter) = match k {
                Binding::Sampler(w, f) => (
                    Some(
                        match w {
                            crate::texture::Wrap::Repeat => "repeat",
                            crate::texture::Wrap::Clamp => "clamp-to-edge",
                            crate::texture::Wrap::Mirror => "mirror-repeat",
                        }
                        .to_owned(),
                    ),
                    Some(
                        match f {
                            crate::texture::Filter::Nearest => "nearest",
                            crate::texture::Filter::Bilinear => "linear",
                        }
                        .to_owned(),
                    ),
                ),
                _ => (None, None),
            };
            BindingEntry {
                group: 0,
                binding: *b,
                name: k.variable(),
                kind: kind.into(),
                visibility: stages(module),
                min_binding_size,
                address_mode,
                filter,
                texture_slot: match k {
                    Binding::Texture(s) => Some(*s),
                    _ => None,
                },
            }
        })
        .collect()
}

/// The parameter block of `module`, each `parameter` member with what `info` says of it.
fn parameter_block(module: &ShaderModule, info: &[ParameterInfo], clamp: ParameterClamp) -> Block {
    Block {
        binding: module
            .bindings
            .iter()
            .any(|(_, b)| *b == Binding::Params)
            .then_some(PARAMS_BINDING),
        size: module.uniforms.size,
        clamp: Some(
            match clamp {
                ParameterClamp::HardRange => "hard-range",
                ParameterClamp::None => "none",
            }
            .into(),
        ),
        members: module
            .uniforms
            .fields
            .iter()
            .map(|f| {
                let (source, parameter) = match &f.source {
                    UniformSource::Parameter(p) => ("parameter", Some(p.clone())),
                    UniformSource::Fixed => ("fixed", None),
                    UniformSource::Time => ("time", None),
                    UniformSource::Table(_) => ("table", None),
                };
                let default = match &f.source {
                    UniformSource::Time => None,
                    UniformSource::Table(rows) => Some(table_json(rows)),
                    _ => Some(f.default.to_json()),
                };
                let about = parameter
                    .as_ref()
                    .and_then(|p| info.iter().find(|i| &i.name == p));
                let pair = |r: crate::node::Range| [r.min, r.max];
                BlockMember {
                    name: f.field.clone(),
                    wgsl_type: f.wgsl_type(),
                    offset: f.offset,
                    source: source.into(),
                    parameter,
                    default,
                    kind: about.map(|i| i.kind.name().into()),
                    unit: about.filter(|i| !i.unit.is_empty()).map(|i| i.unit.into()),
                    range: about.and_then(|i| i.soft).map(pair),
                    hard_range: about.and_then(|i| i.hard).map(pair),
                    choices: about.map_or(Vec::new(), |i| {
                        i.choices.iter().map(|c| (*c).to_owned()).collect()
                    }),
                    doc: about.filter(|i| !i.doc.is_empty()).map(|i| i.doc.clone()),
                    group: about.and_then(|i| i.group.clone()),
                }
            })
            .collect(),
    }
}

/// The contract's entries of the texture slots `infos`.
fn texture_entries(infos: &[super::TextureInfo]) -> Vec<Texture> {
    infos
        .iter()
        .map(|t| Texture {
            slot: t.slot,
            name: t.name.clone(),
            source: match t.source {
                super::TextureSource::File => "file",
                super::TextureSource::Scene => "scene",
            }
            .into(),
            color_space: t.color_space.name().into(),
            format: super::format_name(t.format).into(),
            binding: t.binding,
            width: t.size.map(|s| s.0),
            height: t.size.map(|s| s.1),
            mip_levels: t.size.map(|s| s.2),
        })
        .collect()
}

/// The stages a module's bindings are visible to: `compute` for the compute entry;
/// `vertex`, `fragment` and `compute` for the library module, whose function reads every
/// texture at an explicit level and so may be called from any stage (a renderer displaces
/// with it in a compute pass); `vertex` and `fragment` for the render module.
fn stages(module: &ShaderModule) -> Vec<String> {
    match module.entry {
        crate::wgsl::Entry::Compute => vec!["compute".into()],
        crate::wgsl::Entry::Library(_) => {
            vec!["vertex".into(), "fragment".into(), "compute".into()]
        }
        _ => vec!["vertex".into(), "fragment".into()],
    }
}

pub(super) fn build(m: &Material) -> Contract {
    let render = &m.render;
    let roles = m.roles;
    let role_of = |k: usize| {
        [
            (roles.color, "color"),
            (roles.emission, "emission"),
            (roles.alpha, "alpha"),
            (roles.displacement, "displacement"),
        ]
        .into_iter()
        .find(|(r, _)| *r == Some(k))
        .map(|(_, n)| n)
        .unwrap_or("none")
    };
    let bindings = binding_entries(render);
    let parameters = parameter_block(render, &m.parameter_info, m.options.clamp);
    let frame = Block {
        binding: Some(FRAME_BINDING),
        size: FRAME_SIZE,
        clamp: None,
        members: vec![
            member("view_proj", "mat4x4<f32>", 0, "frame"),
            member("model", "mat4x4<f32>", 64, "frame"),
            member("normal_model", "mat4x4<f32>", 128, "frame"),
            member("camera_position", "vec3<f32>", 192, "frame"),
            member("light_count", "u32", 204, "frame"),
            member("viewport", "vec2<f32>", 208, "frame"),
        ],
    };
    let lights = Lights {
        binding: LIGHTS_BINDING,
        stride: LIGHT_STRIDE,
        members: vec![
            member("vector", "vec3<f32>", 0, "light"),
            member("kind", "u32", 12, "light"),
            member("color", "vec3<f32>", 16, "light"),
        ],
        directional: LIGHT_DIRECTIONAL,
        point: LIGHT_POINT,
        min_distance: LIGHT_MIN_DISTANCE,
    };
    Contract {
        schema: CONTRACT_SCHEMA.into(),
        graph: m.graph.clone(),
        texture_mode: m.options.textures.name().into(),
        // The options that change this module (a graph without displacement or tangents
        // gives the same module, and contract, with those options as without).
        options: RenderOptions {
            sample_shading: m.options.sample_shading,
            displaced_vertices: m.options.displaced_vertices && roles.displacement.is_some(),
            derived_tangents: m.options.derived_tangents
                && crate::wgsl::render::uses_tangents(&render.attributes),
        },
        entry_points: EntryPoints {
            vertex: "mg_vertex".into(),
            fragment: "mg_fragment".into(),
            material: "mg_material".into(),
        },
        vertex_buffer: VertexBuffer {
            array_stride: VERTEX_STRIDE,
            step_mode: "vertex".into(),
            attributes: ["position", "normal", "uv"]
                .iter()
                .zip(VERTEX_ATTRIBUTES)
                .map(|(name, a)| VertexAttribute {
                    name: (*name).into(),
                    shader_location: a.shader_location,
                    format: match a.format {
                        wgpu::VertexFormat::Float32x2 => "float32x2",
                        _ => "float32x3",
                    }
                    .into(),
                    offset: a.offset,
                })
                .collect(),
        },
        tangent_buffer: m.uses_tangents().then(|| VertexBuffer {
            array_stride: TANGENT_STRIDE,
            step_mode: "vertex".into(),
            attributes: vec![VertexAttribute {
                name: "tangent".into(),
                shader_location: TANGENT_ATTRIBUTES[0].shader_location,
                format: "float32x4".into(),
                offset: 0,
            }],
        }),
        color_target: ColorTarget {
            location: 0,
            holds: "premultiplied linear radiance (rgb = alpha * radiance) and alpha".into(),
            blend_color: ["one".into(), "one-minus-src-alpha".into()],
            blend_alpha: ["one".into(), "one-minus-src-alpha".into()],
        },
        pipeline: m.pipeline(),
        geometry: render
            .attributes
            .iter()
            .map(|a| Member {
                name: a.name().into(),
                wgsl_type: wgsl_type(a.ty()).into(),
            })
            .collect(),
        outputs: render
            .outputs
            .iter()
            .enumerate()
            .map(|(k, o)| Output {
                name: o.name.clone(),
                member: o.field.clone(),
                wgsl_type: wgsl_type(o.ty).into(),
                role: role_of(k).into(),
                unit: match role_of(k) {
                    "color" | "emission" => Some("radiance".into()),
                    "alpha" => Some("fraction".into()),
                    "displacement" => Some("m".into()),
                    _ => None,
                },
                color_space: matches!(role_of(k), "color" | "emission")
                    .then(|| "linear-rec709".into()),
            })
            .collect(),
        bindings,
        parameters,
        frame,
        lights,
        textures: texture_entries(&m.textures),
        per_stage: PerStage::from(StageCounts::of(render)),
        limits: Some(ModuleLimits::of(render)),
        normal_step: NORMAL_STEP,
        hooks: vec![
            "mg_light_visibility".into(),
            "mg_surface_depth".into(),
            "mg_generated".into(),
            "mg_camera".into(),
        ],
    }
}
