//! The scene on the device: its packed buffers and meshes, the bubble backdrop's maps, the
//! scene textures' sampler buffers, and the pipelines of the built-in surfaces and the sky
//! (`scene.wgsl`, `objects.wgsl`, `backdrop.wgsl`).

use super::*;

/// The scene on the device: its buffers, the bind group of `scene.wgsl` (group 1) and the
/// pipelines of the built-in surfaces and the sky.
pub(super) struct SceneGpu {
    pub(super) packed: Arc<PackedScene>,
    pub(super) pipes: Arc<ScenePipelines>,
    /// Whether the backdrop's maps are bound as textures ([`backdrop::uses_textures`]).
    pub(super) map_textures: bool,
    pub(super) buffers: Arc<SceneBuffers>,
    pub(super) objects_group: wgpu::BindGroup,
    /// The refraction pass's group, drawing the Snell-refracted positions, when on.
    pub(super) refracted_group: Option<wgpu::BindGroup>,
    /// The scene textures (texels, levels, table): the bubble backdrop's maps, the
    /// environment image.
    pub(super) textures: Arc<[wgpu::Buffer; 3]>,
}

/// A packed scene's buffers on the device (`DeviceState::scenes`), uploaded once per
/// [`PackedScene`]: before, every frame uploaded them (a water scene's seabed and skirts,
/// 3.6 MB).
pub(in crate::gpu) struct SceneBuffers {
    pub(super) lights: wgpu::Buffer,
    pub(super) casters: wgpu::Buffer,
    pub(super) positions: wgpu::Buffer,
    pub(super) normals: wgpu::Buffer,
    pub(super) table: wgpu::Buffer,
    pub(super) index: wgpu::Buffer,
    /// `MgrBackdrop`.
    pub(super) backdrop: wgpu::Buffer,
    /// The Snell-refracted positions, when the scene has them.
    pub(super) refracted: Option<wgpu::Buffer>,
}

impl SceneBuffers {
    pub(super) fn new(s: &DeviceState, packed: &PackedScene) -> SceneBuffers {
        SceneBuffers {
            lights: storage(s, "mgr lights", bytemuck::cast_slice(&packed.lights), 48),
            casters: storage(s, "mgr casters", bytemuck::cast_slice(&packed.casters), 48),
            positions: storage(
                s,
                "mgr positions",
                bytemuck::cast_slice(&packed.positions),
                16,
            ),
            normals: storage(s, "mgr normals", bytemuck::cast_slice(&packed.normals), 16),
            table: storage(
                s,
                "mgr object table",
                bytemuck::cast_slice(&packed.objects),
                80,
            ),
            index: index_buffer(s, &packed.indices),
            backdrop: storage(
                s,
                "mgr backdrop",
                bytemuck::cast_slice(&packed.backdrop),
                96,
            ),
            refracted: packed
                .refracted
                .as_ref()
                .map(|r| storage(s, "mgr refracted", bytemuck::cast_slice(r), 16)),
        }
    }
}

/// A material mesh's buffers on the device (`DeviceState::meshes`), made once per mesh:
/// the indices, the vertices in the contract's layout (drawn as they are without
/// displacement) and, on the first displaced frame, the displacement passes' inputs.
pub(in crate::gpu) struct MeshBuffers {
    pub(super) index: wgpu::Buffer,
    /// Indices drawn.
    pub(super) count: u32,
    pub(super) vertices: wgpu::Buffer,
    pub(super) displacement: std::sync::OnceLock<DisplacementInputs>,
    /// The MikkTSpace tangents and signs (`Mesh::tangents`), made on the first frame whose
    /// material reads them: the second vertex buffer, and storage for rebuilt samples.
    pub(super) tangents: std::sync::OnceLock<wgpu::Buffer>,
}

/// The inputs of the displacement and normal passes: position and uv, normal and uv per
/// vertex, and the welded normals' adjacency (`Mesh::normal_adjacency`: weld groups, their
/// starts, their triangles), whose sort was most of a displaced frame's CPU time.
pub(super) struct DisplacementInputs {
    pub(super) vertices: wgpu::Buffer,
    pub(super) adjacency: [wgpu::Buffer; 3],
}

impl MeshBuffers {
    pub(super) fn new(s: &DeviceState, mesh: &Mesh) -> MeshBuffers {
        let idx: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
        let vertices = s
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("mgr material vertices"),
                contents: bytemuck::cast_slice(&vertex_bytes(mesh)),
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
            });
        MeshBuffers {
            index: index_buffer(s, &idx),
            count: idx.len() as u32,
            vertices,
            displacement: std::sync::OnceLock::new(),
            tangents: std::sync::OnceLock::new(),
        }
    }

    /// The tangent buffer of `mesh` (the mesh these buffers were made from).
    pub(super) fn tangents(&self, s: &DeviceState, mesh: &Mesh) -> &wgpu::Buffer {
        self.tangents.get_or_init(|| {
            s.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("mgr material tangents"),
                    contents: bytemuck::cast_slice(
                        &mesh
                            .tangents()
                            .iter()
                            .map(|t| t.to_array())
                            .collect::<Vec<_>>(),
                    ),
                    usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::STORAGE,
                })
        })
    }

    /// The displacement passes' inputs of `mesh` (the mesh these buffers were made from),
    /// made on the first displaced frame.
    pub(super) fn displacement(&self, s: &DeviceState, mesh: &Mesh) -> &DisplacementInputs {
        self.displacement.get_or_init(|| {
            let vertices: Vec<[f32; 4]> = (0..mesh.positions.len())
                .flat_map(|i| {
                    let (p, q, uv) = (mesh.positions[i], mesh.normals[i], mesh.uvs[i]);
                    [p.extend(uv.x).to_array(), q.extend(uv.y).to_array()]
                })
                .collect();
            let (groups, starts, tris) = mesh.normal_adjacency();
            DisplacementInputs {
                vertices: storage(s, "mgr vertices", bytemuck::cast_slice(&vertices), 16),
                adjacency: [
                    storage(s, "mgr groups", bytemuck::cast_slice(&groups), 16),
                    storage(s, "mgr starts", bytemuck::cast_slice(&starts), 16),
                    storage(s, "mgr adjacency", bytemuck::cast_slice(&tris), 16),
                ],
            }
        })
    }

    /// The buffers of `mesh`, made on the first frame that draws it.
    pub(super) fn of(s: &DeviceState, mesh: &Arc<Mesh>) -> Arc<MeshBuffers> {
        s.meshes.get_or(Same(Some(mesh.clone())), || {
            Arc::new(MeshBuffers::new(s, mesh))
        })
    }
}

/// The bubble backdrop's maps, shared ([`crate::scene::bubble_maps`]).
pub(super) fn backdrop_maps() -> &'static [Arc<Texture>] {
    static MAPS: std::sync::OnceLock<Vec<Arc<Texture>>> = std::sync::OnceLock::new();
    MAPS.get_or_init(|| {
        crate::scene::bubble_maps()
            .named()
            .iter()
            .map(|(_, t)| Arc::new((*t).clone()))
            .collect()
    })
}

/// The scene textures of `packed` as the three buffers of `mgs_sample_texture`: the
/// backdrop's maps (slots 0–5, when drawn), then the environment image (when given). The
/// maps alone are packed once per device.
pub(super) fn scene_textures(
    s: &DeviceState,
    packed: &PackedScene,
    environment: Option<&Arc<Texture>>,
) -> Result<Arc<[wgpu::Buffer; 3]>, EvalError> {
    let buffers = |pack: &TexturePack| {
        [
            storage(s, "mgs_texels", pack.texel_bytes(), 16),
            storage(s, "mgs_levels", pack.level_bytes(), 16),
            storage(s, "mgs_textures", pack.texture_bytes(), 16),
        ]
    };
    let mut set = TextureSet::new();
    if packed.features.backdrop {
        for (k, t) in backdrop_maps().iter().enumerate() {
            set.insert_shared(format!("backdrop {k}"), t.clone())
                .map_err(|e| gpu_err("packing the scene textures", e))?;
        }
    }
    match environment.filter(|_| packed.features.env_image) {
        Some(env) => {
            set.insert_shared("environment", env.clone())
                .map_err(|e| gpu_err("packing the scene textures", e))?;
            let pack = set
                .pack()
                .map_err(|e| gpu_err("packing the scene textures", e))?;
            Ok(Arc::new(buffers(&pack)))
        }
        None => {
            // The maps alone (or nothing) pack the same every frame: once per device.
            let key = format!("scene textures/{}", packed.features.backdrop);
            let mut failed = None;
            let made = cached(s, &key, || match set.pack() {
                Ok(pack) => Some(buffers(&pack)),
                Err(e) => {
                    failed = Some(gpu_err("packing the scene textures", e));
                    None
                }
            });
            match (&*made, failed) {
                (_, Some(e)) => Err(e),
                (Some(b), None) => Ok(Arc::new(b.clone())),
                (None, None) => Err(EvalError::Gpu("packing the scene textures failed".into())),
            }
        }
    }
}

/// The layouts and pipelines of the scene passes at one sample count.
pub(super) struct ScenePipelines {
    pub(super) scene_layout: wgpu::BindGroupLayout,
    pub(super) objects_layout: wgpu::BindGroupLayout,
    pub(super) objects: wgpu::RenderPipeline,
    pub(super) sky: wgpu::RenderPipeline,
}

/// `scene.wgsl` for a scene with `features`, with what it needs before it: the constants
/// that leave out what the scene lacks ([`SceneFeatures::wgsl`]) and the sampler of the
/// scene textures (`texture.rs` SAMPLE_WGSL, its names prefixed `mgs_` so as not to meet
/// the material's own `mg_` sampler) on group 1, bindings 3–5.
pub(super) fn scene_source(features: &SceneFeatures) -> String {
    let sampler = format!(
        "{}\n{}",
        crate::texture::sample_bindings_wgsl(1, 3),
        crate::texture::SAMPLE_WGSL
    );
    format!(
        "{}\n{}\n{}",
        features.wgsl(),
        sampler.replace("mg_", "mgs_"),
        include_str!("scene.wgsl")
    )
}

/// The group-1 layout of `scene.wgsl`.
pub(super) fn scene_layout(s: &DeviceState) -> wgpu::BindGroupLayout {
    layout(
        s,
        "mgr scene",
        &[
            (0, ALL, Kind::Uniform),
            (1, FC, Kind::Storage),
            (2, FC, Kind::Storage),
            (3, FC, Kind::Storage),
            (4, FC, Kind::Storage),
            (5, FC, Kind::Storage),
            (6, FC, Kind::Storage),
        ],
    )
}

impl ScenePipelines {
    /// The pipelines at `spp` samples for a scene with `features`, the backdrop's maps read
    /// from textures when `map_textures` ([`backdrop::uses_textures`]).
    pub(super) fn new(
        s: &DeviceState,
        spp: u32,
        features: &SceneFeatures,
        map_textures: bool,
    ) -> ScenePipelines {
        let scene_layout = scene_layout(s);
        let f = wgpu::ShaderStages::FRAGMENT;
        let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
        let maps = match map_textures {
            true => backdrop::layout_entries().to_vec(),
            false => Vec::new(),
        };
        let objects_layout = layout_with(
            s,
            "mgr objects",
            &[
                (0, vf, Kind::Storage),
                (1, vf, Kind::Storage),
                (2, f, Kind::Storage),
                (3, f, Kind::Storage),
                (4, vf, Kind::Storage),
            ],
            &maps,
        );
        let source = format!(
            "enable primitive_index;\n{}\n{}\n{}",
            scene_source(features),
            backdrop::source(map_textures),
            include_str!("objects.wgsl")
        );
        let m = module(s, "mgr objects", &source);
        let pl = pipeline_layout(s, &[&objects_layout, &scene_layout]);
        let objects = render_pipeline(
            s,
            "mgr objects",
            &m,
            "mgr_object_vs",
            // Varyings at 1 sample per pixel, the CPU's barycentrics rebuilt under MSAA.
            if spp == 1 {
                "mgr_object_fs"
            } else {
                "mgr_object_sample_fs"
            },
            &pl,
            spp,
            true,
        );
        let sky = render_pipeline_depth(
            s,
            "mgr sky",
            (&m, "mgr_sky_vs", Some("mgr_sky_fs")),
            &pl,
            spp,
            (wgpu::CompareFunction::GreaterEqual, false),
        );
        ScenePipelines {
            scene_layout,
            objects_layout,
            objects,
            sky,
        }
    }
}

pub(super) const ALL: wgpu::ShaderStages =
    wgpu::ShaderStages::VERTEX_FRAGMENT.union(wgpu::ShaderStages::COMPUTE);
pub(super) const FC: wgpu::ShaderStages =
    wgpu::ShaderStages::FRAGMENT.union(wgpu::ShaderStages::COMPUTE);

impl SceneGpu {
    /// `scene` on the device for frames of `spp` samples, `environment` the image of an
    /// image environment, the backdrop's maps bound as texture mode `mode` says.
    pub(super) fn new(
        s: &DeviceState,
        scene: &Scene,
        spp: u32,
        environment: Option<&Arc<Texture>>,
        mode: TextureMode,
    ) -> Result<SceneGpu, EvalError> {
        // Packed once per scene and environment (the Snell-refracted seabed alone is a
        // quarter of a water preview's CPU time): frames that change only the material
        // reuse it.
        static PACKED: Memo<(String, Same<Texture>), Arc<PackedScene>, 4> = Memo::new();
        let key = (
            serde_json::to_string(scene).unwrap_or_default(),
            Same(environment.cloned()),
        );
        let packed = PACKED.get_or(key, || {
            let lookup = environment.map(|t| crate::scene::image_lookup(t.clone()));
            Arc::new(scene.packed(lookup.as_ref().map(|f| f as &crate::scene::EnvLookup)))
        });
        let textures = scene_textures(s, &packed, environment)?;
        let features = packed.features;
        let map_textures = backdrop::uses_textures(features.backdrop, mode);
        let pipes = cached(
            s,
            &format!("scene/{spp}/{features:?}/{map_textures}"),
            || ScenePipelines::new(s, spp, &features, map_textures),
        );
        let maps = map_textures.then(|| backdrop::MapTextures::of(s));
        let b = s.scenes.get_or(Same(Some(packed.clone())), || {
            Arc::new(SceneBuffers::new(s, &packed))
        });
        let group = |drawn: &wgpu::Buffer| {
            let mut entries = vec![
                (0, b.positions.as_entire_binding()),
                (1, b.normals.as_entire_binding()),
                (2, b.table.as_entire_binding()),
                (3, b.index.as_entire_binding()),
                (4, drawn.as_entire_binding()),
            ];
            entries.extend(maps.iter().flat_map(|m| m.entries()));
            bind_entries(s, &pipes.objects_layout, &entries)
        };
        let objects_group = group(&b.positions);
        let refracted_group = b.refracted.as_ref().map(group);
        Ok(SceneGpu {
            packed,
            pipes,
            map_textures,
            buffers: b,
            objects_group,
            refracted_group,
            textures,
        })
    }

    /// The group-1 bind group of a pass's frame uniform.
    pub(super) fn frame_group(&self, s: &DeviceState, frame: &[u8]) -> wgpu::BindGroup {
        let u = uniform(s, "mgr frame", frame);
        bind(
            s,
            &self.pipes.scene_layout,
            &[
                u.as_entire_binding(),
                self.buffers.lights.as_entire_binding(),
                self.buffers.casters.as_entire_binding(),
                self.textures[0].as_entire_binding(),
                self.textures[1].as_entire_binding(),
                self.textures[2].as_entire_binding(),
                self.buffers.backdrop.as_entire_binding(),
            ],
        )
    }

    /// Records the sky and the built-in surfaces of `pass` into `color` and `depth`; with
    /// `prepass` over the depth already there (the material's), so that what lies behind
    /// it is not shaded.
    pub(super) fn record(
        &self,
        enc: &mut wgpu::CommandEncoder,
        frame: &wgpu::BindGroup,
        pass: ScenePass,
        color: &wgpu::TextureView,
        depth: &wgpu::TextureView,
        prepass: bool,
    ) {
        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mgr scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: color,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations {
                    load: if prepass {
                        wgpu::LoadOp::Load
                    } else {
                        wgpu::LoadOp::Clear(0.0)
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let group = match (pass, &self.refracted_group) {
            (ScenePass::Refraction, Some(g)) => g,
            _ => &self.objects_group,
        };
        rp.set_bind_group(0, group, &[]);
        rp.set_bind_group(1, frame, &[]);
        rp.set_pipeline(&self.pipes.objects);
        rp.set_index_buffer(self.buffers.index.slice(..), wgpu::IndexFormat::Uint32);
        for (k, r) in self.packed.ranges.iter().enumerate() {
            // The reflection shows what stands above the water only.
            if pass == ScenePass::Reflection && r.underwater {
                continue;
            }
            if !r.indices.is_empty() {
                // The instance is the object (objects.wgsl).
                rp.draw_indexed(r.indices.clone(), 0, k as u32..k as u32 + 1);
            }
        }
        // The sky last, at depth 0 under `GreaterEqual`: only where nothing was drawn (the
        // depth still cleared), so that it is not shaded under the surfaces and the
        // material (the same picture as drawing it first, each fragment shaded once).
        rp.set_pipeline(&self.pipes.sky);
        rp.draw(0..3, 0..1);
    }
}
