// The `scene:environment` map: src/scene/envmap.rs Scene::environment_map, texel centres
// mapped to directions by the inverse of scene::equirect_uv (equirect_direction); from the
// ball's centre each ray is cast against the built-in triangles (ray_triangle, nearest_hit)
// and the hit shaded by mgr_surface, the environment (mgr_sky) where nothing is hit. Needs
// scene.wgsl and objects.wgsl (its group-0 bindings 0 to 3).

// Where the rays start and how many built-in triangles they are cast against (0: the sky
// alone).
struct MgrEnvView {
    origin: vec3<f32>,
    triangles: u32,
}

@group(0) @binding(5) var<storage, read_write> mgr_texels: array<vec4<f32>>;
@group(0) @binding(6) var<uniform> mgr_env_view: MgrEnvView;

// envmap.rs ray_triangle: (t, b1, b2) with t > MIN_HIT, or t = -1 for no hit.
fn mgr_ray_triangle(o: vec3<f32>, d: vec3<f32>, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>) -> vec3<f32> {
    let miss = vec3<f32>(-1.0, 0.0, 0.0);
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if (abs(det) < 1e-12) {
        return miss;
    }
    let inv = 1.0 / det;
    let tv = o - p0;
    let u = dot(tv, pv) * inv;
    if (!(u >= 0.0 && u <= 1.0)) {
        return miss;
    }
    let qv = cross(tv, e1);
    let v = dot(d, qv) * inv;
    if (v < 0.0 || u + v > 1.0) {
        return miss;
    }
    let t = dot(e2, qv) * inv;
    if (!(t > 1e-4)) {
        return miss;
    }
    return vec3<f32>(t, u, v);
}

@compute @workgroup_size(8, 8)
fn mgr_environment(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = u32(mgr_frame.width);
    let h = u32(mgr_frame.height);
    if (id.x >= w || id.y >= h) {
        return;
    }
    let tau = 6.2831855;
    let pi = 3.1415927;
    let phi = ((f32(id.x) + 0.5) / f32(w) - 0.5) * tau;
    let theta = (f32(id.y) + 0.5) / f32(h) * pi;
    let d = vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    let o = mgr_env_view.origin;
    var t_best = 3.4028235e38;
    var best = 0xffffffffu;
    var bc = vec2<f32>(0.0);
    for (var t = 0u; t < mgr_env_view.triangles; t++) {
        let p0 = mgr_positions[mgr_indices[3u * t]].xyz;
        let p1 = mgr_positions[mgr_indices[3u * t + 1u]].xyz;
        let p2 = mgr_positions[mgr_indices[3u * t + 2u]].xyz;
        let hit = mgr_ray_triangle(o, d, p0, p1, p2);
        if (hit.x > 0.0 && hit.x < t_best) {
            t_best = hit.x;
            best = t;
            bc = hit.yz;
        }
    }
    var c = vec3<f32>(0.0);
    if (best == 0xffffffffu) {
        c = mgr_sky(d, true);
    } else {
        // position_normal at the hit's barycentrics, then Shading::surface seen from o.
        let i0 = mgr_indices[3u * best];
        let i1 = mgr_indices[3u * best + 1u];
        let i2 = mgr_indices[3u * best + 2u];
        let b0 = 1.0 - bc.x - bc.y;
        let p = mgr_positions[i0].xyz * b0 + mgr_positions[i1].xyz * bc.x + mgr_positions[i2].xyz * bc.y;
        let n0 = mgr_normals[i0].xyz;
        var n = n0 * b0 + mgr_normals[i1].xyz * bc.x + mgr_normals[i2].xyz * bc.y;
        let len2 = dot(n, n);
        if (len2 > 0.0) {
            n = n * inverseSqrt(len2);
        } else {
            n = n0;
        }
        let object = bitcast<u32>(mgr_normals[i0].w);
        c = mgr_surface(mgr_objects[object], p, n, o);
    }
    mgr_texels[id.y * w + id.x] = vec4<f32>(c, 1.0);
}
