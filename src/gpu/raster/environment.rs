//! The scene's environment as an equirectangular map, ray cast on the GPU (`envmap.wgsl`)
//! as the CPU's `Scene::environment_map`.

use super::*;

/// The scene's environment as a `w × h` equirectangular map (RGBA, alpha 1);
/// `environment` is the image of an image environment.
pub(crate) fn render_environment(
    ctx: &GpuContext,
    scene: &Scene,
    environment: Option<&Arc<Texture>>,
    w: u32,
    h: u32,
) -> Result<Vec<[f32; 4]>, EvalError> {
    let s = &*ctx.state;
    s.scoped("drawing the environment map on the GPU", || {
        // The map is the image-based lighting's source: the exact maps, as on the CPU.
        let gpu = SceneGpu::new(s, scene, 1, environment, TextureMode::Exact)?;
        let packed = &gpu.packed;
        let c = wgpu::ShaderStages::COMPUTE;
        let pipes = cached(s, &format!("environment/{:?}", packed.features), || {
            let l = layout(
                s,
                "mgr environment",
                &[
                    (0, c, Kind::Storage),
                    (1, c, Kind::Storage),
                    (2, c, Kind::Storage),
                    (3, c, Kind::Storage),
                    (5, c, Kind::StorageRw),
                    (6, c, Kind::Uniform),
                ],
            );
            let source = format!(
                "enable primitive_index;\n{}\n{}\n{}\n{}",
                scene_source(&packed.features),
                backdrop::source(false),
                include_str!("objects.wgsl"),
                include_str!("envmap.wgsl")
            );
            let m = module(s, "mgr environment", &source);
            let pl = pipeline_layout(s, &[&l, &gpu.pipes.scene_layout]);
            let p = compute_pipeline(s, "mgr environment", &m, "mgr_environment", &pl);
            (l, p)
        });
        let (l, p) = (&pipes.0, &pipes.1);
        let view = Viewport::whole(w, h);
        let g1 = gpu.frame_group(
            s,
            &scene.frame_uniform(&gpu.packed, w, h, ScenePass::Background, &view),
        );
        // MgrEnvView: the rays' origin and the triangles they meet (none: the sky alone).
        let (origin, triangles) = match scene.environment_origin() {
            Some(o) => (o, packed.indices.len() as u32 / 3),
            None => (glam::Vec3::ZERO, 0),
        };
        let view: [u32; 4] = [
            origin.x.to_bits(),
            origin.y.to_bits(),
            origin.z.to_bits(),
            triangles,
        ];
        let view = uniform(s, "mgr environment view", bytemuck::cast_slice(&view));
        let positions = storage(
            s,
            "mgr positions",
            bytemuck::cast_slice(&packed.positions),
            16,
        );
        let normals = storage(s, "mgr normals", bytemuck::cast_slice(&packed.normals), 16);
        let table = storage(
            s,
            "mgr object table",
            bytemuck::cast_slice(&packed.objects),
            80,
        );
        let index = index_buffer(s, &packed.indices);
        let bytes = w as u64 * h as u64 * 16;
        let out = s.buffer(
            "mgr environment",
            bytes,
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        );
        let g0 = bind_entries(
            s,
            l,
            &[
                (0, positions.as_entire_binding()),
                (1, normals.as_entire_binding()),
                (2, table.as_entire_binding()),
                (3, index.as_entire_binding()),
                (5, out.as_entire_binding()),
                (6, view.as_entire_binding()),
            ],
        );
        let mut enc = s.device.create_command_encoder(&Default::default());
        {
            let mut cp = enc.begin_compute_pass(&Default::default());
            cp.set_pipeline(p);
            cp.set_bind_group(0, &g0, &[]);
            cp.set_bind_group(1, &g1, &[]);
            cp.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        let st = staging(s, bytes);
        enc.copy_buffer_to_buffer(&out, 0, &st, 0, bytes);
        submit_and_wait(s, enc)?;
        let data = read_back(s, st, bytes)?;
        Ok(data
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect())
    })
}
