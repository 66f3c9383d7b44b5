//! The app contract: a graph as a WGSL module an app draws with its own wgpu (or WebGPU,
//! or any Vulkan/Metal/D3D) pipeline. Specified in docs/integration.md; this is its Rust API.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use matgraph::material::{Frame, Light, Material, MaterialOptions};
//! let graph = matgraph::io::load_graph("graphs/fresnel_glass.json".as_ref(), matgraph::Registry::builtin())?;
//! let material = Material::new(&graph, &MaterialOptions::default())?;
//! let wgsl = material.wgsl();                        // mg_vertex + mg_fragment (+ mg_material)
//! let entries = material.bind_group_layout_entries(); // group 0
//! let vertex = Material::vertex_buffer_layout();      // position, normal, uv: 32 bytes
//! let mut params = material.params();
//! params.set("ior", 1.5)?;                           // checked name and type
//! let bytes = params.bytes();                        // at naga's offsets → binding 0
//! # let _ = (wgsl, entries, vertex, bytes); Ok(()) }
//! ```
//!
//! **Shape (stable).** Group 0 holds everything: binding 0 the parameter block `MgParams`
//! (uniform; absent when the graph has no uniform), 1 the per-draw `MgFrame` (uniform,
//! [`Frame::bytes`]), 2 the lights (`array<MgLight>`, read-only storage,
//! [`lights_bytes`]), from 3 the textures ([`TextureInfo`]: in the exact mode three
//! storage buffers, in the hardware mode the samplers then one `texture_2d<f32>` per slot).
//! Groups 1–3 are the app's. The vertex entry reads one interleaved buffer
//! ([`Material::vertex_buffer_layout`]); the fragment entry writes premultiplied colour and
//! alpha to location 0 (blend with [`Material::blend_state`]). An app's own shader can call
//! `mg_material(geom: MgGeometry) -> MgOutputs` from [`Material::library_wgsl`] instead.
//! Scene-specific inputs are two hook functions, `mg_light_visibility` (shadows) and
//! `mg_surface_depth` (the `depth` attribute), which [`Material::wgsl_with_hooks`] replaces.

mod contract;
mod frame;
mod layout;
mod limits;
mod load;
mod params;
mod textures;

pub use contract::{
    Block, BlockMember, CONTRACT_SCHEMA, Contract, GeometryMember, ModuleContract, ModuleOutput,
    Pipeline, RenderOptions,
};
pub use frame::{Frame, Light, lights_bytes};
pub use layout::{
    StageCounts, TANGENT_ATTRIBUTES, TANGENT_STRIDE, VERTEX_ATTRIBUTES, VERTEX_STRIDE,
    tangent_buffer_layout, vertex_buffer_layout,
};
pub use limits::ModuleLimits;
pub use load::LoadError;
pub use params::{IntoParam, ParamBlock};
pub use textures::{
    GpuTextures, TextureInfo, TextureSource, format_name, sampler_descriptor, texel_bytes,
};

use crate::graph::Graph;
use crate::plan::{EvalError, Plan, PlanOptions};
use crate::texture::TextureSet;
use crate::types::SocketType;
use crate::wgsl::render::{DEFAULT_HOOKS_WGSL, Roles};
use crate::wgsl::{
    Binding, Entry, ParameterClamp, ShaderError, ShaderModule, TextureMode, WgslOptions,
};

/// Options of [`Material::new`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MaterialOptions {
    /// How textures are bound: [`TextureMode::Hardware`] (the default for apps) or
    /// [`TextureMode::Exact`] (bit-identical with the CPU).
    pub textures: TextureMode,
    /// Whether the app's device has `wgpu::Features::FLOAT32_FILTERABLE`: OpenEXR textures
    /// are then `rgba32float`, else `rgba16float`.
    pub float32_filterable: bool,
    /// Per-sample shading: the varyings are `@interpolate(perspective, sample)`, so under
    /// MSAA `mg_fragment` runs once per covered sample at its position (supersampled
    /// shading, at the cost of one invocation per sample). Off: once per pixel.
    pub sample_shading: bool,
    /// The vertex buffer holds displaced positions and their normals already (displaced by
    /// the app, e.g. once per frame for several passes, with `mg_material(g).displacement`
    /// of [`Material::library_wgsl`]): `mg_vertex` then transforms them without displacing.
    pub displaced_vertices: bool,
    /// The app binds no tangent buffer: a graph that reads the tangent frame gets it from
    /// screen-space derivatives in `mg_fragment` instead
    /// ([`crate::wgsl::render::derived_tangents`], which states the difference).
    pub derived_tangents: bool,
    /// Whether the modules clamp each parameter to its hard range (the default) or read it
    /// as written ([`ParameterClamp`]).
    pub clamp: ParameterClamp,
}

impl Default for MaterialOptions {
    fn default() -> Self {
        MaterialOptions {
            textures: TextureMode::Hardware,
            float32_filterable: false,
            sample_shading: false,
            displaced_vertices: false,
            derived_tangents: false,
            clamp: ParameterClamp::HardRange,
        }
    }
}

/// Why a graph cannot be made into a material, naming the graph and the thing at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MaterialError {
    /// Generating or validating the WGSL failed.
    #[error("graph '{graph}': {source}")]
    Shader {
        /// The graph.
        graph: String,
        /// What failed.
        source: Box<ShaderError>,
    },
    /// An output with a role has a type the role cannot take.
    #[error("graph '{graph}': output '{output}' is {ty}, expected {expected}")]
    OutputType {
        /// The graph.
        graph: String,
        /// The output.
        output: String,
        /// Its type.
        ty: SocketType,
        /// What the role takes.
        expected: &'static str,
    },
    /// The graph has no output the renderer can show.
    #[error("graph '{0}': no output to render (name one `color` or `emission`)")]
    NoOutputs(String),
    /// A parameter could not be set (unknown, wrong type, out of range): names it.
    #[error(transparent)]
    Parameter(EvalError),
    /// A texture the module samples is not in the set.
    #[error("no texture '{0}' bound (the material samples it)")]
    MissingTexture(String),
    /// A texture could not be prepared.
    #[error("texture '{name}': {message}")]
    Texture {
        /// The texture.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The module needs more bindings in a stage than WebGPU's default limits allow.
    #[error("graph '{graph}': {count} {what} per stage, above WebGPU's default limit of {limit}")]
    Limits {
        /// The graph.
        graph: String,
        /// Which binding kind.
        what: &'static str,
        /// How many the module binds.
        count: u32,
        /// The default limit.
        limit: u32,
    },
}

/// A graph compiled for an app: the render module (vertex and fragment entries), the library
/// module (`mg_material` alone), and what to bind.
#[derive(Clone, Debug)]
pub struct Material {
    graph: String,
    options: MaterialOptions,
    render: ShaderModule,
    library: ShaderModule,
    roles: Roles,
    params: ParamBlock,
    textures: Vec<TextureInfo>,
    parameter_info: Vec<crate::parameter_info::ParameterInfo>,
}

impl Material {
    /// Compiles `graph` (already parsed and validated: the core reads no files) into its
    /// render and library modules, both validated by naga.
    pub fn new(graph: &Graph, options: &MaterialOptions) -> Result<Material, MaterialError> {
        let name = graph.name.clone();
        let shader_err = |source: ShaderError| match source {
            ShaderError::Plan(EvalError::NoOutputs) => MaterialError::NoOutputs(name.clone()),
            source => MaterialError::Shader {
                graph: name.clone(),
                source: Box::new(source),
            },
        };
        let outputs: Vec<(String, SocketType)> = graph
            .outputs()
            .iter()
            .map(|o| (o.name.clone(), o.ty))
            .collect();
        let roles = crate::wgsl::render::roles(outputs.iter().map(|(n, _)| n.as_str()));
        let check = |k: Option<usize>, ok: fn(SocketType) -> bool, expected| match k {
            Some(k) if !ok(outputs[k].1) => Err(MaterialError::OutputType {
                graph: name.clone(),
                output: outputs[k].0.clone(),
                ty: outputs[k].1,
                expected,
            }),
            _ => Ok(()),
        };
        let colorish = |t: SocketType| t != SocketType::Vec2 && t != SocketType::Vec4;
        check(roles.color, colorish, "a color, vec3 or float")?;
        check(roles.emission, colorish, "a color, vec3 or float")?;
        check(roles.alpha, |t| t.width() == 1, "a float")?;
        check(roles.displacement, |t| t == SocketType::Vec3, "a vec3")?;
        // The render module computes the outputs with roles, in role order.
        let wanted: Vec<String> = [roles.color, roles.emission, roles.alpha, roles.displacement]
            .into_iter()
            .flatten()
            .map(|k| outputs[k].0.clone())
            .collect();
        if wanted.is_empty() {
            return Err(MaterialError::NoOutputs(name));
        }
        let plan_options = PlanOptions {
            outputs: wanted,
            bake_parameters: false,
        };
        let mut render = crate::wgsl::generate(
            graph,
            &WgslOptions {
                plan: plan_options.clone(),
                entry: Entry::Render(options.textures),
                clamp: options.clamp,
            },
        )
        .map_err(shader_err)?;
        let derive =
            options.derived_tangents && crate::wgsl::render::uses_tangents(&render.attributes);
        if options.sample_shading || options.displaced_vertices || derive {
            let mut source = crate::wgsl::render::variant(
                &render.source,
                options.sample_shading,
                options.displaced_vertices,
            );
            if derive {
                source = crate::wgsl::render::derived_tangents(&source);
            }
            let (module, info) = validate(&name, &source)?;
            render.source = source;
            render.module = module;
            render.info = info;
            // Byte ranges after the edit no longer name nodes exactly; the node text is unchanged.
            render.spans.clear();
        }
        let library = crate::wgsl::generate(
            graph,
            &WgslOptions {
                plan: PlanOptions::default(),
                entry: Entry::Library(options.textures),
                clamp: options.clamp,
            },
        )
        .map_err(shader_err)?;
        for m in [&render, &library] {
            if let Some((what, count, limit)) = StageCounts::of(m).over_default_limits() {
                return Err(MaterialError::Limits {
                    graph: name,
                    what,
                    count,
                    limit,
                });
            }
        }
        let defaults = Plan::compile(graph, &plan_options)
            .map_err(|e| shader_err(ShaderError::Plan(e)))?
            .default_parameters();
        let roles = crate::wgsl::render::roles(render.outputs.iter().map(|o| o.name.as_str()));
        let params = ParamBlock::new(render.uniforms.clone(), defaults);
        let textures = textures::infos(&render, options.float32_filterable);
        Ok(Material {
            graph: graph.name.clone(),
            options: *options,
            render,
            library,
            roles,
            params,
            textures,
            parameter_info: crate::parameter_info::parameter_info(graph),
        })
    }

    /// What each exposed parameter is (kind, unit, soft and hard range, doc), in the file's
    /// order: the contract's parameter members carry it.
    pub fn parameter_info(&self) -> &[crate::parameter_info::ParameterInfo] {
        &self.parameter_info
    }

    /// The graph's name.
    pub fn graph_name(&self) -> &str {
        &self.graph
    }

    /// The options it was compiled with.
    pub fn options(&self) -> MaterialOptions {
        self.options
    }

    /// The render module's WGSL: `mg_vertex`, `mg_fragment`, `mg_material` and the default
    /// hooks.
    pub fn wgsl(&self) -> &str {
        &self.render.source
    }

    /// The render module with the default hooks (`mg_light_visibility`, `mg_surface_depth`)
    /// replaced by `hooks`, WGSL that defines both with the same signatures (and may declare
    /// bindings of groups 1–3); validated by naga.
    pub fn wgsl_with_hooks(&self, hooks: &str) -> Result<String, MaterialError> {
        let source = self.render.source.replace(DEFAULT_HOOKS_WGSL, hooks);
        validate(&self.graph, &source)?;
        Ok(source)
    }

    /// The library module's WGSL: `mg_material(geom: MgGeometry) -> MgOutputs` over every
    /// graph output, with the same group-0 bindings (parameters at 0, textures from 3) and no
    /// entry point, to paste into an app's own shader.
    pub fn library_wgsl(&self) -> &str {
        &self.library.source
    }

    /// The render module (naga IR, bindings, outputs, uniform layout).
    pub fn render_module(&self) -> &ShaderModule {
        &self.render
    }

    /// The library module.
    pub fn library_module(&self) -> &ShaderModule {
        &self.library
    }

    /// Which outputs of [`Material::render_module`] play which role.
    pub fn roles(&self) -> Roles {
        self.roles
    }

    /// The bind group layout entries of group 0 (vertex and fragment visibility).
    pub fn bind_group_layout_entries(&self) -> Vec<wgpu::BindGroupLayoutEntry> {
        layout::entries(&self.render)
    }

    /// The bind group layout entries of the library module's group 0.
    pub fn library_bind_group_layout_entries(&self) -> Vec<wgpu::BindGroupLayoutEntry> {
        layout::entries(&self.library)
    }

    /// The vertex buffer layout of `mg_vertex` (32-byte interleaved position, normal, uv).
    pub fn vertex_buffer_layout() -> wgpu::VertexBufferLayout<'static> {
        vertex_buffer_layout()
    }

    /// Whether `mg_vertex` reads the tangent buffer (slot 1, [`tangent_buffer_layout`]): the
    /// graph reads `geometry.tangent` or `geometry.bitangent_sign`.
    pub fn uses_tangents(&self) -> bool {
        crate::wgsl::render::uses_tangents(&self.render.attributes)
            && !self.options.derived_tangents
    }

    /// The vertex buffers of `mg_vertex`, slot by slot: the interleaved position, normal, uv
    /// buffer, then the tangent buffer where [`Material::uses_tangents`].
    pub fn vertex_buffer_layouts(&self) -> Vec<wgpu::VertexBufferLayout<'static>> {
        let mut v = vec![vertex_buffer_layout()];
        if self.uses_tangents() {
            v.push(tangent_buffer_layout());
        }
        v
    }

    /// The colour target's blend: premultiplied alpha (`One`, `OneMinusSrcAlpha`), which is
    /// the CPU's `alpha · radiance + (1 − alpha) · background`.
    pub fn blend_state() -> wgpu::BlendState {
        wgpu::BlendState::PREMULTIPLIED_ALPHA_BLENDING
    }

    /// How to draw the mesh (docs/integration.md, "Drawing the mesh"): no culling; for a
    /// graph with an `alpha` output a depth pre-pass, then the colour pass at `less-equal`
    /// without depth writes, so that only the mesh's nearest surface blends.
    pub fn pipeline(&self) -> Pipeline {
        Pipeline::for_alpha(self.roles.alpha.is_some())
    }

    /// A parameter block with the graph's values, ready to be [`ParamBlock::set`].
    pub fn params(&self) -> ParamBlock {
        self.params.clone()
    }

    /// A parameter block at the library module's layout (it computes every output, so its
    /// members may differ from [`Material::params`]'s), with the graph's values.
    pub fn library_params(&self) -> ParamBlock {
        ParamBlock::new(self.library.uniforms.clone(), self.params.values().clone())
    }

    /// Whether the module binds a parameter block (binding 0).
    pub fn has_params(&self) -> bool {
        self.render
            .bindings
            .iter()
            .any(|(_, b)| *b == Binding::Params)
    }

    /// The textures the module samples, in slot order.
    pub fn textures(&self) -> &[TextureInfo] {
        &self.textures
    }

    /// Records the sizes and mip counts of the textures in `set` (for the contract); the
    /// textures missing from `set` keep an unknown size.
    pub fn bind_textures(&mut self, set: &TextureSet) {
        for t in &mut self.textures {
            if let Some(x) = set.index_of(&t.name).and_then(|i| set.get(i)) {
                t.size = Some((x.width(), x.height(), x.level_count() as u32));
            }
        }
    }

    /// Uploads the textures the module samples from `set`, in its texture mode.
    pub fn upload_textures(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &TextureSet,
    ) -> Result<GpuTextures, MaterialError> {
        textures::upload(&self.render, &self.textures, device, queue, set)
    }

    /// Uploads the textures the library module samples from `set` (its slots may differ from
    /// the render module's: it computes every output).
    pub fn upload_library_textures(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        set: &TextureSet,
    ) -> Result<GpuTextures, MaterialError> {
        let infos = textures::infos(&self.library, self.options.float32_filterable);
        textures::upload(&self.library, &infos, device, queue, set)
    }

    /// The textures the library module samples, in its slot order.
    pub fn library_textures(&self) -> Vec<TextureInfo> {
        textures::infos(&self.library, self.options.float32_filterable)
    }

    /// The bind group of group 0: `params` (ignored when the module has no parameter block),
    /// `frame`, `lights` and the uploaded textures.
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        frame: &wgpu::Buffer,
        lights: &wgpu::Buffer,
        textures: &GpuTextures,
    ) -> wgpu::BindGroup {
        bind_group(
            &self.render,
            device,
            layout,
            [Some(params), Some(frame), Some(lights)],
            textures,
        )
    }

    /// The bind group of the library module's group 0 (made with
    /// [`Material::library_bind_group_layout_entries`]): `params` and the textures
    /// from [`Material::upload_library_textures`].
    pub fn library_bind_group(
        &self,
        device: &wgpu::Device,
        layout: &wgpu::BindGroupLayout,
        params: &wgpu::Buffer,
        textures: &GpuTextures,
    ) -> wgpu::BindGroup {
        bind_group(
            &self.library,
            device,
            layout,
            [Some(params), None, None],
            textures,
        )
    }

    /// The contract, for apps in other languages ([`Contract::to_json`]).
    pub fn contract(&self) -> Contract {
        contract::build(self)
    }

    /// The contract of the library module (`matgraph wgsl --entry library --contract`): its
    /// geometry, outputs, bindings, parameter block and textures (sizes as bound).
    pub fn library_contract(&self) -> ModuleContract {
        let mut textures = self.library_textures();
        for t in &mut textures {
            t.size = self
                .textures
                .iter()
                .find(|r| r.name == t.name)
                .and_then(|r| r.size);
        }
        ModuleContract::of(
            &self.graph,
            &self.library,
            &self.parameter_info,
            self.options.clamp,
            &textures,
        )
    }
}

/// `source` parsed and validated by naga; errors name the graph.
fn validate(
    graph: &str,
    source: &str,
) -> Result<(naga::Module, naga::valid::ModuleInfo), MaterialError> {
    let err = |message: String| MaterialError::Shader {
        graph: graph.to_owned(),
        source: Box::new(ShaderError::Naga {
            node: None,
            message,
        }),
    };
    let module = naga::front::wgsl::parse_str(source).map_err(|e| err(e.emit_to_string(source)))?;
    // Per-sample interpolation is core WebGPU (naga's MULTISAMPLED_SHADING).
    let info = naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::MULTISAMPLED_SHADING,
    )
    .validate(&module)
    .map_err(|e| err(e.emit_to_string(source)))?;
    Ok((module, info))
}

/// The bind group of `module`'s group 0 from its buffers (parameters, frame, lights) and
/// textures.
fn bind_group(
    module: &ShaderModule,
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    [params, frame, lights]: [Option<&wgpu::Buffer>; 3],
    textures: &GpuTextures,
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = module
        .bindings
        .iter()
        .filter_map(|(binding, b)| {
            let resource = match (b, textures) {
                (Binding::Params, _) => params?.as_entire_binding(),
                (Binding::Frame, _) => frame?.as_entire_binding(),
                (Binding::Lights, _) => lights?.as_entire_binding(),
                (Binding::TextureTexels, GpuTextures::Exact(t)) => t[0].as_entire_binding(),
                (Binding::TextureLevels, GpuTextures::Exact(t)) => t[1].as_entire_binding(),
                (Binding::TextureTable, GpuTextures::Exact(t)) => t[2].as_entire_binding(),
                (Binding::Texture(k), GpuTextures::Hardware { views, .. }) => {
                    wgpu::BindingResource::TextureView(views.get(*k as usize)?)
                }
                (Binding::Sampler(..), GpuTextures::Hardware { samplers, .. }) => {
                    let s = samplers.iter().find(|(sb, _)| sb == binding)?;
                    wgpu::BindingResource::Sampler(&s.1)
                }
                _ => return None,
            };
            Some(wgpu::BindGroupEntry {
                binding: *binding,
                resource,
            })
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("matgraph material"),
        layout,
        entries: &entries,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const WAVE: &str = r#"{ "version": 1, "name": "wave", "nodes": [
      { "id": "geo", "type": "geometry" },
      { "id": "h", "type": "dot", "inputs": { "a": { "link": "geo.position" }, "b": [0.15, 0.1, 0.05] } },
      { "id": "d", "type": "mul", "inputs": { "a": { "link": "geo.normal" }, "b": { "link": "h.result" } } } ],
      "outputs": [{ "name": "emission", "from": "geo.normal" }, { "name": "displacement", "from": "d.result" }] }"#;

    /// The renderer options change the module as documented, and it stays valid.
    #[test]
    fn sample_shading_and_displaced_vertices_edit_the_render_module() {
        let graph = Graph::from_json(WAVE, crate::Registry::builtin()).unwrap();
        let plain = Material::new(&graph, &MaterialOptions::default()).unwrap();
        assert!(plain.wgsl().contains("let q = mg_displaced(p, n, v.uv);"));
        assert!(!plain.wgsl().contains("@interpolate(perspective, sample)"));
        let m = Material::new(
            &graph,
            &MaterialOptions {
                sample_shading: true,
                displaced_vertices: true,
                ..MaterialOptions::default()
            },
        )
        .unwrap();
        let src = m.wgsl();
        assert_eq!(src.matches("@interpolate(perspective, sample)").count(), 3);
        // mg_vertex no longer displaces (mg_displaced stays defined, uncalled).
        let vertex = &src[src.find("fn mg_vertex(").unwrap()..];
        let vertex = &vertex[..vertex.find("\n}\n").unwrap()];
        assert!(!vertex.contains("mg_displaced("), "{vertex}");
        assert!(vertex.contains("o.position = p;"));
        // The same bindings, outputs and parameter block as the default module.
        assert_eq!(m.render_module().bindings, plain.render_module().bindings);
        assert_eq!(m.params().bytes(), plain.params().bytes());
        assert!(m.wgsl_with_hooks(DEFAULT_HOOKS_WGSL).is_ok());
    }
}
