// Smooth normals of the displaced material mesh, as src/scene/mesh.rs smooth_normals:
// per vertex, the sum of the face normals (unnormalised cross products) of the triangles
// around its weld group, in the CPU's order, normalised; the undisplaced normal where they
// cancel. Written with the positions and uvs as the contract's interleaved vertex buffer
// (position, normal, uv: 8 floats per vertex), which mg_vertex reads.

@group(0) @binding(0) var<storage, read> mgr_displaced: array<vec4<f32>>;
// Per vertex, undisplaced: (position, u) and (normal, v).
@group(0) @binding(1) var<storage, read> mgr_base: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> mgr_indices: array<u32>;
@group(0) @binding(3) var<storage, read> mgr_groups: array<u32>;
@group(0) @binding(4) var<storage, read> mgr_starts: array<u32>;
@group(0) @binding(5) var<storage, read> mgr_triangles: array<u32>;
@group(0) @binding(6) var<storage, read_write> mgr_out: array<f32>;
// Vertices, invocations per dispatch row.
@group(0) @binding(7) var<uniform> mgr_count: vec4<u32>;

@compute @workgroup_size(64)
fn mgr_smooth_normals(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x + id.y * mgr_count.y;
    if (i >= mgr_count.x) {
        return;
    }
    let g = mgr_groups[i];
    var sum = vec3<f32>(0.0);
    for (var k = mgr_starts[g]; k < mgr_starts[g + 1u]; k++) {
        let t = mgr_triangles[k];
        let a = mgr_displaced[mgr_indices[3u * t]].xyz;
        let b = mgr_displaced[mgr_indices[3u * t + 1u]].xyz;
        let c = mgr_displaced[mgr_indices[3u * t + 2u]].xyz;
        sum += cross(b - a, c - a);
    }
    let len = length(sum);
    let a = mgr_base[2u * i];
    let b = mgr_base[2u * i + 1u];
    var n = b.xyz;
    if (len > 0.0 && (bitcast<u32>(len) & 0x7f800000u) != 0x7f800000u) {
        n = sum / len;
    }
    let p = mgr_displaced[i].xyz;
    let o = 8u * i;
    mgr_out[o] = p.x;
    mgr_out[o + 1u] = p.y;
    mgr_out[o + 2u] = p.z;
    mgr_out[o + 3u] = n.x;
    mgr_out[o + 4u] = n.y;
    mgr_out[o + 5u] = n.z;
    mgr_out[o + 6u] = a.w;
    mgr_out[o + 7u] = b.w;
}
