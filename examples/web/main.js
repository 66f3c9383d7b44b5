// matgraph's WebGPU example: binds a graph's render module from its contract JSON alone
// (docs/integration.md) and draws the scene view `matgraph bake-env --view` wrote. Plain
// JavaScript, no build step, no dependency. See index.html for the query string.

const out = document.getElementById('result');
const status = document.getElementById('status');

/** Reports `value` (a result or an error) where a test reads it. */
function report(value) {
  out.textContent = JSON.stringify(value);
  status.textContent = value.status === 'ok' ? `drawn on ${value.adapter}` : `error: ${value.message}`;
}

const query = new URLSearchParams(location.search);
const dir = new URL(query.get('dir') ?? './', location.href);
const graph = query.get('graph');
const texturesBase = new URL(query.get('textures') ?? query.get('dir') ?? './', location.href);

async function fetchOk(url) {
  const r = await fetch(url);
  if (!r.ok) throw new Error(`${url}: ${r.status} ${r.statusText}`);
  return r;
}
const json = async (url) => (await fetchOk(url)).json();
const text = async (url) => (await fetchOk(url)).text();
const bytes = async (url) => (await fetchOk(url)).arrayBuffer();

// --- Numbers -------------------------------------------------------------------------

const f32Scratch = new Float32Array(1);
const u32Scratch = new Uint32Array(f32Scratch.buffer);

/** IEEE 754 binary16 bits of `x`, rounded to nearest even (what the manifest asks). */
function toHalf(x) {
  f32Scratch[0] = x;
  const b = u32Scratch[0];
  const sign = (b >>> 16) & 0x8000;
  const exp = (b >>> 23) & 0xff;
  let mant = b & 0x7fffff;
  if (exp === 0xff) return sign | 0x7c00 | (mant ? 0x200 : 0);
  const e = exp - 127 + 15;
  if (e >= 0x1f) return sign | 0x7c00;
  if (e <= 0) {
    if (e < -10) return sign;
    mant |= 0x800000;
    const shift = 14 - e;
    let h = mant >>> shift;
    const rest = mant & ((1 << shift) - 1);
    const half = 1 << (shift - 1);
    if (rest > half || (rest === half && (h & 1))) h++;
    return sign | h;
  }
  let h = (e << 10) | (mant >>> 13);
  const rest = mant & 0x1fff;
  if (rest > 0x1000 || (rest === 0x1000 && (h & 1))) h++;
  return sign | h;
}

/** The value of binary16 bits `h`. */
function fromHalf(h) {
  const s = h & 0x8000 ? -1 : 1;
  const e = (h >>> 10) & 0x1f;
  const m = h & 0x3ff;
  if (e === 0) return s * m * 2 ** -24;
  if (e === 31) return m ? NaN : s * Infinity;
  return s * (1 + m / 1024) * 2 ** (e - 15);
}

const srgbToLinear = (s) => (s <= 0.04045 ? s / 12.92 : ((s + 0.055) / 1.055) ** 2.4);
const linearToSrgb = (l) => (l <= 0.0031308 ? 12.92 * l : 1.055 * l ** (1 / 2.4) - 0.055);

// --- Textures ------------------------------------------------------------------------

/**
 * One mip step of RGBA float texels along one axis, the documented exact box filter
 * (docs/integration.md, "Scene textures"; src/texture.rs `downsample`): an even side 2n
 * averages pairs, an odd side 2n + 1 → n averages texels 2i, 2i + 1, 2i + 2 with weights
 * (n − i, n, i + 1) / (2n + 1); a side of 1 stays.
 */
function halve(src, w, h, alongX) {
  const len = alongX ? w : h;
  if (len === 1) return { data: src, w, h };
  const n = Math.floor(len / 2);
  const [ow, oh] = alongX ? [n, h] : [w, n];
  const dst = new Float32Array(ow * oh * 4);
  const at = (x, y) => 4 * (y * w + x);
  for (let y = 0; y < oh; y++) {
    for (let x = 0; x < ow; x++) {
      const i = alongX ? x : y;
      const taps = len % 2 === 0
        ? [[2 * i, 0.5], [2 * i + 1, 0.5]]
        : [[2 * i, (n - i) / len], [2 * i + 1, n / len], [2 * i + 2, (i + 1) / len]];
      for (let c = 0; c < 4; c++) {
        let v = 0;
        for (const [k, wgt] of taps) v += wgt * src[alongX ? at(k, y) + c : at(x, k) + c];
        dst[4 * (y * ow + x) + c] = v;
      }
    }
  }
  return { data: dst, w: ow, h: oh };
}

/** Decoded RGBA8 texels of the image at `url`, as stored (no colour conversion). */
async function decode(url) {
  const blob = await (await fetchOk(url)).blob();
  const bitmap = await createImageBitmap(blob, { colorSpaceConversion: 'none', premultiplyAlpha: 'none' });
  const canvas = new OffscreenCanvas(bitmap.width, bitmap.height);
  const ctx = canvas.getContext('2d');
  ctx.drawImage(bitmap, 0, 0);
  return { data: ctx.getImageData(0, 0, bitmap.width, bitmap.height).data, w: bitmap.width, h: bitmap.height };
}

/** A file texture of the contract: every level the contract says, box filtered in linear light. */
async function fileTexture(device, t) {
  const srgb = t.color_space === 'srgb';
  // The key: the path (or a chain's paths joined by '|'), with '#data', '#linear' or '#srgb'
  // where the node reads the file in another colour space than its type's default.
  const files = t.name.replace(/#(data|linear|srgb)$/, '').split('|');
  const levels = [];
  for (const file of files) {
    const img = await decode(new URL(file, texturesBase));
    const f = new Float32Array(img.w * img.h * 4);
    for (let k = 0; k < f.length; k++) {
      const v = img.data[k] / 255;
      f[k] = srgb && k % 4 !== 3 ? srgbToLinear(v) : v;
    }
    levels.push({ data: f, w: img.w, h: img.h });
  }
  const count = t.mip_levels ?? levels.length;
  while (levels.length < count) {
    const last = levels[levels.length - 1];
    const x = halve(last.data, last.w, last.h, true);
    levels.push(halve(x.data, x.w, x.h, false));
  }
  const texture = device.createTexture({
    size: [levels[0].w, levels[0].h],
    mipLevelCount: levels.length,
    format: t.format,
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
  });
  levels.forEach((l, k) => {
    if (!t.format.startsWith('rgba8unorm')) throw new Error(`${t.name}: format ${t.format} is not an 8-bit image here`);
    const b = new Uint8Array(l.w * l.h * 4);
    for (let i = 0; i < b.length; i++) {
      const v = srgb && i % 4 !== 3 ? linearToSrgb(l.data[i]) : l.data[i];
      b[i] = Math.round(Math.min(Math.max(v, 0), 1) * 255);
    }
    device.queue.writeTexture({ texture, mipLevel: k }, b, { bytesPerRow: l.w * 4 }, [l.w, l.h]);
  });
  return texture;
}

/** A scene texture from `matgraph bake-env`'s manifest: its levels as they are, in rgba16float. */
async function sceneTexture(device, t, manifest) {
  const entry = manifest.textures.find((m) => m.name === t.name);
  if (!entry) throw new Error(`${t.name}: not in manifest.json (bake-env writes ${manifest.textures.map((m) => m.name).join(', ')})`);
  const texture = device.createTexture({
    size: [entry.width, entry.height],
    mipLevelCount: entry.levels.length,
    format: t.format,
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
  });
  for (const [k, level] of entry.levels.entries()) {
    const texels = new Float32Array(await bytes(new URL(level.file, dir)));
    const halves = new Uint16Array(texels.length);
    for (let i = 0; i < texels.length; i++) halves[i] = toHalf(texels[i]);
    device.queue.writeTexture({ texture, mipLevel: k }, halves, { bytesPerRow: level.width * 8 }, [level.width, level.height]);
  }
  return texture;
}

// --- Buffers -------------------------------------------------------------------------

/** Writes `value` (number, bool or array) at `offset` as the WGSL type says. */
function writeMember(view, offset, wgslType, value) {
  const values = Array.isArray(value) ? value.flat() : [value];
  if (wgslType === 'i32') view.setInt32(offset, values[0], true);
  else if (wgslType === 'u32') view.setUint32(offset, values[0] === true ? 1 : values[0] === false ? 0 : values[0], true);
  else values.forEach((v, k) => view.setFloat32(offset + 4 * k, v, true));
}

/** The parameter block: every member's default, the scene's time, then `set` values. */
function parameterBlock(contract, time, sets) {
  const p = contract.parameters;
  const buffer = new ArrayBuffer(Math.max(16, Math.ceil(p.size / 16) * 16));
  const view = new DataView(buffer);
  for (const m of p.members) {
    if (m.source === 'time') writeMember(view, m.offset, m.wgsl_type, time);
    else if (m.default !== undefined) writeMember(view, m.offset, m.wgsl_type, m.default);
  }
  for (const set of sets) {
    const [name, text] = set.split('=');
    const m = p.members.find((x) => x.parameter === name);
    if (!m) throw new Error(`set ${name}: no such parameter (the contract has ${p.members.filter((x) => x.parameter).map((x) => x.parameter).join(', ')})`);
    const lanes = { f32: 1, i32: 1, u32: 1, 'vec2<f32>': 2, 'vec3<f32>': 3, 'vec4<f32>': 4 }[m.wgsl_type];
    let v = text.split(',').map(Number);
    if (v.length === 1) v = Array(lanes).fill(v[0]);
    if (m.hard_range && v.some((x) => x < m.hard_range[0] || x > m.hard_range[1])) {
      console.warn(`${name} = ${text} is outside [${m.hard_range}]: the module clamps it (contract clamp: ${p.clamp})`);
    }
    writeMember(view, m.offset, m.wgsl_type, v);
  }
  return buffer;
}

/** MgFrame: view_proj, model and normal_model (identity), camera, light count, viewport. */
function frameBlock(contract, scene) {
  const buffer = new ArrayBuffer(contract.frame.size);
  const f = new Float32Array(buffer);
  const dv = new DataView(buffer);
  const at = Object.fromEntries(contract.frame.members.map((m) => [m.name, m.offset / 4]));
  f.set(scene.view_proj, at.view_proj);
  const identity = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1];
  f.set(identity, at.model);
  f.set(identity, at.normal_model);
  f.set(scene.camera_position, at.camera_position);
  dv.setUint32(at.light_count * 4, scene.lights.length, true);
  f.set([scene.width, scene.height], at.viewport);
  return buffer;
}

/** The lights buffer: one MgLight record per light (one zero record when there are none). */
function lightsBlock(contract, scene) {
  const l = contract.lights;
  const buffer = new ArrayBuffer(l.stride * Math.max(1, scene.lights.length));
  const dv = new DataView(buffer);
  const at = Object.fromEntries(l.members.map((m) => [m.name, m.offset]));
  scene.lights.forEach((light, k) => {
    const base = k * l.stride;
    light.vector.forEach((x, c) => dv.setFloat32(base + at.vector + 4 * c, x, true));
    dv.setUint32(base + at.kind, light.kind, true);
    light.color.forEach((x, c) => dv.setFloat32(base + at.color + 4 * c, x, true));
  });
  return buffer;
}

function buffer(device, data, usage) {
  const b = device.createBuffer({ size: Math.ceil(data.byteLength / 4) * 4, usage: usage | GPUBufferUsage.COPY_DST });
  device.queue.writeBuffer(b, 0, data);
  return b;
}

// --- Shader modules and group 0 ------------------------------------------------------

/** A shader module of `code`, or an error naming `what` with each compiler error's place. */
async function shaderModule(device, code, what) {
  const module = device.createShaderModule({ code });
  const messages = (await module.getCompilationInfo()).messages.filter((m) => m.type === 'error');
  if (messages.length) throw new Error(`${what}: ${messages.map((m) => `${m.lineNum}:${m.linePos} ${m.message}`).join('; ')}`);
  return module;
}

/** Group 0 of a module from its contract's bindings: the layout and the bind group, with
 * the given buffers by binding name, one sampler per sampler binding and the textures. */
async function groupZero(device, contract, manifest, buffers) {
  const stages = (b) => b.visibility.reduce((s, v) => s | { vertex: GPUShaderStage.VERTEX, fragment: GPUShaderStage.FRAGMENT, compute: GPUShaderStage.COMPUTE }[v], 0);
  const layoutEntry = (b) => {
    const e = { binding: b.binding, visibility: stages(b) };
    if (b.kind === 'uniform-buffer') e.buffer = { type: 'uniform', minBindingSize: b.min_binding_size ?? 0 };
    else if (b.kind === 'read-only-storage-buffer') e.buffer = { type: 'read-only-storage' };
    else if (b.kind === 'storage-buffer') e.buffer = { type: 'storage' };
    else if (b.kind === 'filtering-sampler') e.sampler = { type: 'filtering' };
    else if (b.kind === 'texture-2d-float') e.texture = { sampleType: 'float', viewDimension: '2d' };
    else throw new Error(`binding ${b.binding}: unknown kind ${b.kind}`);
    return e;
  };
  const layout = device.createBindGroupLayout({ entries: contract.bindings.map(layoutEntry) });
  const textures = new Map();
  for (const t of contract.textures) {
    if (t.binding === undefined) continue;
    textures.set(t.binding, t.source === 'scene' ? await sceneTexture(device, t, manifest) : await fileTexture(device, t));
  }
  const resource = (b) => {
    if (buffers[b.name]) return { buffer: buffers[b.name] };
    if (b.kind === 'filtering-sampler') {
      return device.createSampler({
        addressModeU: b.address_mode, addressModeV: b.address_mode, addressModeW: b.address_mode,
        magFilter: b.filter, minFilter: b.filter, mipmapFilter: b.filter,
      });
    }
    if (b.kind === 'texture-2d-float') return textures.get(b.binding).createView();
    throw new Error(`binding ${b.binding} (${b.name}): not in the ${contract.module ?? 'render'} contract`);
  };
  const group = device.createBindGroup({
    layout,
    entries: contract.bindings.map((b) => ({ binding: b.binding, resource: resource(b) })),
  });
  return { layout, group };
}

// --- Displacement on the GPU --------------------------------------------------------------

/**
 * The vertex records of `mesh` displaced in a compute pass and their normals rebuilt from
 * the displaced mesh, for a render module written with `--displaced-vertices`
 * (docs/integration.md, "Options for renderers"): the library module (NAME.lib.wgsl, its
 * contract NAME.lib.contract.json) gives each vertex's offset `mg_material(g).displacement`
 * with `normal`, `uv` (and `position`) set and every other geometry member at its default;
 * the normals are the area-weighted face normals summed over the vertices that share an
 * undisplaced position, as the renderer's.
 */
async function displaceOnGpu(device, mesh, m, scene, manifest) {
  const [lib, libContract] = await Promise.all([
    text(new URL(`${graph}.lib.wgsl`, dir)),
    json(new URL(`${graph}.lib.contract.json`, dir)),
  ]);
  const count = m.vertices;
  const params = buffer(device, parameterBlock(libContract, scene.time, query.getAll('set')), GPUBufferUsage.UNIFORM);
  const zero = await groupZero(device, libContract, manifest, { mg_params: params });
  const literal = (g) => `${g.wgsl_type}(${[g.default].flat().join(', ')})`;
  const member = (g) => ({ position: 'p', normal: 'n', uv: 'uv' })[g.name] ?? literal(g);
  const displacement = libContract.outputs.find((o) => o.name === 'displacement');
  if (!displacement) throw new Error(`${graph}: the library module has no displacement output`);
  const code = `${lib}
@group(1) @binding(0) var<storage, read> mg_mesh_in: array<f32>;
@group(1) @binding(1) var<storage, read_write> mg_moved: array<f32>;
@compute @workgroup_size(64)
fn mg_displace(@builtin(global_invocation_id) id: vec3<u32>) {
  let i = id.x;
  if (i >= arrayLength(&mg_moved) / 4u) { return; }
  let r = 8u * i;
  let p = vec3<f32>(mg_mesh_in[r], mg_mesh_in[r + 1u], mg_mesh_in[r + 2u]);
  let n0 = vec3<f32>(mg_mesh_in[r + 3u], mg_mesh_in[r + 4u], mg_mesh_in[r + 5u]);
  let n = select(vec3<f32>(0.0, 0.0, 1.0), normalize(n0), dot(n0, n0) > 0.0);
  let uv = vec2<f32>(mg_mesh_in[r + 6u], mg_mesh_in[r + 7u]);
  let q = p + ${libContract.function}(MgGeometry(${libContract.geometry.map(member).join(', ')})).${displacement.member};
  mg_moved[4u * i] = q.x;
  mg_moved[4u * i + 1u] = q.y;
  mg_moved[4u * i + 2u] = q.z;
}`;
  const module = await shaderModule(device, code, 'displacement WGSL');
  const ioLayout = device.createBindGroupLayout({
    entries: [
      { binding: 0, visibility: GPUShaderStage.COMPUTE, buffer: { type: 'read-only-storage' } },
      { binding: 1, visibility: GPUShaderStage.COMPUTE, buffer: { type: 'storage' } },
    ],
  });
  const pipeline = device.createComputePipeline({
    layout: device.createPipelineLayout({ bindGroupLayouts: [zero.layout, ioLayout] }),
    compute: { module, entryPoint: 'mg_displace' },
  });
  const input = buffer(device, new Uint8Array(mesh, 0, 32 * count), GPUBufferUsage.STORAGE);
  const moved = device.createBuffer({ size: 16 * count, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
  const readback = device.createBuffer({ size: 16 * count, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
  const io = device.createBindGroup({ layout: ioLayout, entries: [{ binding: 0, resource: { buffer: input } }, { binding: 1, resource: { buffer: moved } }] });
  const encoder = device.createCommandEncoder();
  const pass = encoder.beginComputePass();
  pass.setPipeline(pipeline);
  pass.setBindGroup(0, zero.group);
  pass.setBindGroup(1, io);
  pass.dispatchWorkgroups(Math.ceil(count / 64));
  pass.end();
  encoder.copyBufferToBuffer(moved, 0, readback, 0, 16 * count);
  device.queue.submit([encoder.finish()]);
  await readback.mapAsync(GPUMapMode.READ);
  const q = new Float32Array(readback.getMappedRange().slice(0));
  readback.unmap();

  // Weld groups: each vertex's smallest index at bitwise the same undisplaced position
  // (-0 read as 0), then area-weighted face normals summed per group.
  const records = new Float32Array(mesh, 0, 8 * count);
  const bits = new Uint32Array(mesh, 0, 8 * count);
  const first = new Map();
  const group = new Uint32Array(count);
  for (let i = 0; i < count; i++) {
    const key = [0, 1, 2].map((c) => (records[8 * i + c] === 0 ? 0 : bits[8 * i + c])).join(',');
    if (!first.has(key)) first.set(key, i);
    group[i] = first.get(key);
  }
  const sums = new Float64Array(3 * count);
  const indices = new Uint32Array(mesh, m.index_offset, m.indices);
  for (let t = 0; t < indices.length; t += 3) {
    const [a, b, c] = [indices[t], indices[t + 1], indices[t + 2]];
    const e1 = [0, 1, 2].map((k) => q[4 * b + k] - q[4 * a + k]);
    const e2 = [0, 1, 2].map((k) => q[4 * c + k] - q[4 * a + k]);
    const face = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    for (const v of [a, b, c]) for (let k = 0; k < 3; k++) sums[3 * group[v] + k] += face[k];
  }
  const out = new Float32Array(8 * count);
  for (let i = 0; i < count; i++) {
    const g = group[i];
    const s = [sums[3 * g], sums[3 * g + 1], sums[3 * g + 2]];
    const len = Math.hypot(...s);
    const normal = len > 0 && Number.isFinite(len) ? s.map((x) => x / len) : [0, 1, 2].map((k) => records[8 * i + 3 + k]);
    out.set([q[4 * i], q[4 * i + 1], q[4 * i + 2], ...normal, records[8 * i + 6], records[8 * i + 7]], 8 * i);
  }
  return new Uint8Array(out.buffer);
}

// --- Drawing -------------------------------------------------------------------------

async function main() {
  if (!graph) throw new Error('no graph: pass ?dir=URL/&graph=NAME');
  if (!navigator.gpu) throw new Error('this browser has no WebGPU');
  const [contract, source, scene, mesh] = await Promise.all([
    json(new URL(`${graph}.contract.json`, dir)),
    text(new URL(`${graph}.wgsl`, dir)),
    json(new URL('view.json', dir)),
    bytes(new URL('mesh.bin', dir)),
  ]);
  const sceneDepth = new Float32Array(await bytes(new URL(scene.depth, dir)));
  const manifest = contract.textures.some((t) => t.source === 'scene') ? await json(new URL('manifest.json', dir)) : null;
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new Error('no WebGPU adapter');
  const device = await adapter.requestDevice();
  const errors = [];
  device.addEventListener('uncapturederror', (e) => errors.push(e.error.message));

  const module = await shaderModule(device, source, 'WGSL');

  const params = buffer(device, parameterBlock(contract, scene.time, query.getAll('set')), GPUBufferUsage.UNIFORM);
  const frame = buffer(device, frameBlock(contract, scene), GPUBufferUsage.UNIFORM);
  const lights = buffer(device, lightsBlock(contract, scene), GPUBufferUsage.STORAGE);
  const { layout: bindGroupLayout, group: bindGroup } = await groupZero(device, contract, manifest, { mg_params: params, mg_frame: frame, mg_lights: lights });

  // The mesh: vertices, indices and tangents as `view.json` places them in mesh.bin.
  const m = scene.mesh;
  // With `displace=compute`, NAME.wgsl is the `--displaced-vertices` module and the
  // vertices are displaced here first.
  const records = query.get('displace') === 'compute'
    ? await displaceOnGpu(device, mesh, m, scene, manifest)
    : new Uint8Array(mesh, 0, m.index_offset);
  const vertices = buffer(device, records, GPUBufferUsage.VERTEX);
  const indices = buffer(device, new Uint8Array(mesh, m.index_offset, 4 * m.indices), GPUBufferUsage.INDEX);
  const tangents = buffer(device, new Uint8Array(mesh, m.tangent_offset, 16 * m.vertices), GPUBufferUsage.VERTEX);
  const vertexLayout = (v) => ({
    arrayStride: v.array_stride,
    stepMode: v.step_mode,
    attributes: v.attributes.map((a) => ({ shaderLocation: a.shader_location, format: a.format, offset: a.offset })),
  });
  const buffers = [vertexLayout(contract.vertex_buffer)];
  if (contract.tangent_buffer) buffers.push(vertexLayout(contract.tangent_buffer));

  // The pipeline the contract asks for: culling, depth pre-pass, compare and blending.
  const p = contract.pipeline;
  const layout = device.createPipelineLayout({ bindGroupLayouts: [bindGroupLayout] });
  const vertex = { module, entryPoint: contract.entry_points.vertex, buffers };
  const primitive = { topology: 'triangle-list', cullMode: p.cull_mode };
  const blend = (f) => ({ srcFactor: f[0], dstFactor: f[1], operation: 'add' });
  const color = device.createRenderPipeline({
    layout, vertex, primitive,
    fragment: {
      module, entryPoint: contract.entry_points.fragment,
      targets: [{ format: 'rgba16float', blend: { color: blend(contract.color_target.blend_color), alpha: blend(contract.color_target.blend_alpha) } }],
    },
    depthStencil: { format: 'depth32float', depthWriteEnabled: p.depth_write, depthCompare: p.depth_compare },
  });
  const prepass = p.depth_prepass && device.createRenderPipeline({
    layout, vertex, primitive,
    depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'less' },
  });

  const [w, h] = [scene.width, scene.height];
  const target = device.createTexture({ size: [w, h], format: 'rgba16float', usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC });
  const depth = device.createTexture({ size: [w, h], format: 'depth32float', usage: GPUTextureUsage.RENDER_ATTACHMENT });

  // The rest of the scene's depth (view.json's `depth`), loaded into the depth buffer first
  // by a full-screen triangle writing frag_depth: what stands in front of the material
  // hides it, as in the render (the page does not draw the rest of the scene's colour).
  const depthTexels = device.createTexture({ size: [w, h], format: 'r32float', usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST });
  device.queue.writeTexture({ texture: depthTexels }, sceneDepth, { bytesPerRow: w * 4 }, [w, h]);
  const depthModule = await shaderModule(device, `
    @group(0) @binding(0) var depth_texels: texture_2d<f32>;
    @vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
      return vec4<f32>(f32(i & 1u) * 4.0 - 1.0, f32(i >> 1u) * 4.0 - 1.0, 0.0, 1.0);
    }
    @fragment fn fs(@builtin(position) p: vec4<f32>) -> @builtin(frag_depth) f32 {
      return textureLoad(depth_texels, vec2<i32>(p.xy), 0).r;
    }`, 'depth WGSL');
  const depthPipeline = device.createRenderPipeline({
    layout: 'auto',
    vertex: { module: depthModule, entryPoint: 'vs' },
    fragment: { module: depthModule, entryPoint: 'fs', targets: [] },
    primitive: { topology: 'triangle-list' },
    depthStencil: { format: 'depth32float', depthWriteEnabled: true, depthCompare: 'always' },
  });
  const depthBindGroup = device.createBindGroup({
    layout: depthPipeline.getBindGroupLayout(0),
    entries: [{ binding: 0, resource: depthTexels.createView() }],
  });
  const rowBytes = Math.ceil((w * 8) / 256) * 256;
  const readback = device.createBuffer({ size: rowBytes * h, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
  const encoder = device.createCommandEncoder();
  const draw = (pass, pipeline) => {
    pass.setPipeline(pipeline);
    pass.setBindGroup(0, bindGroup);
    pass.setVertexBuffer(0, vertices);
    if (contract.tangent_buffer) pass.setVertexBuffer(1, tangents);
    pass.setIndexBuffer(indices, 'uint32');
    pass.drawIndexed(m.indices);
    pass.end();
  };
  const scenePass = encoder.beginRenderPass({
    colorAttachments: [],
    depthStencilAttachment: { view: depth.createView(), depthClearValue: 1, depthLoadOp: 'clear', depthStoreOp: 'store' },
  });
  scenePass.setPipeline(depthPipeline);
  scenePass.setBindGroup(0, depthBindGroup);
  scenePass.draw(3);
  scenePass.end();
  if (prepass) {
    draw(encoder.beginRenderPass({
      colorAttachments: [],
      depthStencilAttachment: { view: depth.createView(), depthLoadOp: 'load', depthStoreOp: 'store' },
    }), prepass);
  }
  draw(encoder.beginRenderPass({
    colorAttachments: [{ view: target.createView(), clearValue: { r: 0, g: 0, b: 0, a: 0 }, loadOp: 'clear', storeOp: 'store' }],
    depthStencilAttachment: { view: depth.createView(), depthLoadOp: 'load', depthStoreOp: 'store' },
  }), color);
  encoder.copyTextureToBuffer({ texture: target }, { buffer: readback, bytesPerRow: rowBytes }, [w, h]);
  device.queue.submit([encoder.finish()]);
  await readback.mapAsync(GPUMapMode.READ);
  const halves = new Uint16Array(readback.getMappedRange());
  const pixels = new Float32Array(w * h * 4);
  for (let y = 0; y < h; y++) {
    for (let i = 0; i < w * 4; i++) pixels[y * w * 4 + i] = fromHalf(halves[(y * rowBytes) / 2 + i]);
  }
  readback.unmap();
  if (errors.length) throw new Error(`WebGPU: ${errors.join('; ')}`);

  // Shown: exposure 1, clamped, sRGB-encoded over black; reported: the linear texels.
  const canvas = document.getElementById('view');
  canvas.width = w;
  canvas.height = h;
  const image = new ImageData(w, h);
  for (let i = 0; i < pixels.length; i++) {
    image.data[i] = i % 4 === 3 ? 255 : Math.round(255 * linearToSrgb(Math.min(Math.max(pixels[i], 0), 1)));
  }
  canvas.getContext('2d').putImageData(image, 0, 0);
  const raw = new Uint8Array(pixels.buffer);
  let binary = '';
  for (let i = 0; i < raw.length; i += 0x8000) binary += String.fromCharCode(...raw.subarray(i, i + 0x8000));
  const info = adapter.info ?? {};
  report({ status: 'ok', graph, width: w, height: h, adapter: `${info.vendor ?? ''} ${info.architecture ?? ''} ${info.description ?? ''}`.trim(), pixels: btoa(binary) });
}

main().catch((e) => report({ status: 'error', message: String(e && e.message ? e.message : e) }));
