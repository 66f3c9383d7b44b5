// Compiles WGSL files with Tint, the WGSL compiler of Chrome and Dawn, through Dawn's node
// bindings (npm package `webgpu`) on Dawn's null backend: no GPU or driver is needed, and
// `createShaderModule` runs Tint's parser, resolver, validator and constant evaluator, which
// is where Chrome reports a module's errors. Each module's `@compute` or `@fragment` entry is
// then made into a pipeline with an `auto` layout (a fragment entry gets a vertex stage
// written from its input struct, or the module's own `@vertex` entry, fed by one interleaved
// vertex buffer laid out from that entry's input struct), so Dawn's entry-point and binding
// checks run too. A module with no entry point (a library) is compiled only. The null
// device has WebGPU's default limits (8 storage buffers a stage, ...); matgraph's runtime asks
// for the adapter's limits, so going past a default per-stage binding count is a warning.
//
// Usage: node tests/tint/check.mjs FILE.wgsl...
// Prints `FILE:LINE:COL: error: MESSAGE` per diagnostic (warnings too), then one line
// `tint: N files, E errors, W warnings`. Exit 0 without errors, 1 with, 2 when Dawn is
// missing or gives no device.
import { readFileSync } from 'node:fs';

let dawn;
try {
  dawn = await import('webgpu');
} catch (e) {
  console.log(`tint: cannot load the npm package webgpu (npm ci --prefix tests/tint): ${e.message}`);
  process.exit(2);
}
const { create, globals } = dawn;
Object.assign(globalThis, globals);

const gpu = create(['backend=null']);
const adapter = await gpu.requestAdapter();
const device = adapter && (await adapter.requestDevice());
if (!device) {
  console.log('tint: Dawn gave no null-backend device');
  process.exit(2);
}
device.onuncapturederror = () => {};

/** A vertex shader whose outputs are the members of the fragment entry's input struct. */
function vertexFor(code) {
  const entry = /@fragment\s*fn\s+\w+\s*\(\s*\w+\s*:\s*(\w+)\s*\)/.exec(code);
  const members = [];
  if (entry) {
    const struct = new RegExp(`struct\\s+${entry[1]}\\s*\\{([^}]*)\\}`).exec(code);
    for (const m of (struct ? struct[1] : '').split(',')) {
      const t = m.trim();
      if (t && !/@builtin/.test(t)) members.push(t);
    }
  }
  members.unshift('@builtin(position) mg_position: vec4<f32>');
  return `struct MgVertexOut {\n${members.map((m) => `    ${m},`).join('\n')}\n}\n` +
    '@vertex\nfn main() -> MgVertexOut {\n    var o: MgVertexOut;\n    return o;\n}\n';
}

/** The vertex format of a WGSL vertex input type, and its size in bytes. */
const VERTEX_FORMATS = {
  'f32': ['float32', 4],
  'vec2<f32>': ['float32x2', 8],
  'vec3<f32>': ['float32x3', 12],
  'vec4<f32>': ['float32x4', 16],
};

/** The module's own vertex entry and one interleaved buffer for its `@location` inputs. */
function ownVertex(code, module) {
  const entry = /@vertex\s*fn\s+(\w+)\s*\(\s*\w+\s*:\s*(\w+)\s*\)/.exec(code);
  if (!entry) return null;
  const struct = new RegExp(`struct\\s+${entry[2]}\\s*\\{([^}]*)\\}`).exec(code);
  const attributes = [];
  let offset = 0;
  for (const m of (struct ? struct[1] : '').split(',')) {
    const loc = /@location\((\d+)\)\s*\w+\s*:\s*([\w<>]+)/.exec(m.trim());
    if (!loc) continue;
    const [format, size] = VERTEX_FORMATS[loc[2]] ?? ['float32x4', 16];
    attributes.push({ shaderLocation: Number(loc[1]), offset, format });
    offset += size;
  }
  return { module, entryPoint: entry[1], buffers: [{ arrayStride: offset, attributes }] };
}

/** The validation error of `make()`, or null. */
async function scoped(make) {
  device.pushErrorScope('validation');
  make();
  return device.popErrorScope();
}

let errors = 0;
let warnings = 0;
const files = process.argv.slice(2);
for (const file of files) {
  const code = readFileSync(file, 'utf8');
  const module = device.createShaderModule({ code });
  const info = await module.getCompilationInfo();
  let failed = false;
  for (const m of info.messages) {
    if (m.type === 'info') continue;
    if (m.type === 'error') {
      errors += 1;
      failed = true;
    } else {
      warnings += 1;
    }
    console.log(`${file}:${m.lineNum}:${m.linePos}: ${m.type}: ${m.message}`);
  }
  if (failed) continue;
  let err = null;
  if (/@compute/.test(code)) {
    err = await scoped(() => device.createComputePipeline({ layout: 'auto', compute: { module } }));
  } else if (/@fragment/.test(code)) {
    const fragmentName = /@fragment\s*fn\s+(\w+)/.exec(code)[1];
    const vertex = ownVertex(code, module) ?? {
      module: device.createShaderModule({ code: vertexFor(code) }),
    };
    err = await scoped(() =>
      device.createRenderPipeline({
        layout: 'auto',
        vertex,
        fragment: { module, entryPoint: fragmentName, targets: [{ format: 'rgba16float' }] },
      }),
    );
  }
  if (err) {
    const message = err.message.replace(/\s+/g, ' ').trim();
    if (/exceeds the maximum per-stage limit.*While validating binding counts/.test(message)) {
      warnings += 1;
      console.log(`${file}:0:0: warning: pipeline at WebGPU's default limits: ${message}`);
    } else {
      errors += 1;
      console.log(`${file}:0:0: error: pipeline: ${message}`);
    }
  }
}
console.log(`tint: ${files.length} files, ${errors} errors, ${warnings} warnings`);
device.destroy();
process.exit(errors ? 1 : 0);
