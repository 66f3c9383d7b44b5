//! One frame: the scene's passes, the material drawn through the app contract, tiles and
//! samples, the resolve and the read-back ([`render_frame`]).

use super::*;

/// Renders the frame of `scene` with `m` at `w × h` and `spp` samples per pixel, all on the
/// GPU, the material drawn through the app contract ([`Material`]). Returns linear RGB per
/// pixel, rows from the top.
pub(crate) fn render_frame(
    ctx: &GpuContext,
    scene: &Scene,
    environment: Option<&Arc<Texture>>,
    (w, h, spp): (u32, u32, u32),
    m: &MaterialInput,
) -> Result<(Vec<[f32; 3]>, RasterTimings), EvalError> {
    let s = &*ctx.state;
    let mut t = RasterTimings::default();
    s.scoped("rendering on the GPU", || {
        // The material, its module with the scene's hooks, and the pipelines.
        let start = Instant::now();
        // Real MSAA where the device has the count, else one jittered pass per sample.
        let msaa = supports_samples(ctx, spp);
        let (ts, passes) = if msaa { (spp, 1) } else { (1, spp) };
        let options = MaterialOptions {
            textures: m.texture_mode,
            float32_filterable: ctx.features().contains(wgpu::Features::FLOAT32_FILTERABLE),
            // Over one sample the varyings are rebuilt per sample ([`material::sample_source`]).
            sample_shading: false,
            // Displaced by `displace`, in the CPU's order (normals from the displaced mesh).
            displaced_vertices: true,
            // The mesh's MikkTSpace tangents, as the CPU's G-buffer reads them.
            derived_tangents: false,
            clamp: crate::wgsl::ParameterClamp::HardRange,
        };
        // Generated and validated once per graph and options on the device: later frames
        // (an animation) only write their parameters and time. At 1 sample the contract's
        // `mg_fragment` as is; over 1 (MSAA or jittered passes) the varyings rebuilt at the
        // CPU's sample and the CPU's uv derivatives. `screen_uv` is the frame's, through the
        // tile's offset (`mgr_screen_uv`).
        let rebuilt = spp > 1;
        let gpu = SceneGpu::new(s, scene, ts, environment, m.texture_mode)?;
        let features = gpu.packed.features;
        // Keyed without the parameters' values, which `set_values` below replaces: the
        // editor's program of a structure is built with the values of its moment (an edit
        // back to a structure drawn before missed, and made its material again: 19 ms).
        let key = format!(
            "material/{rebuilt}/{options:?}/{features:?}/{}",
            m.graph.structure_key()
        );
        let made = cached(s, &key, || -> Result<(Material, String), MaterialError> {
            let material = Material::new(m.graph, &options)?;
            // The contract's clip position is `@invariant`, so the depth pre-pass and the
            // surface over it (two pipelines, the surface's test `GreaterEqual` against the
            // pre-pass) compute the same depth.
            let hooked = material
                .wgsl_with_hooks(&material::hooks(&features))?
                .replace("v.clip.xy / mg_frame.viewport", "mgr_screen_uv(v.clip.xy)");
            let source = match rebuilt {
                false => Some(hooked),
                true => material::sample_source(&hooked),
            }
            .ok_or_else(|| MaterialError::Shader {
                graph: m.graph.name.clone(),
                source: Box::new(crate::wgsl::ShaderError::Naga {
                    node: None,
                    message: "the render module has no mg_fragment entry".into(),
                }),
            })?;
            Ok((material, source))
        });
        let (material, source) = match &*made {
            Ok((material, source)) => (material, source),
            Err(e) => return Err(material_err(e.clone())),
        };
        // By the source: graphs that differ only in what the source does not show share
        // their pipelines.
        let pipes = cached(s, &format!("material pipeline/{ts}/{source}"), || {
            let mat_layout = s
                .device
                .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("mgr material"),
                    entries: &material.bind_group_layout_entries(),
                });
            let fm = module(s, "mgr material", source);
            let vf = wgpu::ShaderStages::VERTEX_FRAGMENT;
            let tangents = material::reads_tangents(source);
            let mesh_entries = [
                (0, vf, Kind::Storage),
                (1, vf, Kind::Storage),
                (2, vf, Kind::Storage),
            ];
            let mesh_layout = layout(s, "mgr mesh", &mesh_entries[..if tangents { 3 } else { 2 }]);
            let (fs, pl) = match rebuilt {
                false => (
                    "mg_fragment",
                    pipeline_layout(s, &[&mat_layout, &gpu.pipes.scene_layout]),
                ),
                true => (
                    "mgr_material_sample_fs",
                    pipeline_layout(s, &[&mat_layout, &gpu.pipes.scene_layout, &mesh_layout]),
                ),
            };
            use wgpu::CompareFunction::{Greater, GreaterEqual};
            // The material's depth, and its surface over that depth (the samples whose
            // depth it drew).
            let depth_only = material::pipeline(s, &fm, None, &pl, ts, (Greater, true), tangents);
            let surface =
                material::pipeline(s, &fm, Some(fs), &pl, ts, (GreaterEqual, false), tangents);
            (mat_layout, mesh_layout, depth_only, surface)
        });
        let (mat_layout, mesh_layout, depth_only, surface) =
            (&pipes.0, &pipes.1, &pipes.2, &pipes.3);
        // The material's depth is drawn before its colour, so that the material pass shades
        // one fragment per sample, the nearest, as the CPU's G-buffer does (the mesh is not
        // culled: without it a sphere's back faces drawn before its front are shaded too;
        // measured, the bubble's frame 1.14× as long). An opaque material (no alpha) hides
        // what lies behind it, so its depth is drawn first of all and the scene pass shades
        // only the samples the material leaves visible (the composite there is the
        // material's radiance alone, as on the CPU, where alpha 1 weighs the background by
        // 0); a material with alpha draws its depth after the scene, which shows through it.
        let has_mesh = !m.mesh.indices.is_empty();
        let opaque = material.roles().alpha.is_none();
        t.compile = start.elapsed();

        // Buffers: group 0 of the contract (its frame per pass), the scene's group 1, the
        // mesh.
        let start = Instant::now();
        let mut params = material.params();
        params.set_values(m.params);
        params.set_time(m.time);
        let params_buf = uniform(s, "mgr params", &params.bytes());
        let (_, lights_bytes) = material::frame_and_lights(scene, w, h, &Viewport::whole(w, h));
        let lights_buf = storage(s, "mgr material lights", &lights_bytes, 32);
        let owner: Arc<dyn std::any::Any + Send + Sync> = made.clone();
        let textures = uploaded(s, &owner, material, false, m.textures)?;
        let mesh = MeshBuffers::of(s, m.mesh);
        let (index, tri_count) = (&mesh.index, mesh.count);
        let mut enc = s.device.create_command_encoder(&Default::default());

        // 1. Displacement and normals, on the GPU.
        let vertices = match material.roles().displacement {
            None => mesh.vertices.clone(),
            Some(_) => displace(ctx, &mut enc, (&owner, material), m, &mesh)?,
        };
        let tangents = material::reads_tangents(source).then(|| mesh.tangents(s, m.mesh));
        let mut mesh_entries = vec![vertices.as_entire_binding(), index.as_entire_binding()];
        mesh_entries.extend(tangents.map(|t| t.as_entire_binding()));
        let mesh_group = bind(s, mesh_layout, &mesh_entries);
        t.upload = start.elapsed();

        // Tile by tile (one tile where the frame fits the device): 2. the scene, 3. the
        // material surface over its depth, 4. the resolve (or, jittered, the pass's sample
        // added to the tile's sum), 5. the tile read back into the frame.
        let start = Instant::now();
        let offsets = crate::scene::sample_offsets(spp);
        let (tw, th) = tile_size(ctx, w, h, ts);
        let mut pixels = vec![[0.0f32; 3]; w as usize * h as usize];
        let mut readback = Duration::ZERO;
        for y0 in (0..h).step_by(th as usize) {
            for x0 in (0..w).step_by(tw as usize) {
                let size = [tw.min(w - x0), th.min(h - y0)];
                let (cw, ch) = (size[0], size[1]);
                // A small frame in one pass keeps its scene pass ([`drawn`]); any other draws
                // its own, under an opaque material's depth.
                let kept = passes == 1
                    && (cw, ch) == (w, h)
                    && cw as u64 * ch as u64 * ts as u64 <= drawn::MAX_SAMPLES;
                let none = wgpu::TextureUsages::empty();
                let color = (!kept).then(|| target(s, "mgr scene", (cw, ch, ts), COLOR, none));
                let depth = match kept {
                    true => wgpu::TextureUsages::COPY_DST,
                    false => none,
                };
                let depth = target(s, "mgr depth", (cw, ch, ts), DEPTH, depth);
                let mat_target = target(s, "mgr material", (cw, ch, ts), COLOR, none);
                // The resolved pixels (jittered: the passes' sum).
                let bytes = cw as u64 * ch as u64 * 12;
                let out = pixels_buffer(s, bytes);
                for pass in 0..passes {
                    let jitter = if msaa {
                        [0.0, 0.0]
                    } else {
                        let o = offsets[pass as usize];
                        [o[0] - 0.5, o[1] - 0.5]
                    };
                    let view = Viewport {
                        origin: [x0, y0],
                        size,
                        jitter,
                    };
                    let frame_bytes =
                        scene.frame_uniform(&gpu.packed, w, h, ScenePass::Background, &view);
                    let frame = gpu.frame_group(s, &frame_bytes);
                    let (frame_bytes, _) = material::frame_and_lights(scene, w, h, &view);
                    let frame_buf = uniform(s, "mgr material frame", &frame_bytes);
                    let mat_group = material.bind_group(
                        &s.device,
                        mat_layout,
                        &params_buf,
                        &frame_buf,
                        &lights_buf,
                        &textures,
                    );
                    // The material mesh drawn with `pipeline` (depth only, or the surface).
                    let draw_mesh = |rp: &mut wgpu::RenderPass, pipeline| {
                        rp.set_pipeline(pipeline);
                        rp.set_bind_group(0, &mat_group, &[]);
                        rp.set_bind_group(1, &frame, &[]);
                        if rebuilt {
                            rp.set_bind_group(2, &mesh_group, &[]);
                        }
                        rp.set_vertex_buffer(0, vertices.slice(..));
                        if let Some(t) = tangents {
                            rp.set_vertex_buffer(1, t.slice(..));
                        }
                        rp.set_index_buffer(index.slice(..), wgpu::IndexFormat::Uint32);
                        if tri_count > 0 {
                            rp.draw_indexed(0..tri_count, 0, 0..1);
                        }
                    };
                    // The material's depth, over the scene's (`clear`: none yet).
                    let material_depth = |enc: &mut wgpu::CommandEncoder, clear: bool| {
                        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some("mgr material depth"),
                            color_attachments: &[],
                            depth_stencil_attachment: Some(
                                wgpu::RenderPassDepthStencilAttachment {
                                    view: &depth,
                                    depth_ops: Some(wgpu::Operations {
                                        load: match clear {
                                            true => wgpu::LoadOp::Clear(0.0),
                                            false => wgpu::LoadOp::Load,
                                        },
                                        store: wgpu::StoreOp::Store,
                                    }),
                                    stencil_ops: None,
                                },
                            ),
                            timestamp_writes: None,
                            occlusion_query_set: None,
                            multiview_mask: None,
                        });
                        draw_mesh(&mut rp, depth_only);
                    };
                    // The scene's colour: drawn here, or kept from an earlier frame.
                    let kept_scene: Arc<DrawnScene>;
                    let scene_color = match &color {
                        Some(color) => {
                            if has_mesh && opaque {
                                material_depth(&mut enc, true);
                            }
                            gpu.record(
                                &mut enc,
                                &frame,
                                ScenePass::Background,
                                color,
                                &depth,
                                has_mesh && opaque,
                            );
                            if has_mesh && !opaque {
                                material_depth(&mut enc, false);
                            }
                            &color.view
                        }
                        None => {
                            kept_scene =
                                DrawnScene::of(s, &gpu, (&frame_bytes, &frame), [cw, ch, ts]);
                            kept_scene.copy_depth(&mut enc, &depth.texture);
                            if has_mesh {
                                material_depth(&mut enc, false);
                            }
                            &kept_scene.color
                        }
                    };
                    {
                        let mut rp = enc.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some("mgr material"),
                            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                                view: &mat_target,
                                depth_slice: None,
                                resolve_target: None,
                                ops: wgpu::Operations {
                                    load: wgpu::LoadOp::Clear(NO_MATERIAL),
                                    store: wgpu::StoreOp::Store,
                                },
                            })],
                            depth_stencil_attachment: Some(
                                wgpu::RenderPassDepthStencilAttachment {
                                    view: &depth,
                                    depth_ops: Some(wgpu::Operations {
                                        load: wgpu::LoadOp::Load,
                                        store: wgpu::StoreOp::Store,
                                    }),
                                    stencil_ops: None,
                                },
                            ),
                            timestamp_writes: None,
                            occlusion_query_set: None,
                            multiview_mask: None,
                        });
                        draw_mesh(&mut rp, surface);
                    }
                    let samples = match msaa {
                        true => Samples::Whole,
                        false => Samples::Pass(pass),
                    };
                    let targets = (scene_color, &*mat_target);
                    resolve(s, &mut enc, targets, &out, (cw, ch, spp), samples);
                }
                let st = staging(s, bytes);
                enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
                let done = std::mem::replace(
                    &mut enc,
                    s.device.create_command_encoder(&Default::default()),
                );
                submit_and_wait(s, done)?;
                let r = Instant::now();
                let data = read_back(s, st, bytes)?;
                for (row, line) in data.chunks_exact(cw as usize * 3).enumerate() {
                    let first = (y0 as usize + row) * w as usize + x0 as usize;
                    for (k, c) in line.chunks_exact(3).enumerate() {
                        pixels[first + k] = [c[0], c[1], c[2]];
                    }
                }
                readback += r.elapsed();
            }
        }
        drop(enc);
        t.draw = start.elapsed() - readback;
        t.readback = readback;
        Ok(pixels)
    })
    .map(|p| (p, t))
}
