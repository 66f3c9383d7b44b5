//! An app's own wgpu pipeline drawing a matgraph material, through `matgraph::material`
//! alone: a device of its own at WebGPU's default limits, a mesh built here (a plane or a UV
//! sphere), the contract's bind group layout, vertex layout and blend, the parameter block,
//! the lights buffer and the textures, rendered offscreen and written as a PNG.
//!
//! Run: `cargo run --release --example wgpu_app -- [GRAPH] [-o OUT.png] [--size WxH]
//! [--mesh plane|sphere] [--textures hardware|exact] [--time T] [--set NAME=FLOAT]`
//! (default `graphs/skin.json`, `wgpu_app.png`, 256x256, sphere, hardware). There is no
//! `--window`: winit is not a dependency of matgraph, and the offscreen target is what a
//! window's surface texture would be (same pipeline, format aside).
//!
//! `scene:` textures are the app's to render; this example fills them with procedural images
//! ([`scene_textures`]): a sky gradient for `scene:environment`, a checker elsewhere.

use glam::{Mat4, Vec3};
use matgraph::material::{Frame, GpuTextures, Light, Material, MaterialOptions, lights_bytes};
use matgraph::texture::{Image, Texture, TextureSet};
use matgraph::wgsl::TextureMode;
use std::error::Error;

/// An interleaved mesh: per vertex position, normal, uv (the contract's 32-byte layout).
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// `[px, py, pz, nx, ny, nz, u, v]` per vertex.
    pub vertices: Vec<[f32; 8]>,
    /// Triangle list.
    pub indices: Vec<u32>,
}

/// Per-vertex tangents `[tx, ty, tz, bitangent_sign]` of `m` for the contract's tangent
/// buffer (slot 1, read where `Material::uses_tangents`): the direction in which u grows,
/// accumulated over the vertex's triangles (Lengyel 2001, "Computing Tangent Space Basis
/// Vectors for an Arbitrary Mesh"), made orthogonal to the normal, and the sign with which
/// `N × T` points where v grows. An app with MikkTSpace tangents from its baker binds those.
pub fn tangents(m: &MeshData) -> Vec<[f32; 4]> {
    use glam::{Vec2, Vec3};
    let n = m.vertices.len();
    let (mut t, mut b) = (vec![Vec3::ZERO; n], vec![Vec3::ZERO; n]);
    let p = |i: usize| Vec3::from_slice(&m.vertices[i][0..3]);
    let uv = |i: usize| Vec2::from_slice(&m.vertices[i][6..8]);
    for tri in m.indices.chunks_exact(3) {
        let [a, c, d] = [tri[0], tri[1], tri[2]].map(|i| i as usize);
        let (e1, e2) = (p(c) - p(a), p(d) - p(a));
        let (w1, w2) = (uv(c) - uv(a), uv(d) - uv(a));
        let det = w1.x * w2.y - w2.x * w1.y;
        if det.abs() < 1e-20 {
            continue;
        }
        let r = 1.0 / det;
        let (dt, db) = ((e1 * w2.y - e2 * w1.y) * r, (e2 * w1.x - e1 * w2.x) * r);
        for k in [a, c, d] {
            t[k] += dt;
            b[k] += db;
        }
    }
    (0..n)
        .map(|i| {
            let nrm = Vec3::from_slice(&m.vertices[i][3..6]);
            let tt = (t[i] - nrm * nrm.dot(t[i])).normalize_or(nrm.any_orthonormal_vector());
            let sign = if nrm.cross(tt).dot(b[i]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            [tt.x, tt.y, tt.z, sign]
        })
        .collect()
}

/// A square in the xz plane (y = 0, normal +y), `size` metres a side centred on the origin,
/// `n × n` quads; uv (0, 0) at (−size/2, −size/2), u along +x, v along +z.
pub fn plane(n: u32, size: f32) -> MeshData {
    let mut m = MeshData::default();
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            m.vertices
                .push([(u - 0.5) * size, 0.0, (v - 0.5) * size, 0.0, 1.0, 0.0, u, v]);
        }
    }
    quads(&mut m, n, n);
    m
}

/// A UV sphere of radius `r` at the origin: `segments` around y, `rings` from pole to pole;
/// u = longitude / 2π, v = colatitude / π (v = 0 at the top).
pub fn sphere(segments: u32, rings: u32, r: f32) -> MeshData {
    let mut m = MeshData::default();
    for j in 0..=rings {
        for i in 0..=segments {
            let (u, v) = (i as f32 / segments as f32, j as f32 / rings as f32);
            let (theta, phi) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
            let n = [
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ];
            m.vertices
                .push([r * n[0], r * n[1], r * n[2], n[0], n[1], n[2], u, v]);
        }
    }
    quads(&mut m, segments, rings);
    m
}

fn quads(m: &mut MeshData, nx: u32, ny: u32) {
    let row = nx + 1;
    for j in 0..ny {
        for i in 0..nx {
            let a = j * row + i;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            m.indices.extend([a, c, b, b, c, d]);
        }
    }
}

/// The camera, lights and target of one picture.
#[derive(Clone, Debug)]
pub struct Setup {
    /// Target width and height in pixels.
    pub size: (u32, u32),
    /// Eye position (m).
    pub eye: Vec3,
    /// Point looked at.
    pub target: Vec3,
    /// Vertical field of view (radians).
    pub fov_y: f32,
    /// The lights.
    pub lights: Vec<Light>,
    /// Linear premultiplied RGBA the target is cleared to, behind the material (alpha blends
    /// over it). A clear alpha of 0 leaves the material's coverage in the picture's alpha.
    pub background: [f32; 4],
    /// Cull back faces (a closed mesh, or a surface seen from its front only), over the
    /// contract's `pipeline` (which culls nothing: a transparent material shows its nearest
    /// surface alone through the depth pre-pass, as the CPU renderer does).
    pub cull_back_faces: bool,
    /// Time in seconds.
    pub time: f32,
    /// Parameters to set, by name.
    pub parameters: Vec<(String, f32)>,
}

impl Default for Setup {
    fn default() -> Self {
        Setup {
            size: (256, 256),
            eye: Vec3::new(0.0, 0.6, 3.0),
            target: Vec3::ZERO,
            fov_y: 40f32.to_radians(),
            lights: vec![
                Light::Directional {
                    direction: [0.5, 0.8, 0.6],
                    radiance: [1.0, 0.95, 0.9],
                },
                Light::Point {
                    position: [-2.0, 1.5, 2.0],
                    radiance: [2.0, 2.4, 3.0],
                },
            ],
            background: [0.05, 0.06, 0.08, 1.0],
            cull_back_faces: false,
            time: 0.0,
            parameters: Vec::new(),
        }
    }
}

impl Setup {
    /// World → clip (wgpu's depth range [0, 1]).
    pub fn view_proj(&self) -> Mat4 {
        let aspect = self.size.0 as f32 / self.size.1 as f32;
        Mat4::perspective_rh(self.fov_y, aspect, 0.05, 100.0)
            * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }
}

/// Procedural stand-ins for the `scene:` textures the material samples.
pub fn scene_textures(material: &Material, set: &mut TextureSet) -> Result<(), Box<dyn Error>> {
    for t in material.textures() {
        if set.index_of(&t.name).is_some() || t.source != matgraph::material::TextureSource::Scene {
            continue;
        }
        let image = if t.name == "scene:environment" {
            // Equirectangular, zenith on the top row: blue sky to a warm horizon, grey ground.
            Image::from_fn(128, 64, |_, y| {
                let v = (y as f32 + 0.5) / 64.0;
                if v < 0.5 {
                    let s = v / 0.5;
                    [0.2 + 0.8 * s, 0.4 + 0.5 * s, 1.0 - 0.3 * s, 1.0]
                } else {
                    [0.3, 0.28, 0.25, 1.0]
                }
            })
        } else {
            Image::from_fn(128, 128, |x, y| {
                let c = if ((x / 16) + (y / 16)) % 2 == 0 {
                    0.8
                } else {
                    0.1
                };
                [c, c * 0.9, c * 0.7, 1.0]
            })
        };
        set.insert(t.name.clone(), Texture::new(image, true)?)?;
    }
    Ok(())
}

/// A linear RGBA image read back from the target.
pub struct Picture {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Linear RGBA per pixel, rows from the top.
    pub pixels: Vec<[f32; 4]>,
}

/// Opens a device of our own at WebGPU's default limits.
pub fn device() -> Result<(wgpu::Device, wgpu::Queue, String), Box<dyn Error>> {
    let instance =
        wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: None,
        apply_limit_buckets: false,
    }))?;
    let info = adapter.get_info();
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
        label: Some("wgpu_app"),
        required_features: wgpu::Features::empty(),
        required_limits: wgpu::Limits::default(),
        ..Default::default()
    }))?;
    Ok((device, queue, format!("{} ({:?})", info.name, info.backend)))
}

/// Renders `mesh` with `material` and reads the linear colour back.
pub fn render(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    material: &Material,
    textures: &TextureSet,
    mesh: &MeshData,
    setup: &Setup,
) -> Result<Picture, Box<dyn Error>> {
    use wgpu::util::DeviceExt;
    let (width, height) = setup.size;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(material.graph_name()),
        source: wgpu::ShaderSource::Wgsl(material.wgsl().into()),
    });
    let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("material"),
        entries: &material.bind_group_layout_entries(),
    });
    let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("material"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    const COLOR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
    const DEPTH: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
    // How to draw the mesh (the contract's `pipeline`, docs/integration.md "Drawing the
    // mesh"): no culling; for a graph with alpha, its depth first (mg_vertex alone), then the
    // colour pass over that depth, so only the nearest surface blends.
    let draw = material.pipeline();
    let vertex_buffers: Vec<_> = material
        .vertex_buffer_layouts()
        .into_iter()
        .map(Some)
        .collect();
    let primitive = wgpu::PrimitiveState {
        cull_mode: if setup.cull_back_faces {
            Some(wgpu::Face::Back)
        } else {
            draw.wgpu_cull_mode()
        },
        ..Default::default()
    };
    let targets = [Some(wgpu::ColorTargetState {
        format: COLOR,
        blend: Some(Material::blend_state()),
        write_mask: wgpu::ColorWrites::ALL,
    })];
    let make = |fragment: bool, compare, write| {
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(if fragment {
                "material"
            } else {
                "material depth"
            }),
            layout: Some(&pipeline_layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("mg_vertex"),
                compilation_options: Default::default(),
                buffers: &vertex_buffers,
            },
            primitive,
            depth_stencil: Some(wgpu::DepthStencilState {
                format: DEPTH,
                depth_write_enabled: Some(write),
                depth_compare: Some(compare),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: fragment.then(|| wgpu::FragmentState {
                module: &module,
                entry_point: Some("mg_fragment"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    };
    let prepass = draw
        .depth_prepass
        .then(|| make(false, wgpu::CompareFunction::Less, true));
    let pipeline = make(true, draw.wgpu_depth_compare(), draw.depth_write);

    let mut params = material.params();
    for (name, value) in &setup.parameters {
        params.set(name, *value)?;
    }
    params.set_time(setup.time);
    let uniform = |label: &str, bytes: &[u8], usage: wgpu::BufferUsages| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage,
        })
    };
    let params_buf = uniform("params", &params.bytes(), wgpu::BufferUsages::UNIFORM);
    let frame = Frame {
        view_proj: setup.view_proj(),
        model: Mat4::IDENTITY,
        camera_position: setup.eye,
        viewport: [width as f32, height as f32],
    };
    let frame_buf = uniform(
        "frame",
        &frame.bytes(setup.lights.len() as u32),
        wgpu::BufferUsages::UNIFORM,
    );
    let lights_buf = uniform(
        "lights",
        &lights_bytes(&setup.lights),
        wgpu::BufferUsages::STORAGE,
    );
    let gpu_textures: GpuTextures = material.upload_textures(device, queue, textures)?;
    let bind_group = material.bind_group(
        device,
        &layout,
        &params_buf,
        &frame_buf,
        &lights_buf,
        &gpu_textures,
    );
    let vertices = uniform(
        "vertices",
        bytemuck::cast_slice(&mesh.vertices),
        wgpu::BufferUsages::VERTEX,
    );
    // The tangent buffer, for materials that read the tangent frame.
    let tangents = material.uses_tangents().then(|| {
        uniform(
            "tangents",
            bytemuck::cast_slice(&tangents(mesh)),
            wgpu::BufferUsages::VERTEX,
        )
    });
    let indices = uniform(
        "indices",
        bytemuck::cast_slice(&mesh.indices),
        wgpu::BufferUsages::INDEX,
    );

    let size = wgpu::Extent3d {
        width,
        height,
        depth_or_array_layers: 1,
    };
    let target = |format, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: None,
            size,
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let color = target(
        COLOR,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let depth = target(DEPTH, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let color_view = color.create_view(&Default::default());
    let depth_view = depth.create_view(&Default::default());
    let row = (width * 8).next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("readback"),
        size: (row * height) as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    // The depth pre-pass (depth only: a pass without colour attachments), then the colour
    // pass over its depth.
    let passes = prepass
        .iter()
        .map(|p| (p, false))
        .chain([(&pipeline, true)]);
    for (k, (p, colour)) in passes.enumerate() {
        let [r, g, b, a] = setup.background;
        let attachments = [Some(wgpu::RenderPassColorAttachment {
            view: &color_view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations {
                load: wgpu::LoadOp::Clear(wgpu::Color {
                    r: r as f64,
                    g: g as f64,
                    b: b as f64,
                    a: a as f64,
                }),
                store: wgpu::StoreOp::Store,
            },
        })];
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some(if colour { "material" } else { "material depth" }),
            color_attachments: if colour { &attachments } else { &[] },
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: if k == 0 {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(p);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.set_vertex_buffer(0, vertices.slice(..));
        if let Some(t) = &tangents {
            pass.set_vertex_buffer(1, t.slice(..));
        }
        pass.set_index_buffer(indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..mesh.indices.len() as u32, 0, 0..1);
    }
    encoder.copy_texture_to_buffer(
        color.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &readback,
            layout: wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(row),
                rows_per_image: Some(height),
            },
        },
        size,
    );
    queue.submit([encoder.finish()]);
    let slice = readback.slice(..);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    device.poll(wgpu::PollType::wait_indefinitely())?;
    rx.recv()??;
    let data = slice.get_mapped_range()?;
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        let line = &data[(y * row) as usize..(y * row + width * 8) as usize];
        for px in line.chunks_exact(8) {
            let h = |k: usize| half::f16::from_le_bytes([px[2 * k], px[2 * k + 1]]).to_f32();
            pixels.push([h(0), h(1), h(2), h(3)]);
        }
    }
    Ok(Picture {
        width,
        height,
        pixels,
    })
}

/// Command-line options.
struct Args {
    graph: std::path::PathBuf,
    out: std::path::PathBuf,
    mesh: String,
    setup: Setup,
    textures: TextureMode,
}

fn args() -> Result<Args, Box<dyn Error>> {
    let mut a = Args {
        graph: concat!(env!("CARGO_MANIFEST_DIR"), "/graphs/skin.json").into(),
        out: "wgpu_app.png".into(),
        mesh: "sphere".into(),
        setup: Setup::default(),
        textures: TextureMode::Hardware,
    };
    let mut it = std::env::args().skip(1);
    while let Some(arg) = it.next() {
        let mut value = || it.next().ok_or_else(|| format!("{arg} needs a value"));
        match arg.as_str() {
            "-o" | "--out" => a.out = value()?.into(),
            "--mesh" => a.mesh = value()?,
            "--time" => a.setup.time = value()?.parse()?,
            "--size" => {
                let v = value()?;
                let (w, h) = v.split_once('x').ok_or("--size takes WxH")?;
                a.setup.size = (w.parse()?, h.parse()?);
            }
            "--textures" => {
                let v = value()?;
                a.textures = TextureMode::from_name(&v).ok_or("--textures hardware|exact")?;
            }
            "--set" => {
                let v = value()?;
                let (n, x) = v.split_once('=').ok_or("--set NAME=FLOAT")?;
                a.setup.parameters.push((n.to_owned(), x.parse()?));
            }
            "--window" => {
                return Err("--window: winit is not a dependency; render offscreen".into());
            }
            s if !s.starts_with('-') => a.graph = s.into(),
            s => return Err(format!("unknown option {s}").into()),
        }
    }
    Ok(a)
}

fn main() -> Result<(), Box<dyn Error>> {
    let a = args()?;
    let options = MaterialOptions {
        textures: a.textures,
        ..MaterialOptions::default()
    };
    let (material, mut textures) = Material::from_path(&a.graph, &options)?;
    scene_textures(&material, &mut textures)?;
    let mesh = match a.mesh.as_str() {
        "plane" => plane(128, 3.0),
        _ => sphere(96, 48, 1.0),
    };
    let (device, queue, adapter) = device()?;
    println!("adapter: {adapter}");
    let picture = render(&device, &queue, &material, &textures, &mesh, &a.setup)?;
    let image = Image::new(picture.width, picture.height, picture.pixels)?;
    matgraph::image_io::save_png(&a.out, &image)?;
    println!(
        "{}: {}×{} {} mesh, {} textures → {}",
        material.graph_name(),
        picture.width,
        picture.height,
        a.mesh,
        a.textures.name(),
        a.out.display()
    );
    Ok(())
}
