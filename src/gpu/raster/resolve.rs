//! The resolve stage: the composite `alpha · radiance + (1 − alpha) · background` per
//! sample, averaged in the CPU's sample order (`resolve.wgsl`), for one pass or summed over
//! jittered passes.

use super::*;

/// Which samples one resolve dispatch takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Samples {
    /// Every sample of one pass (multisampled when `spp` > 1), averaged into `out`.
    Whole,
    /// Jittered pass `k` of `spp` (one sample per pixel): added to the sum in `out` (pass 0
    /// stores it), the sum divided by `spp` after the last pass.
    Pass(u32),
}

/// The resolve: composite the samples of `scene` and `material` that `samples` names into
/// `out`, linear RGB (`w × h × 3` floats), in the CPU's sample order.
pub(super) fn resolve(
    s: &DeviceState,
    enc: &mut wgpu::CommandEncoder,
    (scene, material): (&wgpu::TextureView, &wgpu::TextureView),
    out: &wgpu::Buffer,
    (w, h, spp): (u32, u32, u32),
    samples: Samples,
) {
    let (key, entry, ms) = match samples {
        Samples::Whole => (format!("resolve/{}", spp > 1), "mgr_resolve_main", spp > 1),
        Samples::Pass(_) => ("accumulate".to_owned(), "mgr_accumulate_main", false),
    };
    let pipes = cached(s, &key, || {
        let texture = match ms {
            true => "texture_multisampled_2d<f32>",
            false => "texture_2d<f32>",
        };
        let source = include_str!("resolve.wgsl").replace("MGR_TEXTURE", texture);
        let m = module(s, "mgr resolve", &source);
        let c = wgpu::ShaderStages::COMPUTE;
        let l = layout(
            s,
            "mgr resolve",
            &[
                (0, c, Kind::Texture { multisampled: ms }),
                (1, c, Kind::Texture { multisampled: ms }),
                (2, c, Kind::StorageRw),
                (3, c, Kind::Uniform),
            ],
        );
        let p = compute_pipeline(s, "mgr resolve", &m, entry, &pipeline_layout(s, &[&l]));
        (l, p)
    });
    let (l, p) = (&pipes.0, &pipes.1);
    let mut words = match samples {
        Samples::Whole => {
            let order =
                crate::scene::standard_sample_order(spp).unwrap_or_else(|| (0..spp).collect());
            [vec![w, h, spp, 0], order].concat()
        }
        Samples::Pass(k) => vec![w, h, spp, k],
    };
    words.resize(20, 0);
    let u = uniform(s, "mgr resolve", bytemuck::cast_slice(&words));
    let g = bind(
        s,
        l,
        &[
            wgpu::BindingResource::TextureView(scene),
            wgpu::BindingResource::TextureView(material),
            out.as_entire_binding(),
            u.as_entire_binding(),
        ],
    );
    let mut cp = enc.begin_compute_pass(&Default::default());
    cp.set_pipeline(p);
    cp.set_bind_group(0, &g, &[]);
    cp.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
}
