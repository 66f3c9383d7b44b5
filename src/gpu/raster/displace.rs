//! Displacement: the material mesh's vertices uploaded in the contract's layout, displaced
//! by the library module's `mg_material` in a compute pass and their welded normals rebuilt
//! (`normals.wgsl`).

use super::*;

/// The contract's interleaved vertex buffer of `mesh` (position, normal, uv), undisplaced.
pub(super) fn vertex_bytes(mesh: &Mesh) -> Vec<[f32; 8]> {
    (0..mesh.positions.len())
        .map(|i| {
            let (p, n, uv) = (mesh.positions[i], mesh.normals[i], mesh.uvs[i]);
            [p.x, p.y, p.z, n.x, n.y, n.z, uv.x, uv.y]
        })
        .collect()
}

/// `material`'s textures from `set`, uploaded for its render module (or with `library` its
/// library module), reused while the material (`owner`, the cached value holding it) and
/// every texture it binds are the same ([`DeviceState::uploads`], or [`DeviceState::small_uploads`]
/// where every texture is small): a frame that changes only
/// parameters, time or camera uploads no texel. Measured on lavapipe at 1024²:
/// `bubble_iridescent`'s `scene:background` with its mips, 27 ms a frame before.
pub(super) fn uploaded(
    s: &DeviceState,
    owner: &Arc<dyn std::any::Any + Send + Sync>,
    material: &Material,
    library: bool,
    set: &TextureSet,
) -> Result<Arc<GpuTextures>, EvalError> {
    let library_infos;
    let infos = match library {
        true => {
            library_infos = material.library_textures();
            &library_infos
        }
        false => material.textures(),
    };
    let key = UploadKey {
        material: owner.clone(),
        library,
        textures: infos
            .iter()
            .map(|t| Same(set.index_of(&t.name).and_then(|i| set.shared(i)).cloned()))
            .collect(),
    };
    let small = infos.iter().all(|t| {
        set.index_of(&t.name)
            .and_then(|i| set.get(i))
            .is_some_and(|t| t.width() as u64 * t.height() as u64 <= SMALL_UPLOAD_TEXELS)
    });
    let make = || {
        match library {
            true => material.upload_library_textures(&s.device, &s.queue, set),
            false => material.upload_textures(&s.device, &s.queue, set),
        }
        .map(Arc::new)
        .map_err(material_err)
    };
    match small {
        true => s.small_uploads.get_or_make(key, make),
        false => s.uploads.get_or_make(key, make),
    }
}

/// The displacement and normal passes: the library module's `displacement` at every
/// vertex, then the welded normals, into a new vertex buffer of the contract's layout;
/// `owner` holds `material` ([`uploaded`]).
pub(super) fn displace(
    ctx: &GpuContext,
    enc: &mut wgpu::CommandEncoder,
    (owner, material): (&Arc<dyn std::any::Any + Send + Sync>, &Material),
    m: &MaterialInput,
    buffers: &MeshBuffers,
) -> Result<wgpu::Buffer, EvalError> {
    let s = &*ctx.state;
    let mesh = m.mesh;
    let n = mesh.positions.len() as u32;
    let library = material.library_module();
    let name = material
        .roles()
        .displacement
        .map(|k| material.render_module().outputs[k].name.clone())
        .unwrap_or_default();
    let field = library
        .outputs
        .iter()
        .find(|o| o.name == name)
        .map(|o| o.field.clone())
        .ok_or_else(|| {
            EvalError::Gpu(format!("output '{name}' missing from the library module"))
        })?;
    let src = material::displacement_source(material.library_wgsl(), &library.attributes, &field);
    let c = wgpu::ShaderStages::COMPUTE;
    let pipes = cached(s, &format!("displace/{src}"), || {
        let mut entries = material.library_bind_group_layout_entries();
        for e in &mut entries {
            e.visibility = c;
        }
        let dl = s
            .device
            .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("mgr displacement"),
                entries: &entries,
            });
        let vl = layout(
            s,
            "mgr displace io",
            &[
                (0, c, Kind::Storage),
                (1, c, Kind::StorageRw),
                (2, c, Kind::Uniform),
            ],
        );
        let dm = module(s, "mgr displacement", &src);
        let dp = compute_pipeline(
            s,
            "mgr displacement",
            &dm,
            "mgr_displace",
            &pipeline_layout(s, &[&dl, &vl]),
        );
        let nl = layout(
            s,
            "mgr normals",
            &[
                (0, c, Kind::Storage),
                (1, c, Kind::Storage),
                (2, c, Kind::Storage),
                (3, c, Kind::Storage),
                (4, c, Kind::Storage),
                (5, c, Kind::Storage),
                (6, c, Kind::StorageRw),
                (7, c, Kind::Uniform),
            ],
        );
        let nm = module(s, "mgr normals", include_str!("normals.wgsl"));
        let np = compute_pipeline(
            s,
            "mgr normals",
            &nm,
            "mgr_smooth_normals",
            &pipeline_layout(s, &[&nl]),
        );
        (dl, vl, dp, nl, np)
    });
    let (dl, vl, dp, nl, np) = (&pipes.0, &pipes.1, &pipes.2, &pipes.3, &pipes.4);
    let mut params = material.library_params();
    params.set_values(m.params);
    params.set_time(m.time);
    let params_buf = uniform(s, "mgr displacement params", &params.bytes());
    let textures = uploaded(s, owner, material, true, m.textures)?;
    let dg = material.library_bind_group(&s.device, dl, &params_buf, &textures);
    let inputs = buffers.displacement(s, mesh);
    let vin = &inputs.vertices;
    let displaced = s.buffer(
        "mgr displaced",
        n.max(1) as u64 * 16,
        wgpu::BufferUsages::STORAGE,
    );
    let max_x = ctx.limits().max_compute_workgroups_per_dimension;
    let (gx, gy, row) = dispatch_shape(n, max_x);
    let count = uniform(s, "mgr count", bytemuck::cast_slice(&[n, row, 0, 0]));
    let vg = bind(
        s,
        vl,
        &[
            vin.as_entire_binding(),
            displaced.as_entire_binding(),
            count.as_entire_binding(),
        ],
    );
    let [g_buf, s_buf, t_buf] = &inputs.adjacency;
    let out = s.buffer(
        "mgr displaced vertices",
        n.max(1) as u64 * VERTEX_STRIDE,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX,
    );
    let ng = bind(
        s,
        nl,
        &[
            displaced.as_entire_binding(),
            vin.as_entire_binding(),
            buffers.index.as_entire_binding(),
            g_buf.as_entire_binding(),
            s_buf.as_entire_binding(),
            t_buf.as_entire_binding(),
            out.as_entire_binding(),
            count.as_entire_binding(),
        ],
    );
    if n > 0 {
        let mut cp = enc.begin_compute_pass(&Default::default());
        cp.set_pipeline(dp);
        cp.set_bind_group(0, &dg, &[]);
        cp.set_bind_group(1, &vg, &[]);
        cp.dispatch_workgroups(gx, gy, 1);
        cp.set_pipeline(np);
        cp.set_bind_group(0, &ng, &[]);
        cp.dispatch_workgroups(gx, gy, 1);
    }
    Ok(out)
}
